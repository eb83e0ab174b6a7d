"""The CalculiX deck writer and result readers of the peer cross-check, without running ccx."""

from __future__ import annotations

import numpy as np
import pytest

from postprocess import peer_ccx as P


def _cube_body(name: str, shift=0.0) -> P.Body:
    """A unit cube as 5 tetrahedra; facet groups: its z = 0 and z = 1 faces."""
    pts = np.array([[x, y, z] for z in (0, 1) for y in (0, 1) for x in (0, 1)], float)
    pts[:, 2] += shift
    tets = np.array([[0, 1, 3, 5], [0, 3, 2, 6], [0, 5, 4, 6], [3, 5, 6, 7], [0, 3, 5, 6]])
    bottom = np.array([[0, 1, 3], [0, 3, 2]])
    top = np.array([[4, 5, 6], [5, 7, 6]])
    return P.Body(name, pts, tets, {f"{name}/bottom": bottom, f"{name}/top": top})


def test_element_faces_match_ccx_numbering():
    b = _cube_body("a")
    P.number([b])
    el, face = P.element_faces(b, b.facets["a/bottom"])
    for e, f, tri in zip(el, face, b.facets["a/bottom"], strict=True):
        local = b.tets[e - 1][list(P.TET_FACES[f - 1])]
        assert sorted(local) == sorted(tri)
    with pytest.raises(ValueError, match="no tet face"):
        P.element_faces(b, np.array([[0, 1, 7]]))


def test_deck_writer(tmp_path):
    lower, upper = _cube_body("lower"), _cube_body("upper", shift=1.0)
    deck = P.Deck(
        [lower, upper],
        206000.0,
        0.3,
        [
            P.Coupling(
                "top",
                "upper",
                "upper/top",
                (0.5, 0.5, 2.0),
                fixed=(1, 2),
                springs={3: 1000, 4: 2.5e9},
                load={3: -100.0},
            )
        ],
        [("lower", "lower/bottom")],
        [P.ContactPair("c", ("upper", ["upper/bottom"]), ("lower", ["lower/top"]))],
        penalty=1.0e7,
        preload=("top", 3, -1e-4),
    )
    info = P.write_deck(tmp_path / "m.inp", deck)
    text = (tmp_path / "m.inp").read_text()
    assert info["fe_nodes"] == 16 and info["ref_nodes"]["top"] == (17, 18)
    # the second body's elements and nodes are offset by the first's
    assert "6, 9, 10, 12, 14" in text
    # ccx reads a stiffness line only if the number has a decimal point
    assert "*SPRING, ELSET=SPR_TOP_3\n3\n1.0000000000e+03" in text
    assert "*SPRING, ELSET=SPR_TOP_4\n1\n2.5000000000e+09" in text
    assert "*RIGID BODY, NSET=N_TOP, REF NODE=17, ROT NODE=18" in text
    assert "TYPE=SURFACE TO SURFACE\nC_S, C_M" in text
    assert text.count("*STEP") == 2 and "*BOUNDARY, OP=NEW" in text
    assert "17, 3, 3, -1.000000000e-04" in text  # the preload step
    assert "*CLOAD\n17, 3, -1.000000000e+02" in text


def test_readers(tmp_path):
    frd = tmp_path / "r.frd"
    rows = [
        "    1PSTEP                         1           1           1",
        " -4  CONTACT     6    1",
        " -5  COPEN       1    1    0    0",
        " -5  CSLIP1      1    1    0    0",
        " -5  CSLIP2      1    1    0    0",
        " -5  CPRESS      1    1    0    0",
        " -5  CSHEAR1     1    1    0    0",
        " -5  CSHEAR2     1    1    0    0",
        " -1         5-1.00000E-03 0.00000E+00 0.00000E+00 1.00000E+02 0.00000E+00 0.00000E+00",
        " -1         6-1.00000E-03 0.00000E+00 0.00000E+00 3.00000E+02 0.00000E+00 0.00000E+00",
        " -3",
    ]
    frd.write_text("\n".join(rows) + "\n")
    comps, data = P.read_frd_block(frd, "CONTACT")
    assert comps[3] == "CPRESS" and data[6][3] == 300.0 and data[5][0] == -1e-3
    with pytest.raises(ValueError, match="no result block"):
        P.read_frd_block(frd, "DISP")
    dat = tmp_path / "r.dat"
    dat.write_text(
        "\n displacements (vx,vy,vz) for set REFS and time  0.5000000E+00\n\n"
        "        17  1.0E+00  2.0E+00  3.0E+00\n"
        "\n displacements (vx,vy,vz) for set REFS and time  0.1000000E+01\n\n"
        "        17  4.0E+00 -5.0E-01  6.0E-03\n        18  0.0 0.0 1.0E-04\n"
    )
    u = P.read_dat_displacements(dat)
    assert np.allclose(u[17], [4.0, -0.5, 6e-3]) and np.allclose(u[18], [0, 0, 1e-4])


def test_contact_resultant_uniform_pressure():
    """A uniform pressure p on the unit top face: force p along -n, centroid at its z."""
    b = _cube_body("a")
    P.number([b])
    pressure = {n + 1: 2.0 for n in range(8)}
    res = P.contact_resultant(b, ["a/top"], pressure, centre=(0.5, 0.5, 0.0))
    # the facets' winding decides the normal's sign: the force is along -normal, |F| = p A
    assert res["normal_force_N"] == pytest.approx(2.0)
    assert abs(res["force_N"][2]) == pytest.approx(2.0)
    assert res["z_centroid_mm"] == pytest.approx(1.0)
    # the resultant acts at the face centre above ``centre``: no moment about it
    assert np.allclose(res["moment_Nmm"], 0.0, atol=1e-12)

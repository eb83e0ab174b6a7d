"""The CalculiX deck writer and result readers of the peer cross-check, without running ccx."""

from __future__ import annotations

import os
import shutil
import subprocess
from types import SimpleNamespace

import numpy as np
import pytest

from studies.peer import ccx as P
from studies.peer.driver import _centroid_split


def _cube_body(name: str, shift=0.0) -> P.Body:
    """A unit cube as 5 tetrahedra; facet groups: its z = 0 and z = 1 faces."""
    pts = np.array([[x, y, z] for z in (0, 1) for y in (0, 1) for x in (0, 1)], float)
    pts[:, 2] += shift
    tets = np.array([[0, 1, 3, 5], [0, 3, 2, 6], [0, 5, 4, 6], [3, 5, 6, 7], [0, 3, 5, 6]])
    x = pts[tets]
    neg = np.linalg.det(x[:, 1:] - x[:, :1]) < 0  # ccx needs positive volumes
    tets[neg] = tets[neg][:, [0, 2, 1, 3]]
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


def test_deck_prints_what_the_read_back_needs(tmp_path):
    """Every body's nodes at 7 digits (``*NODE PRINT``) and ccx's totals per pair, named by
    its surfaces (without SLAVE/MASTER ccx 2.20 stops: "no existing contact pair")."""
    deck = _two_cubes()
    info = P.write_deck(tmp_path / "m.inp", deck)
    text = (tmp_path / "m.inp").read_text()
    assert "*NSET, NSET=ALL_UPPER, GENERATE\n9, 16, 1" in text
    assert "*NODE PRINT, NSET=ALL_LOWER\nU" in text
    s, m = info["surfaces"]["c"]
    assert f"*CONTACT PRINT, SLAVE={s}, MASTER={m}\nCF" in text


def _two_cubes(load=-100.0) -> P.Deck:
    """The upper unit cube pressed on the lower one by ``load`` (N, z) on a rigid top face;
    the lower cube's bottom clamped."""
    lower, upper = _cube_body("lower"), _cube_body("upper", shift=1.0)
    top = P.Coupling(
        "top", "upper", "upper/top", (0.5, 0.5, 2.0), fixed=(1, 2, 4, 5, 6), load={3: load}
    )
    return P.Deck(
        [lower, upper],
        206000.0,
        0.3,
        [top],
        [("lower", "lower/bottom")],
        [P.ContactPair("c", ("upper", ["upper/bottom"]), ("lower", ["lower/top"]))],
        penalty=1.0e6,
        preload=("top", 3, -1e-5),
    )


def test_contact_statistics_reader(tmp_path):
    """ccx 2.20's CF block (format of printoutcontact.f): the last time wins; titles skipped."""
    block = (
        " statistics for slave set C_ST, master set C_MT and time  {t}\n\n"
        "   total surface force (fx,fy,fz) and moment about the origin (mx,my,mz)\n\n"
        "    1.0E+00 -2.0E+00  {f}  5.0E+01 -5.0E+01 -1.0E-12\n\n"
        "   center of gravity and mean normal\n\n"
        "    5.0E-01  5.0E-01  1.0E+00 0.0E+00  0.0E+00 -1.0E+00\n\n"
        "   moment about the center of gravity(mx,my,mz)\n\n"
        "    1.5E-07 -3.8E-09 -1.1E-12\n\n"
        "   area,  normal force (+ = tension) and shear force (size)\n\n"
        "    1.0E+00 -{f}  1.4E-09\n"
    )
    dat = tmp_path / "r.dat"
    dat.write_text(block.format(t="0.1E+01", f="9.0E+01") + block.format(t="0.2E+01", f="1.0E+02"))
    (rec,) = P.read_dat_contact_statistics(dat).values()
    assert rec["force_N"] == [1.0, -2.0, 100.0] and rec["normal_force_N"] == -100.0
    assert rec["centre_mm"] == [0.5, 0.5, 1.0] and rec["area_mm2"] == 1.0
    dat.write_text(block.format(t="0.1E+01", f="9.0E+01").split("area")[0])
    with pytest.raises(ValueError, match="cut short"):
        P.read_dat_contact_statistics(dat)


def test_displacements_of_every_set_at_the_last_time(tmp_path):
    dat = tmp_path / "r.dat"
    dat.write_text(
        " displacements (vx,vy,vz) for set A and time  0.1E+01\n\n  1  9.0 9.0 9.0\n\n"
        " displacements (vx,vy,vz) for set A and time  0.2E+01\n\n  1  1.0 2.0 3.0\n\n"
        " displacements (vx,vy,vz) for set B and time  0.2E+01\n\n  7  4.0 5.0 6.0\n"
    )
    u = P.read_dat_displacements(dat)
    assert sorted(u) == [1, 7] and np.allclose(u[1], [1, 2, 3]) and np.allclose(u[7], [4, 5, 6])


def test_nodal_forces_patch_test():
    """Uniaxial stress sigma_zz = E e on the cube (u = e (-nu x, -nu y, z)): K u sums to
    +-E e on the top / bottom face nodes, zero elsewhere; flank_resultant reads the top face's
    force as a normal (compressive) load E |e| at z = 1 with no moment about its centre."""
    b = _cube_body("a")
    P.number([b])
    E, nu, e = 206000.0, 0.3, -1e-4
    u = e * b.points * np.array([-nu, -nu, 1.0])
    f = P.nodal_forces(b.points, b.tets, u, E, nu)
    top = b.points[:, 2] == 1.0
    assert np.allclose(f[top].sum(0), [0, 0, E * e], atol=1e-9)
    assert np.allclose(f[~top].sum(0), [0, 0, -E * e], atol=1e-9)
    sig = P.tet_stress(b.points, b.tets, u, E, nu)
    assert np.allclose(sig[:, 2, 2], E * e) and np.allclose(sig[:, :2, :2], 0.0, atol=1e-9)
    res = P.flank_resultant(b, ["a/top"], f, centre=(0.5, 0.5, 1.0))
    assert res["normal_force_N"] == pytest.approx(-E * e)  # e < 0: pressed
    assert res["centroid_mm"][2] == pytest.approx(1.0)
    assert np.allclose(res["moment_Nmm"], 0.0, atol=1e-9)


def test_nodal_forces_are_self_equilibrated():
    """For any displacement the internal forces have zero resultant and zero moment."""
    b = _cube_body("a")
    u = np.random.default_rng(1).normal(size=b.points.shape) * 1e-3
    f = P.nodal_forces(b.points, b.tets, u, 206000.0, 0.3)
    assert np.abs(f).max() > 1.0  # not trivially zero
    assert np.allclose(f.sum(0), 0.0, atol=1e-9)
    assert np.allclose(np.cross(b.points, f).sum(0), 0.0, atol=1e-9)


def test_outward_winding():
    b = _cube_body("a")
    P.number([b])
    for tag, nz in (("a/bottom", -1.0), ("a/top", 1.0)):
        t = P.outward(b, b.facets[tag])
        a, c, d = (b.points[t[:, i]] for i in range(3))
        assert np.all(np.cross(c - a, d - a)[:, 2] * nz > 0)


@pytest.mark.skipif(shutil.which("ccx") is None, reason="CalculiX (ccx) not installed")
def test_ccx_read_back_balances_the_load(tmp_path):
    """Two cubes pressed by 100 N, solved by ccx: the upper cube's K u at its contact nodes,
    ccx's own CF total and the applied load agree (the read-back of the peer benchmark)."""
    deck = _two_cubes(-100.0)
    info = P.write_deck(tmp_path / "c.inp", deck)
    run = subprocess.run(
        ["ccx", "-i", "c"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        env={**os.environ, "OMP_NUM_THREADS": "1"},
    )
    assert run.returncode == 0, run.stdout[-2000:]
    u = P.read_dat_displacements(tmp_path / "c.dat")
    upper = deck.bodies[1]
    ub = np.array([u[n] for n in range(upper.node0 + 1, upper.node0 + 9)])
    f = P.nodal_forces(upper.points, upper.tets, ub, deck.E, deck.nu)
    res = P.flank_resultant(upper, ["upper/bottom"], f, centre=(0.5, 0.5, 1.0))
    # ccx's default convergence check: residual forces below 5e-3 of the mean force
    assert res["normal_force_N"] == pytest.approx(100.0, rel=5e-3)
    (cf,) = P.read_dat_contact_statistics(tmp_path / "c.dat").values()
    assert abs(cf["normal_force_N"]) == pytest.approx(100.0, rel=5e-3)
    # one solution read two ways; 0.1 N: the 7-digit print of displacements of ~1e-4 mm
    assert np.allclose(res["force_N"], cf["force_N"], atol=0.1)
    assert info["surfaces"]["c"] == ("C_S", "C_M")


def test_facet_sag_on_a_cylinder():
    """A triangulated cylinder (radius 10 mm, 1 mm chords round it, 1 mm along it): every
    facet has a chord across the curvature, whose sag is R (1 - cos(dtheta / 2))."""
    R, dth = 10.0, 0.1
    th, z = np.meshgrid(np.arange(8) * dth, np.arange(6.0), indexing="ij")
    pts = np.c_[R * np.cos(th.ravel()), R * np.sin(th.ravel()), z.ravel()]
    idx = np.arange(pts.shape[0]).reshape(th.shape)
    tris = []
    for i in range(7):
        for j in range(5):
            a, b, c, d = idx[i, j], idx[i + 1, j], idx[i + 1, j + 1], idx[i, j + 1]
            tris += [(a, b, c), (a, c, d)]
    body = P.Body("c", pts, np.zeros((0, 4), int), {"c/f": np.array(tris)})
    sag = P.facet_sag(body, ["c/f"])
    # a quadratic fitted to a circle over +-2 chords overestimates its curvature by < 3 %
    assert np.allclose(sag, R * (1 - np.cos(dth / 2)), rtol=0.03)


def test_centroid_split_moves_ccx_forces_to_our_centroids():
    """The moment difference a centroid shift carries: (c_ours - c_ccx) x F_ccx, in N m."""
    ours = {"mesh_centroid_pinion_mm": {"a": [0.0, 0.0, 1.0], "b": [0.0, 2.0, 0.0]}}
    ccx = {
        "meshes": {
            "a": {"centroid_pinion_mm": [0.0, 0.0, 0.0], "force_pinion_N": [0.0, 1000.0, 0.0]},
            "b": {"centroid_pinion_mm": [0.0, 0.0, 0.0], "force_pinion_N": [0.0, 0.0, 500.0]},
        }
    }
    # a: dz = 1 mm under Fy = 1000 N -> Mx = -1 N m; b: dy = 2 mm under Fz = 500 N -> Mx = +1
    assert np.allclose(_centroid_split(ours, ccx), [0.0, 0.0])
    ccx["meshes"]["b"]["force_pinion_N"] = [0.0, 0.0, 0.0]
    assert np.allclose(_centroid_split(ours, ccx), [-1.0, 0.0])


def test_ccx_root_stress_reads_a_field_as_our_own_routine_does():
    """The read-back of ccx's displacement into our root-stress routine (node matching by
    coordinates, scene -> body frame), without ccx: a displacement given at ccx's numbered
    nodes in the scene frame must give the values our routine gives for the same field
    interpolated on our own mesh in the body frame. Quadratic in x, so both the node order
    and the turn matter (a wrong sign of the turn changes the stresses)."""
    import dolfinx
    from mpi4py import MPI

    from meshing.scene_bodies import load_body_meshes
    from solvers import root_stress as RS
    from solvers.elastic_body import Material
    from studies.peer.driver import build_deck, ccx_root_stress

    def u_scene(x):  # (n, 3) scene-frame points -> (n, 3) displacement, mm
        return 1e-5 * np.c_[x[:, 0] ** 2, x[:, 0] * x[:, 1], 0.5 * x[:, 1] ** 2 + x[:, 2] ** 2]

    _, scene, deck, _, _ = build_deck("1-GA", 0, 0.0, 100.0, 1e3)
    P.number(deck.bodies)
    u = {}
    for b in deck.bodies:
        for i, v in enumerate(u_scene(b.points)):
            u[b.node0 + 1 + i] = v
    keyed: dict[str, dict[str, list[int]]] = {}
    for key, name, _, _ in RS.loaded_fillets(scene):
        keyed.setdefault(name, {})[key] = [0, 1]
    ours_bs = {
        "locations": {k: {"teeth": t, "tooth": None} for v in keyed.values() for k, t in v.items()}
    }
    got = ccx_root_stress(scene, 0, deck, u, ours_bs)
    meshes = load_body_meshes(scene, 0, MPI.COMM_SELF)
    for name, keys in keyed.items():
        bm, pl = meshes[name], scene.gear(name).placement
        V = dolfinx.fem.functionspace(bm.bundle.mesh, ("Lagrange", 1, (3,)))
        xb = V.tabulate_dof_coordinates()
        a = -pl.angle  # scene -> body: the turn back by the placement angle
        R = np.array([[np.cos(a), -np.sin(a), 0.0], [np.sin(a), np.cos(a), 0.0], [0, 0, 1.0]])
        fn = dolfinx.fem.Function(V)
        fn.x.array[:] = (u_scene(pl.apply(xb)) @ R.T).ravel()
        body = SimpleNamespace(
            name=name,
            mesh=bm.bundle.mesh,
            facet_tags=bm.bundle.facet_tags,
            tags=bm.tags,
            comm=MPI.COMM_SELF,
            gdim=3,
            degree=1,
            material=Material(deck.E, deck.nu),
        )
        want = RS.body_root_stress(body, fn, scene.gear(name).gear, keys)
        for k in keys:
            assert want[k]["value"] > 1.0  # a field that stresses the fillets read
            # the same nodal values through the same routine: equal to round-off
            assert got[k]["value"] == pytest.approx(want[k]["value"], rel=1e-9), k
            assert got[k]["tangent"] == pytest.approx(want[k]["tangent"], rel=1e-9), k

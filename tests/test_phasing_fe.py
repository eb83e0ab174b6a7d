"""Planet phasing from the all-planet FE (studies.phasing.driver, studies.phasing.fe) and the
``planet_angles_deg`` option of the all-planet scene."""

from __future__ import annotations

import math
import tomllib

import numpy as np
import pytest
from mpi4py import MPI

from cases.gearset import GEARSET_DIR, load_gearset
from cases.study_case import load_study_case
from meshing.scenes import build_scene
from meshing.sizing import MeshingError
from solvers.body_store import BodyStore
from studies.phasing import fe as pf
from studies.phasing.driver import planet_angles
from studies.position import solve_position
from studies.settings import RunSettings

STEP = 360.0 / 126  # deg, assemblable step of parker2000 (Zs + Zr = 126)


def test_harmonics_of_known_signals():
    m = 12
    k = np.arange(m)
    x = 3.0 + 2.0 * np.cos(2 * np.pi * k / m + 0.3) + 0.5 * np.sin(2 * np.pi * 3 * k / m)
    a = pf.harmonics(x)
    assert a[:4] == pytest.approx([3.0, 2.0, 0.0, 0.5], abs=1e-12)
    # a force vector turning once per cycle: its first harmonic is its length
    v = np.c_[np.cos(2 * np.pi * k / m), np.sin(2 * np.pi * k / m)] * 7.0
    assert pf.harmonics(v)[1] == pytest.approx(7.0, rel=1e-12)


def test_four_planet_gear_set_differs_only_in_planets():
    def data(name):
        return tomllib.loads((GEARSET_DIR / f"{name}.toml").read_text())

    three, four = data("parker2000"), data("parker2000-4")
    assert (three.pop("planets"), four.pop("planets")) == (3, 4)
    assert (three.pop("name"), four.pop("name")) == ("parker2000", "parker2000-4")
    assert three == four


def test_parker_angles_snap_and_assemble():
    study = load_study_case("parker2000-4")
    psi, snap = planet_angles(study, [0.0, 91.4, 180.0, 271.4])
    assert psi == pytest.approx([0.0, 32 * STEP, 180.0, 95 * STEP], abs=1e-12)
    assert snap == pytest.approx(32 * STEP - 91.4, abs=1e-12)
    gs = study.gearset
    sc = build_scene("all_planets", gs, 0.0, planet_angles_deg=tuple(psi))
    centres = [sc.gear(p).placement.centre for p in sc.pinion_names]
    got = [math.degrees(math.atan2(c[1], c[0])) % 360 for c in centres]
    assert got == pytest.approx(psi, abs=1e-9)
    # unsnapped, branch 2 is out of phase with the ring (the assembly check of the scene)
    with pytest.raises(MeshingError, match="out of phase with the ring"):
        build_scene("all_planets", gs, 0.0, planet_angles_deg=(0.0, 91.4, 180.0, 271.4))


@pytest.mark.parametrize(
    ("kind", "angles", "match"),
    [
        ("all_planets", (0.0, 120.0), "must be 3 finite numbers"),
        ("all_planets", (0.0, 120.0, math.nan), "must be 3 finite numbers"),
        ("all_planets", (0.0, 120.0, 360.0), "two planets at one angle"),
        # planets of 38.0 mm tip radius 20 deg apart on a 63.0 mm circle: 21.9 mm between centres
        ("all_planets", (0.0, 20.0, 240.0), r"tip circles of planet1 and planet2 overlap by"),
        ("one_branch", (0.0, 120.0, 240.0), "only for the all-planet scenes"),
        ("system", (0.0, 120.0, 240.0), "carrier body"),
    ],
)
def test_planet_angles_are_checked(kind, angles, match):
    with pytest.raises(MeshingError, match=match):
        build_scene(kind, load_gearset("parker2000"), 0.0, planet_angles_deg=angles)


@pytest.fixture(scope="module")
def three_planets():
    """parker2000, three planets, four positions over one mesh cycle, level 0 (the first
    harmonic without aliasing from the second)."""
    study = load_study_case("parker2000-3")  # spur
    gs = study.gearset
    m, pitch, store = 4, 2 * math.pi / 27, BodyStore()
    recs = [
        pf.position_record(
            solve_position(study, k * pitch / m, MPI.COMM_SELF, RunSettings(level=0), store=store),
            gs,
        )
        for k in range(m)
    ]
    r_b = gs.gears["sun"].base_radius
    return pf.analyse(recs, 27, [0.0, 120.0, 240.0], r_b, 1)


@pytest.mark.slow
def test_three_planets_cancel_the_first_harmonic_of_the_net_sun_force(three_planets):
    row = three_planets["harmonics"][0]
    single = max(row["excitation"]["mesh_N"])  # a single mesh's first harmonic (N)
    assert single > 0.1 * three_planets["mean_mesh_force_N"]  # single/double tooth contact
    # k = mod(27, 3) = 0: the net sun force has no first harmonic. As solved (torque held) the
    # in-phase planets share the load equally; measured 1/500 of a single mesh's harmonic.
    assert row["solved"]["net_force_N"] < single / 100
    # The excitation's net force cancels down to the level-0 mesh asymmetry between planets
    # (each tooth meshed differently: about 1 % of a mesh's harmonic, measured 1/57)
    assert row["excitation"]["net_force_N"] < single / 20
    # ... while the torque adds in phase (k = 0: rotation excited) and the TE has the harmonic
    assert row["excitation"]["torque_ratio"] == pytest.approx(1.0, abs=1e-3)
    assert row["solved"]["te_um"] > 1e-3 * three_planets["mean_te_um"]
    assert row["agrees"]


def test_the_case_section_names_the_sizes_solved():
    """A phasing case solved at its case file's sizes (another level's flanks and fillets,
    studies.phasing.driver records them in its inputs) says so; a level's own sizes read as
    before."""
    res = {
        "harmonics": [],
        "planets": 3,
        "planet_angles_deg": [0.0, 120.0, 240.0],
        "mean_mesh_force_N": 1.0,
        "mean_te_um": 1.0,
        "mean_sun_torque_Nm": 1.0,
        "sun_torque_spread_Nm": 0.0,
        "equilibrium_rel": 0.0,
        "mesh_force_ripple_rel": 0.0,
        "mesh_stiffness_ripple_rel": 0.0,
    }
    inp = {"description": "d", "positions": 12, "level": 1, "dofs": 10, "wall_s": 1.0, "zs": 21}
    varied = " ".join(pf.case_section("x", res, {**inp, "flank_level": 2, "fillet_level": 2}))
    assert "pitch, level 1 (level-2 flanks and fillets), 10 DOFs" in varied
    assert "pitch, level 1, 10 DOFs" in " ".join(pf.case_section("x", res, inp))

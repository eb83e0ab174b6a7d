"""Radial mesh stiffness from the FE contact solve (studies.radial_stiffness.driver) and the
floating-sun models built on it (studies.radial_stiffness.fe)."""

from __future__ import annotations

import json
import math

import pytest
from mpi4py import MPI

from cases.study_case import load_study_case
from gears.analytic import radial_stiffness as rs
from solvers.body_store import BodyStore
from studies.case_variants import global_root_stress
from studies.radial_stiffness import fe as rf
from studies.radial_stiffness.driver import (
    K_R_FROM,
    main,
    normal_backlash_um,
    solve_offsets,
    with_backlash,
)

H = 0.01  # mm, the larger step of `make radial-stiffness`


@pytest.fixture(scope="module")
def case():
    """1-GB on the line contact model: the closed form k_r is the geometric stiffness of
    forces along the exact plane of action, which the line grid's points carry; a zone
    grid's cells off the line carry turned normals and add their own share (level 0:
    -854.7 against -761.4 N/mm at the external mesh, h = 5 um; the report splits it,
    studies.radial_stiffness.fe.checks). The root stress is not read here: on the global
    model (studies/case_variants.py)."""
    import dataclasses

    study = global_root_stress(load_study_case("1-GB"))
    return dataclasses.replace(
        study, numerics=dataclasses.replace(study.numerics, contact_model="line")
    )


@pytest.fixture(scope="module")
def offsets(case):
    """Level-0 one-branch solves at d = -H, 0, +H; the pinion thinned if the set has too
    little backlash for +-H (the coast flanks of one mesh close by 0.87 H)."""
    study = case if normal_backlash_um(case) > 2 * H * 1e3 else with_backlash(case, 0.03)
    return solve_offsets(study, (-H, 0.0, H), 0.0, MPI.COMM_SELF, 0, BodyStore(), lambda *_: None)


def test_backlash_allowance_keeps_the_operating_geometry(case):
    thin = with_backlash(case, 0.03)
    p0, p1 = (s.gearset.gears["pinion"] for s in (case, thin))
    assert p1.tooth_thickness(p1.reference_radius) < p0.tooth_thickness(p0.reference_radius)
    assert (p1.tip_radius, p1.root_radius, p1.base_radius) == pytest.approx(
        (p0.tip_radius, p0.root_radius, p0.base_radius), abs=1e-12
    )
    assert normal_backlash_um(thin) > normal_backlash_um(case) + 30  # 2 x m_n sin(a_n) 0.03
    # k_r depends on the base radii and the centre distance only
    t = rf.sun_torque_nmm(case.gearset)
    a0, a1 = (rf.analytic_stiffness(s.gearset, t) for s in (case, thin))
    for kind in rf.KINDS:
        assert a1[kind]["k_r_pitch_form_N_per_mm"] == pytest.approx(
            a0[kind]["k_r_pitch_form_N_per_mm"], rel=1e-12
        )


@pytest.mark.slow
def test_fe_radial_stiffness_signs(offsets):
    k_ext = rf.central_difference(offsets, "external", H)
    k_int = rf.central_difference(offsets, "internal", H)
    assert k_ext < 0.0  # external mesh: negative stiffness (pust2016)
    assert k_int > 0.0  # internal mesh: restoring


@pytest.mark.slow
def test_fe_radial_stiffness_equals_the_closed_form(case, offsets):
    # The transverse normal force is fixed by the sun's moment balance (F_bt = T / r_b) and
    # acts along the exact plane of action at each offset, so the FE derivative is the
    # closed form up to the central difference's truncation, h^2 F''' / 6 ~ 1.2e-6 relative
    # at h = 10 um: 1e-5 leaves a margin of ten.
    an = rf.analytic_stiffness(case.gearset, rf.sun_torque_nmm(case.gearset))
    for kind in rf.KINDS:
        k = rf.central_difference(offsets, kind, H)
        assert k == pytest.approx(an[kind]["k_r_pitch_form_N_per_mm"], rel=1e-5)
        fbt = [offsets[d][kind]["transverse_force_N"] for d in offsets]
        assert max(fbt) - min(fbt) < 1e-9 * fbt[0]  # held torque: the same normal force


def test_branch_model_one_branch_is_the_two_dof_threshold():
    # N = 1: the sun's motion along the line of action is a mechanism (rotation free) and
    # the radial direction carries -k_r through the planet on k_c: pust2016's threshold.
    k_r, k_c = -761.4, 2.33e6
    out = rf.branch_model(1, 3.5e5, 4.2e5, k_r, 668.6, k_c, math.radians(21.3), math.radians(23.6))
    # (the planet's radial DOF also carries k_r,int and the mesh: ~k_r k_int / k_c^2 ~ 1e-7)
    assert out["threshold_k3_N_per_mm"] == pytest.approx(
        rs.stability_threshold(k_c, abs(k_r)), rel=1e-6
    )


def test_branch_model_two_and_three_branches():
    k_r, a = -761.4, math.radians(21.3)
    two = rf.branch_model(2, 3.5e5, 4.2e5, k_r, 668.6, 2.33e6, a, math.radians(23.6))
    # across the line of action only the two radial stiffnesses act: 2 |k_r| cos^2(a), up to
    # the coupling through the finite mesh and pin stiffnesses (k_r / k_mesh ~ 2e-3, measured
    # 1.0e-3 here)
    assert two["threshold_k3_N_per_mm"] == pytest.approx(2 * abs(k_r) * math.cos(a) ** 2, rel=5e-3)
    three = rf.branch_model(3, 3.5e5, 4.2e5, k_r, 668.6, 2.33e6, a, math.radians(23.6))
    lam = three["eigenvalues_N_per_mm"]
    assert three["threshold_k3_N_per_mm"] == 0.0  # stable without support
    assert lam[0] == pytest.approx(lam[1], rel=1e-9)  # isotropic for N >= 3


def _synthetic(ratio: float, model: str = "zone", jitter: float = 0.0) -> dict:
    """A radial_stiffness.json of 1-GB built from the closed form: F_rad(d) its on-plane
    part F_bt sin(alpha_wt(a + d)) plus an off-plane rest -(ratio - 1) k_closed d, so that
    FE / closed form = ratio (up to the truncation), plus ``jitter`` N on the rest at the
    offsets +-5 um, of opposite signs (a zone grid's changing cell set)."""
    import dataclasses

    study = load_study_case("1-GB")
    study = dataclasses.replace(
        study, numerics=dataclasses.replace(study.numerics, contact_model=model)
    )
    gs = study.gearset
    t = rf.sun_torque_nmm(gs)
    an = rf.analytic_stiffness(gs, t)
    steps, sweep = [0.005, 0.01], [0.02, 0.03]
    offs = sorted({0.0, *(s * h for h in steps + sweep for s in (-1, 1))})

    def record(d):
        out = {}
        for kind, sgn in (("external", 1.0), ("internal", -1.0)):
            a = an[kind]
            rb = a["centre_distance_mm"] * math.cos(math.radians(a["alpha_wt_deg"]))
            plane = sgn * rs.separating_force(
                an["transverse_force_N"], rb, a["centre_distance_mm"] + d
            )
            wiggle = jitter * ((d == -0.005) - (d == 0.005))
            out[kind] = {
                "radial_force_N": plane - (ratio - 1) * a["k_r_pitch_form_N_per_mm"] * d + wiggle,
                "plane_radial_force_N": plane,
                "transverse_force_N": an["transverse_force_N"],
                "alpha_wt_deg": math.degrees(math.acos(rb / (a["centre_distance_mm"] + d))),
                "active_points": 150,
            }
        return out

    recs = {d: record(d) for d in offs}
    ks = {k: {str(h): rf.central_difference(recs, k, h) for h in steps} for k in rf.KINDS}
    nominal = {
        "torque_factor": 1.0,
        "sun_torque_Nm": t / 1e3,
        "analytic": an,
        "records": {str(d): r for d, r in recs.items()},
        "k_r_steps": ks,
        "k_r": {k: rf.fit_stiffness(recs, k) for k in rf.KINDS},
    }
    k_ext, k_int = nominal["k_r"]["external"], nominal["k_r"]["internal"]
    a_s, a_r = (math.radians(an[k]["alpha_wt_deg"]) for k in rf.KINDS)
    return {
        "inputs": {
            "case": "1-GB",
            "gearset": gs.name,
            "contact_model": model,
            "level": 0,
            "degree": 1,
            "dofs": 1,
            "bearing_radial_N_per_mm": 2.33e6,
            "backlash_shift": 0.0,
            "backlash_normal_um": 89.0,
            "steps_mm": steps,
            "sweep_mm": steps + sweep,
            "torque_factors": [1.0],
            "rolls_pitch": [0.0, 0.5],
            "k_r_from": K_R_FROM,
        },
        "nominal": nominal,
        "torque_runs": [nominal],
        "second_roll": dict(nominal["k_r"]),
        "second_roll_records": nominal["records"],
        "coast_min_gap_um": 50.0,
        "coast_force_max_N": 0.0,
        "pinion_radial_deflection_um": 0.3,
        "pinion_tangential_deflection_um": 13.0,
        "mesh_stiffness": {
            "k_r_external": k_ext,
            "k_r_internal": k_int,
            "k_ms": 3.2e5,
            "k_mr": 4.0e5,
            "k_c": 2.33e6,
        },
        "stability": rf.stability(
            k_ext, k_int, 3.2e5, 4.0e5, 2.33e6, a_s, a_r, rf.body_masses(gs), (1, 2, 3)
        ),
    }


def test_report_claims_the_exact_match_only_on_agreement():
    text = rf.report(_synthetic(1.0, "line"))
    assert "Contact model line" in text
    assert "## Why the FE gives the closed form" in text
    assert "The match is exact to the truncation error" in text
    assert "independent of the mesh position" in text
    assert "the steps are in the linear range" in text
    assert "does not give the closed form" not in text


def test_report_states_the_disagreement():
    data = _synthetic(1.12)
    c = rf.checks(data)
    assert not c["exact"] and c["kinds"]["external"]["exact"]["rel"] == pytest.approx(0.12, 1e-4)
    # the rest off the plane of action carries the whole difference
    assert c["kinds"]["external"]["k_off_N_per_mm"] == pytest.approx(
        0.12 * c["kinds"]["external"]["closed_form_N_per_mm"], rel=1e-6
    )
    text = rf.report(data)
    assert "Contact model zone" in text
    assert "The match is exact" not in text and "## Why the FE gives the closed form" not in text
    assert "**the FE does not give the closed form**" in text
    assert "+12.0% / +12.0%" in text  # FE / closed form - 1, external / internal
    assert "## Why the FE differs from the closed form" in text
    # one torque: a departure from the closed form says nothing about proportionality (the
    # report said "not proportional to the load" from one torque until 2026-11-29)
    assert "One torque solved: whether the FE k_r is proportional to it is not tested" in text
    assert "not proportional" not in text
    # two torques with k_r in proportion (12 % off the closed form at both): a spread of 0
    half = {
        **data["nominal"],
        "sun_torque_Nm": data["nominal"]["sun_torque_Nm"] / 2,
        "k_r": {k: v / 2 for k, v in data["nominal"]["k_r"].items()},
    }
    two = {**data, "torque_runs": [half, data["nominal"]]}
    assert "a spread of 0.0% over the torques" in rf.report(two)
    half["k_r"] = {k: v / 2 * 1.1 for k, v in data["nominal"]["k_r"].items()}
    assert "a spread of 9.5% over the torques" in rf.report(two)
    # a second mesh position that disagrees is reported as such
    data["second_roll"]["internal"] *= 0.77
    text = rf.report(data)
    assert "independent of the mesh position" not in text
    assert "**k_r depends on the mesh position**" in text


def test_the_fit_over_the_sweep_is_the_stiffness_not_a_short_difference():
    # 1 N of opposite signs at +-5 um (the size of the level-1 zone grid's scatter, 0.95 N)
    # moves the 5 um central difference by 1 / 0.005 = 200 N/mm, 26 % of the closed form's
    # -761 N/mm; the fit over 0, +-5, +-10, +-20, +-30 um moves by 2 x 1 x 0.005 / 2.85e-3 =
    # 3.5 N/mm (0.46 %). The report leads with the fit and bounds it by the scatter.
    data = _synthetic(1.0, "zone", jitter=1.0)
    c = rf.checks(data)
    json.dumps(c)  # written into radial_stiffness.json: plain floats and bools
    for kind in rf.KINDS:
        k = c["kinds"][kind]
        kc = k["closed_form_N_per_mm"]
        assert k["k_cd_N_per_mm"] - kc == pytest.approx(200.0, rel=1e-3)
        k_line = kc * (1 + k["fit_truncation_rel"])  # the closed form's own fit
        assert k["k_r_N_per_mm"] - k_line == pytest.approx(2 * 0.005 / 2.85e-3, rel=1e-9)
        # the jitter is all off the plane: the on-plane slope is the closed form's fit
        assert k["k_plane_N_per_mm"] / kc - 1 == pytest.approx(k["fit_truncation_rel"], abs=1e-9)
        # its bound: s sum|d| / sum d^2 with s the largest departure about the line (~1 N)
        assert k["fit_scatter_bound_N_per_mm"] >= abs(k["k_r_N_per_mm"] - kc)
    assert not c["exact"] and not c["steps"]
    text = rf.report(data)
    assert "**the FE does not give the closed form**" in text
    assert "-0.5% / +0.5%" in text  # the fit's departure, external / internal (k_ext < 0)
    assert "-26.3% / +29.9%" in text  # the 5 um central difference's
    assert "which is why k_r is the fit over the whole sweep" in text


def test_report_only_refuses_a_study_of_central_differences(tmp_path, capsys):
    data = _synthetic(1.0, "line")
    del data["inputs"]["k_r_from"]
    (tmp_path / "radial_stiffness.json").write_text(json.dumps(data))
    assert main(["--case", "1-GB", "--out", str(tmp_path), "--report-only"]) == 3
    err = capsys.readouterr().err
    assert "written before k_r was taken from the least-squares line" in err
    assert "Traceback" not in err and not (tmp_path / "report.md").exists()

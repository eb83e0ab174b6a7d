"""Radial mesh stiffness from the FE contact solve (studies.radial_stiffness) and the
floating-sun models built on it (postprocess.radial_stiffness_fe)."""

from __future__ import annotations

import math

import pytest
from mpi4py import MPI

from cases.study_case import load_study_case
from gears.analytic import radial_stiffness as rs
from postprocess import radial_stiffness_fe as rf
from solvers.body_store import BodyStore
from studies.radial_stiffness import normal_backlash_um, solve_offsets, with_backlash

H = 0.01  # mm, the larger step of `make radial-stiffness`


@pytest.fixture(scope="module")
def case():
    """1-GB on the line contact model: the closed form k_r is the geometric stiffness of
    forces along the exact plane of action, which the line grid's points carry; a zone
    grid's cells off the line carry turned normals and add their own share (measured
    -850.3 against -761.4 N/mm at the external mesh, level 0; a study of it is open)."""
    import dataclasses

    study = load_study_case("1-GB")
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

"""The analytical study: every closed-form table of the reference papers from the gear data.

Inputs are the gear data of singh2007 section 1 (teeth, module, angles, face widths, centre
distances, torque) and the stated parameters of pust2016 and parker2000. The operating
geometry (pitch radii, pressure and helix angles) comes from the :mod:`gears` package;
nothing derived is typed in. :func:`build_tables` returns one JSON-ready dict (moments N m,
forces N, lengths mm, angles deg unless a key says otherwise); ``report.py`` and
``figures.py`` turn it into ``report.md`` and the figures.
"""

from __future__ import annotations

import math
from dataclasses import asdict

import numpy as np

from gears.analytic import double_pinion as dp
from gears.analytic import parametric, phasing, printed
from gears.analytic import radial_stiffness as rs
from gears.analytic import single_pinion as sp
from gears.analytic.planetary import (
    PlanetaryInput,
    double_pinion_axial_forces,
    double_pinion_geometry,
    double_pinion_triangle,
    single_pinion_geometry,
)

# parker2000 example system (US Army OH-58): teeth and the four-planet angles (deg).
OH58 = {"Zs": 27, "Zp": 35, "Zr": 99, "four_planet_angles_deg": (0.0, 91.4, 180.0, 271.4)}
PHASING_HARMONICS = 8  # l = 1..8 in the tables


# --------------------------------------------------------------------------- sections


def _deg(x: float) -> float:
    return math.degrees(x)


def single_section(case1: PlanetaryInput) -> dict:
    """singh2007 Tables 3, 8, 9 and the case-1 geometry."""
    g = single_pinion_geometry(case1)
    forces = sp.mesh_forces(case1.torque_per_branch, g)
    pinion = case1.gears[1]
    sun_pin = case1.pairs()[0]
    rows = sp.offset_cases(forces, g, pinion.face_width / 4.0)  # a quarter of the face width
    geometry = {
        "R_SUN": g.r_sun,
        "R_pS": g.r_pin_sun,
        "R_pR": g.r_pin_ring,
        "alpha1": _deg(g.alpha1),
        "alpha2": _deg(g.alpha2),
        "beta1": _deg(g.beta1),
        "beta2": _deg(g.beta2),
        "torque_per_mesh": case1.torque_per_branch,
        "centre_distances": list(case1.centre_distances),
        "load_offset": pinion.face_width / 4.0,
        # The sun-pinion pair is standard: its exact a0 and R_pS there (report note 0).
        "a0_sun_mesh": sun_pin.standard_centre_distance,
        "R_pS_at_a0": pinion.reference_radius,
    }
    return {
        "geometry": geometry,
        "single": sp.concentrated_load(case1.torque_per_branch, g),
        "table8": rows,
        "table9": rows,
    }


def _double_entry(fz: dp.AxialForces, g: dp.DoublePinionGeometry) -> dict:
    parts = dp.per_force_moments(fz, g)
    return {
        **dp.double_pinion_moments(fz, g),
        "theta_deg": _deg(g.theta),
        "phi_deg": _deg(g.phi),
        "per_force": {
            pinion: {force: {"Mx": m[0], "My": m[1]} for force, m in rows.items()}
            for pinion, rows in parts.items()
        },
    }


def double_section(case1: PlanetaryInput, case2: PlanetaryInput) -> dict:
    """singh2007 Tables 4-5 (cases 2-A and 2-B) and the case-2 geometry."""
    tri = double_pinion_triangle(case2)
    g_b = double_pinion_geometry(case2)
    g_a = double_pinion_geometry(case2, theta=math.pi, phi=0.0)
    fz = double_pinion_axial_forces(case2)
    entry_a, entry_b = _double_entry(fz, g_a), _double_entry(fz, g_b)
    single = sp.concentrated_load(case1.torque_per_branch, single_pinion_geometry(case1))
    geometry = {
        "R_SP_SUN": g_b.r_sp_sun,
        "R_SP_RP": g_b.r_sp_rp,
        "R_RP_SP": g_b.r_rp_sp,
        "R_RP_RING": g_b.r_rp_ring,
        "a1": _deg(g_b.a1),
        "a2": _deg(g_b.a2),
        "a3": _deg(g_b.a3),
        "psi": _deg(tri.psi),
        "theta": _deg(tri.theta),
        "phi": _deg(tri.phi),
        "axial_forces": asdict(fz),
        "FA": fz.FzSUN,
        "torque_per_branch": case2.torque_per_branch,
        "centre_distances": list(case2.centre_distances),
    }
    return {
        "geometry": geometry,
        "double": {
            "2-A": entry_a,
            "2-B": entry_b,
            # The paper's printed 2-A SP row is the case-1 single pinion (ring mesh in the
            # RP's place), not the 2-A formulas with the case-2 SP-RP mesh; see report.
            "2-A_SP_as_case1": {
                "Mx_SP": single["Mx_pin"],
                "My_SP": single["My_pin"],
                "M_SP": math.hypot(single["Mx_pin"], single["My_pin"]),
                "M_LOA_SP_SUN": single["M_LOA_sun"],
                "M_LOA_SP_RP": single["M_LOA_ring"],
            },
            "ratio_SP_SUN": entry_b["M_LOA_SP_SUN"] / entry_a["M_LOA_SP_SUN"],
            "ratio_RP_RING": entry_b["M_LOA_RP_RING"] / entry_a["M_LOA_RP_RING"],
            "ratio_SP_SUN_vs_case1": entry_b["M_LOA_SP_SUN"] / single["M_LOA_sun"],
            "SP_RP_differential": entry_b["M_LOA_RP_SP"] + entry_b["M_LOA_SP_RP"],
        },
    }


def parametric_section(case1: PlanetaryInput, case2: PlanetaryInput) -> dict:
    """singh2007 Table 6 (paper's FA R), FA R from the case-2 geometry, Fig. 6 curves."""
    g = double_pinion_geometry(case2)
    fa = double_pinion_axial_forces(case2).FzSUN
    my_case1 = sp.concentrated_load(case1.torque_per_branch, single_pinion_geometry(case1))[
        "My_pin"
    ]
    fa_r = {
        "paper": parametric.FA_R_PAPER,
        "FA": fa,
        "FA*R_SP_SUN": fa * g.r_sp_sun * sp.MM_TO_M,
        "FA*R_SP_RP": fa * g.r_sp_rp * sp.MM_TO_M,
        "FA*R_RP_SP": fa * g.r_rp_sp * sp.MM_TO_M,
        "FA*R_RP_RING": fa * g.r_rp_ring * sp.MM_TO_M,
        "half_My_pin_case1": 0.5 * my_case1,
    }
    meshes = {}
    for mesh, alpha, worst, operating in (
        ("sun_SP", g.a1, parametric.worst_theta(g.a1), g.theta),
        ("RP_ring", g.a3, parametric.worst_phi(g.a3), g.phi),
    ):
        curve = parametric.m_sp_sun_loa if mesh == "sun_SP" else parametric.m_rp_ring_loa
        single = parametric.single_equivalent(alpha, 1.0)
        meshes[mesh] = {
            "pressure_angle": _deg(alpha),
            "worst_angle": _deg(worst),
            "worst_ratio": parametric.worst_ratio(alpha),
            "operating_angle": _deg(operating),
            "operating_ratio": float(curve(operating, alpha, 1.0)) / single,
        }
    return {
        "table6": parametric.table6(parametric.FA_R_PAPER),
        "parametric": {
            "FA_R": fa_r,
            "table6_FA_R_SP_SUN": parametric.table6(fa_r["FA*R_SP_SUN"]),
            # The printed single-equivalent column follows My-PIN(case 1) sin(a); see report.
            "single_moment_My_case1": [
                my_case1 * math.sin(math.radians(a)) for a in parametric.TABLE6_PRESSURE_ANGLES_DEG
            ],
            "case2": meshes,
        },
    }


def pust_section(case1: PlanetaryInput, bearing_radial: dict[str, float]) -> dict:
    """pust2016 example, Table 1 as stated and as printed, case-1 mesh radial stiffness
    against the radial pin-bearing stiffness of each named study case (N/mm)."""
    ex = rs.PUST_EXAMPLE
    alpha = math.radians(ex["alpha_deg"])
    k_ex = rs.k_r_external(ex["force"], alpha, ex["r_sun"], ex["r_planet"])
    k_ex_base = rs.k_r_external_base(
        ex["force"], alpha, ex["r_sun"] * math.cos(alpha), ex["r_planet"] * math.cos(alpha)
    )
    stated = {"m2": rs.PUST_M2, "m3": rs.PUST_M3, "k_c": rs.PUST_KC, "k_r": rs.PUST_KR}
    printed_w1 = [row["omega1_sq"] for row in printed.PUST_TABLE1]
    m3_implied = [
        rs.mass_m3_from_eigenvalue(w, rs.PUST_M2, rs.PUST_KC, k3, rs.PUST_KR)
        for w, k3 in zip(printed_w1, rs.PUST_K3, strict=True)
    ]
    k_r_implied = [
        rs.k_r_from_eigenvalue(w, rs.PUST_M2, rs.PUST_M3, rs.PUST_KC, k3)
        for w, k3 in zip(printed_w1, rs.PUST_K3, strict=True)
    ]
    m3_identified = round(float(np.mean(m3_implied)), 3)

    g = single_pinion_geometry(case1)
    f = sp.mesh_forces(case1.torque_per_branch, g)
    a_sun, a_ring = case1.centre_distances
    k_sun = rs.k_r_helical(-f.FyS, g.alpha1, a_sun)  # N/mm
    k_ring = rs.k_r_helical(-f.FyR, g.alpha2, a_ring, internal=True)
    return {
        "k_r_example": k_ex,
        "k_r_example_base": k_ex_base,
        "stated": stated,
        "table1": rs.table1(),
        "threshold_k3": rs.stability_threshold(rs.PUST_KC, rs.PUST_KR),
        "identified": {
            "m3_implied_per_row": m3_implied,
            "m3": m3_identified,
            "table1_m3_identified": rs.table1(m3=m3_identified),
            "k_r_implied_per_row_at_stated_m3": k_r_implied,
        },
        "case1": {
            "k_r_sun_mesh_N_per_mm": k_sun,
            "k_r_ring_mesh_N_per_mm": k_ring,
            "k_r_pinion_net_N_per_mm": k_sun + k_ring,
            "k_r_sun_three_planets_N_per_mm": 1.5 * k_sun,
            "ratio_to_bearing_radial": {name: abs(k_sun) / k for name, k in bearing_radial.items()},
        },
    }


def _phasing_case(zs: int, psi: np.ndarray) -> dict:
    return {
        "Zs": zs,
        "psi_deg": [float(x) for x in np.degrees(psi)],
        "harmonics": phasing.harmonic_table(zs, psi, PHASING_HARMONICS),
    }


def phasing_section(case1: PlanetaryInput, case2: PlanetaryInput) -> dict:
    """parker2000 rules against direct phasor sums: OH-58 and the singh2007 sets."""
    zs, zr = OH58["Zs"], OH58["Zr"]
    oh58_four = np.radians(OH58["four_planet_angles_deg"])
    zs1, zr1 = case1.gears[0].teeth, case1.gears[-1].teeth
    zs2, zr2 = case2.gears[0].teeth, case2.gears[-1].teeth
    n1, n2 = case1.planets, case2.planets
    return {
        "OH58_three_equal": _phasing_case(zs, phasing.equally_spaced_angles(3)),
        "OH58_four_opposed": _phasing_case(zs, oh58_four),
        "OH58_four_snapped": _phasing_case(zs, phasing.snap_to_assemblable(oh58_four, zs, zr)),
        "OH58_assembly": {
            "N=3": phasing.assembly_number(zs, zr, 3),
            "N=4": phasing.assembly_number(zs, zr, 4),
        },
        "case1_equal": _phasing_case(zs1, phasing.equally_spaced_angles(n1)),
        "case1_assemblable": _phasing_case(zs1, phasing.assemblable_angles(zs1, zr1, n1)),
        "case1_assembly_number": phasing.assembly_number(zs1, zr1, n1),
        "case2_equal": _phasing_case(zs2, phasing.equally_spaced_angles(n2)),
        "case2_assembly_number": phasing.assembly_number(zs2, zr2, n2, double_pinion=True),
    }


def build_tables(
    case1: PlanetaryInput, case2: PlanetaryInput, bearing_radial: dict[str, float]
) -> dict:
    """Every analytical table, JSON-ready (see the module docstring for units), from the
    single and double pinion sets and the radial pin-bearing stiffness (N/mm) of the study
    cases the pust2016 comparison names."""
    s = single_section(case1)
    d = double_section(case1, case2)
    p = parametric_section(case1, case2)
    return {
        "geometry": {"case1": s["geometry"], "case2": d["geometry"]},
        "single": s["single"],
        "table8": s["table8"],
        "table9": s["table9"],
        "double": d["double"],
        "table6": p["table6"],
        "parametric": p["parametric"],
        "pust": pust_section(case1, bearing_radial),
        "phasing": phasing_section(case1, case2),
    }

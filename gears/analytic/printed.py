"""The reference papers' printed results, typed once from /work/shared/reference/*.md.

These are the numbers the analytical model is compared with (report side by side, tests);
they are never inputs to a computation. Units as printed: N, N m, mm, deg, (rad/s)^2, N/m.
Inputs (gear data, stated parameters) live with the code that uses them.
"""

from __future__ import annotations

# singh2007 section 2: derived operating geometry of case 1 (mm, deg).
SINGH_GEOMETRY_CASE1 = {
    "R_SUN": 29.805,
    "R_pS": 22.141,
    "R_pR": 22.510,
    "alpha1": 21.30,
    "alpha2": 23.59,
    "beta1": 21.00,
    "beta2": 21.32,
}
# singh2007 section 2: operating pitch radii of case 2-B (mm).
SINGH_GEOMETRY_CASE2 = {
    "R_SP_SUN": 22.14,
    "R_SP_RP": 22.23,
    "R_RP_SP": 20.52,
    "R_RP_RING": 20.68,
}
# singh2007 section 5: triangle angles of case 2-B (deg) and the axial force FA (N).
SINGH_ANGLES_2B = {"psi": 45.002, "theta": 75.768, "phi": 59.230}
SINGH_FA = 5919.0

# singh2007 Table 3 (N, N m).
SINGH_TABLE3 = {
    "FyS": -15419.0,
    "FyR": -15167.0,
    "FxS": 6011.0,
    "FxR": -6623.0,
    "FzS": 5919.0,
    "FzR": -5919.0,
    "Fx_pin": -612.0,
    "Fy_pin": -30586.0,
    "Fz_pin": 0.0,
    "Mx_pin": 0.0,
    "Mz_pin": 0.0,
    "My_pin": 264.3,
    "M_LOA_sun": 96.0,
    "M_LOA_ring": -105.8,
}

# singh2007 Table 8 (ZS, ZR in mm; moments N m, integers).
SINGH_TABLE8 = {
    "A": {"ZS": 0.0, "ZR": 0.0, "Mx_LD": 0, "My_LD": 0, "Mx_pin": 0, "My_pin": 264},
    "B": {"ZS": 7.25, "ZR": 7.25, "Mx_LD": 222, "My_LD": -4, "Mx_pin": 222, "My_pin": 260},
    "C": {"ZS": 7.25, "ZR": -7.25, "Mx_LD": 2, "My_LD": 92, "Mx_pin": 2, "My_pin": 356},
    "D": {"ZS": -7.25, "ZR": 7.25, "Mx_LD": -2, "My_LD": -92, "Mx_pin": -2, "My_pin": 172},
    "E": {"ZS": -7.25, "ZR": -7.25, "Mx_LD": -222, "My_LD": 4, "Mx_pin": -222, "My_pin": 268},
}
SINGH_TABLE8_OFFSET = 7.25  # mm, a quarter of the pinion face width 29.0

# singh2007 Table 9 (N m, integers).
SINGH_TABLE9 = {
    "A": {"M_LOA_sun_LD": 0, "M_LOA_ring_LD": 0, "M_LOA_sun": 96, "M_LOA_ring": -106},
    "B": {"M_LOA_sun_LD": 205, "M_LOA_ring_LD": 205, "M_LOA_sun": 301, "M_LOA_ring": 99},
    "C": {"M_LOA_sun_LD": 35, "M_LOA_ring_LD": -35, "M_LOA_sun": 131, "M_LOA_ring": -141},
    "D": {"M_LOA_sun_LD": -35, "M_LOA_ring_LD": 35, "M_LOA_sun": 61, "M_LOA_ring": -71},
    "E": {"M_LOA_sun_LD": -205, "M_LOA_ring_LD": -205, "M_LOA_sun": -109, "M_LOA_ring": -310},
}

# singh2007 Table 5 (N m, integers): per case the SP and RP rows.
SINGH_TABLE5 = {
    "2-A": {
        "Mx_SP": 0,
        "My_SP": 264,
        "M_SP": 264,
        "M_LOA_SP_SUN": 96,
        "M_LOA_SP_RP": -106,
        "Mx_RP": 0,
        "My_RP": 244,
        "M_RP": 244,
        "M_LOA_RP_SP": 91,
        "M_LOA_RP_RING": -95,
    },
    "2-B": {
        "Mx_SP": 128,
        "My_SP": 99,
        "M_SP": 161,
        "M_LOA_SP_SUN": 155,
        "M_LOA_SP_RP": -155,
        "Mx_RP": 104,
        "My_RP": 185,
        "M_RP": 212,
        "M_LOA_RP_SP": 166,
        "M_LOA_RP_RING": -168,
    },
}
# singh2007 Table 5 per-force rows of case 2-B: (Mx, My), N m.
SINGH_TABLE5_PER_FORCE_2B = {
    "SP": {"FzSUN": (0, 131), "FzRP": (128, -32)},
    "RP": {"FzSP": (104, 62), "FzRING": (0, 122)},
}
# singh2007 section 5 text: 2-B over 2-A misalignment ratios and the SP-RP differential.
SINGH_RATIO_SP_SUN = 1.62
SINGH_RATIO_RP_RING = 1.77
SINGH_SP_RP_DIFFERENTIAL = 11.0  # N m

# singh2007 section 6 text: case 2-B worst / single ratios and the worst angles (deg).
SINGH_CASE2_WORST = {
    "sun_SP": {"ratio": 1.88, "angle": 111.0},
    "RP_ring": {"ratio": 1.78, "angle": 67.0},
}
# singh2007 Table 6 (FA R = 133 N m): one row per pressure angle (deg, N m).
SINGH_TABLE6 = [
    {
        "pressure_angle": 15,
        "worst_moment": 167,
        "single_moment": 68,
        "ratio": 2.44,
        "worst_theta": 105,
        "equiv_theta": 30,
        "worst_phi": 75,
    },
    {
        "pressure_angle": 20,
        "worst_moment": 178,
        "single_moment": 90,
        "ratio": 1.97,
        "worst_theta": 110,
        "equiv_theta": 40,
        "worst_phi": 70,
    },
    {
        "pressure_angle": 25,
        "worst_moment": 189,
        "single_moment": 112,
        "ratio": 1.69,
        "worst_theta": 115,
        "equiv_theta": 50,
        "worst_phi": 65,
    },
    {
        "pressure_angle": 30,
        "worst_moment": 199,
        "single_moment": 132,
        "ratio": 1.50,
        "worst_theta": 120,
        "equiv_theta": 60,
        "worst_phi": 60,
    },
]

# pust2016: printed radial stiffness example (N/m, "about") and Table 1 ((rad/s)^2, rad/s).
PUST_EXAMPLE_KR = -13_000.0
PUST_TABLE1 = [
    {"k3": 0.0, "omega1_sq": -520.06, "omega2_sq": 2.000e6, "omega1": "22.80i", "omega2": 1414.21},
    {"k3": 5e3, "omega1_sq": -320.07, "omega2_sq": 2.000e6, "omega1": "17.89i", "omega2": 1414.21},
    {"k3": 1e4, "omega1_sq": -120.07, "omega2_sq": 2.000e6, "omega1": "10.96i", "omega2": 1414.21},
    {"k3": 1.5e4, "omega1_sq": 79.93, "omega2_sq": 2.000e6, "omega1": "8.94", "omega2": 1414.21},
    {"k3": 2e4, "omega1_sq": 279.93, "omega2_sq": 2.000e6, "omega1": "16.73", "omega2": 1414.21},
]

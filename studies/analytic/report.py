"""``report.md``: each analytical table beside the paper's printed values, with the
differences, a flag where a difference exceeds the printed rounding, and the notes that
explain every such difference (the numbers in the notes are computed, not typed).

A printed value with resolution r (its last printed digit) agrees if
|computed - printed| <= r / 2.
"""

from __future__ import annotations

import math
from pathlib import Path

from gears.analytic import printed

_TOL = 1e-9


class _Report:
    def __init__(self) -> None:
        self.lines: list[str] = []
        self.flags: list[str] = []

    def add(self, *lines: str) -> None:
        self.lines.extend(lines)

    def compare_header(self, first: str = "quantity") -> None:
        self.add(
            "",
            f"| {first} | computed | printed | difference | within printed rounding |",
            "|---|---|---|---|---|",
        )

    def compare(
        self, where: str, name: str, computed: float, paper: float, res: float, extra: float = 0.0
    ) -> None:
        """One row; ``extra`` widens the tolerance by a stated propagation of input rounding."""
        diff = computed - paper
        ok = abs(diff) <= 0.5 * res + extra + _TOL * max(1.0, abs(paper))
        digits = max(0, 2 - math.floor(math.log10(res)))
        pd = max(0, -math.floor(math.log10(res)))
        flag = "yes" if ok else "**no**"
        self.add(
            f"| {name} | {computed:.{digits}f} | {paper:.{pd}f} | {diff:+.{digits}f} | {flag} |"
        )
        if not ok:
            self.flags.append(
                f"{where}, {name}: computed {computed:.{digits}f}, printed {paper:.{pd}f} "
                f"(difference {diff:+.{digits}f}, printed resolution {res:g})"
            )


def _geometry(r: _Report, t: dict) -> None:
    g1, g2 = t["geometry"]["case1"], t["geometry"]["case2"]
    r.add("## 1. Operating geometry (singh2007 section 2)", "")
    r.add(
        "Computed by `gears` from the section-1 gear data (teeth, normal module "
        "1.59, 20 deg normal pressure angle, 21 deg helix, centre distances). Lengths mm, "
        "angles deg. Case-1 radii: tolerance half a printed unit plus the propagation of the "
        "+-0.0005 mm rounding of the printed centre distance (R / a x 0.0005 mm)."
    )
    r.compare_header()
    a_sun = g1["centre_distances"][0]
    for key, res in (("R_SUN", 1e-3), ("R_pS", 1e-3), ("R_pR", 1e-3)):
        extra = g1[key] / a_sun * 0.0005
        r.compare("geometry case 1", key, g1[key], printed.SINGH_GEOMETRY_CASE1[key], res, extra)
    for key in ("alpha1", "alpha2", "beta1", "beta2"):
        r.compare("geometry case 1", key, g1[key], printed.SINGH_GEOMETRY_CASE1[key], 0.01)
    r.compare(
        "geometry case 1",
        "ZS, ZR offset (face width / 4)",
        g1["load_offset"],
        printed.SINGH_TABLE8_OFFSET,
        0.01,
    )
    for key in ("R_SP_SUN", "R_SP_RP", "R_RP_SP", "R_RP_RING"):
        r.compare("geometry case 2", key, g2[key], printed.SINGH_GEOMETRY_CASE2[key], 0.01)
    for key in ("psi", "theta", "phi"):
        r.compare("geometry case 2", key, g2[key], printed.SINGH_ANGLES_2B[key], 1e-3)
    r.compare("geometry case 2", "FA (N)", g2["FA"], printed.SINGH_FA, 1.0)
    r.add(
        "",
        f"Not printed: case 2 operating pressure angles a1 = {g2['a1']:.3f}, "
        f"a2 = {g2['a2']:.3f}, a3 = {g2['a3']:.3f} deg; axial forces "
        + ", ".join(f"{k} = {v:.1f} N" for k, v in g2["axial_forces"].items())
        + " (equal magnitude: one lead per pinion).",
        "",
    )


def _single(r: _Report, t: dict) -> None:
    r.add("## 2. Concentrated load, single pinion (singh2007 Table 3)", "")
    r.add(
        f"Torque per mesh {t['geometry']['case1']['torque_per_mesh']:.2f} N m. Forces N, "
        "moments N m."
    )
    r.compare_header()
    s = t["single"]
    for key, paper in printed.SINGH_TABLE3.items():
        res = 0.1 if key in ("My_pin", "M_LOA_sun", "M_LOA_ring") else 1.0
        r.compare("Table 3", key, s[key], paper, res)
    r.add("")
    r.add("## 3. Distributed load, centroid offsets (singh2007 Tables 8 and 9)", "")
    r.add("ZS, ZR in mm, moments N m; `_LD` = the load-distribution part alone.")
    r.compare_header("case: quantity")
    for row in t["table8"]:
        paper = printed.SINGH_TABLE8[row["case"]]
        for key in ("ZS", "ZR"):
            r.compare("Table 8", f"{row['case']}: {key}", row[key], paper[key], 0.01)
        for key in ("Mx_LD", "My_LD", "Mx_pin", "My_pin"):
            r.compare("Table 8", f"{row['case']}: {key}", row[key], paper[key], 1.0)
    r.compare_header("case: quantity")
    for row in t["table9"]:
        paper = printed.SINGH_TABLE9[row["case"]]
        for key in ("M_LOA_sun_LD", "M_LOA_ring_LD", "M_LOA_sun", "M_LOA_ring"):
            r.compare("Table 9", f"{row['case']}: {key}", row[key], paper[key], 1.0)
    r.add("")


def _double(r: _Report, t: dict) -> None:
    d = t["double"]
    r.add("## 4. Double pinion (singh2007 Tables 4 and 5)", "")
    r.add(
        "Case 2-A: theta = 180, phi = 0 with the case-2 radii and pressure angles; case 2-B: "
        "the real triangle. Moments N m; `M_SP`, `M_RP` are the totals sqrt(Mx^2 + My^2)."
    )
    for case in ("2-A", "2-B"):
        r.compare_header(f"{case}: quantity")
        for key, paper in printed.SINGH_TABLE5[case].items():
            r.compare("Table 5", f"{case}: {key}", d[case][key], paper, 1.0)
    r.add("", "Per-force rows of case 2-B (Mx, My), N m:")
    r.compare_header("2-B: force on pinion")
    for pinion, rows in printed.SINGH_TABLE5_PER_FORCE_2B.items():
        for force, (mx, my) in rows.items():
            m = d["2-B"]["per_force"][pinion][force]
            r.compare("Table 5 per force", f"{force} on {pinion}: Mx", m["Mx"], mx, 1.0)
            r.compare("Table 5 per force", f"{force} on {pinion}: My", m["My"], my, 1.0)
    r.add("", "The printed 2-A SP row against the case-1 single pinion (Table 3):")
    r.compare_header("2-A SP as case 1: quantity")
    for key in ("Mx_SP", "My_SP", "M_SP", "M_LOA_SP_SUN", "M_LOA_SP_RP"):
        paper = printed.SINGH_TABLE5["2-A"][key]
        r.compare("Table 5 (case-1 SP)", f"2-A: {key}", d["2-A_SP_as_case1"][key], paper, 1.0)
    r.add("", "Ratios stated in the text:")
    r.compare_header()
    r.compare(
        "section 5 text",
        "M_LOA SP-SUN 2-B / 2-A",
        d["ratio_SP_SUN"],
        printed.SINGH_RATIO_SP_SUN,
        0.01,
    )
    r.compare(
        "section 5 text",
        "M_LOA RP-RING 2-B / 2-A",
        d["ratio_RP_RING"],
        printed.SINGH_RATIO_RP_RING,
        0.01,
    )
    r.compare(
        "section 5 text",
        "SP-RP net differential (N m)",
        d["SP_RP_differential"],
        printed.SINGH_SP_RP_DIFFERENTIAL,
        1.0,
    )
    r.add("")


def _parametric(r: _Report, t: dict) -> None:
    p = t["parametric"]
    r.add("## 5. Parametric study (singh2007 Fig. 6 and Table 6)", "")
    r.add("![Fig. 6](fig6_misalignment.png)", "")
    r.add("Case 2-B worst points (section 6 text; pressure angles from the case-2 geometry):")
    r.compare_header()
    for mesh, paper in printed.SINGH_CASE2_WORST.items():
        m = p["case2"][mesh]
        r.compare(
            "section 6 text", f"{mesh}: worst / single", m["worst_ratio"], paper["ratio"], 0.01
        )
        r.compare(
            "section 6 text", f"{mesh}: worst angle (deg)", m["worst_angle"], paper["angle"], 1.0
        )
    r.add("", "Table 6 with the paper's FA R = 133 N m (moments N m, angles deg):")
    r.compare_header("pressure angle: quantity")
    for row, paper in zip(t["table6"], printed.SINGH_TABLE6, strict=True):
        a = paper["pressure_angle"]
        for key in (
            "worst_moment",
            "single_moment",
            "ratio",
            "worst_theta",
            "equiv_theta",
            "worst_phi",
        ):
            res = 0.01 if key == "ratio" else 1.0
            r.compare("Table 6", f"{a:g} deg: {key}", row[key], paper[key], res)
    fa_r = p["FA_R"]
    r.add(
        "",
        "FA R from the case-2 geometry (N m): "
        + ", ".join(f"{k} = {v:.2f}" for k, v in fa_r.items() if k not in ("paper", "FA"))
        + f" (FA = {fa_r['FA']:.1f} N); the paper states {fa_r['paper']:g}.",
        "",
        "The printed single-equivalent column against My-PIN(case 1) sin(a):",
    )
    r.compare_header("pressure angle")
    for value, paper in zip(p["single_moment_My_case1"], printed.SINGH_TABLE6, strict=True):
        r.compare(
            "Table 6 (My case 1)",
            f"{paper['pressure_angle']:g} deg",
            value,
            paper["single_moment"],
            1.0,
        )
    r.add("")


def _pust(r: _Report, t: dict) -> None:
    p = t["pust"]
    st = p["stated"]
    r.add("## 6. Radial mesh stiffness and the floating sun (pust2016)", "")
    r.compare_header()
    r.compare(
        "pust2016 example",
        "k_r,ext (N/m), pitch-radius form",
        p["k_r_example"],
        printed.PUST_EXAMPLE_KR,
        1000.0,
    )
    r.compare(
        "pust2016 example",
        "k_r,ext (N/m), base-radius form",
        p["k_r_example_base"],
        printed.PUST_EXAMPLE_KR,
        1000.0,
    )
    r.add(
        "",
        '("about -13,000" is read as two significant figures, resolution 1000 N/m.)',
        "",
        f"Table 1 from the stated parameters m2 = {st['m2']:g} kg, m3 = {st['m3']:g} kg, "
        f"k_c = {st['k_c']:g} N/m, k_r = {st['k_r']:g} N/m:",
    )
    r.compare_header("k3 (N/m): quantity")
    for row, paper in zip(p["table1"], printed.PUST_TABLE1, strict=True):
        r.compare(
            "pust2016 Table 1", f"{row['k3']:g}: W1^2", row["omega1_sq"], paper["omega1_sq"], 0.01
        )
        r.compare(
            "pust2016 Table 1", f"{row['k3']:g}: W2^2", row["omega2_sq"], paper["omega2_sq"], 1e3
        )
    ident = p["identified"]
    r.add(
        "",
        "The sun mass m3 that makes each printed W1^2 a root of the stated determinant "
        "(linear in m3): "
        + ", ".join(f"{m:.4f}" for m in ident["m3_implied_per_row"])
        + f" kg. With m3 = {ident['m3']:g} kg and everything else as stated:",
    )
    r.compare_header("k3 (N/m): quantity")
    for row, paper in zip(ident["table1_m3_identified"], printed.PUST_TABLE1, strict=True):
        r.compare(
            "pust2016 Table 1 (identified m3)",
            f"{row['k3']:g}: W1^2",
            row["omega1_sq"],
            paper["omega1_sq"],
            0.01,
        )
        r.compare(
            "pust2016 Table 1 (identified m3)",
            f"{row['k3']:g}: W1 = sqrt|W1^2|",
            math.sqrt(abs(row["omega1_sq"])),
            float(paper["omega1"].rstrip("i")),
            0.01,
        )
    r.add(
        "",
        "k_r alone cannot give the printed column: at the stated m3 the k_r each printed "
        "W1^2 implies is "
        + ", ".join(f"{k:.0f}" for k in ident["k_r_implied_per_row_at_stated_m3"])
        + " N/m (not one value). "
        f"W1^2 changes sign at k3 = k_r (k_c + k_r) / k_c = {p['threshold_k3']:.2f} N/m "
        "for any masses.",
        "",
        "![pust stability](pust_stability.png)",
        "",
    )
    c = p["case1"]
    r.add(
        "Extension, case 1 (transverse plane, k_r = -+Ft / (a tan(alpha_wt))): "
        f"sun-pinion mesh {c['k_r_sun_mesh_N_per_mm']:.1f} N/mm, pinion-ring mesh "
        f"{c['k_r_ring_mesh_N_per_mm']:+.1f} N/mm, net on the pinion "
        f"{c['k_r_pinion_net_N_per_mm']:.1f} N/mm; on the sun from three planets "
        f"{c['k_r_sun_three_planets_N_per_mm']:.1f} N/mm in every radial direction. "
        "|k_r,sun mesh| / pin bearing radial stiffness: "
        + ", ".join(f"{k} {v:.1e}" for k, v in c["ratio_to_bearing_radial"].items())
        + ": negligible for the pinion bearings of the FE cases.",
        "",
    )


def _phasing_table(r: _Report, title: str, case: dict) -> None:
    r.add(
        "",
        f"{title}: Zs = {case['Zs']}, planets at "
        + ", ".join(f"{x:.3f}" for x in case["psi_deg"])
        + " deg.",
        "",
        "| l | k | rule: force / torque | S- | S+ | T | direct: force / torque | agree |",
        "|---|---|---|---|---|---|---|---|",
    )
    for h in case["harmonics"]:
        rule = "-"
        agree = "-"
        if "rule" in h:
            rule = f"{'F' if h['rule_force'] else '0'} / {'T' if h['rule_torque'] else '0'}"
            ok = (h["rule_force"], h["rule_torque"]) == (h["force_nonzero"], h["torque_nonzero"])
            agree = "yes" if ok else "**no**"
            if not ok:
                r.flags.append(f"phasing {title}, l = {h['l']}: rule and direct sums disagree")
        direct = f"{'F' if h['force_nonzero'] else '0'} / {'T' if h['torque_nonzero'] else '0'}"
        r.add(
            f"| {h['l']} | {h.get('k', '-')} | {rule} | {h['force_minus']:.3f} | "
            f"{h['force_plus']:.3f} | {h['torque']:.3f} | {direct} | {agree} |"
        )


def _phasing(r: _Report, t: dict) -> None:
    p = t["phasing"]
    r.add("## 7. Planet phasing (parker2000)", "")
    r.add(
        "S-, S+ = |sum exp(i (l phi_i -+ psi_i))| (the two rotating components of the net sun "
        "force), T = |sum exp(i l phi_i)| (net sun torque), phi_i = Zs psi_i with psi_i in "
        "radians; N means all planets in phase. F / T = non-zero, 0 = zero (below 1e-9 N)."
    )
    _phasing_table(r, "OH-58, three planets equally spaced", p["OH58_three_equal"])
    _phasing_table(r, "OH-58, four planets as printed (opposed pairs)", p["OH58_four_opposed"])
    _phasing_table(r, "OH-58, four planets snapped to assemblable angles", p["OH58_four_snapped"])
    a = p["OH58_assembly"]
    r.add(
        "",
        f"OH-58 assembly: (Zs + Zr) / N = {a['N=3']:g} for N = 3 (assemblable), {a['N=4']:g} "
        "for N = 4 (equal spacing impossible, hence the unequal pairs). The printed 91.4 deg "
        f"is the assemblable {p['OH58_four_snapped']['psi_deg'][1]:.4f} deg rounded; "
        "either way the pairs are diametrically opposed and the pair rule holds.",
    )
    _phasing_table(r, "Case 1 sun, three planets equally spaced", p["case1_equal"])
    _phasing_table(r, "Case 1 sun, three planets at assemblable angles", p["case1_assemblable"])
    _phasing_table(r, "Case 2 sun, three pinion pairs equally spaced", p["case2_equal"])
    r.add(
        "",
        f"Assembly: case 1 (Zs + Zr) / N = {p['case1_assembly_number']:.4f}, not an integer: "
        "three equally spaced pinions cannot be assembled in the case-1 set; the nearest "
        "assemblable positions are listed above and suppress no harmonic exactly. Case 2 "
        f"(double pinion) (Zr - Zs) / N = {p['case2_assembly_number']:g}: assemblable.",
        "",
    )


_SP_ROW = ("Mx_SP", "My_SP", "M_SP", "M_LOA_SP_SUN", "M_LOA_SP_RP")


def _notes(r: _Report, t: dict) -> None:
    s8 = {row["case"]: row for row in t["table8"]}
    d = t["double"]
    p = t["parametric"]
    t6 = t["table6"]
    pu = t["pust"]
    p8 = printed.SINGH_TABLE8
    g1 = t["geometry"]["case1"]
    r.add("## Notes on every difference from the printed values", "")
    r.add(
        f"0. R_pS: {g1['R_pS']:.5f} mm at the printed centre distance "
        f"{g1['centre_distances'][0]:.3f} mm rounds to {g1['R_pS']:.3f}, printed "
        f"{printed.SINGH_GEOMETRY_CASE1['R_pS']:.3f}. The "
        f"sun-pinion pair is standard; at its exact standard centre distance a0 = "
        f"{g1['a0_sun_mesh']:.6f} mm (printed rounded) R_pS = "
        f"{g1['R_pS_at_a0']:.5f} mm, which rounds to the printed value: the paper used a0. "
        "Within the tolerance that includes the centre-distance rounding; immaterial.",
        f"1. Table 8, My-PIN of D and E: the formulas give {s8['D']['My_pin']:.2f} and "
        f"{s8['E']['My_pin']:.2f} N m; the paper prints {p8['D']['My_pin']} and "
        f"{p8['E']['My_pin']}, which are the sums of its own rounded columns "
        f"({p8['A']['My_pin']} {p8['D']['My_LD']:+d} and {p8['A']['My_pin']} "
        f"{p8['E']['My_LD']:+d}).",
        f"2. Table 9, M_LOA-ring of E: the formulas give {s8['E']['M_LOA_ring']:.2f} N m "
        f"(concentrated {s8['A']['M_LOA_ring']:.2f} plus distributed "
        f"{s8['E']['M_LOA_ring_LD']:.2f}); printed "
        f"{printed.SINGH_TABLE9['E']['M_LOA_ring']}. The sum of the printed parts is "
        f"{printed.SINGH_TABLE9['A']['M_LOA_ring'] + printed.SINGH_TABLE9['E']['M_LOA_ring_LD']}"
        " too. Truncation would give -310, but the paper rounds everywhere else (C: "
        f"{s8['C']['M_LOA_ring']:.2f} is printed {printed.SINGH_TABLE9['C']['M_LOA_ring']}); "
        "every other Table 9 entry matches: a slip in the paper.",
        "3. Table 5, 2-A SP row: printed ("
        + ", ".join(str(printed.SINGH_TABLE5["2-A"][k]) for k in _SP_ROW)
        + ") is the case-1 single pinion "
        f"(Table 3: My {d['2-A_SP_as_case1']['My_SP']:.2f}, LOA "
        f"{d['2-A_SP_as_case1']['M_LOA_SP_SUN']:.2f} / "
        f"{d['2-A_SP_as_case1']['M_LOA_SP_RP']:.2f}), i.e. the case-1 ring mesh (R_pR, "
        "alpha2) in place of the SP-RP mesh. The 2-A formulas with the case-2 SP-RP mesh "
        f"give My {d['2-A']['My_SP']:.2f}, LOA {d['2-A']['M_LOA_SP_SUN']:.2f} / "
        f"{d['2-A']['M_LOA_SP_RP']:.2f}; the text's ratio {printed.SINGH_RATIO_SP_SUN} follows "
        "from these "
        f"({d['ratio_SP_SUN']:.3f}; against the case-1 value it would be "
        f"{d['ratio_SP_SUN_vs_case1']:.3f}). The 2-A RP row follows the formulas.",
        "4. Table 6, single-equivalent column: 2 FA R sin(a) with the stated FA R = 133 gives "
        + ", ".join(f"{row['single_moment']:.2f}" for row in t6)
        + "; printed "
        + ", ".join(f"{row['single_moment']}" for row in printed.SINGH_TABLE6)
        + ". The printed column is My-PIN(case 1) sin(a) = "
        + ", ".join(f"{v:.2f}" for v in p["single_moment_My_case1"])
        + f", i.e. FA R = {p['FA_R']['half_My_pin_case1']:.2f} N m (FA times the mean of R_pS and "
        "R_pR), while the worst-moment column follows FA R = 133.",
        "5. Table 6, ratio column: (1 + sin a) / (2 sin a) gives "
        + ", ".join(f"{row['ratio']:.4f}" for row in t6)
        + "; printed "
        + ", ".join(f"{row['ratio']:.2f}" for row in printed.SINGH_TABLE6)
        + ". The printed entries exceed the formula by "
        + ", ".join(
            f"{round(paper['ratio'] - row['ratio'], 4) + 0.0:.4f}"
            for row, paper in zip(t6, printed.SINGH_TABLE6, strict=True)
        )
        + " (the rounding allows 0.005). The ratio of the worst (FA R = 133) to the single "
        "column of note 4 gives "
        + ", ".join(
            f"{row['worst_moment'] / v:.4f}"
            for row, v in zip(t6, p["single_moment_My_case1"], strict=True)
        )
        + ", which rounds to the printed values at 20 and 25 deg only; truncated to two "
        "decimals it gives all four printed values. That is consistent with the printed ratios "
        "mixing the two FA R values of note 4, but it is a reading, not a proof.",
        "6. FA R = 133 N m is not FA times any case-2 radius "
        f"({p['FA_R']['FA*R_SP_SUN']:.2f}, {p['FA_R']['FA*R_SP_RP']:.2f}, "
        f"{p['FA_R']['FA*R_RP_SP']:.2f}, {p['FA_R']['FA*R_RP_RING']:.2f}); FA times the case-1 "
        f"R_pR = {t['geometry']['case1']['R_pR']:.4f} mm gives "
        f"{p['FA_R']['FA'] * t['geometry']['case1']['R_pR'] * 1e-3:.2f}, the only radius that "
        "rounds to 133. Table 6 uses 133 as stated.",
        "7. pust2016 Table 1: the stated parameters give W1^2 = "
        + ", ".join(f"{row['omega1_sq']:.2f}" for row in pu["table1"])
        + " (rad/s)^2, about a quarter of the printed values. The printed column follows from "
        f"m3 = {pu['identified']['m3']:g} kg instead of {pu['stated']['m3']:g} kg (the printed "
        "values imply m3 = "
        f"{min(pu['identified']['m3_implied_per_row']):.4f} to "
        f"{max(pu['identified']['m3_implied_per_row']):.4f} kg); W2^2 = 2.000e6 either way. "
        f"With m3 = {pu['identified']['m3']:g} kg the k3 = 0 entry is "
        f"{pu['identified']['table1_m3_identified'][0]['omega1_sq']:.4f}, printed "
        f"{printed.PUST_TABLE1[0]['omega1_sq']:.2f} "
        "(one unit in the last digit; the other four agree to the printed rounding). The "
        "sign change of W1^2 at k3 ~ k_r is the same for any m3.",
        f"8. pust2016 example: -F cos^2(a) / ((r1 + r2) sin(a)) = {pu['k_r_example']:.0f} N/m: "
        '"about -13,000" follows (base-radius form identical).',
        "9. Case 1 cannot carry three equally spaced pinions ((Zs + Zr) / N = "
        f"{t['phasing']['case1_assembly_number']:.4f} is not an integer); the analytical model "
        "(and the paper) assume equal load sharing per mesh regardless. Case 2 can "
        f"((Zr - Zs) / N = {t['phasing']['case2_assembly_number']:g}).",
        "",
    )


def render(tables: dict) -> str:
    """The whole ``report.md`` text."""
    r = _Report()
    r.add(
        "# Analytical model: singh2007, pust2016, parker2000",
        "",
        "Generated by `python -m studies.analytic`. Computed values come from the gear "
        "data alone (no derived number typed in); printed values are the reference pages in "
        "`/work/shared/reference/`. Units: mm, N, N m, deg unless stated.",
        "",
    )
    _geometry(r, tables)
    _single(r, tables)
    _double(r, tables)
    _parametric(r, tables)
    _pust(r, tables)
    _phasing(r, tables)
    _notes(r, tables)
    intro, body = r.lines[:4], r.lines[4:]
    summary = ["## Differences beyond the printed rounding (automatic list)", ""]
    summary += [f"- {f}" for f in r.flags] or ["- none"]
    summary += ["", "Each is explained in the notes at the end.", ""]
    return "\n".join(intro + summary + body) + "\n"


def write_report(tables: dict, path: Path) -> Path:
    path.write_text(render(tables))
    return path

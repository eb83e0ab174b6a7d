"""Root and contact stress sections of the case reports: the FE values over the mesh cycle
beside ISO 6336-3 (root) and ISO 6336-2 / Hertz (contact), and where and why they differ.

Reads only summaries (:func:`postprocess.summary.summarise`): ``bending_stress`` (FE surface
maximum of the max principal stress over the mesh cycle, :mod:`solvers.root_submodel`,
:mod:`solvers.root_stress`),
``bending_stress_tangent`` (on ISO's 30 / 60 deg line), ``bending_stress_global`` (read on
submodels: the global model's own value) or ``bending_stress_cell`` (the largest cell value),
``bending_stress_method``, ``bending_stress_at``, the recovered reading
(``bending_stress_recovered``, ``bending_stress_tangent_recovered``,
``bending_stress_recovered_at``; :func:`recovered_section`), ``bending_stress_iso6336`` (sigma_F0
with the 2006 and 2019 Y_beta and the factors, :func:`postprocess.mesh_stress.
iso_root_stress_factors`) and ``contact_stress_cycle`` (:func:`postprocess.mesh_stress.
contact_stress_cycle`). Older summaries without a field print "-".
"""

from __future__ import annotations

from postprocess.plus_minus import plus_minus
from postprocess.run_scalars import level_text


def _f(v, fmt: str = ".0f") -> str:
    return "-" if v is None else format(v, fmt)


def _pm(summary: dict, group: str, key: str, values: dict) -> str:
    """`` ± x`` of ``group.key`` from the summary's uncertainty ('' without one)."""
    v = values.get(key)
    return "" if v is None else plus_minus(summary, f"{group}.{key}", ".0f", v)


def _ratio(a, b) -> str:
    return f"{a / b:.2f}" if a is not None and b else "-"


def _label(key: str) -> str:
    """ "pinion_sun_side" -> "pinion (sun side)"."""
    if key.endswith("_side"):
        gear, mate = key.removesuffix("_side").rsplit("_", 1)
        return f"{gear} ({mate} side)"
    return key


def reported_root_stress(s: dict) -> tuple[str, dict]:
    """The summary key and the values ({gear key: MPa}) of the root stress a report quotes:
    the recovered reading (``bending_stress_recovered``, what the convergence studies
    target) where the summary holds it for every gear with a nodal maximum, else the nodal
    maxima (``bending_stress``) of all of them: one reading per summary, and no gear left
    out of a maximum over the gears because its recovery is missing."""

    def values(name: str) -> dict:
        got = s.get(name) or {}
        return {k: v for k, v in got.items() if k != "locations" and v is not None}

    nodal, rec = values("bending_stress"), values("bending_stress_recovered")
    if rec and set(nodal) <= set(rec):
        return "bending_stress_recovered", rec
    return "bending_stress", nodal


def root_section(runs: dict[str, dict], keys, order) -> list[str]:
    """Markdown lines: the FE root stress against ISO 6336-3 for the cases ``order`` of
    ``runs`` (name -> summary) and the gear keys ``keys``."""
    first = runs[order[0]] if order else {}
    sub = "submodel" in (first.get("bending_stress_method") or "")
    read = (
        [
            "FE: the maximum principal stress at the fillet surface of the loaded teeth, read on a",
            "P2 submodel of those teeth (`solvers/root_submodel.py`: a sector of the gear as wide",
            "as the most teeth loaded in the mesh cycle, from the first loaded tooth, reaching a",
            "tooth space beyond and 2.5 modules below the root, meshed at the next finer level",
            "than the global model, its loaded fillets at 0.2 / 0.15 / 0.1 mm for levels",
            "0 / 1 / 2, driven at its cut faces by the global displacement and loaded by the",
            "solved contact forces): at each fillet vertex the mean",
            "of the surface cells' own (linear) stress there,",
        ]
        if sub
        else [
            "FE: the maximum principal stress at the fillet surface of the loaded teeth, read on",
            "the global model's fillets: at each fillet vertex the mean of the surface cells' own",
            "stress there (P1: constant per cell, a lower estimate converging as h),",
        ]
    )
    check = "global" if sub else "P1 cell"
    recovered = recovered_section(runs, keys, order)
    lines = [
        "## Root stress: FE fillet surface against ISO 6336-3 (MPa)",
        "",
        *(
            [*recovered, "", "Nodal maxima (the earlier reading; a check on the one above):", ""]
            if recovered
            else []
        ),
        *read,
        "maximum over the vertices farther than one normal module from a face end and over the",
        "mesh positions (`solvers/root_stress.py`); `face end`: the largest within that band (a",
        "corner under edge load, growing with refinement); `30/60 deg`: the largest value on",
        "ISO's critical line (fillet tangent at 30 deg to the tooth centre line, 60 deg for the",
        "ring) along the face width; "
        + (
            "`global`: the global model's own P1 surface value, the earlier estimate (its"
            if sub
            else "`P1 cell`: the largest cell value (the earlier estimate)."
        ),
        *(
            [
                "fillets are 0.45 / 0.15 / 0.12 mm at levels 0 / 1 / 2). The ± beside a value is",
                "its discretisation error from the convergence study of its gear set.",
            ]
            if sub
            else []
        ),
        "ISO: method B nominal sigma_F0 (K factors 1, Y_B = Y_DT = 1; tooth thickness allowance",
        "included; the ring by ISO's substitute rack at 60 deg) with Y_beta of the 2006 edition;",
        "in brackets with the 2019 edition's Y_beta (the 2006 one divided by cos(beta)^3).",
        "`at`: the maximum's tooth, flank side and place along the face, Z = -z (scene) as in",
        "ZS and ZR, from the face centre.",
        "",
        "| case | level / P | gear | FE surface | at (tooth, side, Z mm) | face end"
        f" | FE 30/60 deg | {check} | ISO sigma_F0 (2019) | surface / ISO | 30/60 / ISO |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    ratios, tang, near = [], [], []
    for name in order:
        s = runs[name]
        fe = s.get("bending_stress") or {}
        tan = s.get("bending_stress_tangent") or {}
        cell = s.get("bending_stress_global" if sub else "bending_stress_cell") or {}
        end = s.get("bending_stress_face_end") or {}
        at = s.get("bending_stress_at") or {}
        beside = s.get("bending_stress_near_load") or {}
        iso = s.get("bending_stress_iso6336") or {}
        iso0 = s.get("bending_stress_iso6336_nominal") or {}
        for i, k in enumerate(keys):
            if k not in fe and k not in iso0:
                continue
            sig = (iso.get(k) or {}).get("sigma_F0", iso0.get(k))
            sig19 = (iso.get(k) or {}).get("sigma_F0_Ybeta2019")
            # Z = -z (scene), the axis of ZS / ZR (solvers.gear_train): a root maximum at the
            # face end the load centroid leans to has the centroid's sign (0.0 - z: no -0.0)
            where = _where(at.get(k))
            lv = level_text(s) if "level" in s else "-"
            head = f"| {name} | {lv} / {s.get('degree', '-')} " if i == 0 else ("| | ")
            iso_txt = f"{_f(sig)} ({_f(sig19)})" if sig19 else _f(sig)
            lines.append(
                f"{head}| {_label(k)} | {_f(fe.get(k))}{_pm(s, 'bending_stress', k, fe)} | "
                f"{where} | {_f(end.get(k))} | "
                f"{_f(tan.get(k))}{_pm(s, 'bending_stress_tangent', k, tan)} | "
                f"{_f(cell.get(k))} | {iso_txt} | {_ratio(fe.get(k), sig)} | "
                f"{_ratio(tan.get(k), sig)} |"
            )
            if beside.get(k) and fe.get(k) and beside[k] > fe[k]:
                near.append(f"{name} {_label(k)} {_f(beside[k])} (reported {_f(fe[k])})")
            if fe.get(k) and sig:
                ratios.append(fe[k] / sig)
            if fe.get(k) and tan.get(k):
                tang.append(tan[k] / fe[k])
    if sub and any(runs[n].get("bending_stress_near_load") is not None for n in order):
        lines += [
            "",
            "Beside a load: the fillet vertices within one fillet element of a contact point "
            "force on the submodel (a mate's tip at the form circle) hold the contact's own "
            "near field, not root stress, and are kept out of the values above "
            "(`solvers/root_stress.py`, near_load); over the mesh cycle they read more than "
            "the reported maximum at " + ("; ".join(near) if near else "no row of the table") + ".",
        ]
    lines += ["", *_root_differences(ratios, tang, runs[order[0]] if order else {})]
    return lines


def _where(a: dict | None) -> str:
    """``tooth, side, Z`` of a maximum's location, Z = -z (scene) as in ZS and ZR."""
    a = a or {}
    return (
        f"{a['tooth']}, {a['side']}, {0.0 - a['z_mm']:+.1f}" if a.get("tooth") is not None else "-"
    )


def recovered_section(runs: dict[str, dict], keys, order) -> list[str]:
    """Markdown lines: the root stress's recovered reading (``bending_stress_recovered``,
    ``bending_stress_tangent_recovered``, ``bending_stress_recovered_at`` of the summaries;
    :mod:`solvers.surface_recovery`), the reported value, against ISO 6336-3 and the nodal
    maxima of :func:`root_section`. Empty where no run has one (summaries written before the
    recovery was added)."""

    def holds(s: dict) -> bool:
        return any(v is not None for v in (s.get("bending_stress_recovered") or {}).values())

    have = [n for n in order if holds(runs[n])]
    if not have:
        return []
    lines = [
        "**Reported: the recovered reading** (`solvers/surface_recovery.py`), the value the",
        "convergence studies target and the reports quote. Per tensor component a weighted",
        "least-squares fit over the fillet's nodes in the fillet's own coordinates (arc length",
        "across the profile, quadratic over ± 2 node spacings; face width, linear over ± 4),",
        "evaluated at the nodes and on ISO's line; the maximum principal stress of the fitted",
        "tensor, maximum over the same vertices and positions as the nodal values below. The",
        "nodal maximum is the largest of values that scatter from node to node at the element",
        "scale and carries the scatter's upper half; the recovered one does not, and its spread",
        "between equally valid sectors is smaller (1-GB's ring line 4.6 -> 1.6 %). ISO:",
        "sigma_F0 with the 2006 edition's Y_beta, as in the nodal table below.",
        "",
        "| case | gear | FE surface, recovered | at (tooth, side, Z mm) | FE 30/60 deg, "
        "recovered | ISO sigma_F0 | surface / ISO | surface: recovered / nodal | "
        "30/60: recovered / nodal |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for name in have:
        s = runs[name]
        rec = s.get("bending_stress_recovered") or {}
        tan = s.get("bending_stress_tangent_recovered") or {}
        fe = s.get("bending_stress") or {}
        fe_tan = s.get("bending_stress_tangent") or {}
        at = s.get("bending_stress_recovered_at") or {}
        iso = s.get("bending_stress_iso6336") or {}
        iso0 = s.get("bending_stress_iso6336_nominal") or {}
        first = True
        for k in keys:
            if rec.get(k) is None and tan.get(k) is None:
                continue
            sig = (iso.get(k) or {}).get("sigma_F0", iso0.get(k))
            lines.append(
                f"| {name if first else ''} | {_label(k)} | "
                f"{_f(rec.get(k))}{_pm(s, 'bending_stress_recovered', k, rec)} | "
                f"{_where(at.get(k))} | "
                f"{_f(tan.get(k))}{_pm(s, 'bending_stress_tangent_recovered', k, tan)} | "
                f"{_f(sig)} | {_ratio(rec.get(k), sig)} | "
                f"{_ratio(rec.get(k), fe.get(k))} | {_ratio(tan.get(k), fe_tan.get(k))} |"
            )
            first = False
    return lines


def _root_differences(ratios: list[float], tang: list[float], s: dict) -> list[str]:
    """Where and why the FE and ISO root stresses differ (the numbers from the table and the
    ISO factors of the summary ``s``)."""
    out = ["Where and why FE and ISO differ:", ""]
    if ratios:
        out.append(
            f"- FE surface / ISO (2006) spans {min(ratios):.2f}-{max(ratios):.2f} over the "
            "table. ISO's sigma_F0 is a nominal stress: a cantilever of the virtual spur gear "
            "loaded at the outer point of single pair contact, times a stress correction Y_S "
            "fitted to spur-tooth notch stresses, times Y_beta for the inclined contact lines; "
            "the FE resolves the real helical tooth, its load sharing and its fillet."
        )
    if tang:
        out.append(
            f"- Location: on ISO's 30/60 deg line the FE stress is {min(tang):.2f}-"
            f"{max(tang):.2f} of the FE surface maximum; the maximum sits off that line "
            "and along the face where the contact lines carry most (its Z in the table), "
            "while ISO takes one transverse section."
        )
    iso = s.get("bending_stress_iso6336") or {}
    ext = [v for v in iso.values() if v and not v.get("internal")]
    inn = [v for v in iso.values() if v and v.get("internal")]
    if ext or inn:
        ys = lambda vs: f"{min(v['Y_S'] for v in vs):.2f}-{max(v['Y_S'] for v in vs):.2f}"  # noqa: E731
        txt = f"- Y_S: ISO's empirical notch factor is {ys(ext)} here for the external gears"
        if inn:
            v = inn[0]
            txt += (
                f" and {v['Y_S']:.2f} for the internal gear (q_s = s_Fn / (2 rho_F) = "
                f"{v['q_s']:.2f}: the substitute rack's fillet radius rho_F = {v['rho_F']:.3f} "
                f"mm, where the shaper-cut fillet has {v['rho_F_generated']:.3f} mm at 60 deg)"
            )
        out.append(
            txt + "; the FE fillet is the generated trochoid, its notch stress is "
            "computed, not fitted."
        )
    out += [
        "- Rim: ISO's Y_B = 1 assumes a rim at least 1.2 tooth depths thick; the modelled "
        "ring is a thin rim that bends as a ring between its supports, which ISO does not "
        "see, and the internal tooth is wider at the root than the external teeth.",
        "- Load distribution: ISO's nominal has K_Fbeta = K_Falpha = 1 (the load spread evenly "
        "over the face and the contact lines); the FE carries the real distribution (K_Hbeta "
        "in the contact table), which raises the local root stress where the load "
        "concentrates.",
        "- Helix factor: the 2006 and 2019 editions' Y_beta differ by 1 / cos(beta)^3; the "
        "comparison uses 2006 (the paper's era, and the form we can quote).",
    ]
    return out


def correction_note(runs: dict[str, dict]) -> list[str]:
    """Markdown lines on the zone model's body correction (solvers/contact.py eq. (6)): per
    run the largest clipped eigenvalue ratio over the positions (``contact_correction_
    clipped``; 0: eq. (5) unchanged) and what the clip moved, the largest over the positions
    (``contact_correction_clip_effect``: load shares and the pinions' motion, where the
    summary has it). None for runs without the entry (line grid, older summaries)."""
    got = {
        n: s["contact_correction_clipped"]
        for n, s in runs.items()
        if s.get("contact_correction_clipped") is not None
    }
    if not got:
        return []
    vals = ", ".join(f"{n} {v:.2f}" for n, v in got.items())
    lines = [
        "Zone contact, FE body correction (solvers/contact.py eq. (6)): the negative part of",
        "its symmetric part, the mesh's discretisation error, is clipped so every tooth pair's",
        f"compliance block stays positive definite; largest clipped / kept eigenvalue: {vals}",
        "(0: nothing clipped).",
    ]
    moved = {
        n: runs[n]["contact_correction_clip_effect"]
        for n in got
        if runs[n].get("contact_correction_clip_effect") is not None
    }
    if moved:
        lines += [
            "What the clip moved (the load shares and the pinions' motion, to first order, the",
            "largest over the positions; a run warns above 0.1 %): "
            + ", ".join(f"{n} {v:.1e}" for n, v in moved.items())
            + ".",
        ]
    return lines


def contact_definition(runs: dict[str, dict]) -> list[str]:
    """Markdown lines saying what the FE contact stress of these runs is: the zone grid's
    solved cell pressure or the line grid's Hertz stress at each point's line load (by the
    ``grid_model`` of their ``contact_stress_cycle`` records)."""
    models = {
        c.get("grid_model", "line")
        for s in runs.values()
        for c in (s.get("contact_stress_cycle") or {}).values()
    }
    zone = [
        "FE (zone grid): the solved contact pressure of each grid cell (half-space near field",
        "over the whole contact zone), largest over the interior cells of the mesh cycle",
        "(cells at a tip or form circle or a face end are edge loads, left out).",
    ]
    line = [
        "FE (line grid): Hertz line contact with the exact curvatures under the FE line load",
        "of each grid point (the grid's contact force per contact-line length), largest over",
        "the interior points of the mesh cycle (line ends and tip/form points are edge loads).",
    ]
    if models == {"line"}:
        return line
    if models == {"zone"}:
        return zone
    return zone + line


def contact_section(runs: dict[str, dict], meshes, order) -> list[str]:
    """Markdown lines: FE contact stress against ISO 6336-2 and Hertz at the pitch point."""
    lines = [
        "## Contact stress: FE against ISO 6336-2 and Hertz (MPa)",
        "",
        *contact_definition(runs),
        "Hertz at C: the pitch point's curvature under the FE's largest and mean interior line",
        "load. ISO 6336-2 method B at the pitch point, K factors 1 (sigma_H0), and with the",
        "FE's K_Hbeta = w_max / w_mean (sigma_H0 sqrt(K_Hbeta)); Hertz at C under ISO's mean",
        "load per contact length is sigma_H0 / Z_beta (the check that both use one load).",
        *(["", *note] if (note := correction_note(runs)) else []),
        "",
        "| case | mesh | FE interior max | at s mm | Hertz C, w_max | Hertz C, w_mean "
        "| ISO sigma_H0 | K_Hbeta | ISO sigma_H0 sqrt(K_Hbeta) | FE / ISO(K_Hbeta) |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for name in order:
        cyc = runs[name].get("contact_stress_cycle") or {}
        first = True
        for m in meshes:
            c = cyc.get(m)
            if c is None:
                continue
            at = (c.get("interior_at") or {}).get("s_mm")
            lines.append(
                f"| {name if first else ''} | {m.replace('_', '-')} | "
                f"{_f(c.get('interior_p_max_MPa'))}"
                f"{_pm(runs[name], f'contact_stress_cycle.{m}', 'interior_p_max_MPa', c)} | "
                f"{_f(at, '+.2f')} | "
                f"{_f(c.get('hertz_pitch_w_max_MPa'))} | {_f(c.get('hertz_pitch_w_mean_MPa'))} | "
                f"{_f(c.get('sigma_H0_MPa'))} | {_f(c.get('K_Hbeta'), '.2f')} | "
                f"{_f(c.get('sigma_H_MPa'))} | "
                f"{_ratio(c.get('interior_p_max_MPa'), c.get('sigma_H_MPa'))} |"
            )
            first = False
    lines += [
        "",
        "The FE maximum and ISO's pitch-point value differ where the largest line load sits "
        "away from the pitch point (s in the table: the relative curvature there is not C's), "
        "where ISO's Z_eps (mean contact-line length) and Z_beta stand for the FE's actual "
        "load sharing between the contact lines, and because K_Hbeta here holds the load "
        "sharing along and between the lines, not only ISO's face load factor.",
    ]
    return lines

"""Lead correction (beyond the paper, issue 11 item 7): the lead slopes that re-centre the
contact pattern of a single-pinion set under its own bearing stiffness and torque, and the
report section.

Unknowns u = (f_P, f_S) (um): the lead slope f_Hb (helix angle modification, um across the
face width; :mod:`gears.microgeometry`: s f_Hb z / b removed from the flank of side s) of the
pinion and of the sun. Residual r(u) = (ZS, ZR) (mm): the load-centroid offsets of the
sun-pinion and pinion-ring meshes from mid face, means over the mesh positions (singh2007
section 7). Wanted: |ZS|, |ZR| <= tol (0.5 mm). Newton with a finite-difference Jacobian,
then Broyden's update (:func:`newton_step`, :func:`broyden_update`):

    J_ij = (r_i(u + h e_j) - r_i(u)) / h                                          (1)
    du = -J^-1 r(u), scaled down so that max |du_j| <= max_step                   (2)
    J <- J + (dr - J du) du^T / (du^T du),  dr = r(u + du) - r(u)                 (3)

Why the pinion and the sun. The pinion's tilt on its bearing is what moves both patterns;
its sun mesh runs on its ``pos`` flank and its ring mesh on its ``neg`` flank, and a lead
slope removes material at opposite face ends of the two, so a single pinion slope (a helix
angle change of the pinion, ground on every planet alike) moves ZS and ZR the same way a
pinion tilt does, and takes out most of the misalignment of both meshes. The two meshes do
not need exactly the same correction (different stiffness and contact lines); the second
unknown, the sun's slope, trims the sun mesh alone (the sun meets every planet with the same
mismatch, so one sun slope serves all branches). The ring is left unmodified: an internal
gear is shaped or broached, and its lead is not normally modified. Flank-specific pinion
slopes (sun-side and ring-side different) would do the same job on the pinion alone, but
the gear-set file holds one lead slope per gear.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from gears.microgeometry import NONE
from postprocess.run_scalars import level_text
from postprocess.stress_tables import reported_root_stress

#: the root stress reading a row quotes, in words (:func:`reported_root_stress`'s key)
ROOT_READING = {"bending_stress_recovered": "surface, recovered", "bending_stress": "nodal"}

UM = 1e-3  # mm per um
#: the quantities reported before and after (summary keys, mean over the positions)
MOMENT_KEYS = ("ZS", "ZR", "Mx_pin", "My_pin", "Mz_pin", "M_LOA_sun", "M_LOA_ring")


def corrected_gearset(gearset, slopes_um: dict[str, float], crowns_um: dict | None = None):
    """``gearset`` with the lead slope (and, if given, lead crown) of the named gears set to
    the values given (um); the gears' other modifications kept. An out-of-range value raises
    :class:`gears.spec.GeometryError` naming the field."""
    mods = dict(gearset.modifications)
    for name in set(slopes_um) | set(crowns_um or {}):
        if name not in gearset.gears:
            raise KeyError(f"{gearset.name}: no gear {name!r} to modify")
        new = {"lead_slope_um": float(slopes_um.get(name, mods.get(name, NONE).lead_slope_um))}
        if crowns_um and name in crowns_um:
            new["lead_crown_um"] = float(crowns_um[name])
        mods[name] = dataclasses.replace(mods.get(name, NONE), **new)
    return dataclasses.replace(
        gearset, modifications={k: v for k, v in mods.items() if not v.is_zero}
    )


def residual(summary: dict) -> np.ndarray:
    """r = (ZS, ZR) (mm) of a study summary."""
    return np.array([summary["ZS"], summary["ZR"]], dtype=float)


def newton_step(jac: np.ndarray, r: np.ndarray, max_step: float) -> np.ndarray:
    """du = -J^-1 r (eq. 2), scaled down as a whole to max |du_j| <= ``max_step``; a
    singular J (one slope does not move the patterns) raises ValueError."""
    if abs(np.linalg.det(jac)) < 1e-12 * max(np.abs(jac).max() ** 2, 1e-300):
        raise ValueError(f"lead correction: the Jacobian {jac.tolist()} is singular")
    du = -np.linalg.solve(jac, r)
    big = np.abs(du).max()
    return du * (max_step / big) if big > max_step else du


def broyden_update(jac: np.ndarray, du: np.ndarray, dr: np.ndarray) -> np.ndarray:
    """Broyden's rank-one update of J after the step du gave dr (eq. 3)."""
    return jac + np.outer(dr - jac @ du, du) / float(du @ du)


def converged(r: np.ndarray, tol: float) -> bool:
    return bool(np.all(np.abs(r) <= tol))


def state_row(summary: dict) -> dict:
    """What the report compares before and after, from a study summary: the paper's
    moments and centroids, the contact stress over the mesh cycle (interior maximum, edge
    maximum, K_Hbeta, ISO sigma_H0 sqrt(K_Hbeta)) and the FE root stress the reports quote
    (maximum over the cycle; :func:`postprocess.stress_tables.reported_root_stress`: the
    recovered surface reading where it covers every gear, else the nodal maxima)."""
    root_key, root = reported_root_stress(summary)
    cyc = summary["contact_stress_cycle"]
    return {
        **{k: float(summary[k]) for k in MOMENT_KEYS},
        "contact": {
            m: {
                "interior_MPa": v.get("interior_p_max_MPa"),
                "edge_MPa": v.get("edge_p_max_MPa"),
                "K_Hbeta": v.get("K_Hbeta"),
                "sigma_H_iso_MPa": v.get("sigma_H_MPa"),
            }
            for m, v in cyc.items()
        },
        "root_MPa": root,
        "root_reading": ROOT_READING[root_key],
        "coast_min_gap_mm": (summary.get("coast") or {}).get("min_gap_mm"),
        # singh2007's closed form with both mesh loads at mid face (ZS = ZR = 0)
        "closed_form_mid_face": dict((summary.get("analytic") or {}).get("concentrated") or {}),
    }


def modification_toml(gearset, slopes_um: dict[str, float], crowns_um: dict | None = None):
    """The ``[gears.X.modifications]`` tables to paste into the gear-set file: every field
    the gear already has, with the lead slope (and crown) replaced."""
    out = []
    for name in slopes_um:
        old = gearset.modifications.get(name, NONE)
        mods = dataclasses.replace(old, lead_slope_um=round(float(slopes_um[name]), 1))
        if crowns_um and name in crowns_um:
            mods = dataclasses.replace(mods, lead_crown_um=round(float(crowns_um[name]), 1))
        out.append(f"[gears.{name}.modifications]")
        for field, value in dataclasses.asdict(mods).items():
            if value is None or (value == 0.0 and field != "lead_slope_um"):
                continue
            out.append(f"{field} = {value!r}")
        out.append("")
    return "\n".join(out).rstrip() + "\n"


def _f(x, fmt=".1f") -> str:
    return "-" if x is None or (isinstance(x, float) and math.isnan(x)) else format(x, fmt)


def report(data: dict) -> str:
    """``report.md`` of a lead-correction run (``data`` as written by the study)."""
    inp, before, after = data["inputs"], data["before"], data["after"]
    names = inp["unknowns"]
    lines = [
        f"# Lead correction, case {inp['case']}",
        "",
        f"Gear set {inp['gearset']}, pinion bearing {inp['bearing_radial_N_per_mm']:.3g} N/mm, "
        f"{inp['bearing_tilting_Nmm_per_rad']:.3g} N mm/rad, sun torque "
        f"{inp['input_torque_Nm']:g} N m; scene {inp['scene']}, level {level_text(inp)}, "
        f"{inp['positions']} mesh positions over one base pitch (ZS, ZR: means over them).",
        "",
        "The lead slopes (helix angle modifications, um across the face width, "
        "gears/microgeometry.py) of the "
        + " and the ".join(names)
        + f" that bring the load centroids of both meshes within {inp['tol_mm']:g} mm of mid "
        "face: Newton on (ZS, ZR) with a finite-difference Jacobian "
        f"(step {inp['fd_step_um']:g} um), then Broyden updates "
        "(studies/lead_correction/report.py). The pinion slope takes out the tilt of the pinion "
        "on its bearing for both meshes (its sun and ring meshes run on its two flanks); the "
        "sun slope trims the sun mesh; the ring, an internal gear, is left as it is.",
        "",
        f"Result: **{'converged' if data['converged'] else 'NOT converged'}** after "
        f"{len(data['history'])} solves of the {inp['positions']} positions.",
        "",
        *_share_note(data),
        "## Iterations",
        "",
        "| solve | " + " | ".join(f"{n} slope (um)" for n in names) + " | ZS (mm) | ZR (mm) |"
        " My_pin (N m) | kind |",
        "|---:|" + "---:|" * len(names) + "---:|---:|---:|---|",
    ]
    for k, h in enumerate(data["history"]):
        lines.append(
            f"| {k} | "
            + " | ".join(f"{h['slopes_um'][n]:+.1f}" for n in names)
            + f" | {h['ZS']:+.3f} | {h['ZR']:+.3f} | {h['My_pin']:.1f} | {h['kind']} |"
        )
    lines += [
        "",
        "## Before and after",
        "",
        "The closed form (singh2007, both mesh loads at mid face, ZS = ZR = 0) is what a "
        "centred pattern should give: the correction leaves the pinion's tilt on its bearing "
        "(the flanks are cut to meet it), so the moments move to the mid-face values.",
        "",
        "| quantity | before | after | closed form, ZS = ZR = 0 |",
        "|---|---:|---:|---:|",
    ]
    units = {"ZS": "mm", "ZR": "mm"}
    mid = after.get("closed_form_mid_face", {})
    for k in MOMENT_KEYS:
        u = units.get(k, "N m")
        ref = 0.0 if k in units else mid.get(k)
        lines.append(
            f"| {k} ({u}) | {before[k]:+.3f} | {after[k]:+.3f} | "
            f"{'-' if ref is None else format(ref, '+.3f')} |"
        )
    for m in before["contact"]:
        b, a = before["contact"][m], after["contact"][m]
        lines += [
            f"| contact stress {m}, interior max over the cycle (MPa) | "
            f"{_f(b['interior_MPa'], '.0f')} | {_f(a['interior_MPa'], '.0f')} | |",
            f"| contact stress {m}, edge (face end / tip) max (MPa) | "
            f"{_f(b['edge_MPa'], '.0f')} | {_f(a['edge_MPa'], '.0f')} | |",
            f"| K_Hbeta {m} = w_max / w_mean | {_f(b['K_Hbeta'], '.2f')} | "
            f"{_f(a['K_Hbeta'], '.2f')} | |",
            f"| ISO sigma_H0 sqrt(K_Hbeta) {m} (MPa) | {_f(b['sigma_H_iso_MPa'], '.0f')} | "
            f"{_f(a['sigma_H_iso_MPa'], '.0f')} | |",
        ]
    # a file written before the rows named their reading holds the nodal maxima
    read = {before.get("root_reading", "nodal"), after.get("root_reading", "nodal")}
    for g in before["root_MPa"]:
        lines.append(
            f"| FE root stress {g} (MPa, {' / '.join(sorted(read))}, maximum over the cycle) | "
            f"{_f(before['root_MPa'].get(g), '.0f')} | {_f(after['root_MPa'].get(g), '.0f')} | |"
        )
    lines.append(
        f"| smallest coast-flank gap (um) | {_f(_um(before['coast_min_gap_mm']))} | "
        f"{_f(_um(after['coast_min_gap_mm']))} | |"
    )
    lines += [
        "",
        "## Modification table for the gear-set file",
        "",
        f"Paste into `{inp['gearset_path']}` (replacing any table of the same gear); the "
        "contact takes the modifications as initial gaps (the meshes keep the exact flanks):",
        "",
        "```toml",
        data["toml"].rstrip(),
        "```",
        "",
        "Sign: a positive lead slope removes f/2 at the +z end of the gear's `pos` flank and "
        "adds it at the -z end, the `neg` flank the other way round (gears/microgeometry.py); "
        "z is the axis of the gear set, z = 0 at mid face.",
        "",
        "Limits: the correction holds for this torque and this bearing; at other loads the "
        "tilt, hence the pattern, moves again (a crown keeps the pattern off the face ends "
        "over a load range). The slopes are found at the level the run states; a finer "
        "level moves ZS and ZR by its discretisation error.",
    ]
    return "\n".join(lines) + "\n"


def _share_note(data: dict) -> list[str]:
    """A sentence when the first unknown (the pinion) does the correction alone."""
    names, f = data["inputs"]["unknowns"], data["slopes_um"]
    main, trim = abs(f[names[0]]), abs(f[names[1]])
    if main > 0 and trim < 0.05 * main:
        return [
            f"The {names[0]} slope alone does the correction: the {names[1]}'s share, "
            f"{f[names[1]]:+.1f} um, is below what grinding holds (a few um), so one helix "
            f"modification of the {names[0]} serves both meshes.",
            "",
        ]
    return []


def _um(mm):
    return None if mm is None else mm / UM

"""System-scene report: each case in the one-branch scene and in the system scene side by side.

Reads ``<branch>/<case>/summary.json`` and ``<system>/<case>/summary.json`` for the cases it
is given (whatever has been run) and writes ``<system>/report.md``: the pinion moments, load
centroids and LOA moments of both scenes, what the system adds (load shares, K_gamma, the
sun's float, the carrier's wind-up, the torque balance), the comparison of the case pair that
separates gear stiffness from bearing stiffness (1-GB-R against 1-GC in the paper), and the
loaded-scene pictures. Single-pinion sets report section 3's pinion moments; double-pinion
sets (:data:`KIND_QUANTITIES`) section 5's SP and RP moments and the four LOA moments, per pair
too, the carrier's six-pin layout and what the elastic carrier changes against the branch;
both kinds the root stress of every gear in both scenes.
Numbers come from the summaries alone, inputs included.
"""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

from postprocess.convergence_record import uncertainty_note
from postprocess.failed_positions import failed_positions_lines
from postprocess.plus_minus import plus_minus
from postprocess.run_scalars import level_text

#: the columns of the comparison, per gear-set kind (single pinion: section 3's pinion
#: frame; double pinion: section 5's SP and RP frames and the four LOA moments)
KIND_QUANTITIES = {
    "single_pinion": ("My_pin", "Mx_pin", "ZS", "ZR", "M_LOA_sun", "M_LOA_ring"),
    "double_pinion": (
        "Mx_SP",
        "My_SP",
        "Mx_RP",
        "My_RP",
        "ZS",
        "Z_SPRP",
        "ZR",
        "M_LOA_sun_SP",
        "M_LOA_SP_RP",
        "M_LOA_RP_SP",
        "M_LOA_RP_ring",
    ),
}
QUANTITIES = KIND_QUANTITIES["single_pinion"]
OFFSETS = ("ZS", "Z_SPRP", "ZR")  # mm; the rest N m


def _urad(rad) -> str:
    """A rotation (rad) in urad; n/a where the summary has none (no elastic carrier)."""
    return "n/a" if rad is None else f"{rad * 1e6:.0f}"


def summary_kind(s: dict) -> str:
    """The gear-set kind of a summary (``single_pinion`` or ``double_pinion``)."""
    return s["inputs"]["gearset"]["kind"]


def _load(folder: Path, cases: list[str]) -> dict[str, dict]:
    out = {}
    for name in cases:
        path = folder / name / "summary.json"
        if path.is_file():
            out[name] = json.loads(path.read_text())
    return out


def _fmt(q: str, v) -> str:
    if v is None:
        return "-"
    return f"{v:+.2f}" if q in OFFSETS else f"{v:.1f}"


def _pm(s: dict, q: str) -> str:
    """`` ± u`` of quantity ``q`` of a summary (its discretisation uncertainty), or ''."""
    return plus_minus(s, q, ".2f" if q in OFFSETS else ".1f") if s.get(q) is not None else ""


def _inputs(s: dict) -> str:
    inp = s["inputs"]["study_case"]
    b, m = inp["bearing"], inp["material"]
    return (
        f"bearing radial {b['radial_stiffness']:.3g} N/mm, tilt {b['tilting_stiffness']:.3g} "
        f"N mm/rad; gears E x {m['gear_modulus_factor']:g}"
    )


def root_fillets(s: dict) -> str:
    """The root fillets ("refined" or "coarse") of the global model a summary's scene was
    meshed with, as the run recorded them (``root_fillets``); a summary written before that
    field: from its root stress, which the scenes then read only on refined fillets."""
    if s.get("root_fillets") in ("refined", "coarse"):
        return s["root_fillets"]
    return "refined" if s.get("bending_stress") else "coarse"


def _fillet_note(branch: dict, system: dict) -> str:
    """Whether the branch and system runs compare like with like in their root fillets."""
    if not any(n in branch for n in system):
        return (
            "No one-branch run of these cases to compare with (run them with "
            "`--root-fillets coarse`, as `make case1-system` does)."
        )
    mixed = sorted(
        n for n in system if n in branch and root_fillets(branch[n]) != root_fillets(system[n])
    )
    used = sorted({root_fillets(r) for r in (*branch.values(), *system.values())})
    if mixed:
        return (
            f"**Not like with like**: {', '.join(mixed)} ran with refined root fillets in one "
            "scene and coarse ones in the other; finer fillets make the teeth more "
            "compliant and move the moments by 1-3 % (README, case-1 study), which this "
            "comparison then mixes into the carrier's effect. Run the branch with "
            "`--root-fillets coarse` (`make case1-system` does)."
        )
    coarse = used == ["coarse"]
    return (
        f"Both scenes ran with {used[0] if len(used) == 1 else ' and '.join(used)} root "
        "fillets"
        + (" (every fillet of the global model at the level's fillet_far size)" if coarse else "")
        + ", so the differences below are the system's, "
        "not the fillets' (numerics.root_fillets)."
    )


def _set_stress(s: dict, name: str) -> tuple[dict, dict]:
    """Per gear-set key (``sun``, ``pinion_sun_side``, ...) the cycle maximum of root-stress
    quantity ``name`` (``bending_stress`` or ``bending_stress_tangent``) and the output key it
    was read on: a scene with several planets holds them per gear set
    (:func:`postprocess.summary.cycle_bending`), a one-branch scene per key."""
    if s.get(f"{name}_set") is not None:
        return s[f"{name}_set"], s.get("bending_stress_set_key") or {}
    vals = {k: v for k, v in (s.get(name) or {}).items() if isinstance(v, (int, float))}
    return vals, {k: k for k in vals}


def _root_stress_text(branch: dict, system: dict) -> list[str]:
    """Root stress of each case's gears, branch against system (cycle maxima, MPa)."""
    rows = []
    for name, sy in system.items():
        br = branch.get(name) or {}
        sv, sk = _set_stress(sy, "bending_stress")
        st, _ = _set_stress(sy, "bending_stress_tangent")
        bv, _ = _set_stress(br, "bending_stress")
        bt, _ = _set_stress(br, "bending_stress_tangent")
        for key in [*(k for k in bv if k in sv), *(k for k in sv if k not in bv)]:
            b, v = bv.get(key), sv[key]
            ratio = f"{v / b:.3f}" if b else "-"
            line = f"{_num(bt.get(key))} / {_num(st.get(key))}"
            rows.append(
                f"| {name} | {key} | {_num(b)} | {_num(v)} ({sk.get(key, '-')}) | "
                f"{ratio} | {line} |"
            )
    if not rows:
        why = "numerics.root_stress 'none', or 'global' on its coarse root fillets"
        return ["", "## Root stress", "", f"Not read in the system scene ({why})."]
    return [
        "",
        "## Root stress: branch against system",
        "",
        "FE root stress at the fillet surface, the maximum over the mesh cycle (MPa), read in",
        "both scenes on P2 submodels of the loaded teeth driven by the scene's own solution",
        "(`solvers.root_submodel`); in the system scene on the most loaded mesh of each gear",
        "and side at each position (the key read in brackets: the other planets' meshes of",
        "that gear carry less load). Last column: the value on ISO 6336-3's 30 deg (ring:",
        "60 deg) line, branch / system. On coarse global fillets the submodels read higher",
        "than on the refined global model of the case reports (0.2-4.6 % measured for 1-GA",
        "and 1-GB, README, Design: root fillets), so compare these with each other, not",
        "with the case reports.",
        "",
        "| case | gear | branch | system (read on) | system / branch | ISO line: branch / system |",
        "|---|---|---|---|---|---|",
        *rows,
    ]


def _contact_stress_text(branch: dict, system: dict) -> list[str]:
    """Contact stress of each mesh of the gear set, branch against system (cycle maxima)."""
    rows = []
    for name, sy in system.items():
        per_set = sy.get("contact_stress_cycle_set") or {}
        br = (branch.get(name) or {}).get("contact_stress_cycle") or {}
        for mesh, v in per_set.items():
            b = br.get(mesh) or {}
            p_b, p_s = b.get("interior_p_max_MPa"), v.get("interior_p_max_MPa")
            ratio = f"{p_s / p_b:.3f}" if p_b and p_s else "-"
            rows.append(
                f"| {name} | {mesh} | {_num(p_b)} | {_num(p_s)} ({v.get('mesh') or '-'}) | "
                f"{ratio} | {_num(b.get('sigma_H_MPa'))} / {_num(v.get('sigma_H_MPa'))} | "
                f"{_num(b.get('w_max_N_per_mm'))} / {_num(v.get('w_max_N_per_mm'))} |"
            )
    if not rows:
        return []
    return [
        "",
        "## Contact stress: branch against system",
        "",
        "The largest contact pressure over the mesh cycle at the interior grid points (MPa;",
        "the face-end and tip/form edges kept apart, as in the case reports), in the system",
        "scene the largest over the planets' meshes of each gear pair (the mesh in brackets);",
        "ISO 6336-2's sigma_H from each scene's own face load factor, and the largest line",
        "load (N/mm), branch / system.",
        "",
        "| case | mesh | branch | system (mesh) | system / branch | sigma_H: branch / system "
        "| w_max: branch / system |",
        "|---|---|---|---|---|---|---|",
        *rows,
    ]


def _num(v) -> str:
    return "-" if v is None else f"{v:.0f}"


def _per_pair(system: dict, quantities) -> list[str]:
    """Per pair of each case: angle, load share and the quantities (means over positions)."""
    lines = [
        "",
        "### Per pair",
        "",
        "| case | pair | angle (deg) | load share | " + " | ".join(quantities) + " |",
        "|---|---|---|---|" + "---|" * len(quantities),
    ]
    for name, s in system.items():
        for k, p in enumerate(s["pinions"]):
            vals = " | ".join(_fmt(q, p.get(q)) for q in quantities)
            lines.append(
                f"| {name} | {k + 1} | {p['angle_deg']:.3f} | {p['load_share']:.4f} | {vals} |"
            )
    return lines


def _double_pinion_text(branch: dict, system: dict) -> list[str]:
    """The carrier layout (from the gear set's centre distances) and what the system scene
    changes against the one-branch scene, case by case (numbers from the summaries)."""
    s0 = next(iter(system.values()))
    a1, a2, a3 = (m["centre_distance"] for m in s0["inputs"]["gearset"]["meshes"])
    psi_t = math.degrees(math.acos((a1 * a1 + a3 * a3 - a2 * a2) / (2 * a1 * a3)))
    lines = [
        "",
        f"Carrier: six pins, the SP pins {a1:g} mm from the sun axis (sun-SP centre distance) "
        f"at the pair angles, the RP pins {a3:g} mm out (RP-ring centre distance) and "
        f"{psi_t:.3f} deg ahead (the triangle's angle at the sun, from the three centre "
        f"distances {a1:g}, {a2:g}, {a3:g} mm), one post per pair in the gap to the next pair, "
        "clear of every SP and RP tip circle (`meshing.carrier.carrier_spec`).",
    ]
    for name, s in system.items():
        b = branch.get(name)
        if b is None:
            continue
        moved = {
            k: s[k] - b[k] for k in ("M_LOA_sun_SP", "M_LOA_SP_RP", "M_LOA_RP_SP", "M_LOA_RP_ring")
        }
        worst = max(moved, key=lambda k: abs(moved[k]))
        lines += [
            "",
            f"{name}: from the branch to the system the LOA moments move by "
            + ", ".join(f"{k} {v:+.1f}" for k, v in moved.items())
            + f" N m (largest: {worst}); the SP-RP differential is "
            f"{s['M_LOA_SPRP_diff']:.1f} N m in the system against {b['M_LOA_SPRP_diff']:.1f} "
            f"in the branch. The carrier, held at the hub of one plate only, winds up by "
            f"{_urad(s.get('carrier_windup_rad'))} urad (mean pin rotation about the "
            "sun axis) under the pin loads; the pins, anchored in both plates, follow the "
            "plates' unequal wind-up and lean, which moves Mx of SP and RP most; in the branch "
            "the pins are rigid.",
        ]
    return lines


def _spacing_text(s: dict) -> list[str]:
    """Why the load shares are what they are, from the set's planets and angles."""
    gs = s["inputs"]["gearset"]
    z = {n: g["teeth"] for n, g in gs["gears"].items()}
    path, n = gs["power_path"], gs["planets"]
    zs, zr = z[path[0]], z[path[-1]]
    double = len(path) == 4
    steps, rule = (zr - zs, "Zr - Zs") if double else (zs + zr, "Zs + Zr")
    angles = [p["angle_deg"] for p in s["pinions"]]
    if steps % n == 0:
        phase = (zs * 360.0 / n / 360.0) % 1.0
        return [
            f"Load sharing: {rule} = {steps} is divisible by {n}: the "
            f"{'pairs' if double else 'pinions'} are equally spaced "
            f"({', '.join(f'{a:.3f}' for a in angles)} deg) and a floating sun balanced by "
            f"{n} mesh forces, each along its branch's plane of action, shares the load "
            f"equally by statics (three magnitudes, two force equations and the torque), "
            f"although the branches sit at different mesh positions (the sun mesh of branch 2 "
            f"lags branch 1 by Zs / {n} = {zs / n:.3f} teeth, {phase:.3f} of a mesh cycle) "
            "and their moments differ. Only coast flanks that close (the summary's `coast`) "
            "act on the sun too and could move the shares.",
        ]
    psi = math.radians(angles[1] - angles[0]) if len(angles) > 1 else 0.0
    ratio = -2.0 * math.cos(psi)
    return [
        f"Load sharing: with a floating sun the three sun-mesh forces balance the sun, so the "
        f"unequal spacing the assembly condition forces ({rule} = {steps} is not divisible "
        f"by {n}) gives the pinion at 0 deg a share of 3 (-2 cos {math.degrees(psi):.3f} deg) "
        f"/ (2 - 2 cos {math.degrees(psi):.3f} deg) = {3 * ratio / (ratio + 2):.3f} whatever "
        "the stiffness, as long as only the drive flanks carry load: a property of the set, "
        "not of the model. Where coast flanks close (the summary's `coast`), their forces act "
        "on the sun too and the shares move.",
    ]


def write_system_report(
    branch_dir: Path, system_dir: Path, cases: list[str], pair: tuple[str, str] | None = None
) -> Path:
    """Write ``system_dir/report.md``. ``pair``: (gears stiffer, bearing softer) cases whose
    difference the system scene must show (the paper's 1-GB-R and 1-GC)."""
    branch, system = _load(branch_dir, cases), _load(system_dir, cases)
    if not system:
        raise FileNotFoundError(f"no system-scene summary under {system_dir}")
    kind = summary_kind(next(iter(system.values())))
    quantities = KIND_QUANTITIES[kind]
    if kind == "double_pinion":
        intro = [
            "# The system scene: every pinion pair on the elastic carrier",
            "",
            "Each case in the one-branch scene (one SP-RP pair on rigid pins, sun held, sectors",
            "of sun and ring) and in the system scene (sun floating radially, the three pairs at",
            "the assemblable angles, full ring held at its rim, the steel carrier with an SP and",
            "an RP pin per pair, each pinion on its own pin through its needle bearing, held at",
            "the hub of its -z plate; the gears' modulus factor does not apply to the carrier).",
            "Means over the mesh positions, SP and RP frames of singh2007 section 5; system",
            "values are the means over the pairs (per pair below). Moments N m, offsets mm.",
        ]
    else:
        intro = [
            "# The system scene: every pinion on the elastic carrier",
            "",
            "Each case in the one-branch scene (one pinion on a rigid pin, sun held, sectors of",
            "sun and ring) and in the system scene (sun floating radially, all pinions at the",
            "nearest assemblable angles, full ring held at its rim, the steel carrier with one",
            "pin per pinion held at the hub of its -z plate; the gears' modulus factor does not",
            "apply to the carrier). Means over the mesh positions, pinion frame of singh2007",
            "section 3; system values are the means over the pinions. Moments N m, offsets mm.",
        ]
    lines = [
        *intro,
        "",
        "| case | inputs | scene | level | " + " | ".join(quantities) + " |",
        "|---|---|---|---|" + "---|" * len(quantities),
    ]
    for name in system:
        for label, runs in (("branch", branch), ("system", system)):
            r = runs.get(name)
            if r is None:
                continue
            vals = " | ".join(_fmt(q, r.get(q)) + _pm(r, q) for q in quantities)
            lines.append(f"| {name} | {_inputs(r)} | {label} | {level_text(r)} | {vals} |")
    scenes = {
        f"{n} ({lab})": rs[n]
        for n in system
        for lab, rs in (("branch", branch), ("system", system))
        if n in rs
    }
    lines += [
        "",
        uncertainty_note(scenes),
        *failed_positions_lines(scenes),
        "",
        _fillet_note(branch, system),
    ]
    unit = "pair" if kind == "double_pinion" else "pinion"
    lines += [
        "",
        "## What the system adds",
        "",
        f"| case | K_gamma | load shares ({unit}: angle deg, share) | sun centre (um) |"
        " carrier wind-up (urad) | torque balance (rel.) |",
        "|---|---|---|---|---|---|",
    ]
    for name, s in system.items():
        shares = ", ".join(f"{p['angle_deg']:.3f}: {p['load_share']:.4f}" for p in s["pinions"])
        sc = s.get("sun_centre_displacement_mm")
        centre = "n/a" if sc is None else f"({sc[0] * 1e3:+.2f}, {sc[1] * 1e3:+.2f})"
        lines.append(
            f"| {name} | {s['K_gamma']:.4f} | {shares} | {centre} | "
            f"{_urad(s.get('carrier_windup_rad'))} | "
            f"{s.get('torque_balance_rel', float('nan')):.1e} |"
        )
    lines += ["", *_spacing_text(next(iter(system.values())))]
    lines += _root_stress_text(branch, system)
    lines += _contact_stress_text(branch, system)
    if kind == "double_pinion":
        lines += _per_pair(system, quantities)
        lines += _double_pinion_text(branch, system)
    if pair and kind == "single_pinion" and all(n in system for n in pair):
        a, b = (system[n] for n in pair)
        ba, bb = branch.get(pair[0]), branch.get(pair[1])
        lines += ["", f"## {pair[0]} against {pair[1]}", ""]
        head = f"| quantity | {pair[0]} system | {pair[1]} system | difference |"
        lines.append(head + (f" {pair[0]} branch | {pair[1]} branch |" if ba and bb else ""))
        lines.append("|---|---|---|---|" + ("---|---|" if ba and bb else ""))
        for q in QUANTITIES:
            row = f"| {q} | {_fmt(q, a[q])} | {_fmt(q, b[q])} | {_fmt(q, a[q] - b[q])} |"
            if ba and bb:
                row += f" {_fmt(q, ba[q])} | {_fmt(q, bb[q])} |"
            lines.append(row)

        def rel(x, y):
            return max(abs(x[q] - y[q]) / max(abs(y[q]), 1e-9) for q in QUANTITIES)

        if ba and bb:
            d = rel(ba, bb)
            why = (
                "There the only compliances are the gears and the bearing, and scaling the "
                "gears by 10 is scaling the bearing by 1/10: the cases coincide."
                if d < 1e-6
                else "Scaling the gears by 10 is scaling the bearing by 1/10 only while the "
                "geometry has no length of its own: the backlash is one, and the coast flanks "
                "of the softer case close where those of the stiffer one stay open."
            )
            lines += ["", f"One-branch scene: largest relative difference {d:.1e}. {why}"]
        lines += [
            f"System scene: My_pin differs by {100 * (a['My_pin'] / b['My_pin'] - 1):+.1f} %, "
            f"Mx_pin by {a['Mx_pin'] - b['Mx_pin']:+.1f} N m, ZS by {a['ZS'] - b['ZS']:+.2f} mm "
            f"and ZR by {a['ZR'] - b['ZR']:+.2f} mm. The carrier and pins stay steel, so stiffer "
            "gears make the carrier's compliance (its wind-up tilting the pins) count for more: "
            "singh2007's reason for case 1-GB-R.",
        ]
    pin = system_dir / "pin_errors.json"
    if pin.is_file():
        res = json.loads(pin.read_text())
        lines += [
            "",
            f"## Load sharing under a pin-hole error ({res['case']}, level "
            f"{res['level']}, one position)",
            "",
            f"The pin of pinion 1 displaced {res['direction']}ly in the carrier "
            "(`python -m studies.pin_errors`; the other pins exact):",
            "",
            *_pin_error_table(res["rows"]),
        ]
        lines += ["", *_pin_error_reading(res["rows"])]
        lines += ["", "![K_gamma against the pin-hole error](pin_errors.png)"]
    lines += ["", "## Pictures", ""]
    for name in system:
        lines.append(f"- {name}: ![{name} loaded system]({name}/loaded_scene.png)")
    path = system_dir / "report.md"
    system_dir.mkdir(parents=True, exist_ok=True)
    path.write_text("\n".join(lines) + "\n")
    return path


def _pin_error_table(rows) -> list[str]:
    """The pin-error rows: K_gamma, the load shares and, where read, the root stress per
    gear-set key on its most loaded planet (MPa, the planet read in brackets)."""
    keys = list(next((r["root_stress"] for r in rows if r.get("root_stress")), None) or {})
    head = "| sun support (N/mm) | error (um) | K_gamma | load shares |"
    if keys:
        head += f" root stress (MPa, most loaded planet): {' / '.join(keys)} |"
    out = [head, "|---" * (4 + bool(keys)) + "|"]
    for r in rows:
        shares = ", ".join(f"{s:.4f}" for s in r["load_shares"])
        k = r.get("sun_radial_stiffness", 0.0)
        sun = "floating" if k == 0 else f"{k:.3g}"
        line = f"| {sun} | {r['error_um']:g} | {r['K_gamma']:.4f} | {shares} |"
        if keys:
            stress, at = r.get("root_stress") or {}, r.get("root_stress_key") or {}
            line += (
                " "
                + " / ".join(f"{_num(stress.get(q))} ({_planet(at.get(q))})" for q in keys)
                + " |"
            )
        out.append(line)
    return out


def _planet(key: str | None) -> str:
    """The planet of a root-stress output key (``pinion2_sun_side`` -> ``2``), else ``-``."""
    m = re.search(r"\d+", key or "")
    return m.group(0) if m else "-"


def root_stress_ratios(rows: list[dict]) -> dict:
    """Per sun support and gear-set key: (error, root stress / root stress at zero error)
    for the rows that read it; empty without a zero-error row of that support."""
    out: dict = {}
    for k_sun in sorted({r["sun_radial_stiffness"] for r in rows}):
        series = [r for r in rows if r["sun_radial_stiffness"] == k_sun and r.get("root_stress")]
        ref = next((r["root_stress"] for r in series if r["error_um"] == 0), None)
        if ref is None:
            continue
        for key, v0 in ref.items():
            pts = [
                (r["error_um"], r["root_stress"][key] / v0)
                for r in series
                if v0 and r["root_stress"].get(key) is not None
            ]
            out.setdefault(k_sun, {})[key] = sorted(pts)
    return out


def _kgamma_range(rows, floating: bool) -> tuple[float, float] | None:
    ks = [r["K_gamma"] for r in rows if (r.get("sun_radial_stiffness", 0.0) == 0) == floating]
    return (min(ks), max(ks)) if ks else None


def _pin_error_reading(rows) -> list[str]:
    """What the pin-error table shows, from its numbers: how far K_gamma moves over the errors
    with the sun floating (statics of three forces on a free sun: the shares do not depend on
    the pin positions when the mesh forces act on their planes of action; forces off those
    planes, tip-corner cells of the zone grid, leave a small dependence; with more planets
    statics do not fix them) and supported (pinion 1's share and K_gamma at the extremes),
    and the most loaded planet's root stress at the largest error against none."""
    out = []
    fl, sup = _kgamma_range(rows, True), _kgamma_range(rows, False)
    planets = len(rows[0]["load_shares"]) if rows else 0
    if fl is not None:
        why = (
            "three mesh forces balance a free sun, so a pin error moves the sun rather than "
            "the shares (exactly so for forces on the planes of action; contact off them, at "
            "tip corners, leaves what remains)"
            if planets == 3
            else f"with {planets} planets the forces on a free sun do not fix the shares by "
            "statics alone"
        )
        out.append(
            f"Floating sun: K_gamma {fl[0]:.4f} to {fl[1]:.4f} over the errors "
            f"({100 * (fl[1] - fl[0]):.2f} % of the mean load): {why}."
        )
    if sup is not None:
        k = min(r["sun_radial_stiffness"] for r in rows if r.get("sun_radial_stiffness"))
        series = sorted(
            (r for r in rows if r.get("sun_radial_stiffness") == k), key=lambda r: r["error_um"]
        )
        lo, hi = series[0], series[-1]
        out.append(
            f"Supported sun ({k:.3g} N/mm): the sun cannot follow. Pinion 1's share is "
            f"{lo['load_shares'][0]:.4f} at {lo['error_um']:g} um and "
            f"{hi['load_shares'][0]:.4f} at {hi['error_um']:g} um (a pin moved along the "
            "sun's rotation opens both meshes of its pinion, which gives up load to the "
            f"others; moved against it, the pinion takes load), K_gamma {sup[0]:.4f} to "
            f"{sup[1]:.4f}."
        )
    for k_sun, per_key in root_stress_ratios(rows).items():
        far = {q: max(pts, key=lambda p: abs(p[0])) for q, pts in per_key.items() if pts}
        if not far or all(e == 0 for e, _ in far.values()):
            continue
        series = [r for r in rows if r["sun_radial_stiffness"] == k_sun]
        e_far = max((e for e, _ in far.values()), key=abs)
        k0 = next(r["K_gamma"] for r in series if r["error_um"] == 0)
        k_far = next(r["K_gamma"] for r in series if r["error_um"] == e_far)
        keys = [k for r in series for k in (r.get("root_stress_key") or {}).values()]
        read = sorted({_planet(k) for k in keys})
        sun = "floating sun" if k_sun == 0 else f"sun on {k_sun:.3g} N/mm"
        out.append(
            f"Root stress of the most loaded planet (read on pinion {', '.join(read)}), {sun}, "
            f"at {e_far:g} um against none: "
            + ", ".join(f"{q} x{r:.3f}" for q, (_, r) in far.items())
            + f"; K_gamma x{k_far / k0:.3f}."
        )
    if any(r.get("root_stress") for r in rows):
        out.append(
            "The planets sit at different mesh phases, and a tooth's root stress per unit load "
            "changes with the phase (the one-branch scene's positions show by how much), so "
            "compare the root stress within a series, read on one planet, not across series "
            "read on different planets."
        )
    return out

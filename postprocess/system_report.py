"""System-scene report: each case in the one-branch scene and in the system scene side by side.

Reads ``<branch>/<case>/summary.json`` and ``<system>/<case>/summary.json`` for the cases it
is given (whatever has been run) and writes ``<system>/report.md``: the pinion moments, load
centroids and LOA moments of both scenes, what the system adds (load shares, K_gamma, the
sun's float, the carrier's wind-up, the torque balance), the comparison of the case pair that
separates gear stiffness from bearing stiffness (1-GB-R against 1-GC in the paper), and the
loaded-scene pictures. Numbers come from the summaries alone, inputs included.
"""

from __future__ import annotations

import json
from pathlib import Path

QUANTITIES = ("My_pin", "Mx_pin", "ZS", "ZR", "M_LOA_sun", "M_LOA_ring")
UNITS = {"ZS": "mm", "ZR": "mm"}


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
    return f"{v:+.2f}" if q in ("ZS", "ZR") else f"{v:.1f}"


def _inputs(s: dict) -> str:
    inp = s["inputs"]["study_case"]
    b, m = inp["bearing"], inp["material"]
    return (f"bearing radial {b['radial_stiffness']:.3g} N/mm, tilt {b['tilting_stiffness']:.3g} "
            f"N mm/rad; gears E x {m['gear_modulus_factor']:g}")  # fmt: skip


def write_system_report(branch_dir: Path, system_dir: Path, cases: list[str],
                        pair: tuple[str, str] | None = None) -> Path:  # fmt: skip
    """Write ``system_dir/report.md``. ``pair``: (gears stiffer, bearing softer) cases whose
    difference the system scene must show (the paper's 1-GB-R and 1-GC)."""
    branch, system = _load(branch_dir, cases), _load(system_dir, cases)
    if not system:
        raise FileNotFoundError(f"no system-scene summary under {system_dir}")
    lines = [
        "# The system scene: every pinion on the elastic carrier",
        "",
        "Each case in the one-branch scene (one pinion on a rigid pin, sun held, sectors of sun",
        "and ring) and in the system scene (sun floating radially, all pinions at the nearest",
        "assemblable angles, full ring held at its rim, the steel carrier with one pin per",
        "pinion held at the hub of its -z plate; the gears' modulus factor does not apply to",
        "the carrier). Means over the mesh positions, pinion frame of singh2007 section 3;",
        "system values are the means over the pinions. Moments N m, offsets mm.",
        "",
        "| case | inputs | scene | level | " + " | ".join(QUANTITIES) + " |",
        "|---|---|---|---|" + "---|" * len(QUANTITIES),
    ]
    for name in system:
        for label, runs in (("branch", branch), ("system", system)):
            r = runs.get(name)
            if r is None:
                continue
            vals = " | ".join(_fmt(q, r.get(q)) for q in QUANTITIES)
            lines.append(f"| {name} | {_inputs(r)} | {label} | {r['level']} | {vals} |")
    lines += ["", "## What the system adds", "",
              "| case | K_gamma | load shares (pinion: angle deg, share) | sun centre (um) |"
              " carrier wind-up (urad) | torque balance (rel.) |",
              "|---|---|---|---|---|---|"]  # fmt: skip
    for name, s in system.items():
        shares = ", ".join(f"{p['angle_deg']:.3f}: {p['load_share']:.4f}" for p in s["pinions"])
        sc = s.get("sun_centre_displacement_mm", [0.0, 0.0])
        lines.append(
            f"| {name} | {s['K_gamma']:.4f} | {shares} | ({sc[0] * 1e3:+.2f}, "
            f"{sc[1] * 1e3:+.2f}) | {s.get('carrier_windup_rad', 0.0) * 1e6:.0f} | "
            f"{s.get('torque_balance_rel', float('nan')):.1e} |"
        )
    lines += [
        "",
        "Load sharing: with a floating sun the three sun-mesh forces balance the sun, so the",
        "unequal spacing the assembly condition forces (Zs + Zr = 121 is not divisible by 3)",
        "gives the pinion at 0 deg a share of 3 (-2 cos 119.008 deg) / (2 - 2 cos 119.008 deg)",
        "= 0.980 whatever the stiffness, as long as only the drive flanks carry load: a",
        "property of the set, not of the model. Where coast flanks close (the summary's",
        "`coast`), their forces act on the sun too and the shares move.",
    ]
    if pair and all(n in system for n in pair):
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
        lines += ["", f"## Load sharing under a pin-hole error ({res['case']}, level "
                  f"{res['level']}, one position)", "",
                  f"The pin of pinion 1 displaced {res['direction']}ly in the carrier "
                  "(`python -m studies.pin_errors`; the other pins exact):", "",
                  "| sun support (N/mm) | error (um) | K_gamma | load shares |",
                  "|---|---|---|---|"]  # fmt: skip
        for r in res["rows"]:
            shares = ", ".join(f"{s:.4f}" for s in r["load_shares"])
            k = r.get("sun_radial_stiffness", 0.0)
            sun = "floating" if k == 0 else f"{k:.3g}"
            lines.append(f"| {sun} | {r['error_um']:g} | {r['K_gamma']:.4f} | {shares} |")
        lines += ["", "A floating sun balanced by three mesh forces shares the load by statics "
                  "alone: a pin error moves the sun, not the shares. A radially supported sun "
                  "cannot follow, and the error loads its pinion."]  # fmt: skip
        lines += ["", "![K_gamma against the pin-hole error](pin_errors.png)"]
    lines += ["", "## Pictures", ""]
    for name in system:
        lines.append(f"- {name}: ![{name} loaded system]({name}/loaded_scene.png)")
    path = system_dir / "report.md"
    system_dir.mkdir(parents=True, exist_ok=True)
    path.write_text("\n".join(lines) + "\n")
    return path

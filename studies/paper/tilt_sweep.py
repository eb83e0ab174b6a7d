"""The case-1 report's section on the bearing's tilting stiffness: 1-GB's moments and load
centroids over a sweep of it (``make case1-sweep``: :mod:`studies.sweep`), each moment beside
its closed form at the FE's own centroids (singh2007 Table 7, the paper's Tables 8-9 at the
centroids the FE finds instead of +-7.25 mm)."""

from __future__ import annotations

import os
from pathlib import Path

from studies.files import read_json
from studies.sweep import CLOSED_FORM, sweep_folder

#: the sweep the section reads: case and field (``make case1-sweep``)
SWEEP = ("1-GB", "bearing.tilting_stiffness")
MOMENTS = ("Mx_pin", "My_pin", "M_LOA_sun", "M_LOA_ring")


def _pair(q: dict, k: str) -> str:
    fe, cf = q.get(k), q.get(k + CLOSED_FORM)
    if fe is None or cf is None:
        return "-"
    diff = f"{(fe - cf) / abs(cf):+.0%}" if cf else "-"
    return f"{fe:.1f} / {cf:.1f} ({diff})"


def sweep_section(results: Path, report_dir: Path) -> list[str]:
    """Markdown lines of the section: a row per swept value (ZS, ZR, and per moment the FE /
    the closed form (FE against it)), the sweep's plot, the sizes it ran at; a line saying how
    to make it where the sweep has not been run."""
    folder = sweep_folder(results, *SWEEP)
    head = ["## Moments against the bearing's tilting stiffness", ""]
    if not (folder / "sweep.json").exists():
        return [*head, f"Not run here: `make case1-sweep` sweeps {SWEEP[0]}'s {SWEEP[1]}."]
    rec = read_json(folder / "sweep.json")
    done = [r for r in rec["variants"] if r["quantities"] is not None]
    lines = [
        *head,
        f"{SWEEP[0]} with its {SWEEP[1]} swept (the radial stiffness kept), means over the "
        "positions. Each moment (N m) is given as FE / closed form at the FE's own ZS, ZR "
        "(singh2007 Table 7): the difference is the share of the moment that the axial shift "
        "of the load centroids does not explain (the closed form puts each mesh force on its "
        "pitch cylinder at its centroid's Z).",
        "",
        "| tilting stiffness (N mm/rad) | ZS (mm) | ZR (mm) | " + " | ".join(MOMENTS) + " |",
        "|---" * (3 + len(MOMENTS)) + "|",
    ]
    for r in done:
        q = r["quantities"]
        lines.append(
            f"| {r['label']} | {q['ZS']:+.2f} | {q['ZR']:+.2f} | "
            + " | ".join(_pair(q, k) for k in MOMENTS)
            + " |"
        )
    runs = sorted({f"{r['run']['sizes']}, {r['run']['positions']} position(s)" for r in done})
    missing = [r["label"] for r in rec["variants"] if r["quantities"] is None]
    lines += ["", f"Run: {'; '.join(runs)}."]
    if missing:
        lines.append(f"No results for {', '.join(missing)} (see the sweep's own table).")
    rel = os.path.relpath(folder, report_dir)
    lines += ["", f"![sweep]({rel}/sweep.png)", ""]
    lines.append(f"The sweep's own table: [sweep.md]({rel}/sweep.md).")
    return lines


__all__ = ["SWEEP", "sweep_section"]

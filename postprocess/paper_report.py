"""The whole study on one page: ``results/report.md``.

    python -m studies.paper_report --results results [--started results/bench/.make_start]

Reads only what the study wrote under ``results``: the analytic study (``analytic/
tables.json``, ``report.md``, figures), every case report (``*/report.md``), every case
summary (``*/summary.json`` and ``*/*/summary.json``: the one-branch cases and those of a
system-scene folder), the benchmarks (``bench/*.json``), the convergence studies
(``convergence/*/convergence.json``) and the wall time of the last full
``make`` (``bench/make_all.json``, :func:`record_wall_time`). It links every case report
and picture, gives one row per case with its headline numbers (so a case file of one's own,
run with ``make study``, has its section too), checks the paper's stated trends on the
numbers of the paper's own study cases only (:mod:`postprocess.paper_cases`), and shows the
speed-against-error table of the benchmark. No case is named here: cases are told apart by
what their summaries hold (gear-set kind, bearing, scene).
"""

from __future__ import annotations

import itertools
import json
import os
import platform
import time
from pathlib import Path

from gears.analytic import printed
from postprocess.failed_positions import failed_positions_lines
from postprocess.paper_cases import paper_case_difference
from postprocess.plus_minus import plus_minus
from postprocess.run_scalars import level_text, row_label
from postprocess.stress_tables import reported_root_stress

#: the goal of issue 12 for the whole ``make`` on 2 cores at the default level
GOAL_WALL_S = 20 * 60.0
PICTURES = ("contact_patterns.png", "flank_patterns.png", "loaded_scene.png")
SINGLE = ("My_pin", "Mx_pin", "M_LOA_sun", "M_LOA_ring")
DOUBLE = ("M_LOA_sun_SP", "M_LOA_SP_RP", "M_LOA_RP_SP", "M_LOA_RP_ring", "M_LOA_SPRP_diff")


# --------------------------------------------------------------------------- wall time


def record_wall_time(results: Path, started: Path) -> dict | None:
    """Turn the start stamp ``started`` (seconds since the epoch, written by ``make`` as its
    first step) into ``<results>/bench/make_all.json`` (start, end, wall time, machine, the
    level of every case run) and remove the stamp, so a later report alone does not time
    itself. Returns the record, or None if there is no stamp."""
    if not started.is_file():
        return None
    t0 = float(started.read_text().split()[0])
    t1 = time.time()
    summaries = [s for _, s in _summaries(results)]
    levels = sorted({s["level"] for s in summaries})
    runs = sorted({row_label(s) for s in summaries if "degree" in s})  # with their sizes
    rec = {
        "what": "wall time of the whole `make` (target all): setup, analytic study, meshes, "
        "case 1, case 2 and this report",
        "started": time.strftime("%Y-%m-%d %H:%M:%S %Z", time.localtime(t0)),
        "finished": time.strftime("%Y-%m-%d %H:%M:%S %Z", time.localtime(t1)),
        "wall_s": t1 - t0,
        "goal_s": GOAL_WALL_S,
        "within_goal": t1 - t0 <= GOAL_WALL_S,
        "levels": levels,
        "runs": runs,
        "machine": {
            "cpus": os.cpu_count(),
            "load_average_1_5_15": list(os.getloadavg()),
            "platform": platform.platform(),
        },
    }
    bench = results / "bench"
    bench.mkdir(parents=True, exist_ok=True)
    (bench / "make_all.json").write_text(json.dumps(rec, indent=1) + "\n")
    started.unlink()
    return rec


# --------------------------------------------------------------------------- reading


def _json(path: Path) -> dict | None:
    try:
        return json.loads(path.read_text()) if path.is_file() else None
    except (OSError, ValueError):
        return None


def _summaries(results: Path) -> list[tuple[Path, dict]]:
    """(folder, summary) of every case under ``results`` (one and two levels deep)."""
    return _read_summaries(results)[0]


def _read_summaries(results: Path) -> tuple[list[tuple[Path, dict]], list[str]]:
    """(folder, summary) of every case under ``results`` (one and two levels deep), and a
    line per case folder left out: a ``summary.json`` that cannot be read or is not a case
    summary, and a folder of solved positions without one (a run that was interrupted or
    whose every position failed; ``positions/`` keeps what it finished)."""
    found, missed = [], []
    for path in sorted([*results.glob("*/summary.json"), *results.glob("*/*/summary.json")]):
        s = _json(path)
        rel = path.relative_to(results)
        if s and isinstance(s, dict) and "inputs" in s and "positions" in s:
            found.append((path.parent, s))
        elif s is None:
            missed.append(f"`{rel}`: cannot be read (not JSON, or cut short)")
        else:
            missed.append(f"`{rel}`: not a case summary (no inputs or positions)")
    for pos in sorted([*results.glob("*/positions"), *results.glob("*/*/positions")]):
        if pos.is_dir() and not (pos.parent / "summary.json").exists():
            n = len(list(pos.glob("*.json")))
            missed.append(
                f"`{pos.parent.relative_to(results)}/`: {n} solved position file(s) and no "
                "summary.json (the run was interrupted or every position failed; run it again "
                "to reuse them)"
            )
    return found, missed


def _link(target: Path, results: Path, text: str | None = None) -> str:
    rel = Path(os.path.relpath(target, results)).as_posix()
    return f"[{text or rel}]({rel})"


def _image(target: Path, results: Path, alt: str) -> str:
    return f"![{alt}]({Path(os.path.relpath(target, results)).as_posix()})"


def _bearing(s: dict) -> dict:
    return s["inputs"]["study_case"]["bearing"]


def _tilt(s: dict) -> float:
    return _bearing(s)["tilting_stiffness"]


def _max(values) -> float | None:
    vals = [v for v in values if v is not None]
    return max(vals) if vals else None


# --------------------------------------------------------------------------- sections


def _wall_section(results: Path) -> list[str]:
    rec = _json(results / "bench" / "make_all.json")
    if rec is None:
        return ["Wall time of `make`: not measured yet (it is recorded by a full `make`).", ""]
    mins = rec["wall_s"] / 60.0
    verdict = (
        "within the 20-minute goal"
        if rec["within_goal"]
        else f"OVER the {rec['goal_s'] / 60:.0f}-minute goal"
    )
    load = rec["machine"]["load_average_1_5_15"]
    return [
        f"Wall time of the last full `make` ({rec['started']} -> {rec['finished']}): "
        f"**{mins:.1f} min**, {verdict}, on {rec['machine']['cpus']} cores at mesh level(s) "
        f"{', '.join(str(v) for v in rec['levels'])}"
        + (f" (runs {', '.join(rec['runs'])})" if rec.get("runs") else "")
        + "; load average at the end "
        f"{load[0]:.1f} / {load[1]:.1f} / {load[2]:.1f} (1 / 5 / 15 min; other jobs on the "
        "machine count in it). Recorded in `bench/make_all.json`.",
        "",
    ]


def _analytic_section(results: Path) -> list[str]:
    folder = results / "analytic"
    t = _json(folder / "tables.json")
    lines = ["## The closed-form model (singh2007 sections 2-6, pust2016, parker2000)", ""]
    if t is None:
        return [*lines, "Not run yet (`make analytic`).", ""]
    s, b = t["single"], t["double"]["2-B"]
    p3, p5 = printed.SINGH_TABLE3, printed.SINGH_TABLE5["2-B"]
    lines += [
        f"{_link(folder / 'report.md', results, 'analytic/report.md')}: every printed number "
        "beside the value computed from the gear data, with the cause of each difference. "
        f"Table 3: My-PIN {s['My_pin']:.1f} (printed {p3['My_pin']:g}), M_LOA sun / ring "
        f"{s['M_LOA_sun']:.1f} / {s['M_LOA_ring']:.1f} (printed {p3['M_LOA_sun']:g} / "
        f"{p3['M_LOA_ring']:g}) N m. Table 5, 2-B: the four LOA moments "
        f"{b['M_LOA_SP_SUN']:.1f}, {b['M_LOA_SP_RP']:.1f}, {b['M_LOA_RP_SP']:.1f}, "
        f"{b['M_LOA_RP_RING']:.1f} (printed {p5['M_LOA_SP_SUN']}, {p5['M_LOA_SP_RP']}, "
        f"{p5['M_LOA_RP_SP']}, {p5['M_LOA_RP_RING']}) N m.",
        "",
    ]
    for pic, alt in (("fig6_misalignment.png", "Fig. 6"), ("pust_stability.png", "pust2016")):
        if (folder / pic).is_file():
            lines += [_image(folder / pic, results, alt), ""]
    return lines


def _reports_section(results: Path) -> list[str]:
    reports = sorted(p for p in results.glob("*/report.md") if p.parent.name != "analytic")
    lines = ["## Case reports", ""]
    if not reports:
        return [*lines, "None yet.", ""]
    for rep in reports:
        pics = sorted(p for p in rep.parent.glob("*.png"))
        extra = ", ".join(_link(p, results, p.name) for p in pics)
        lines.append(
            f"- {_link(rep, results)}: {_title(rep)}" + (f" (pictures: {extra})" if extra else "")
        )
    lines.append("")
    for rep in reports:
        for pic in sorted(rep.parent.glob("*.png"))[:2]:
            lines += [_image(pic, results, f"{rep.parent.name}: {pic.stem}"), ""]
    return lines


def _title(report: Path) -> str:
    for line in report.read_text().splitlines():
        if line.startswith("# "):
            return line[2:].strip()
    return report.parent.name


def _cases_section(results: Path, runs: list[tuple[Path, dict]]) -> list[str]:
    lines = [
        "## Every case run",
        "",
        "One row per `summary.json` under `results/`: means over the mesh positions; moments N m",
        "(pinion frames of singh2007), offsets mm from mid face width, stresses MPa (contact:",
        "largest interior contact stress over the mesh cycle, the solved cell pressure on a",
        "zone grid and Hertz at the line load on a line grid, growing as the square root of",
        "the gears' modulus; root: largest FE fillet surface stress over the mesh cycle, the",
        "recovered reading (`solvers/surface_recovery.py`, what the convergence studies",
        "target), the nodal maximum marked `n` for a summary without it). level: the run's",
        "sizes (`1 (level-2 flanks and fillets)`: the case files' `flank_level` /",
        "`fillet_level`). ±: the discretisation uncertainty of that run from the convergence",
        "study of its gear set (`make convergence`; see Convergence below); none where no",
        "study matches.",
        "",
    ]
    single = [(f, s) for f, s in runs if s["inputs"]["gearset"]["kind"] == "single_pinion"]
    double = [(f, s) for f, s in runs if s["inputs"]["gearset"]["kind"] == "double_pinion"]
    if single:
        lines += [
            "Single pinion (ZS, ZR: sun and ring mesh centroids):",
            "",
            "| case | folder | scene | tilt (N mm/rad) | gears E x | level | pos. | DOFs | "
            + " | ".join(SINGLE)
            + " | ZS | ZR | contact | root | pictures |",
            "|---|---|---|---|---|---|---|---|" + "---|" * (len(SINGLE) + 5),
        ]
        lines += [_row(f, s, SINGLE, ("ZS", "ZR"), results) for f, s in single]
        lines.append("")
    if double:
        lines += [
            "Double pinion (ZS, Z_SPRP, ZR: sun-SP, SP-RP and RP-ring mesh centroids;",
            "M_LOA_SPRP_diff = M_LOA_SP_RP + M_LOA_RP_SP):",
            "",
            "| case | folder | scene | tilt (N mm/rad) | gears E x | level | pos. | DOFs | "
            + " | ".join(DOUBLE)
            + " | ZS | Z_SPRP | ZR | contact | root | pictures |",
            "|---|---|---|---|---|---|---|---|" + "---|" * (len(DOUBLE) + 6),
        ]
        lines += [_row(f, s, DOUBLE, ("ZS", "Z_SPRP", "ZR"), results) for f, s in double]
        lines.append("")
    if not runs:
        lines += ["None yet.", ""]
    lines += failed_positions_lines({f"{s['case']} ({f.name})": s for f, s in runs})
    missed = _read_summaries(results)[1]
    if missed:
        lines += ["**Case folders not in this report:**", ""]
        lines += [f"- {m}" for m in missed] + [""]
    return lines


def _row(folder: Path, s: dict, moments, offsets, results: Path) -> str:
    cyc = s.get("contact_stress_cycle") or {}
    contact = _max(c.get("interior_p_max_MPa") for c in cyc.values())
    # the recovered root stress where the summary has it (the convergence studies' target)
    r_name, r_vals = reported_root_stress(s)
    root = _max(r_vals.values())
    # the keys of the two maxima, for their uncertainty
    c_key = next(
        (
            f"contact_stress_cycle.{m}.interior_p_max_MPa"
            for m, c in cyc.items()
            if contact and c.get("interior_p_max_MPa") == contact
        ),
        "",
    )
    r_key = next((f"{r_name}.{k}" for k, v in r_vals.items() if root and v == root), "")
    nodal = "" if r_name == "bending_stress_recovered" else " n"
    pics = ", ".join(
        _link(folder / p, results, p.removesuffix(".png").split("_")[0])
        for p in PICTURES
        if (folder / p).is_file()
    )
    cells = [
        s["case"],
        _link(folder, results, Path(os.path.relpath(folder, results)).as_posix()),
        s.get("scene", "-"),
        f"{_tilt(s):.3g}",
        f"{s['inputs']['study_case']['material']['gear_modulus_factor']:g}",
        level_text(s),
        str(len(s["positions"])),
        str(s.get("dofs", "-")),
        *(f"{s[k]:.1f}{plus_minus(s, k)}" if k in s else "-" for k in moments),
        *(f"{s[k]:+.2f}{plus_minus(s, k, '.2f')}" if k in s else "-" for k in offsets),
        f"{contact:.0f}{plus_minus(s, c_key, '.0f')}" if contact else "-",
        f"{root:.0f}{plus_minus(s, r_key, '.0f')}{nodal}" if root else "-",
        pics or "-",
    ]
    return "| " + " | ".join(cells) + " |"


def _trends_section(results: Path, runs: list[tuple[Path, dict]]) -> list[str]:
    """The paper's stated trends, checked on the one-branch runs of each gear-set kind of
    the paper's own study cases (:func:`postprocess.paper_cases.paper_case_difference`);
    the one-branch runs left out are named with the reason."""
    lines = ["## The paper's conclusions, checked on our numbers", ""]
    branch, others = [], []
    for folder, s in runs:
        if s.get("scene") != "one_branch":
            continue
        why = paper_case_difference(s)
        if why is None:
            branch.append(s)
        else:
            others.append(f"`{s.get('case')}` in `{folder.relative_to(results)}/` ({why})")
    single = sorted(
        (
            s
            for s in branch
            if s["inputs"]["gearset"]["kind"] == "single_pinion"
            and s["inputs"]["study_case"]["material"]["gear_modulus_factor"] == 1.0
        ),
        key=lambda s: -_tilt(s),
    )
    double = sorted(
        (s for s in branch if s["inputs"]["gearset"]["kind"] == "double_pinion"),
        key=lambda s: -_tilt(s),
    )
    if len(single) >= 2:
        a, b = single[0], single[-1]
        ok = all(
            x["ZS"] > y["ZS"] and x["ZR"] < y["ZR"] and x["My_pin"] > y["My_pin"]
            for x, y in itertools.pairwise(single)
        )
        lines.append(
            "- Softer bearings push the sun-mesh load to -Z and the ring-mesh load to +Z and "
            "lower My-PIN (single pinion, steel): ZS "
            + " -> ".join(f"{s['ZS']:+.2f}" for s in single)
            + ", ZR "
            + " -> ".join(f"{s['ZR']:+.2f}" for s in single)
            + " mm, My_pin "
            + " -> ".join(f"{s['My_pin']:.1f}" for s in single)
            + f" N m ({a['case']} -> {b['case']}): {'yes' if ok else 'NO'}."
        )
        at = a["analytic"].get("at_fe_ZS_ZR", {})
        if at:
            lines.append(
                f"- The stiffest bearing run ({a['case']}: {a.get('description', '')}) against "
                f"the closed form: My_pin "
                f"{a['My_pin']:.1f} against {at['My_pin']:.1f} N m at its own ZS, ZR "
                f"({100 * (a['My_pin'] / at['My_pin'] - 1):+.1f} %)."
            )
    if double:
        a, b = double[0], double[-1]
        t5, at = a["analytic"]["table5"], a["analytic"]["at_fe_centroids"]
        lines.append(
            f"- Double pinion, the stiffest bearing run ({a['case']}: "
            f"{a.get('description', '')}): LOA moments "
            + ", ".join(f"{a[k]:.1f}" for k in DOUBLE[:4])
            + " against the closed form at the FE's own load centroids "
            + ", ".join(f"{at[k]:.1f}" for k in DOUBLE[:4])
            + " and Table 5 "
            + ", ".join(f"{t5[k]:.1f}" for k in DOUBLE[:4])
            + " N m."
        )
        if len(double) >= 2:
            ok = abs(b["Z_SPRP"]) < 0.3 * min(abs(b["ZS"]), abs(b["ZR"]))
            lines.append(
                f"- The SP-RP mesh stays nearly centred while the others move ({b['case']}): "
                f"Z_SPRP {b['Z_SPRP']:+.2f} mm against ZS {b['ZS']:+.2f}, ZR {b['ZR']:+.2f} "
                f"mm: {'yes' if ok else 'NO'}. Its LOA differential is {b['M_LOA_SPRP_diff']:.1f} "
                f"N m ({a['case']}: {a['M_LOA_SPRP_diff']:.1f}) against Table 5's "
                f"{t5['M_LOA_SPRP_diff']:.1f}: the case-2 report splits it over the load "
                "centroids (a concentrated-load idealisation, not an error)."
            )
        for d in double:
            match = [s for s in single if _bearing(s) == _bearing(d)]
            if match and max(abs(match[0]["ZS"]), abs(match[0]["ZR"])) > 1.0:
                s = match[0]
                ok = abs(d["ZS"]) > abs(s["ZS"]) and abs(d["ZR"]) > abs(s["ZR"])
                lines.append(
                    f"- The sun-SP and RP-ring patterns move further off centre than in the "
                    f"single pinion with the same bearing ({d['case']} against {s['case']}): "
                    f"|ZS| {abs(s['ZS']):.2f} -> {abs(d['ZS']):.2f}, |ZR| {abs(s['ZR']):.2f} -> "
                    f"{abs(d['ZR']):.2f} mm: {'yes' if ok else 'NO'}."
                )
    if len(lines) == 2:
        lines.append("No one-branch run of the paper's study cases yet.")
    if others:
        lines += [
            "",
            "Not the paper's cases, so left out of these checks: " + "; ".join(others) + ".",
        ]
    return [*lines, ""]


def _convergence_lines(results: Path, runs: list[tuple[Path, dict]]) -> list[str]:
    """One line per convergence study: first those the summaries ``runs`` take their ± from
    (``uncertainty_source.convergence_study``: a record in the repository, or a study of
    this machine), then the others under ``results/convergence``, each with its
    recommendation and a link to its report and chart. The summaries' studies come first so
    a study left in the results by an earlier make does not speak for them."""
    used: dict[Path, list[str]] = {}
    for _, s in runs:
        src = (s.get("uncertainty_source") or {}).get("convergence_study")
        if src and s.get("uncertainty"):
            used.setdefault(Path(src).resolve(), []).append(s["case"])
    local = [p.resolve() for p in sorted((results / "convergence").glob("*/convergence.json"))]
    lines = []
    for path in [*used, *(p for p in local if p not in used)]:
        c = _json(path)
        if not c or "recommendation" not in c:
            continue
        labels = ", ".join(c.get("labels", [])) or "none finished"
        kind = " (recorded)" if c.get("recorded") else ""
        whose = (
            f"the ± of {', '.join(used[path])}"
            if path in used
            else "no summary here takes its ± from it"
        )
        lines += [
            f"Convergence{kind}, {_link(path.parent / 'report.md', results, c['case'])} (runs "
            f"{labels}; {c.get('positions', '?')} position; {whose}): "
            f"{c['recommendation']['note']}.",
            "",
        ]
        png = path.parent / "speed_error.png"
        if png.is_file():
            lines += [_image(png, results, f"{c['case']} speed against error"), ""]
    return lines


def _bench_section(results: Path, runs: list[tuple[Path, dict]]) -> list[str]:
    bench = results / "bench"
    lines = ["## Speed against error", ""]
    lines += _convergence_lines(results, runs)
    rows_found = (results / "convergence").is_dir()
    study = _json(bench / "study.json")
    if study:
        rows_found = True
        lines += [
            f"{_link(bench / 'study.json', results)}: body reuse speeds a level-"
            f"{study['level']} study up {study['speedup_reuse']:.1f}x "
            f"({study['wall_s_no_reuse']:.0f} -> {study['wall_s_reuse']:.0f} s); one "
            f"system-scene position on 2 MPI ranks {study['mpi2_speedup']:.2f}x.",
            "",
        ]
    others = [p for p in (bench / "solver.md", bench / "meshing.json") if p.is_file()]
    if others:
        rows_found = True
        lines += ["Also: " + ", ".join(_link(p, results) for p in others) + ".", ""]
    if not rows_found:
        lines += ["No benchmark run yet (`make bench-case1`, `make bench-study`).", ""]
    return lines


def write_paper_report(results: Path) -> Path:
    """Write ``<results>/report.md`` from what is under ``results`` (see the module doc)."""
    results = Path(results)
    results.mkdir(parents=True, exist_ok=True)
    runs = _summaries(results)
    lines = [
        "# Planetary needle-bearing tilt (singh2007): the whole study on one page",
        "",
        "A. Singh, *Influence of planetary needle bearings on the performance of single and "
        "double pinion planetary systems*, ASME J. Mech. Des. 129 (2007) 85-94, reproduced "
        "with an open finite element pipeline (FEniCSx). Each section links the report that "
        "holds the full tables; every number here is read from the results below this folder.",
        "",
    ]
    lines += _wall_section(results)
    lines += _analytic_section(results)
    lines += _trends_section(results, runs)
    lines += _reports_section(results)
    lines += _cases_section(results, runs)
    lines += _bench_section(results, runs)
    path = results / "report.md"
    path.write_text("\n".join(lines) + "\n")
    return path

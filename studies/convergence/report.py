"""``report.md`` and ``speed_error.png`` of a convergence study (``convergence.json`` as
written by ``studies.convergence.driver``): the runs and their cost, per scalar the values, status,
observed order and extrapolated value, the error and the GCI uncertainty of every run, the
recommended level, and the speed-against-error chart (wall time and peak memory of each
run against its worst error relative to the extrapolated value, moments and stresses)."""

from __future__ import annotations

import math
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
from matplotlib.ticker import FormatStrFormatter, FuncFormatter, NullFormatter, PercentFormatter

from postprocess.convergence_record import SAFETY_TWO_GRID, reproduction_text
from postprocess.run_scalars import VARIANT_WORDS, row_label, sizes_in_words, variant
from studies.convergence.reduction import CG_NOISE, P_CAP
from studies.convergence.richardson import NEAR_ZERO

CHART = "speed_error.png"


def _pct(x) -> str:
    return "-" if x is None else f"{100 * x:+.2f} %"


def _upct(x) -> str:
    return "-" if x is None else f"{100 * x:.2f} %"


def _num(x, unit: str) -> str:
    if x is None:
        return "-"
    return f"{x:.1f}" if unit == "MPa" else f"{x:.4g}"


def _labels(conv: dict) -> list[str]:
    return [r["label"] for r in conv["runs"] if "error" not in r]


def _out_of_core(conv: dict) -> set[str]:
    """The labels of the runs solved with their LU factors on disk (``numerics.out_of_core``:
    the same answer, another time and memory)."""
    return {r["label"] for r in conv["runs"] if (r.get("numerics") or {}).get("out_of_core")}


def _memory(conv: dict, label: str, mb: float) -> str:
    """A run's peak memory (GB), marked when its factors were on disk."""
    return f"{mb / 1024:.1f}" + (" (factors on disk)" if label in _out_of_core(conv) else "")


def _level(r: dict) -> str:
    """A run's level, and which of its sizes are another level's."""
    other = "; ".join(f"{VARIANT_WORDS[k]} of {v}" for k, v in variant(r).items())
    return f"{r['level']}" + (f" ({other})" if other else "")


def _in_words(r: dict) -> str:
    return f"{sizes_in_words(r['level'], variant(r))}, degree {r['degree']}"


def _runs_table(conv: dict) -> list[str]:
    lines = [
        "| run | level | degree | DOFs | grid points | total (s) | scene, meshes (s) | bodies (s)"
        " | of which factorization (s) | compliance (s) | peak memory (GB) | process (s) | "
        "reused |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in conv["runs"]:
        if "error" in r:
            lines.append(f"| {r['label']} | {_level(r)} | {r['degree']} | failed: {r['error']} |")
            continue
        t = r["time_s"]
        lines.append(
            f"| {r['label']} | {_level(r)} | {r['degree']} | {r['dofs']} | "
            f"{r['grid_points_total']} | {t['total']:.1f} | {t.get('scene_meshes', 0):.1f} | "
            f"{t.get('bodies', 0):.1f} | {t['factorization']:.1f} | {t['compliance']:.1f} | "
            f"{_memory(conv, r['label'], r['peak_rss_mb'])} | "
            f"{r.get('process_wall_s', float('nan')):.0f} | "
            f"{'yes' if r.get('reused') else 'no'} |"
        )
    for s in conv.get("skipped", []):
        lines.append(f"| {s['label']} | {_level(s)} | {s['degree']} | skipped: {s['why']} |")
    return lines


def _scalar_rows(conv: dict, targeted: bool) -> list[tuple[str, dict]]:
    rows = [(k, e) for k, e in conv["scalars"].items() if e.get("status") != "mesh-independent"]
    return [(k, e) for k, e in rows if (e.get("target") is not None) == targeted]


def _values_table(conv: dict, rows, labels) -> list[str]:
    lines = [
        "| scalar | unit | target | " + " | ".join(labels) + " | extrapolated | status | order |",
        "|---|---|---|" + "---|" * len(labels) + "---|---|---|",
    ]
    for key, e in rows:
        vals = " | ".join(_num(e["values"].get(lab), e["unit"]) for lab in labels)
        tgt = "-" if e.get("target") is None else f"{e['target']:.0%}"
        p = "-" if e.get("order") is None else f"{e['order']:.2f}"
        lines.append(
            f"| {key} | {e['unit']} | {tgt} | {vals} | "
            f"{_num(e.get('extrapolated'), e['unit'])} | {e['status']} | {p} |"
        )
    return lines


def _errors_table(conv: dict, rows, labels) -> list[str]:
    lines = [
        "| scalar | "
        + " | ".join(f"error {lab}" for lab in labels)
        + " | "
        + " | ".join(f"U {lab}" for lab in labels)
        + " |",
        "|---|" + "---|" * (2 * len(labels)),
    ]
    for key, e in rows:
        err = " | ".join(_pct((e.get("rel_error") or {}).get(lab)) for lab in labels)
        unc = " | ".join(_upct((e.get("uncertainty") or {}).get(lab)) for lab in labels)
        lines.append(f"| {key} | {err} | {unc} |")
    return lines


def _root_targets(reading: str | None) -> str:
    """The sentence saying which root-stress reading the targets are (None: a study reduced
    before the recovered readings, whose targets were the nodal ones)."""
    if reading == "recovered":
        return (
            " The root stresses targeted are the recovered fillet readings (`_recovered`: a "
            "moving least-squares fit over the fillet's nodes, `solvers/surface_recovery.py`); "
            "the nodal maxima, the largest of values that scatter from node to node, are checks."
        )
    if reading == "nodal":
        return (
            " The root stresses targeted are the nodal maxima: these runs hold no recovered "
            "reading (solved before 2026-11-30)."
        )
    return ""


def _recommendation(conv: dict) -> list[str]:
    rec = conv["recommendation"]
    lines = ["## Which level", ""]
    lines.append(
        f"Targets (issue 13): moments within {rec['targets']['moment']:.0%}, stresses "
        f"within {rec['targets']['stress']:.0%}, judged on each run's U, the ± the reports "
        "print (the GCI with the capped order, or the bound without an extrapolation; the "
        "SP-RP differential relative to the larger of its two moments). A targeted scalar a "
        "run lacks, or that has no U, fails it." + _root_targets(rec.get("root_stress_targets"))
    )
    lines.append("")
    lines.append("| run | time (s) | memory (GB) | worst moment | worst stress | meets |")
    lines.append("|---|---|---|---|---|---|")
    for v in rec["runs"]:

        def w(kind, v=v):
            d = v["worst"].get(kind)
            if d is None:
                return "-"
            how = "" if d["how"] == "U (GCI)" else f" ({d['how']})"
            return f"{d['key']} {d['error']:.2%}{how}"

        lines.append(
            f"| {v['run']} | {v['time_s']:.1f} | {_memory(conv, v['run'], v['peak_rss_mb'])} | "
            f"{w('moment')} | {w('stress')} | {'yes' if v['meets'] else 'no'} |"
        )
    lines += ["", f"**Recommendation:** {rec['note']}.", ""]
    if conv.get("recommendation_context"):
        lines += [conv["recommendation_context"], ""]
    return lines


def _h_measure(conv: dict) -> list[str]:
    diffs = [
        (k, e["h_measure_difference"])
        for k, e in conv["scalars"].items()
        if e.get("target") is not None and e.get("h_measure_difference") is not None
    ]
    if not diffs:
        return []
    key, worst = max(diffs, key=lambda kv: abs(kv[1]))
    return [
        "Grid size h: the flank element size (fillet size for root stresses). Extrapolating "
        f"with h = N_dof^(-1/3) instead moves the targeted values by at most {abs(worst):.2%} "
        f"({key}); a large number here means the ladder is not yet asymptotic.",
        "",
    ]


def _split_table(conv: dict) -> list[str]:
    """The root stresses whose error is split into driver and submodel
    (:func:`studies.convergence.reduction.root_stress_split`): both ladders."""
    rows = [(k, e["split"]) for k, e in conv["scalars"].items() if e.get("split")]
    if not rows:
        return []
    sp0 = rows[0][1]
    drv_at, sub_at = sp0["driver"]["at"], sp0["submodel"]["at"]
    lines = [
        "## Root stress: driver and submodel",
        "",
        "The root stresses are read on P2 submodels driven by the global solution "
        "(solvers/root_submodel.py), so their error has two sources, studied apart: the "
        f"driver (every level's global solution read on the {sp0['fillet_mm']:g} mm submodel "
        "of the case's level, against the flank size) and the submodel (the case level's "
        "global solution read on its submodel and those of the levels beside it, the whole "
        "sector refined, with read fillets of "
        + " / ".join(f"{f:g}" for f in sub_at)
        + " mm, against the fillet size). Extrapolated = driver limit x submodel limit / "
        "the case level's value; U of a run = the driver's U at its level + the submodel's "
        "at its fillet (a fillet coarser than the ladder's: the step to "
        f"{sp0['fillet_mm']:g} mm at the same driver plus the submodel's U there). Refining "
        "both at once (the columns above) mixes the two, and a coarse level's unresolved "
        "fillet then reads as the default level's error. The submodel's U at each fillet is "
        "at least the sector scatter: the spread of the case level's solution read on "
        "sectors of other sizes at one read fillet (`make sector-sizes`, then "
        "`make sector-scatter`; studies/convergence/scatter.py), which a ladder that refines "
        "every size at once can miss when its values agree by chance; `-`: not measured, "
        "the ladder's U alone.",
        "",
        "| scalar | driver "
        + " | ".join(drv_at)
        + " | status | extrapolated | U "
        + " | ".join(drv_at)
        + " | submodel "
        + " | ".join(f"{f:g} mm" for f in sub_at)
        + " | status | extrapolated | U "
        + " | ".join(f"{f:g} mm" for f in sub_at)
        + " | sector scatter |",
        "|---|" + "---|" * (2 * len(drv_at) + 2 + 2 * len(sub_at) + 3),
    ]
    for k, sp in rows:
        d, s = sp["driver"], sp["submodel"]
        lines.append(
            f"| {k} | "
            + " | ".join(f"{v:.1f}" for v in d["values"])
            + f" | {d['status']} | {_num(d['extrapolated'], 'MPa')} | "
            + " | ".join(_upct(u) for u in d["uncertainty"])
            + " | "
            + " | ".join(f"{v:.1f}" for v in s["values"])
            + f" | {s['status']} | {_num(s['extrapolated'], 'MPa')} | "
            + " | ".join(_upct(u) for u in s["uncertainty"])
            + f" | {_upct(sp.get('sector_floor'))} |"
        )
    targeted = {k for k, e in conv["scalars"].items() if e.get("target") is not None}
    bare = [k for k, sp in rows if sp.get("sector_floor") is None and k in targeted]
    return [*lines, *_scatter_lines(conv, bare), ""]


def _scatter_lines(conv: dict, bare: list[str] = ()) -> list[str]:
    """Where the sector scatter under the root stresses' U was measured, and the targeted
    root stresses ``bare`` of no measurement."""
    entries = conv.get("sector_scatter") or []
    if not entries:
        return [
            "",
            "No sector scatter is kept with this study: the submodel's U is its "
            "ladder's alone, which may be optimistic where the ladder's values agree by "
            "chance.",
        ]
    lines = []
    if bare:
        lines += [
            "",
            "**Targeted without a measured sector scatter** (their submodel U is the "
            "ladder's alone; the measurements below do not hold them): " + ", ".join(bare) + ".",
        ]
    lines += ["", "Sector scatter measured (the largest spread per scalar is the floor):"]
    for e in entries:
        used = (
            ""
            if e.get("level") == conv.get("case_level")
            else (f" (not used: the case level is {conv.get('case_level')})")
        )
        worst = max(e["spread"].items(), key=lambda kv: kv[1], default=None)
        lines.append(
            f"- driver level {e['level']}, roll {e['roll']:g}, read fillet "
            f"{e['fillet_mm']:g} mm, variants {', '.join(e['variants'])}, source "
            f"hash {e['code_hash']}"
            + (f"; largest {worst[0]} {worst[1]:.2%}" if worst else "")
            + used
        )
    return lines


def _runs_code(conv: dict) -> list[str]:
    """A line where the runs were solved by other code than the reduction's (``python -m
    studies.convergence.driver --reduce-only``)."""
    other = [h for h in conv.get("runs_code_hash", []) if h != conv.get("code_hash")]
    if not other:
        return []
    added = conv.get("added") or {}
    if added:  # the ladder's code; the added runs' is in _off_ladder
        mine = sorted(
            {
                r["reuse_key"]["code_hash"]
                for r in conv["runs"]
                if "reuse_key" in r and r.get("label") not in added
            }
        )
        return [
            f"The ladder's runs were solved by code {', '.join(mine)}; the reduction, "
            f"targets and report are code {conv['code_hash']}'s.",
            "",
        ]
    return [
        f"Reduced again (`--reduce-only`) by code {conv['code_hash']} from runs solved by "
        f"code {', '.join(other)}: the runs' values are those of that code; the reduction, "
        "targets and report are this code's.",
        "",
    ]


def _off_ladder(conv: dict) -> list[str]:
    """How the runs off the ladder are judged, and which were added to a record later
    (``python -m studies.convergence CASE --add-to-record L:D:F``) by which code."""
    off = [
        r
        for r in conv["runs"]
        if "error" not in r and (variant(r) or r.get("degree") != conv.get("ladder_degree"))
    ]
    if not off:
        return []
    lines = [
        "Off the ladder: "
        + ", ".join(f"{r['label']} ({_in_words(r)})" for r in off)
        + ". Each is judged against the ladder's extrapolation X: error = (value - X) / |X|, "
        "U = 1.25 |value - X| relative to the value; without an X, the spread of the ladder "
        "and its value. A root stress read on the case level's sector is a point of its "
        "driver ladder: U = 1.25 |value - D_ext| / |value| (the spread of the driver ladder "
        "and its value without a D_ext) plus the sector's U there, as a ladder run's; one read "
        "on another sector: U as above, at least the sector scatter.",
    ]
    added = sorted((conv.get("added") or {}).items())
    for label, a in added:
        commit = str(a.get("git_revision"))[:10]
        lines[0] += (
            f" {label} was added to the record on {a.get('date')} by code "
            f"{a.get('code_hash')} (commit {commit})."
        )
    if added:
        lines[0] += " The ladder's runs keep the code that solved them."
    return [*lines, ""]


def _reproductions(conv: dict) -> list[str]:
    """The record's runs solved again by later code (``python -m studies.convergence CASE
    --reproduce L``), one line each."""
    again = conv.get("reproduced") or []
    if not again:
        return []
    lines = ["Solved again by later code (`--reproduce`):", ""]
    for e in again:
        lines.append(f"- {reproduction_text(e)}; commit {str(e.get('git_revision'))[:10]}")
    return [*lines, ""]


def _missing_scalars(conv: dict) -> list[str]:
    """The scalars some finished ladder runs hold and others do not (a stress read that
    failed, a grid without contact; 2B-GA's record: the ring's near-load value, not a target,
    absent at level 2): the study has no ± for them, and a targeted one fails the verdict of
    the run that lacks it (:func:`studies.convergence.reduction.recommend`)."""
    ladder = [
        r
        for r in conv["runs"]
        if "error" not in r and r.get("degree") == conv.get("ladder_degree") and not variant(r)
    ]
    have = {row_label(r): set(r.get("scalars") or {}) for r in ladder}
    every = set().union(*have.values()) if have else set()
    missing = {k: [lab for lab, keys in have.items() if k not in keys] for k in sorted(every)}
    missing = {k: labs for k, labs in missing.items() if labs}
    if not missing:
        return []
    lines = ["## Scalars missing from a ladder run (no ±; a targeted one fails that run)", ""]
    lines += [f"- {k}: not in {', '.join(labs)}" for k, labs in missing.items()]
    return [*lines, ""]


def write_report(conv: dict, folder: Path) -> Path:
    """Write ``report.md`` and the chart into ``folder``; returns the report path."""
    folder = Path(folder)
    labels = _labels(conv)
    m = conv["match"]
    lines = [
        f"# Convergence study: {conv['case']} (gear set {m['gearset']}, {m['scene']} scene)",
        "",
        f"{conv['positions_note']} Each run is one child process (wall time and peak memory of "
        "that run alone). Ladder: the three finest h-levels at degree "
        f"{conv['ladder_degree']}; Richardson extrapolation with the observed order over "
        "non-constant refinement ratios, GCI with factor of safety 1.25 and the order capped "
        f"at the formal one ({P_CAP:g}; 1 for a stress read on P1 elements; postprocess/"
        "convergence_study.py); error = (value - extrapolated) / "
        "|extrapolated|; U = the GCI uncertainty of that run (relative). Where convergence is "
        "not monotone (oscillatory, stagnant, divergent) there is no extrapolation and U is "
        f"the spread of the levels; `zero`: every level below {NEAR_ZERO:.1%} of the largest "
        "scalar of "
        "its kind and unit (the round-off of a quantity that vanishes, such as Mz of a "
        "pinion free to spin), no extrapolation and no U. "
        f"A root stress read on a CG submodel has a noise floor of "
        f"{CG_NOISE:.1%}: a change between levels within it has no sign, so it counts as "
        "stagnant (the finer pair) or divergent (the coarser pair).",
        "",
    ]
    if any(s.get("status") == "two-grid" for s in conv["scalars"].values()):
        lines += [
            "This study has two finished ladder levels only: no extrapolation; U is Roache's "
            f"two-grid GCI with factor of safety {SAFETY_TWO_GRID:g} and the formal order "
            "(status `two-grid`).",
            "",
        ]
    lines += _h_measure(conv)
    lines += _runs_code(conv)
    lines += _reproductions(conv)
    lines += ["## Runs", "", *_runs_table(conv), ""]
    lines += _off_ladder(conv)
    if not conv["scalars"]:
        lines += ["No scalar table: fewer than one finished ladder run.", ""]
    else:
        for title, targeted in (
            ("Targeted scalars (moments, stresses)", True),
            ("Other scalars (offsets, factors, edge peaks)", False),
        ):
            rows = _scalar_rows(conv, targeted)
            if not rows:
                continue
            lines += [f"## {title}", "", *_values_table(conv, rows, labels), ""]
            lines += [*_errors_table(conv, rows, labels), ""]
        lines += _split_table(conv)
        same = [k for k, e in conv["scalars"].items() if e.get("status") == "mesh-independent"]
        if same:
            lines += [f"Mesh-independent (inputs, not FE results): {', '.join(same)}.", ""]
        lines += _missing_scalars(conv)
        lines += _recommendation(conv)
    if (folder / CHART).is_file():
        lines += ["## Speed against error", "", f"![speed against error]({CHART})", ""]
    path = folder / "report.md"
    path.write_text("\n".join(lines) + "\n")
    return path


def _minor_labels(fmt, span: float):
    """A log axis's minor-tick labels: every one within a factor 3 (``span`` = max / min of
    the data), those at 2, 3 and 5 times a power of ten within two decades (all nine crowd
    near a decade's top: 1-GB's 0.35-12.8 % at 7-9 %, its 216-1687 s at 600-900 s), none
    beyond."""
    if span < 3.0:
        return fmt
    if span >= 100.0:
        return NullFormatter()

    def label(x, pos=None):
        mantissa = x / 10.0 ** math.floor(math.log10(x) + 1e-9)
        return fmt(x, pos) if any(abs(mantissa - m) < 1e-6 for m in (2.0, 3.0, 5.0)) else ""

    return FuncFormatter(label)


def speed_error_chart(conv: dict, path: Path) -> bool:
    """Wall time and peak memory of each run against its worst error (moments, stresses)
    relative to the extrapolated value; False (nothing drawn) without a verdict to plot."""
    verdicts = [v for v in conv["recommendation"]["runs"] if v["worst"]]
    if not verdicts:
        return False
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5), sharey=True)
    styles = {"moment": ("o", "C0"), "stress": ("s", "C3")}
    targets = conv["recommendation"]["targets"]
    for ax, xkey, xlabel in (
        (axes[0], "time_s", "wall time per run (s)"),
        (axes[1], "peak_rss_mb", "peak memory per run (GB)"),
    ):
        for kind, (marker, colour) in styles.items():
            pts = [
                (
                    v[xkey] / (1024.0 if xkey == "peak_rss_mb" else 1.0),
                    max(v["worst"][kind]["error"], 1e-5),
                    v["run"],
                    v["worst"][kind]["how"] != "U (GCI)",
                )
                for v in verdicts
                if kind in v["worst"]
            ]
            if not pts:
                continue
            placed: list[tuple[float, float]] = []
            for x, y, lab, bound in sorted(pts):
                ax.loglog(x, y, marker, color=colour, mfc="none" if bound else colour)
                text = lab + ("*" if lab in _out_of_core(conv) else "")  # short: runs crowd
                # a label beside one of a point within 40 % in x and 15 % in y would overlap
                # it (2B-GA's L1P1, L1P1F2, L1P1F2R2 at 297-402 s): step it down a line
                near = sum(
                    1
                    for px, py in placed
                    if abs(math.log(x / px)) < 0.34 and abs(math.log(y / py)) < 0.14
                )
                placed.append((x, y))
                ax.annotate(
                    text, (x, y), textcoords="offset points", xytext=(4, 3 - 9 * near), fontsize=7
                )
            ax.plot([], [], marker, color=colour, label=f"worst {kind}")
            ax.axhline(
                targets[kind],
                color=colour,
                lw=0.8,
                ls="--",
                label=f"{kind} target {targets[kind]:.0%}",
            )
        ax.set_xlabel(xlabel + ("  (*: factors on disk)" if _out_of_core(conv) else ""))
        ax.grid(True, which="both", alpha=0.3)
        ax.xaxis.set_major_formatter(FormatStrFormatter("%g"))
        xs = [v[xkey] for v in verdicts]
        # label minor ticks too, else no tick may carry a number (2B-GA's 113-384 s)
        ax.xaxis.set_minor_formatter(_minor_labels(FormatStrFormatter("%g"), max(xs) / min(xs)))
        ax.margins(x=0.12)  # room for the run labels right of the last point
        ys = [max(v["worst"][k]["error"], 1e-5) for v in verdicts for k in v["worst"]]
        pct = PercentFormatter(1.0, decimals=None)
        ax.yaxis.set_major_formatter(pct)
        # within a decade no major tick may fall in range: label the minor ones as percent
        # too, not as matplotlib's 6x10^-2 beside a 1.0 % (2B-GA: 0.66-6.7 %)
        ax.yaxis.set_minor_formatter(_minor_labels(pct, max(ys) / min(ys)))
    axes[0].set_ylabel("worst U (the ± printed; hollow: a bound)")
    axes[0].legend(fontsize=8, loc="best", framealpha=0.9)
    fig.suptitle(
        f"{conv['case']}: speed against U (filled: from the extrapolation X, the GCI or, off "
        "the ladder, 1.25 |value - X|;\nhollow: no X: spread, two-grid GCI, or a root "
        "stress's driver + submodel U)",
        fontsize=10,
    )
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return True

"""The generated parts of the Background pages, so their figures come from the files that hold
them instead of being copied into the pages.

* ``docs/_generated/records.md`` (gitignored, written at ``builder-inited``; the folder is
  added to ``exclude_patterns``, it is read through ``{include}`` only): every convergence
  record under ``studies/records/convergence/<case>/convergence.json`` as Markdown tables
  (the runs with their sizes, cost and verdict; the targeted moments and the main stresses at
  every run with their uncertainty U). ``validation.md`` includes it. The record's own
  ``report.md`` beside it has every scalar; these tables are the part a reader of the docs
  needs. A record that cannot be read fails the build (a warning, and the docs build treats
  warnings as errors).
* ``docs/_generated/bench.md``: every benchmark file recorded under ``studies/records/bench/``
  (``make record-bench``, :mod:`studies.benchmarks.record`) with the date, commit and machine
  it was measured on; a benchmark's own Markdown report is included as it wrote it, its JSON
  and pictures are linked. ``performance.md`` includes it.
* On ``theory.md`` the module docstrings that ``automodule`` renders are written as plain
  text with ASCII equations (``sigma = lambda tr(eps) I + 2 mu eps``, aligned matrices,
  ``|z| <= b/2``), not as reStructuredText: each indented block after a blank line is made a
  literal block without highlighting (so an equation keeps its lines and alignment) and a
  ``|`` in the prose is escaped (it is an absolute value, not a substitution); a section
  title in a docstring becomes a bold paragraph. The docstrings stay as they are in the code.
"""

from __future__ import annotations

import json
import os
import re
from pathlib import Path

from sphinx.util import logging

LOG = logging.getLogger(__name__)

#: the pages whose automodule docstrings are read as plain text with equations
PLAIN_DOCSTRING_PAGES = {"theory"}
#: where the records live, relative to the repository root (docs/..)
RECORDS = Path("studies/records/convergence")
#: the generated page section, relative to the docs source folder
OUT = Path("_generated/records.md")
#: the recorded benchmark files, relative to the repository root, and their page section
BENCH = Path("studies/records/bench")
BENCH_OUT = Path("_generated/bench.md")


# --- convergence records ----------------------------------------------------------------


def _sig(x: float, digits: int = 4) -> str:
    """``x`` to ``digits`` significant digits, without an exponent for the sizes met here."""
    if x == 0:
        return "0"
    if abs(x) >= 10**digits:
        return f"{x:.0f}"
    return f"{x:#.{digits}g}".rstrip(".")  # keeps trailing zeros: 216.0, not 216


def _pct(u: float | None, decimals: int = 2) -> str:
    return "-" if u is None else f"{100 * u:.{decimals}f} %"


def _positions(n: int) -> str:
    return "one mesh position" if n == 1 else f"{n} mesh positions"


def _label(key: str) -> str:
    """A readable name of a summary scalar key (the key itself where no rule applies)."""
    rules = (
        (r"bending_stress_recovered\.(.+)", "root stress, fillet surface: {}"),
        (r"bending_stress_tangent_recovered\.(.+)", "root stress, ISO 30/60 deg line: {}"),
        (r"bending_stress\.(.+)", "root stress, fillet surface (nodal): {}"),
        (r"bending_stress_tangent\.(.+)", "root stress, ISO line (nodal): {}"),
        (r"contact_stress_cycle\.(.+)\.sigma_H_MPa", "sigma_H, ISO with the FE's K_Hbeta: {}"),
        (r"contact_stress_cycle\.(.+)\.interior_p_max_MPa", "contact pressure, interior max: {}"),
    )
    for pattern, text in rules:
        m = re.fullmatch(pattern, key)
        if m:
            return text.format(m.group(1).replace("_", "-"))
    return f"`{key}`"


def _shown(key: str, entry: dict) -> bool:
    """The scalars the docs table shows: every targeted moment, the interior contact pressure
    and ISO's sigma_H of every mesh, and the targeted root stresses (the record's report.md
    lists every targeted scalar, the Hertz variants and the checks too)."""
    if not entry.get("target"):
        return False
    if entry.get("kind") == "moment":
        return True
    return key.startswith("bending_stress") or key.endswith((".sigma_H_MPa", ".interior_p_max_MPa"))


def _worst(worst: dict, kind: str) -> str:
    """The worst U of a kind in a run's verdict, with its scalar."""
    got = worst.get(kind)
    return f"{_pct(got['error'])} ({_label(got['key'])})" if got else "-"


def _sizes(run: dict) -> str:
    text = f"level {run['level']}, P{run['degree']}"
    if run.get("flank_level") is not None:
        text += f", flanks and grid of level {run['flank_level']}"
    if run.get("fillet_level") is not None:
        text += f", fillets of level {run['fillet_level']}"
    return text


def record_markdown(rec: dict) -> str:
    """Markdown of one convergence record (``convergence.json``)."""
    case, labels = rec["case"], rec["labels"]
    runs = {r["label"]: r for r in rec["runs"]}
    verdicts = {v["run"]: v for v in rec["recommendation"]["runs"]}
    targets = rec["recommendation"]["targets"]
    match = rec["match"]
    lines = [
        f"### {case} ({rec.get('description', '')})",
        "",
        f"Gear set `{match['gearset']}`, `{match['scene']}` scene, `{match['contact_model']}` "
        f"contact, linear solver `{match['linear_solver']}`, {_positions(rec['positions'])}; "
        f"reduced by code `{rec['code_hash']}`. Targets: every moment's U within "
        f"{_pct(targets['moment'], 0)}, every targeted stress's U within "
        f"{_pct(targets['stress'], 0)} (root stresses: the "
        f"{rec['recommendation']['root_stress_targets']} reading). Verdict of the record: "
        f"{rec['recommendation']['note']}.",
        "",
    ]
    rep = rec.get("reproduced") or []
    if rep:
        last = rep[-1]
        diff = last.get("max_rel_diff")
        change = (
            "every one the same to the bit"
            if last["identical"] == last["scalars"]
            else f"{last['identical']} the same to the bit"
            + ("" if diff is None else f", the largest relative change {diff:.1e}")
        )
        lines += [
            f"Its run {last['run']} last solved again by code `{last['code_hash']}` "
            f"(`make reproduce-records`): {last['scalars']} scalars, {change}.",
            "",
        ]
    lines += [
        "| run | sizes | solved by code | DOFs | time (s) | peak memory (GB) | meets the targets "
        "| worst moment U | worst stress U |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for label in labels:
        run, verdict = runs.get(label), verdicts.get(label, {})
        if run is None:
            lines.append(f"| {label} | not solved | | | | | no | | |")
            continue
        disk = " (factors on disk)" if (run.get("numerics") or {}).get("out_of_core") else ""
        worst = verdict.get("worst") or {}
        code = (run.get("reuse_key") or {}).get("code_hash")
        lines.append(
            f"| {label} | {_sizes(run)} | {f'`{code}`' if code else '-'} | "
            f"{run['dofs'] / 1000:.0f}k | "
            f"{run['time_s']['total']:.0f} | {run['peak_rss_mb'] / 1024:.1f}{disk} | "
            f"{'yes' if verdict.get('meets') else 'no'} | {_worst(worst, 'moment')} | "
            f"{_worst(worst, 'stress')} |"
        )
    lines += [
        "",
        "Value ± U (relative) at each run; `extrapolated`: Richardson's limit where the three "
        "levels converge monotonically; `split`: a root stress whose driver and sector errors "
        "are studied apart (its U is their sum, with the scatter between equally valid "
        "sectors as a floor).",
        "",
        "| scalar | unit | " + " | ".join(labels) + " | extrapolated | status |",
        "|---|---|" + "---|" * len(labels) + "---|---|",
    ]
    seen = []  # the values of the rows shown: an alias of a shown key (same numbers) is left out
    for key, entry in rec["scalars"].items():
        if not _shown(key, entry) or entry.get("values") in seen:
            continue
        seen.append(entry.get("values"))
        cells = []
        for label in labels:
            v = (entry.get("values") or {}).get(label)
            u = (entry.get("uncertainty") or {}).get(label)
            cells.append("-" if v is None else _sig(v) + ("" if u is None else f" ± {_pct(u)}"))
        x = entry.get("extrapolated")
        lines.append(
            f"| {_label(key)} | {entry.get('unit', '')} | "
            + " | ".join(cells)
            + f" | {'-' if x is None else _sig(x)} | {entry.get('status', '')} |"
        )
    lines += [
        "",
        f"Every scalar, the errors, the orders and the root stresses' split: "
        f"`studies/records/convergence/{case}/report.md`.",
        "",
    ]
    return "\n".join(lines)


def records_markdown(root: Path) -> str:
    """Markdown of every record under ``root / RECORDS`` (a note when there is none)."""
    head = [
        "<!-- generated by docs/_ext/records_table.py from studies/records/convergence/; "
        "do not edit -->",
        "",
    ]
    files = sorted((root / RECORDS).glob("*/convergence.json"))
    if not files:
        return "\n".join([*head, "No convergence record is in the repository.", ""])
    parts = []
    for f in files:
        try:
            parts.append(record_markdown(json.loads(f.read_text())))
        except (OSError, ValueError, KeyError, TypeError) as e:
            LOG.warning("convergence record %s cannot be rendered: %s", f, e)
            parts.append(f"### {f.parent.name}\n\nThe record `{f}` cannot be read.\n")
    return "\n".join([*head, *parts])


def _write_records(app) -> None:
    root = Path(app.srcdir).resolve().parent
    page = Path(app.srcdir) / OUT
    page.parent.mkdir(parents=True, exist_ok=True)
    text = records_markdown(root)
    if not page.is_file() or page.read_text() != text:  # unchanged: no rebuild
        page.write_text(text)


# --- recorded benchmarks --------------------------------------------------------------------


def _demoted(md: str, by: int = 3) -> str:
    """A benchmark report's Markdown with its headings ``by`` levels deeper (it sits under a
    section of the performance page)."""
    return re.sub(r"^(#+) ", lambda m: "#" * min(6, len(m.group(1)) + by) + " ", md, flags=re.M)


def bench_markdown(root: Path, docs: Path) -> str:
    """Markdown of every recorded benchmark under ``root / BENCH`` (a note when none is)."""
    head = [
        "<!-- generated by docs/_ext/records_table.py from studies/records/bench/; do not edit -->",
        "",
    ]
    folder = root / BENCH
    stamps_file = folder / "recorded.json"
    if not stamps_file.is_file():
        return "\n".join([*head, "No benchmark is recorded in the repository yet.", ""])
    stamps = json.loads(stamps_file.read_text())
    by_stem: dict[str, list[str]] = {}
    for name in stamps:
        by_stem.setdefault(Path(name).stem, []).append(name)
    rel = Path(os.path.relpath(folder, docs / BENCH_OUT.parent)).as_posix()
    parts = []
    for stem, names in sorted(by_stem.items()):
        if not all((folder / n).is_file() for n in names):
            LOG.warning("benchmark record %s: a stamped file is missing in %s", stem, folder)
            continue
        st = stamps[names[0]]
        m = st.get("machine", {})
        parts += [
            f"### `{stem}`",
            "",
            f"Measured {st.get('date')} on commit `{str(st.get('git_revision'))[:10]}` "
            f"(source {st.get('code_hash')}), {m.get('cpus')} CPUs, {m.get('platform')}. "
            "Files: " + ", ".join(f"{{download}}`{n} <{rel}/{n}>`" for n in sorted(names)) + ".",
            "",
        ]
        if f"{stem}.md" in names:
            parts += [_demoted((folder / f"{stem}.md").read_text()).strip(), ""]
        if f"{stem}.png" in names:
            parts += [f"![{stem}]({rel}/{stem}.png)", ""]
    return "\n".join([*head, *parts])


def _write_bench(app) -> None:
    root = Path(app.srcdir).resolve().parent
    page = Path(app.srcdir) / BENCH_OUT
    page.parent.mkdir(parents=True, exist_ok=True)
    text = bench_markdown(root, Path(app.srcdir).resolve())
    if not page.is_file() or page.read_text() != text:
        page.write_text(text)


# --- module docstrings as plain text with equations ----------------------------------------


def _titles_as_paragraphs(lines: list[str]) -> list[str]:
    """A section title of a docstring (a line underlined with ``-`` or ``=``) as a bold
    paragraph: the page's own headings give its structure."""
    out: list[str] = []
    for line in lines:
        under = line.strip()
        if (
            out
            and out[-1].strip()
            and not out[-1].startswith(" ")
            and len(under) >= 3
            and set(under) <= {"-"} | {"="}
            and len(set(under)) == 1
            and len(under) == len(out[-1].rstrip())
        ):
            out[-1] = f"**{out[-1].strip()}**"
            out.append("")
            continue
        out.append(line)
    return out


def plain_docstring(lines: list[str]) -> list[str]:
    """reST lines for a plain-text docstring: an indented block after a blank line becomes a
    ``code-block:: text`` (a literal block without highlighting; a paragraph before it
    ending ``::`` keeps one colon), and a ``|`` outside those blocks is escaped. Bullet items
    (``* `` with indented continuation lines, no blank line before them) stay prose, and a
    section title becomes a bold paragraph."""
    out: list[str] = []
    literal = False  # inside a literal block
    blank = True  # the previous line was blank (or the start)
    lines = _titles_as_paragraphs(lines)
    for line in lines:
        if not line.strip():
            out.append(line)
            blank = True
            continue
        indented = line[0] == " "
        if literal and indented:
            out.append(line)
            blank = False
            continue
        literal = False
        if indented and blank:
            prose = [i for i, s in enumerate(out) if s.strip()]
            if prose and out[prose[-1]].rstrip().endswith("::"):
                head = out[prose[-1]].rstrip()[:-1]
                out[prose[-1]] = "" if head.strip() == ":" else head
            out += [".. code-block:: text", ""]
            literal = True
            out.append(line)
        else:
            out.append(line.replace("|", "\\|"))
        blank = False
    return out


def _process_docstring(app, what, name, obj, options, lines) -> None:
    if what != "module" or app.env.docname not in PLAIN_DOCSTRING_PAGES:
        return
    lines[:] = plain_docstring(lines)


def _exclude_generated(app, config) -> None:
    """The generated files are read through ``{include}`` only, not as pages of their own."""
    if OUT.parent.as_posix() not in config.exclude_patterns:
        config.exclude_patterns.append(OUT.parent.as_posix())


def setup(app):
    app.connect("config-inited", _exclude_generated)
    app.connect("builder-inited", _write_records)
    app.connect("builder-inited", _write_bench)
    app.connect("autodoc-process-docstring", _process_docstring)
    return {"parallel_read_safe": True}

"""``python -m studies.analytic --out results/analytic``: the analytical study.

Reads ``cases/analytic/singh2007.toml`` (which gear sets and bearing cases) and writes
``tables.json`` (every table, see :mod:`studies.analytic.tables`), ``report.md``
(computed beside printed values, with notes on the differences), ``fig6_misalignment.png``
and ``pust_stability.png``.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from cases.analytic_study import load_analytic_study
from studies.analytic import figures, report, tables


def run(out: Path, study: str | Path = "singh2007") -> dict[str, Path]:
    """Build the tables of the analytic study file ``study`` and write every output into
    ``out``."""
    inp = load_analytic_study(study)
    out.mkdir(parents=True, exist_ok=True)
    t = tables.build_tables(
        inp.single_pinion.planetary_input(),
        inp.double_pinion.planetary_input(),
        inp.bearing_radial_stiffness,
    )
    paths = {"tables": out / "tables.json"}
    paths["tables"].write_text(json.dumps(t, indent=1) + "\n")
    paths["report"] = report.write_report(t, out / "report.md")
    paths["fig6"] = figures.fig6_misalignment(t, out / "fig6_misalignment.png")
    paths["pust"] = figures.pust_stability(t, out / "pust_stability.png")
    return paths


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(prog="python -m studies.analytic", description=__doc__)
    parser.add_argument(
        "--out",
        type=Path,
        default=Path("results/analytic"),
        help="output directory (default: results/analytic)",
    )
    parser.add_argument("--study", default="singh2007", help="a name in cases/analytic/ or a path")
    args = parser.parse_args(argv)
    for path in run(args.out, args.study).values():
        print(path)


if __name__ == "__main__":
    main()

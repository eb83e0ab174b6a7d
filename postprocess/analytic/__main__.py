"""``python -m postprocess.analytic --out results/analytic``: the analytical study.

Writes ``tables.json`` (every table, see :mod:`postprocess.analytic.study`), ``report.md``
(computed beside printed values, with notes on the differences), ``fig6_misalignment.png``
and ``pust_stability.png``.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from postprocess.analytic import figures, report, study


def run(out: Path) -> dict[str, Path]:
    """Build the tables from the default inputs and write every output into ``out``."""
    out.mkdir(parents=True, exist_ok=True)
    tables = study.build_tables(*study.default_inputs())
    paths = {"tables": out / "tables.json"}
    paths["tables"].write_text(json.dumps(tables, indent=1) + "\n")
    paths["report"] = report.write_report(tables, out / "report.md")
    paths["fig6"] = figures.fig6_misalignment(tables, out / "fig6_misalignment.png")
    paths["pust"] = figures.pust_stability(tables, out / "pust_stability.png")
    return paths


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(prog="python -m postprocess.analytic", description=__doc__)
    parser.add_argument(
        "--out",
        type=Path,
        default=Path("results/analytic"),
        help="output directory (default: results/analytic)",
    )
    args = parser.parse_args(argv)
    for path in run(args.out).values():
        print(path)


if __name__ == "__main__":
    main()

"""``python -m studies.paper.case2 --results results --cases 2B-GA 2B-GB [--single 1-GA 1-GB]``:
the double-pinion report (:func:`studies.paper.case2_report.write_report`) from the summaries
under ``results``, against the analytic study's ``tables.json`` when it is there."""

from __future__ import annotations

import argparse
from pathlib import Path

from studies.paper.case2_report import write_report


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(prog="python -m studies.paper.case2", description=__doc__)
    ap.add_argument("--results", type=Path, default=Path("results"))
    ap.add_argument("--cases", nargs="+", required=True, help="double-pinion cases")
    ap.add_argument(
        "--single",
        nargs="*",
        default=[],
        help="single-pinion cases to compare the pattern shift with",
    )
    ap.add_argument("--out", type=Path, default=None, help="default: <results>/case2")
    ap.add_argument(
        "--tables",
        type=Path,
        default=None,
        help="analytic tables (default: <results>/analytic/tables.json)",
    )
    args = ap.parse_args(argv)
    print(write_report(args.results, args.cases, args.out, args.tables, args.single))


if __name__ == "__main__":
    main()

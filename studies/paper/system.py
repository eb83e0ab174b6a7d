"""``python -m studies.paper.system --branch results --system results/case1-system
--cases 1-GA 1-GB 1-GC 1-GB-R --pair 1-GB-R 1-GC`` (or ``--system results/case2-system
--cases 2B-GA 2B-GB``, double pinion): the system-scene report
(:func:`studies.paper.system_report.write_system_report`) from the summaries."""

from __future__ import annotations

import argparse
from pathlib import Path

from studies.paper.system_report import write_system_report


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(prog="python -m studies.paper.system", description=__doc__)
    ap.add_argument("--branch", type=Path, default=Path("results"), help="one-branch results")
    ap.add_argument("--system", type=Path, required=True, help="system-scene results")
    ap.add_argument("--cases", nargs="+", required=True)
    ap.add_argument("--pair", nargs=2, default=None, metavar=("STIFFER_GEARS", "SOFTER_BEARING"))
    args = ap.parse_args(argv)
    pair = tuple(args.pair) if args.pair else None
    print(write_system_report(args.branch, args.system, args.cases, pair))


if __name__ == "__main__":
    main()

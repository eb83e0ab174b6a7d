"""``python -m studies.paper_report --results results [--started FILE]``: the one-page report
of the whole study, ``results/report.md`` (:func:`postprocess.paper_report.
write_paper_report`). ``--started``: the start stamp the full ``make`` wrote as its first
step; its wall time is recorded in ``results/bench/make_all.json`` first (and the stamp
removed), so the page reports how long the whole run took."""

from __future__ import annotations

import argparse
from pathlib import Path

from postprocess.paper_report import record_wall_time, write_paper_report


def main(argv=None, prog: str = "python -m studies.paper_report") -> None:
    ap = argparse.ArgumentParser(
        prog=prog,
        description="Write results/report.md: every case report and picture under the results "
        "folder on one page, one row per case run, speed against error.",
    )
    ap.add_argument("--results", type=Path, default=Path("results"))
    ap.add_argument(
        "--started",
        type=Path,
        default=None,
        help="start stamp of a full make (seconds since the epoch)",
    )
    args = ap.parse_args(argv)
    if args.started is not None:
        rec = record_wall_time(args.results, args.started)
        if rec is not None:
            print(f"make: {rec['wall_s'] / 60:.1f} min (goal {rec['goal_s'] / 60:.0f} min)")
    print(write_paper_report(args.results))


if __name__ == "__main__":
    main()

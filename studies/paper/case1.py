"""``python -m studies.paper.case1 --results results``: the case-1 report
(:func:`studies.paper.case1_report.write_report`) from the summaries under ``results``."""

from __future__ import annotations

import argparse
from pathlib import Path

from studies.paper.case1_report import write_report


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(prog="python -m studies.paper.case1", description=__doc__)
    ap.add_argument("--results", type=Path, default=Path("results"))
    print(write_report(ap.parse_args(argv).results))


if __name__ == "__main__":
    main()

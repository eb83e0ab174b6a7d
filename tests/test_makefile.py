"""``make help`` lists every target a user runs: the product's first, then the research
studies, then the diagnostics (issue 57: the per-case targets the README names were missing)."""

import re
import subprocess
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
INTERNAL = {"start-clock"}  # a step of `make all`, not run on its own


def test_make_help_lists_every_target_in_its_group():
    text = (ROOT / "Makefile").read_text()
    targets = set(re.findall(r"^([a-zA-Z0-9_-]+):", text, flags=re.M)) - INTERNAL
    out = subprocess.run(
        ["make", "--no-print-directory", "-s", "help"], cwd=ROOT, capture_output=True, text=True
    )
    assert out.returncode == 0, out.stderr
    groups = re.split(r"\n(?=\S)", out.stdout.strip())
    assert [g.splitlines()[0] for g in groups] == [
        "The product (make VARIABLE=value TARGET):",
        "Research and verification studies:",
        "Diagnostics and benchmarks:",
    ]
    listed = {line.split()[0] for g in groups for line in g.splitlines()[1:]}
    assert targets <= listed, sorted(targets - listed)
    product = groups[0]
    for name in ("1-GA", "study", "case1", "case2", "test", "docs"):
        assert re.search(rf"^  {name}\b", product, flags=re.M), name


def test_a_case_target_says_the_runs_own_exit_code(tmp_path):
    """GNU make exits 2 whatever a recipe's code (its manual: 0, 1 for -q, 2 on errors), so
    the run targets say the run's documented code on stderr (issue 57 item 7): a results
    folder that is a file is code 3, which `make study` used to hide behind make's 2."""
    results = tmp_path / "a-file"
    results.write_text("")
    out = subprocess.run(
        ["make", "--no-print-directory", "-s", "study", "CASE=1-GA", f"RESULTS={results}"],
        cwd=ROOT,
        capture_output=True,
        text=True,
    )
    assert out.returncode == 2  # make's own
    assert "planetary-fe run ended with code 3" in out.stderr, out.stderr

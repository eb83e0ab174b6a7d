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

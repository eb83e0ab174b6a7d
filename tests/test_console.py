"""The console command ``planetary-fe``: its help, ``check`` on shipped and broken cases
(one line naming file and field, exit 2, no traceback), the dispatch of ``run`` and
``report``, and the entry point declared for installation."""

import subprocess
import sys
import tomllib
from importlib.metadata import entry_points
from pathlib import Path

import pytest

from studies.cli import EXIT_INVALID_INPUT, EXIT_OK

ROOT = Path(__file__).resolve().parents[1]


def _console(*args: str, cwd: Path = ROOT) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "studies.console", *args],
        cwd=cwd,
        capture_output=True,
        text=True,
        timeout=120,
    )


def test_the_entry_point_is_declared():
    scripts = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["scripts"]
    assert scripts == {"planetary-fe": "studies.console:main"}
    installed = {e.name: e.value for e in entry_points(group="console_scripts")}
    assert installed.get("planetary-fe") == "studies.console:main"


def test_help_lists_the_commands():
    out = _console("--help")
    assert out.returncode == EXIT_OK
    for command in ("run", "check", "report"):
        assert f"\n  {command} " in out.stdout


@pytest.mark.parametrize("command", ["run", "check", "report"])
def test_each_command_has_help(command):
    out = _console(command, "--help")
    assert out.returncode == EXIT_OK, out.stderr
    assert out.stdout.startswith(f"usage: planetary-fe {command}")


def test_no_or_unknown_command_is_invalid_input():
    for args in ((), ("solve",)):
        out = _console(*args)
        assert out.returncode == EXIT_INVALID_INPUT
        assert out.stderr.splitlines()[-1].startswith("error: ")


def test_check_a_shipped_case():
    out = _console("check", "1-GB", "2B-GA")
    assert out.returncode == EXIT_OK, out.stderr
    lines = out.stdout.splitlines()
    assert lines[0].startswith("1-GB: valid: gear set case1 (single pinion, 3 planets")
    assert lines[1].startswith("2B-GA: valid: gear set case2 (double pinion")
    assert "sizes L1P1F2R2, 5 positions" in lines[0]  # the case file's [model] sizes


def test_check_a_broken_case_names_file_and_field(tmp_path):
    text = (ROOT / "cases" / "1-GB.toml").read_text()
    broken = tmp_path / "mine.toml"
    broken.write_text(
        text.replace('gearset = "case1"', f'gearset = "{ROOT}/cases/gearsets/case1.toml"').replace(
            "positions = 5 ", "positions = 500 "
        )
    )
    out = _console("check", str(broken), "1-GB", cwd=tmp_path)
    assert out.returncode == EXIT_INVALID_INPUT
    assert out.stderr == f"error: {broken}: model.positions = 500: must be an integer 1..50\n"
    assert out.stdout.startswith("1-GB: valid")  # the other case is still checked

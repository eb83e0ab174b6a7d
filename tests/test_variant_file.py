"""The diagnostics that solve named variants in one process (studies.convergence.driver_sizes,
studies.convergence.sector_sizes, through studies.convergence.variant_file) keep a finished variant
only while the case's inputs and the source are those it was solved with, and write their report
beside it."""

from types import SimpleNamespace

import pytest

import studies.convergence.driver_sizes as ds
import studies.convergence.sector_sizes as ss
import studies.convergence.variant_file as variant_file
from studies.files import ResultFileError, read_json


def _row(name):
    return {
        "variant": name,
        "wall_s": 60.0,
        "peak_rss_mb": 2048.0,
        "read_fillet_mm": 0.15,
        "sizes": {"fillet": 0.1},
        "sector_dofs": {"sun": 10},
        "dofs": 10,
        "moments": {"My_pin": 200.0},
        "surface": {"sun": 800.0},
        "tangent": {"sun": 700.0},
    }


@pytest.mark.parametrize(
    "module, level, names", [(ds, 0, ["base", "grid"]), (ss, 1, ["2:0.15", "2:0.1"])]
)
def test_finished_variants_are_kept_only_for_the_same_inputs_and_code(
    module, level, names, monkeypatch, tmp_path
):
    solved = []

    def fake_variant(study, name, level, roll, comm, log=None):
        solved.append(name)
        return _row(name)

    monkeypatch.setattr(module, "solve_variant", fake_variant)
    args = SimpleNamespace(case="1-GB", level=level, roll=0.0, variants=names, out=tmp_path)
    path = module.run(args)
    assert solved == names
    module.run(args)  # the same inputs and code: nothing solved again
    assert solved == names
    monkeypatch.setattr(variant_file, "code_hash", lambda: "other")  # another code: afresh
    module.run(args)
    assert solved == names * 2
    monkeypatch.setattr(variant_file, "tool_hash", lambda solve: "edited")  # the tool changed
    module.run(args)
    assert solved == names * 3
    assert [r["variant"] for r in read_json(path)["variants"]] == names
    assert path.with_suffix(".md").is_file()


def test_a_file_that_cannot_be_written_is_an_error_naming_it(monkeypatch, tmp_path):
    monkeypatch.setattr(ss, "solve_variant", lambda *a, **k: _row("2:0.1"))
    (tmp_path / "1-GB").write_text("a file where the case folder goes")
    args = SimpleNamespace(case="1-GB", level=1, roll=0.0, variants=["2:0.1"], out=tmp_path)
    with pytest.raises(ResultFileError, match=r"writing .*sector_sizes_L1\.json"):
        ss.run(args)


def test_each_position_keeps_its_own_file(monkeypatch, tmp_path):
    """A run at another roll neither replaces nor takes the variants of roll 0's file."""
    solved = []

    def fake_variant(study, name, level, roll, comm, log=None):
        solved.append((name, roll))
        return _row(name)

    monkeypatch.setattr(ss, "solve_variant", fake_variant)
    at = {
        r: SimpleNamespace(case="1-GB", level=1, roll=r, variants=["2:0.1"], out=tmp_path)
        for r in (0.0, 0.0718078)
    }
    first = ss.run(at[0.0])
    second = ss.run(at[0.0718078])
    assert first.name == "sector_sizes_L1.json"
    assert second.name == "sector_sizes_L1_roll0.0718078.json"
    assert solved == [("2:0.1", 0.0), ("2:0.1", 0.0718078)]
    ss.run(at[0.0])  # roll 0's variants are still kept
    assert len(solved) == 2 and read_json(first)["roll"] == 0.0

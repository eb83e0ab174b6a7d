"""A benchmark's files are kept with where and by what they were measured
(studies.benchmarks.record), and the docs' performance page is built from what is kept
(docs/_ext/records_table.bench_markdown): its figures come from the file, not from prose."""

import sys
from pathlib import Path

import pytest

from studies.benchmarks.record import STAMPS, main, record
from studies.cli import InputError
from studies.files import read_json
from studies.provenance import code_hash

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "docs" / "_ext"))
import records_table


def _bench(folder: Path) -> list[Path]:
    folder.mkdir()
    (folder / "solver.json").write_text('{"levels": [0, 1]}\n')
    (folder / "solver.md").write_text(
        "# Contact solver\n\n| level | ratio |\n|---|---|\n| 0 | 3.2 |\n"
    )
    return [folder / "solver.json", folder / "solver.md"]


def test_record_stamps_each_file_and_the_page_shows_the_report_as_written(tmp_path):
    files = _bench(tmp_path / "bench")
    records = tmp_path / "repo" / "studies" / "records" / "bench"
    stamps = read_json(record(files, records))
    assert set(stamps) == {"solver.json", "solver.md"}
    assert stamps["solver.md"]["code_hash"] == code_hash() and stamps["solver.md"]["date"]
    assert (records / "solver.md").read_text() == files[1].read_text()
    docs = tmp_path / "repo" / "docs"
    docs.mkdir()
    page = records_table.bench_markdown(tmp_path / "repo", docs)
    assert "### `solver`" in page and "| 0 | 3.2 |" in page
    assert "#### Contact solver" in page  # its headings sit under the page's section
    assert "{download}`solver.json <../../studies/records/bench/solver.json>`" in page


def test_no_record_is_said_and_a_wrong_file_is_refused(tmp_path, capsys):
    docs = tmp_path / "docs"
    docs.mkdir()
    assert "No benchmark is recorded" in records_table.bench_markdown(tmp_path, docs)
    with pytest.raises(InputError, match="no such file"):
        record([tmp_path / "nothing.json"], tmp_path / "records")
    (tmp_path / "notes.txt").write_text("x")
    assert main([str(tmp_path / "notes.txt"), "--records", str(tmp_path / "r")]) == 2
    assert "a benchmark's file is one of .json, .md, .png" in capsys.readouterr().err
    assert not (tmp_path / "r" / STAMPS).exists()

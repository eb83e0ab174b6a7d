"""The one-page report names every case folder it leaves out (an unreadable summary, an
interrupted run) instead of dropping it without a word."""

import json

from postprocess.paper_report import write_paper_report


def test_the_report_names_the_case_folders_it_could_not_read(tmp_path):
    res = tmp_path / "results"
    (res / "cut").mkdir(parents=True)
    (res / "cut" / "summary.json").write_text('{"case": "cut", "inputs": {')  # cut short
    (res / "other").mkdir()
    (res / "other" / "summary.json").write_text(json.dumps({"wall_s": 3.0}))
    (res / "stopped" / "positions").mkdir(parents=True)
    for k in range(2):
        (res / "stopped" / "positions" / f"{k}.json").write_text("{}")
    (res / "fine" / "positions").mkdir(parents=True)  # a summary beside its positions: not named
    (res / "fine" / "positions" / "0.json").write_text("{}")
    (res / "fine" / "summary.json").write_text('{"broken": ')
    text = write_paper_report(res).read_text()
    assert "**Case folders not in this report:**" in text
    assert "`cut/summary.json`: cannot be read" in text
    assert "`other/summary.json`: not a case summary" in text
    assert "`stopped/`: 2 solved position file(s) and no summary.json" in text
    assert "`fine/`:" not in text and "`fine/summary.json`: cannot be read" in text
    # a results folder with nothing left out says nothing of it
    clean = tmp_path / "clean"
    assert "not in this report" not in write_paper_report(clean).read_text()

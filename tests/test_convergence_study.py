"""The convergence study from its runs (studies.convergence.reduction, convergence_report) and
the lookup of a summary's uncertainty (studies.uncertainty), on synthetic runs with known
limits: no FE solve."""

from __future__ import annotations

from dataclasses import replace

import pytest

from cases.study_case import load_study_case
from meshing.sizing import LEVELS, MeshingError, run_sizes, with_fillet, with_sizes
from postprocess.convergence_record import missing_runs
from studies.case_variants import coarse_root_fillets, global_root_stress
from studies.convergence.driver import write_study
from studies.convergence.reduction import (
    compare_runs,
    ladder,
    recommend,
    reduce_study,
    scalar_table,
    target,
)
from studies.convergence.report import speed_error_chart, write_report
from studies.files import read_json, write_json
from studies.uncertainty import (
    RECORDS,
    STUDY_FILE,
    match_key,
    recorded,
    same_match,
    summary_uncertainty,
)

LIMITS = {
    "My_pin": 40.0,
    "M_LOA_sun": 30.0,
    "Mz_pin": 0.0,
    "ZS": -0.8,
    "bending_stress.sun": 700.0,
    "contact_stress.sun_pinion": 3000.0,
}


def _row(level: int, degree: int, seconds: float, gb: float) -> dict:
    lv = LEVELS[level]
    h, hf = lv.fine, lv.fillet
    scale = 0.25 if degree == 2 else 1.0  # P2 at a level: a quarter of the P1 error
    scalars = {
        "My_pin": 40.0 * (1 - scale * 0.03 * h**2),  # 3 % low at level 0, order 2
        "M_LOA_sun": 30.0 * (1 + scale * 0.02 * h**1.5),
        "Mz_pin": 1e-11 * (1 + level),  # round-off of a free spin
        "ZS": -0.8 + scale * 0.1 * h,
        "bending_stress.sun": 700.0 * (1 - scale * 0.1 * hf),  # fillet size, order 1
        "contact_stress.sun_pinion": 3000.0 * (1 + 0.1 * (-1) ** level),  # an edge peak
        "bending_stress_iso6336_nominal.sun": 650.0,
    }
    return {
        "label": f"L{level}P{degree}",
        "level": level,
        "degree": degree,
        "dofs": int(2e5 / h**3),
        "h_mm": {"fine": h, "fillet": hf},
        "grid_points_total": 100,
        "time_s": {"total": seconds, "factorization": 1.0, "compliance": 1.0},
        "peak_rss_mb": gb * 1024,
        "scalars": scalars,
    }


ROWS = [_row(0, 1, 10, 3.5), _row(1, 1, 20, 4.5), _row(2, 1, 110, 9.9), _row(0, 2, 130, 14)]


def _flank_row(seconds: float = 30.0) -> dict:
    """Level 1 with level 2's flanks (L1P1F2): in the synthetic scalars every flank-read
    value is level 2's and every fillet-read one level 1's."""
    row = _row(1, 1, seconds, 5.0)
    two, one = _row(2, 1, 0, 0)["scalars"], row["scalars"]
    scalars = {k: (one if k.startswith("bending_stress") else two)[k] for k in one}
    return {
        **row,
        "label": "L1P1F2",
        "flank_level": 2,
        "scalars": scalars,
        "h_mm": {"fine": LEVELS[2].fine, "fillet": LEVELS[1].fillet},
    }


def test_a_run_with_another_levels_flanks_is_judged_off_the_ladder(tmp_path):
    """L1P1F2 (level 1 with level 2's flanks and contact grid, the candidate default where
    level 1's errors come from the flanks and grid) does not enter the ladder: it is judged
    against the ladder's extrapolation like a P2 run, and can be the recommended run."""
    from postprocess.run_scalars import row_label, run_label, sizes_in_words

    assert with_sizes(1, 2) == replace(LEVELS[1], fine=LEVELS[2].fine)
    assert with_sizes(1, 2, 2) == replace(LEVELS[1], fine=LEVELS[2].fine, fillet=LEVELS[2].fillet)
    assert with_sizes(1) == LEVELS[1]
    with pytest.raises(MeshingError, match="level = 9"):
        with_sizes(1, 9)
    # a run of a level's own sizes is named by its index (the mesh cache and the records)
    assert run_sizes(1) == 1 and run_sizes(1, 2, 2) == with_sizes(1, 2, 2)
    assert run_sizes(1, None, 2) == replace(LEVELS[1], fillet=LEVELS[2].fillet)
    with pytest.raises(MeshingError, match="level = 9"):
        run_sizes(9)
    assert sizes_in_words(1, {}) == "level 1"
    assert sizes_in_words(1, {"flank_level": 2, "fillet_level": 2}) == (
        "level 1 with level 2's flanks and contact grid and level 2's refined fillets"
    )
    assert run_label(1, 1) == "L1P1" and run_label(1, 1, 2) == "L1P1F2"
    assert run_label(1, 1, 2, 2) == "L1P1F2R2" and run_label(1, 1, None, 2) == "L1P1R2"
    flank = _flank_row()
    assert row_label(flank) == "L1P1F2" and row_label(ROWS[1]) == "L1P1"
    rows = [*ROWS[:3], flank]
    lad, others = ladder(rows)
    assert lad == ROWS[:3] and others == [flank]
    table, plain = scalar_table(rows), scalar_table(ROWS[:3])
    for key in ("My_pin", "M_LOA_sun", "bending_stress.sun"):
        e = table[key]
        assert e["extrapolated"] == plain[key]["extrapolated"]  # the ladder's alone
        # error against the extrapolation: a flank-read value level 2's, a fillet one level 1's
        like = "L1P1" if key.startswith("bending_stress") else "L2P1"
        assert e["rel_error"]["L1P1F2"] == pytest.approx(e["rel_error"][like], rel=1e-9)
        err_abs = abs(e["values"]["L1P1F2"] - e["extrapolated"])
        assert e["uncertainty_abs"]["L1P1F2"] == pytest.approx(1.25 * err_abs)
    rec = recommend(rows, table)
    (v,) = [v for v in rec["runs"] if v["run"] == "L1P1F2"]
    assert v["flank_level"] == 2 and v["meets"]
    assert not next(v for v in rec["runs"] if v["run"] == "L1P1")["meets"]  # My_pin 1.8 %
    # cheaper than level 2 (30 against 110 s) and within every target: recommended
    assert rec["recommended"] == {
        "run": "L1P1F2",
        "level": 1,
        "degree": 1,
        "flank_level": 2,
        "time_s": 30.0,
        "peak_rss_mb": 5.0 * 1024,
    }
    conv = {
        "case": "1-GB",
        "match": {"gearset": "case1", "scene": "one_branch"},
        "positions_note": "One position.",
        "ladder_degree": 1,
        "runs": rows,
        "labels": [r["label"] for r in rows],
        "scalars": table,
        "recommendation": rec,
    }
    text = write_report(conv, tmp_path).read_text()
    assert "| L1P1F2 | 1 (flanks and contact grid of 2) | 1 |" in text
    assert (
        "Off the ladder: L1P1F2 (level 1 with level 2's flanks and contact grid, degree 1)" in text
    )
    both = {**flank, "label": "L1P1F2R2", "fillet_level": 2}
    assert ladder([*ROWS[:3], both])[1] == [both]
    text = write_report({**conv, "runs": [*rows, both]}, tmp_path).read_text()
    assert "| L1P1F2R2 | 1 (flanks and contact grid of 2; refined fillets of 2) | 1 |" in text
    assert (
        "L1P1F2R2 (level 1 with level 2's flanks and contact grid and level 2's refined "
        "fillets, degree 1)"
    ) in text


def test_table_extrapolates_each_scalar_with_its_own_h():
    table = scalar_table(ROWS)
    for key in ("My_pin", "M_LOA_sun", "ZS", "bending_stress.sun"):
        assert table[key]["status"] == "monotone"
        assert table[key]["extrapolated"] == pytest.approx(LIMITS[key], rel=1e-8, abs=1e-10)
    assert table["My_pin"]["order"] == pytest.approx(2.0, abs=1e-6)
    assert table["bending_stress.sun"]["order"] == pytest.approx(1.0, abs=1e-6)  # fillet h
    assert table["contact_stress.sun_pinion"]["status"] == "oscillatory"
    assert table["bending_stress_iso6336_nominal.sun"]["status"] == "mesh-independent"
    assert table["Mz_pin"]["uncertainty"]["L1P1"] is None  # zero by physics: no relative
    assert table["Mz_pin"]["target"] is None
    # P2 off the ladder: a quarter of the level-0 P1 error
    e0, e2 = table["My_pin"]["rel_error"]["L0P1"], table["My_pin"]["rel_error"]["L0P2"]
    assert e2 == pytest.approx(e0 / 4, rel=1e-6)


def test_targets_leave_edge_peaks_and_offsets_out():
    assert target("My_pin") == 0.01 and target("bending_stress.sun") == 0.05
    assert target("contact_stress_cycle.sun_pinion.interior_p_max_MPa") == 0.05
    for key in (
        "ZS",
        "contact_stress.sun_pinion",
        "contact_stress_cycle.sun_pinion.p_max_MPa",
        "contact_stress_cycle.sun_pinion.edge_p_max_MPa",
        "contact_stress_cycle.sun_pinion.K_Hbeta",
        "bending_stress_face_end.sun",  # the corner at a face end
        "bending_stress_near_load.sun",  # beside a submodel's point force
        "bending_stress_global.sun",  # the check beside a submodel's value
    ):
        assert target(key) is None, key


def test_the_recovered_root_stress_is_the_target_where_a_study_holds_it():
    """Runs since 2026-11-30 read the fillet twice (nodal maxima, solvers.root_stress;
    recovered, solvers.surface_recovery): the recovered readings are the targets and the
    nodal ones checks; a study of runs without them targets the nodal ones."""
    for key in ("bending_stress_recovered.ring", "bending_stress_tangent_recovered.ring"):
        assert target(key) is None and target(key, recovered=True) == 0.05
    for key in ("bending_stress.ring", "bending_stress_tangent.ring"):
        assert target(key) == 0.05 and target(key, recovered=True) is None
    assert target("bending_stress_global.ring", recovered=True) is None
    assert target("My_pin", recovered=True) == 0.01

    def with_recovered(row: dict) -> dict:
        # the nodal line scatters by +-3 % from level to level; the recovered one converges
        # (order 1 in the fillet size, 2 % low at level 0)
        lv = LEVELS[row["level"]]
        s = dict(row["scalars"])
        s["bending_stress_tangent.ring"] = 600.0 * (1 + 0.03 * (-1) ** row["level"])
        s["bending_stress_tangent_recovered.ring"] = 590.0 * (1 - 0.05 * lv.fillet)
        return dict(row, scalars=s)

    rows = [with_recovered(r) for r in ROWS]
    table = scalar_table(rows)
    assert table["bending_stress_tangent.ring"]["target"] is None
    assert table["bending_stress_tangent_recovered.ring"]["target"] == 0.05
    assert table["bending_stress.sun"]["target"] is None  # nodal: a check in this study
    rec = recommend(rows, table)
    # the scattered nodal line would fail every level; as a check it fails none
    assert rec["recommended"]["run"] == "L2P1"
    assert not any("bending_stress_tangent.ring" in v["failing"] for v in rec["runs"])
    assert rec["root_stress_targets"] == "recovered"
    # the old study's rows (no recovered reading): the nodal line is a target and fails
    old = [
        dict(r, scalars={k: v for k, v in r["scalars"].items() if "recovered" not in k})
        for r in rows
    ]
    rec_old = recommend(old, scalar_table(old))
    assert rec_old["recommended"] is None
    assert all("bending_stress_tangent.ring" in v["failing"] for v in rec_old["runs"])
    assert rec_old["root_stress_targets"] == "nodal"
    # an off-ladder run of older code (no recovered reading) does not move the targets:
    # the ladder's readings set them, in the table and in the verdict alike
    p2_old = {**old[3], "label": "L0P2"}
    both = [*rows[:3], p2_old]
    rec_p2 = recommend(both, scalar_table(both))
    assert rec_p2["root_stress_targets"] == "recovered"
    assert scalar_table(both)["bending_stress_tangent_recovered.ring"]["target"] == 0.05
    # runs of older and newer code reduced together (--reduce-only): the recovered ones in
    # one run only are no ladder, so the nodal ones stay the targets (the root stress is
    # not left without one)
    mixed = [rows[0], *old[1:]]
    table = scalar_table(mixed)
    assert table["bending_stress_tangent.ring"]["target"] == 0.05
    assert recommend(mixed, table)["root_stress_targets"] == "nodal"
    # a reproduction compares the targeted ones: the recovered where both rows hold them
    a = {"scalars": {"bending_stress.sun": 700.0, "bending_stress_recovered.sun": 690.0}}
    b = {"scalars": {"bending_stress.sun": 707.0, "bending_stress_recovered.sun": 690.69}}
    got = compare_runs(a, b)["targets"]["stress"]
    assert got["key"] == "bending_stress_recovered.sun"
    assert got["max_rel_diff"] == pytest.approx(1e-3)
    nodal = compare_runs(
        {"scalars": {"bending_stress.sun": 700.0}}, {"scalars": {"bending_stress.sun": 707.0}}
    )
    assert nodal["targets"]["stress"]["key"] == "bending_stress.sun"


def test_recommendation_is_the_cheapest_run_meeting_the_targets():
    table = scalar_table(ROWS)
    rec = recommend(ROWS, table)
    by = {v["run"]: v for v in rec["runs"]}
    # level 0: My_pin 3 %, root stress 6 % off; level 1: My_pin 1.5 %; level 2: 0.6 %, 3 %
    assert not by["L0P1"]["meets"] and "My_pin" in by["L0P1"]["failing"]
    assert not by["L1P1"]["meets"]
    assert by["L2P1"]["meets"]
    assert rec["recommended"]["run"] == "L2P1"  # cheaper than L0P2
    assert "L2P1" in rec["note"]


def test_report_and_chart(tmp_path):
    table = scalar_table(ROWS)
    rows = [dict(r, numerics={"out_of_core": r["level"] == 2}) for r in ROWS]
    conv = {
        "case": "1-GB",
        "match": {"gearset": "case1", "scene": "one_branch"},
        "positions_note": "One position.",
        "ladder_degree": 1,
        "runs": rows,
        "skipped": [{"label": "L1P2", "level": 1, "degree": 2, "why": "memory"}],
        "scalars": table,
        "recommendation": recommend(ROWS, table),
    }
    assert speed_error_chart(conv, tmp_path / "speed_error.png")
    text = write_report(conv, tmp_path).read_text()
    assert "**Recommendation:** L2P1" in text and "skipped: memory" in text
    assert "targeted are the nodal maxima: these runs hold no recovered" in text
    assert "oscillatory" in text and "speed_error.png" in text
    # the run solved out of core says so beside its memory (runs table, level table)
    assert text.count("9.9 (factors on disk)") == 2 and "4.5 (factors" not in text


def test_chart_labels_the_minor_ticks_that_do_not_crowd():
    """All nine minor ticks of a decade crowd near its top (1-GB's 216-1687 s printed
    600 700 800 900 1000 run together): beyond a factor 3 only 2, 3 and 5 carry a number,
    beyond two decades none."""
    from matplotlib.ticker import FormatStrFormatter

    from studies.convergence.report import _minor_labels

    fmt = FormatStrFormatter("%g")
    wide = _minor_labels(fmt, 1687.0 / 216.0)
    assert [wide(x) for x in (200.0, 300.0, 500.0, 600.0, 700.0, 900.0)] == [
        "200",
        "300",
        "500",
        "",
        "",
        "",
    ]
    assert _minor_labels(fmt, 2.0)(700.0) == "700"  # a narrow axis keeps every label
    assert _minor_labels(fmt, 150.0)(200.0) == ""


def test_report_names_a_scalar_missing_from_a_ladder_run(tmp_path):
    """A root stress that one ladder run did not read has no ± (the table keeps the keys
    every run has): the report names it and the run that lacks it, and that run fails the
    verdict."""
    rows = [dict(r) for r in ROWS]
    rows[1] = {
        **rows[1],
        "scalars": {k: v for k, v in rows[1]["scalars"].items() if k != "bending_stress.sun"},
    }
    table = scalar_table(rows)
    assert "bending_stress.sun" not in table and "My_pin" in table
    conv = {
        "case": "1-GB",
        "match": {"gearset": "case1", "scene": "one_branch"},
        "positions_note": "One position.",
        "ladder_degree": 1,
        "runs": rows,
        "skipped": [],
        "scalars": table,
        "recommendation": recommend(rows, table),
    }
    text = write_report(conv, tmp_path).read_text()
    assert "## Scalars missing from a ladder run (no ±; a targeted one fails that run)" in text
    assert "- bending_stress.sun: not in L1P1" in text
    assert "| L1P1 |" in text and not conv["recommendation"]["runs"][1]["meets"]
    conv = {**conv, "runs": ROWS, "scalars": scalar_table(ROWS)}
    assert "missing from a ladder run" not in write_report(conv, tmp_path).read_text()


def test_summary_finds_the_study_of_its_gear_set(tmp_path):
    table = scalar_table(ROWS)
    gb, ga = load_study_case("1-GB"), load_study_case("1-GA")
    conv = {
        "case": "1-GB",
        "match": match_key(gb),
        "labels": [r["label"] for r in ROWS],
        "positions": 1,
        "code_hash": "x",
        "scalars": table,
    }
    (tmp_path / "convergence" / "1-GB").mkdir(parents=True)
    write_json(tmp_path / "convergence" / "1-GB" / STUDY_FILE, conv)
    got = summary_uncertainty(ga, 1, 1, tmp_path, records=None)  # 1-GA: same gear set, scene
    assert got["uncertainty"]["My_pin"] == table["My_pin"]["uncertainty"]["L1P1"]
    assert "1-GB" in got["uncertainty_source"]["convergence_study"]
    assert "bending_stress_iso6336_nominal.sun" not in got["uncertainty"]
    missing = summary_uncertainty(ga, 3, 1, tmp_path, records=None)
    assert (
        missing["uncertainty"] is None and "no run L3P1" in (missing["uncertainty_source"]["note"])
    )
    case2 = summary_uncertainty(load_study_case("2B-GA"), 1, 1, tmp_path, records=None)
    assert case2["uncertainty"] is None and "gear set case2" in case2["uncertainty_source"]["note"]
    # a damaged study beside it is named in the note, not passed over in silence
    (tmp_path / "convergence" / "1-GC").mkdir()
    (tmp_path / "convergence" / "1-GC" / STUDY_FILE).write_text("{ not json")
    again = summary_uncertainty(ga, 1, 1, tmp_path, records=None)
    assert again["uncertainty"] == got["uncertainty"]
    assert "skipped as unreadable: " in again["uncertainty_source"]["note"]
    assert "1-GC" in again["uncertainty_source"]["note"]
    # a study of the zone contact model (the default) does not serve a line-model case
    # (other numerics)
    line = replace(ga, numerics=replace(ga.numerics, contact_model="line"))
    assert summary_uncertainty(line, 1, 1, tmp_path, records=None)["uncertainty"] is None
    # nor a run on coarse root fillets (more compliant teeth: another model)
    assert (
        summary_uncertainty(coarse_root_fillets(ga), 1, 1, tmp_path, records=None)["uncertainty"]
        is None
    )


def test_a_recorded_study_serves_where_the_results_have_none(tmp_path):
    """make runs the ladders only where no record matches (--unless-recorded); a summary takes
    a record's ± when its results folder has no study, and says when the code has changed
    since the record was solved."""
    from studies.convergence.driver import record
    from studies.provenance import code_hash

    table = scalar_table(ROWS)
    gb, ga = load_study_case("1-GB"), load_study_case("1-GA")
    ladder = {"runs": ["L0P1", "L1P1", "L2P1"], "positions": 1, "split_root_stress": True}
    conv = {
        "case": "1-GB",
        "match": match_key(gb),
        "labels": [r["label"] for r in ROWS],
        "positions": 1,
        "code_hash": "x",
        "runs_code_hash": [code_hash()],
        "ladder": ladder,
        "scalars": table,
    }
    study_dir, records = tmp_path / "study", tmp_path / "records"
    study_dir.mkdir()
    (study_dir / "report.md").write_text("# the study\n")
    path = record(study_dir, conv, records)
    assert path == records / "1-GB" / STUDY_FILE and (records / "1-GB" / "report.md").is_file()
    stored = read_json(path)
    assert stored["recorded"]["date"] and stored["runs_code_hash"] == [code_hash()]
    # found by match key and ladder: another ladder or another gear set is not it
    assert recorded(ga, ladder, records) == path
    assert recorded(ga, {**ladder, "positions": 5}, records) is None
    assert recorded(load_study_case("2B-GA"), ladder, records) is None
    # no study under the results: the record's ± with its provenance, code unchanged
    got = summary_uncertainty(ga, 1, 1, tmp_path / "results", records=records)
    assert got["uncertainty"]["My_pin"] == table["My_pin"]["uncertainty"]["L1P1"]
    assert got["uncertainty_source"]["recorded"] == stored["recorded"]
    assert got["uncertainty_source"]["code_changed"] is False
    assert "other code" not in got["uncertainty_source"]["note"]
    # a study left in the results by other code does not stand before a current record
    stale = {**conv, "scalars": scalar_table(ROWS[:2]), "runs_code_hash": ["0" * 16]}
    (tmp_path / "results" / "convergence" / "1-GB").mkdir(parents=True)
    write_json(tmp_path / "results" / "convergence" / "1-GB" / STUDY_FILE, stale)
    got = summary_uncertainty(ga, 1, 1, tmp_path / "results", records=records)
    assert got["uncertainty_source"]["convergence_study"] == str(path)
    # a record solved by other code: still a ±, the first found (this machine's), flagged
    write_study(path, {**stored, "runs_code_hash": ["1" * 16]})  # as the driver writes
    got = summary_uncertainty(ga, 1, 1, tmp_path / "results", records=records)
    assert "results" in got["uncertainty_source"]["convergence_study"]
    assert got["uncertainty"]["My_pin"] == stale["scalars"]["My_pin"]["uncertainty"]["L1P1"]
    assert got["uncertainty_source"]["code_changed"] is True
    assert "solved by other code (source 0000000000000000" in got["uncertainty_source"]["note"]
    (tmp_path / "results" / "convergence" / "1-GB" / STUDY_FILE).unlink()
    got = summary_uncertainty(ga, 1, 1, tmp_path / "results", records=records)
    assert (
        got["uncertainty_source"]["code_changed"] is True
        and "recorded" in (got["uncertainty_source"])
    )
    # the reports' ± line names the record and that the code changed since
    from postprocess.convergence_record import uncertainty_note

    line = uncertainty_note({"1-GA": {**got}})
    assert f"recorded {stored['recorded']['date']} on commit" in line
    assert "solved by other code than today's" in line
    # make's convergence-main: a matching record means nothing to run, nothing written
    from studies.convergence.driver import main

    out = tmp_path / "out"
    argv = [
        "1-GA",
        "--levels",
        "0",
        "1",
        "2",
        "--extra",
        "--split-root-stress",
        "--unless-recorded",
        "--records",
        str(records),
        "--out",
        str(out),
    ]
    assert main(argv) == 0 and not out.exists()
    # a study of this machine solved by today's code comes first
    mine = {**conv, "scalars": scalar_table(ROWS[:2])}
    (tmp_path / "results" / "convergence" / "1-GB").mkdir(parents=True, exist_ok=True)
    write_json(tmp_path / "results" / "convergence" / "1-GB" / STUDY_FILE, mine)
    got = summary_uncertainty(ga, 1, 1, tmp_path / "results", records=records)
    assert "recorded" not in got["uncertainty_source"]
    assert "results" in got["uncertainty_source"]["convergence_study"]


def test_a_record_with_a_failed_run_is_no_record(tmp_path, capsys):
    """--record writes what finished; a record missing a ladder run (a timeout) must not stop
    make's --unless-recorded from solving the ladder again, and says why."""
    from studies.convergence.driver import record

    gb = load_study_case("1-GB")
    ladder = {"runs": ["L0P1", "L1P1", "L2P1"], "positions": 1, "split_root_stress": True}
    runs = [
        {"label": "L0P1"},
        {"label": "L1P1", "error": "timeout after 3600 s"},
        {"label": "L2P1"},
    ]
    conv = {
        "case": "1-GB",
        "match": match_key(gb),
        "labels": ladder["runs"],
        "positions": 1,
        "code_hash": "x",
        "ladder": ladder,
        "scalars": scalar_table(ROWS),
        "runs": runs,
    }
    path = record(tmp_path / "study", conv, tmp_path / "records")
    assert recorded(gb, ladder, tmp_path / "records") is None
    assert "not the run(s) L1P1 (failed or skipped when recorded)" in capsys.readouterr().out
    write_study(path, {**read_json(path), "runs": [runs[0], {"label": "L1P1"}, runs[2]]})
    assert recorded(gb, ladder, tmp_path / "records") == path
    # an extra run skipped for memory (--min-free-gb) is missing as a failed one is
    extra = {**ladder, "runs": [*ladder["runs"], "L1P1F2"]}
    skipped = [
        {
            "label": "L1P1F2",
            "level": 1,
            "degree": 1,
            "flank_level": 2,
            "why": "MemAvailable 9.0 GB < 16 GB asked for",
        }
    ]
    write_study(path, {**read_json(path), "ladder": extra, "skipped": skipped})
    assert recorded(gb, extra, tmp_path / "records") is None
    assert "not the run(s) L1P1F2 (failed or skipped" in capsys.readouterr().out
    write_study(path, {**read_json(path), "skipped": []})
    assert recorded(gb, extra, tmp_path / "records") == path


def test_record_refuses_a_study_with_a_failed_run(tmp_path, monkeypatch, capsys):
    """--record of a study whose level-1 run timed out records nothing and says which run
    failed (exit 2); the study itself stays in the results; once the run finishes, the study
    is recorded."""
    from studies.convergence import driver as convergence
    from studies.provenance import code_hash

    case = load_study_case("1-GB")
    folder, records = tmp_path / case.name, tmp_path / "records"
    _stored_runs(folder, case, code_hash())
    (folder / "runs" / "L1P1.json").unlink()
    outcome = {"level": 1, "degree": 1, "error": "timeout after 3600 s"}
    monkeypatch.setattr(convergence, "run_child", lambda *a: dict(outcome))
    argv = [
        "1-GB",
        "--levels",
        "0",
        "1",
        "2",
        "--extra",
        "--out",
        str(tmp_path),
        "--record",
        "--records",
        str(records),
    ]
    assert convergence.main(argv) == 2
    assert "--record: run(s) L1P1 failed" in capsys.readouterr().err
    assert (folder / STUDY_FILE).is_file() and not (records / case.name).exists()
    outcome = dict(ROWS[1])
    assert convergence.main(argv) == 0  # the failed run is solved again, not reused
    assert not missing_runs(read_json(records / case.name / STUDY_FILE))


def test_a_study_without_the_run_of_the_level_does_not_stand_before_one_with_it(tmp_path):
    """A study of this machine by today's code whose level-1 run failed (its labels lack
    L1P1) gives no ± at level 1; a record that has the run is taken instead, not a silent
    'no uncertainty'."""
    from studies.convergence.driver import record
    from studies.provenance import code_hash

    ga, gb = load_study_case("1-GA"), load_study_case("1-GB")
    full = {
        "case": "1-GB",
        "match": match_key(gb),
        "labels": [r["label"] for r in ROWS],
        "positions": 1,
        "code_hash": "x",
        "runs_code_hash": ["1" * 16],
        "ladder": {"runs": ["L0P1", "L1P1", "L2P1"]},
        "scalars": scalar_table(ROWS),
    }
    path = record(tmp_path / "study", full, tmp_path / "records")
    rows = [r for r in ROWS if r["label"] != "L1P1"]
    broken = {
        **full,
        "labels": [r["label"] for r in rows],
        "runs_code_hash": [code_hash()],
        "scalars": scalar_table(rows),
    }
    (tmp_path / "results" / "convergence" / "1-GB").mkdir(parents=True)
    write_json(tmp_path / "results" / "convergence" / "1-GB" / STUDY_FILE, broken)
    got = summary_uncertainty(ga, 1, 1, tmp_path / "results", records=tmp_path / "records")
    assert got["uncertainty_source"]["convergence_study"] == str(path)
    assert got["uncertainty"]["My_pin"] == full["scalars"]["My_pin"]["uncertainty"]["L1P1"]
    # at level 0 both have the run: today's code first, as before
    got = summary_uncertainty(ga, 0, 1, tmp_path / "results", records=tmp_path / "records")
    assert "results" in got["uncertainty_source"]["convergence_study"]


@pytest.mark.parametrize("case", ["1-GB", "2B-GA"])
def test_the_recorded_ladders_match_their_cases(case):
    """The records behind the main study's ± (make convergence-main RECORD=1) are of today's
    gear set, scene and numerics: a change to the case data without a new record would make
    every make solve the ladder again, and this test says which record to renew."""
    path = RECORDS / case / STUDY_FILE
    if not path.is_file():
        pytest.skip(f"no record of {case} yet (make convergence-main RECORD=1)")
    conv = read_json(path)
    # as the lookup compares them (a field the key gained later at the value the record was
    # solved with: studies.uncertainty.KEY_ADDED)
    assert same_match(conv["match"], match_key(load_study_case(case))), (
        f"{path} is of other inputs: make convergence-main RECORD=1"
    )
    assert conv["scalars"] and conv["recorded"]["git_revision"] and conv["runs_code_hash"]
    assert not missing_runs(conv), f"{path} misses failed runs: make convergence-main RECORD=1"


@pytest.mark.parametrize("case", ["1-GB", "2B-GA"])
def test_a_record_holds_todays_reductions_of_its_runs(case, tmp_path):
    """The reductions (studies.convergence.richardson, studies.convergence.reduction) are outside
    the source hash and applied again whenever a study is read; the record's stored scalars,
    recommendation and report must be what they give today, or the committed files say other
    numbers than the summaries print. Fails after a change to the reductions until
    ``python -m studies.convergence --reduce-records`` rewrites the records."""
    import json

    from studies.convergence.reduction import reduce_study

    path = RECORDS / case / STUDY_FILE
    conv = read_json(path)
    assert "case_level" in conv, f"{path}: python -m studies.convergence --reduce-records"
    again = reduce_study(conv)
    for part in ("scalars", "recommendation"):
        assert json.dumps(again[part], sort_keys=True) == json.dumps(conv[part], sort_keys=True), (
            f"{path}: its {part} are not today's; python -m studies.convergence --reduce-records"
        )
    speed_error_chart(again, tmp_path / "speed_error.png")
    write_report(again, tmp_path)
    assert (tmp_path / "report.md").read_text() == (path.parent / "report.md").read_text()


def test_reduce_records_rewrites_stale_reductions(tmp_path):
    """A record whose stored reductions are stale (a scalar's values edited after the
    reduction) is reduced again from its runs, and its report with it."""
    from studies.convergence.driver import reduce_records
    from studies.convergence.reduction import reduce_study

    rows = [{**r, "label": f"L{r['level']}P{r['degree']}"} for r in ROWS[:3]]
    match = {"gearset": "case1", "scene": "one_branch"}
    conv = {
        "case": "1-GB",
        "description": "x",
        "match": match,
        "code_hash": "x",
        "runs_code_hash": ["x"],
        "positions": 1,
        "positions_note": "One position.",
        "ladder_degree": 1,
        "ladder": {},
        "labels": [r["label"] for r in rows],
        "runs": rows,
        "skipped": [],
        "scalars": {"stale": {}},
        "recommendation": {},
    }
    (tmp_path / "1-GB").mkdir()
    write_json(tmp_path / "1-GB" / STUDY_FILE, conv)
    assert reduce_records(tmp_path) == [tmp_path / "1-GB" / STUDY_FILE]
    got = read_json(tmp_path / "1-GB" / STUDY_FILE)
    assert got["case_level"] == load_study_case("1-GB").model.level
    assert "stale" not in got["scalars"] and got["scalars"] == reduce_study(got)["scalars"]
    assert got["recommendation"]["runs"] and (tmp_path / "1-GB" / "report.md").is_file()


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["1-GB", "--levels", "1", "1"], "--levels"),
        (["1-GB", "--extra", "0:3"], "--extra '0:3': the degree must be 1 or 2"),
        (["1-GB", "--extra", "x"], "must be LEVEL:DEGREE"),
        (["1-GB", "--levels", "0", "1", "9"], "level = 9"),
        (["1-GB", "--levels", "0", "1", "--out-of-core", "2"], "--out-of-core 2: not a run"),
        (["1-GB", "--levels", "0", "1", "--out-of-core", "0:x"], "--out-of-core '0:x': must be"),
        (["no-such-case"], "no-such-case"),
    ],
)
def test_convergence_cli_refuses_bad_input(argv, message, capsys, tmp_path):
    from studies.convergence.driver import main

    assert main([*argv, "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: ") and message in err and len(err.strip().splitlines()) == 1
    assert not any(tmp_path.iterdir())  # nothing solved, nothing written


def _stored_runs(folder, case, code: str, ooc: tuple[int, ...] = ()) -> None:
    """ROWS's ladder as finished runs of ``case`` solved by code ``code``, the levels
    ``ooc`` out of core; the others' keys as stored before the out-of-core option (no
    ``out_of_core`` entry)."""
    from studies.convergence.driver import _reuse_key

    (folder / "runs").mkdir(parents=True)
    for row in ROWS[:3]:
        key = {**_reuse_key(case, (row["level"], row["degree"], None, None), 1), "code_hash": code}
        if row["level"] in ooc:
            key["out_of_core"] = True
        else:
            del key["out_of_core"]
        write_json(folder / "runs" / f"{row['label']}.json", {**row, "reuse_key": key})


def test_reduce_only_reduces_stored_runs_of_other_code(tmp_path):
    """--reduce-only solves nothing: it reduces the stored runs of the same inputs, whatever
    code solved them, and the report names that code; a ladder run it does not find is an
    input error that writes nothing, and a run of other inputs is not taken."""
    from studies.convergence.driver import main

    case = load_study_case("1-GB")
    folder = tmp_path / case.name
    argv = ["1-GB", "--levels", "0", "1", "2", "--out", str(tmp_path), "--reduce-only"]
    _stored_runs(folder, case, "0123456789abcdef")
    assert main(argv) == 0  # P2 (the default extra) is not stored: skipped, not solved
    conv = read_json(folder / STUDY_FILE)
    assert conv["runs_code_hash"] == ["0123456789abcdef"] != [conv["code_hash"]]
    assert conv["labels"] == ["L0P1", "L1P1", "L2P1"] and conv["skipped"][0]["label"] == "L0P2"
    assert conv["scalars"]["My_pin"]["extrapolated"] == pytest.approx(40.0, rel=1e-8)
    assert "runs solved by code 0123456789abcdef" in (folder / "report.md").read_text()
    # other inputs (another position count) are not reduced: nothing new is written
    (folder / STUDY_FILE).unlink()
    assert main([*argv, "--positions", "2"]) == 2
    assert not (folder / STUDY_FILE).exists()


def test_an_out_of_core_run_is_reduced_only_as_one(tmp_path):
    """A run solved out of core is taken for a study that asks for that level out of core
    (its time and memory are on the chart), and not for one that asks for it in core; the
    runs stored before the option count as in core."""
    from studies.convergence.driver import main

    case = load_study_case("1-GB")
    folder = tmp_path / case.name
    _stored_runs(folder, case, "0123456789abcdef", ooc=(2,))
    argv = ["1-GB", "--levels", "0", "1", "2", "--out", str(tmp_path), "--reduce-only"]
    assert main(argv) == 2  # L2P1 in core is not stored
    assert not (folder / STUDY_FILE).exists()
    assert main([*argv, "--out-of-core", "2"]) == 0
    assert read_json(folder / STUDY_FILE)["labels"] == ["L0P1", "L1P1", "L2P1"]


def test_failed_child_is_a_row_with_its_error():
    from studies.convergence.position_runs import run_child

    row = run_child(
        "studies.convergence.driver", ["--one", "no-such-case", "0", "1", "1"], 0, 1, 120
    )
    assert row["level"] == 0 and "exit code" in row["error"]
    assert any("no-such-case" in line for line in row["stderr_tail"])


def test_a_child_with_a_log_writes_its_stderr_there(tmp_path):
    """A ladder run's child writes its progress (a line per submodel) to runs/<run>.log as
    it runs; a failed one's row still holds the tail."""
    from studies.convergence.position_runs import run_child

    log = tmp_path / "L0P1.log"
    row = run_child(
        "studies.convergence.driver", ["--one", "no-such-case", "0", "1", "1"], 0, 1, 120, log
    )
    assert "no-such-case" in log.read_text()
    assert any("no-such-case" in line for line in row["stderr_tail"])


def test_only_an_in_core_extra_run_waits_for_free_memory(tmp_path, monkeypatch):
    """An extra run (P2) is skipped when less memory is free than ``--min-free-gb``, unless it
    is solved out of core (a few GB whatever the level: 2B-GA's level-0 P2 peaked at 4.5)."""
    from studies.convergence import driver as convergence
    from studies.provenance import code_hash

    case = load_study_case("1-GB")
    calls = []

    def child(module, args, level, degree, timeout, log=None):
        calls.append(args)
        return dict(ROWS[3])

    monkeypatch.setattr(convergence, "run_child", child)
    argv = [
        "1-GB",
        "--levels",
        "0",
        "1",
        "2",
        "--extra",
        "0:2",
        "--out",
        str(tmp_path),
        "--min-free-gb",
        "1e9",
    ]
    _stored_runs(tmp_path / case.name, case, code_hash())
    assert convergence.main(argv) == 0
    assert calls == [] and read_json(tmp_path / case.name / STUDY_FILE)["skipped"]
    assert convergence.main([*argv, "--out-of-core", "0:2"]) == 0
    assert len(calls) == 1 and "--out-of-core-run" in calls[0]
    assert read_json(tmp_path / case.name / STUDY_FILE)["skipped"] == []


def test_a_killed_child_leaves_no_factor_files(tmp_path, monkeypatch):
    """A child's out-of-core folder is its own and is removed when the child ends, also when
    the timeout kills it (its factor files would otherwise stay: tens of GB at level 2)."""
    from studies.convergence.position_runs import run_child

    (tmp_path / "oocwriter.py").write_text(
        "import os, pathlib, time\n"
        "pathlib.Path(os.environ['PLANETARY_OOC_DIR'], 'factor').write_bytes(b'0' * 1000)\n"
        "time.sleep(60)\n"
    )
    root = tmp_path / "ooc"
    monkeypatch.setenv("PYTHONPATH", str(tmp_path))
    monkeypatch.setenv("PLANETARY_OOC_DIR", str(root))
    row = run_child("oocwriter", [], 2, 1, timeout=5.0)
    assert row["error"] == "timeout after 5 s"
    assert root.is_dir() and not any(root.iterdir())


def test_two_levels_give_the_two_grid_gci(tmp_path):
    """A ladder of two levels (the third did not fit): every scalar gets Roache's two-grid
    GCI at both levels with the formal order of its kind (stress 1, moment 2), no
    extrapolated value and no error; the report says so where it states the method."""
    table = scalar_table(ROWS[:2])
    conv = {
        "case": "x",
        "match": {"gearset": "case1", "scene": "one_branch"},
        "positions_note": "One position.",
        "ladder_degree": 1,
        "labels": ["L0P1", "L1P1"],
        "runs": ROWS[:2],
        "skipped": [],
        "scalars": table,
    }
    conv["recommendation"] = recommend(ROWS[:2], table)
    text = write_report(conv, tmp_path).read_text()
    assert "two finished ladder levels only" in text and "factor of safety 3" in text
    three = {**conv, "scalars": scalar_table(ROWS[:3]), "runs": ROWS[:3]}
    three["recommendation"] = recommend(ROWS[:3], three["scalars"])
    assert "two finished ladder levels" not in write_report(three, tmp_path).read_text()
    my, bs = table["My_pin"], table["bending_stress.sun"]
    assert my["status"] == bs["status"] == "two-grid"
    assert my["extrapolated"] is None and my["rel_error"] == {"L0P1": None, "L1P1": None}
    assert (my["gci_order"], bs["gci_order"]) == (2.0, 1.0)
    r = LEVELS[0].fine / LEVELS[1].fine
    e21 = ROWS[0]["scalars"]["My_pin"] - ROWS[1]["scalars"]["My_pin"]
    assert my["uncertainty_abs"]["L1P1"] == pytest.approx(3.0 * abs(e21) / (r**2 - 1.0))


def test_without_a_recommendation_the_note_says_which_kind_meets_its_target():
    """Moments converged, a root stress not: the note names the cheapest run with every
    moment within 1 % and the stress families that fail; a face-end root stress (a corner
    value that grows with refinement) is not a target."""
    rows = [dict(r, scalars=dict(r["scalars"])) for r in ROWS[:3]]
    for k, r in enumerate(rows):
        r["scalars"]["bending_stress.sun"] = 700.0 * (1 + 0.1 * (-1) ** k)  # oscillates 20 %
        r["scalars"]["bending_stress_face_end.sun"] = 300.0 * (1 + k)  # grows with refinement
    table = scalar_table(rows)
    assert table["bending_stress_face_end.sun"]["target"] is None
    note = recommend(rows, table)["note"]
    assert "every moment within 1% from L2P1 on" in note
    assert "no run has every stress within 5% (failing: bending_stress)" in note


# ------------------------------------------------ root stress: driver and submodel apart
A_ROOT = 800.0  # the limit of the synthetic root stress


def _separable(h: float, f: float) -> float:
    """A root stress whose driver error (flank size h) and submodel error (fillet f) are
    separable, both order 2: A (1 - 0.02 h^2) (1 - 2 f^2)."""
    return A_ROOT * (1.0 - 0.02 * h * h) * (1.0 - 2.0 * f * f)


def _split_rows(extras: bool = True, case_level: int = 1) -> list[dict]:
    """Ladder runs at levels 0-2, each on its own sector (meshing.submodel.submodel_level),
    with the extra submodel readings of studies.convergence.driver.submodel_levels for a case at
    ``case_level``: its run on two other sectors (level 1: the two finer ones; level 2: one
    finer, one coarser), the others on the case's."""
    from meshing.submodel import submodel_level

    near = {1: (2, 3), 2: (1, 3)}[case_level]
    rows = []
    for level in (0, 1, 2):
        h, f = LEVELS[level].fine, submodel_level(level).fillet
        extra = [submodel_level(k).fillet for k in (near if level == case_level else (case_level,))]
        rows.append(
            {
                "label": f"L{level}P1",
                "level": level,
                "degree": 1,
                "dofs": int(2e5 / h**3),
                "h_mm": {"fine": h, "fillet": f},
                "grid_points_total": 100,
                "time_s": {"total": 10.0 * (level + 1), "factorization": 1.0, "compliance": 1.0},
                "peak_rss_mb": 1024.0,
                "scalars": {"bending_stress.ring": _separable(h, f)},
                "fillet_scalars": {
                    f"{x:g}": {"bending_stress.ring": _separable(h, x)} for x in extra
                }
                if extras
                else {},
            }
        )
    return rows


def test_root_stress_split_recovers_the_limit_of_separable_errors():
    rows = _split_rows()
    e = scalar_table(rows, case_level=1)["bending_stress.ring"]
    assert e["status"] == "split"
    sp = e["split"]
    assert sp["driver"]["status"] == sp["submodel"]["status"] == "monotone"
    assert sp["driver"]["order"] == pytest.approx(2.0, rel=1e-6)
    assert sp["submodel"]["order"] == pytest.approx(2.0, rel=1e-6)
    # the submodel ladder: the case's sector (0.15 mm) and the two finer ones
    assert sp["fillet_mm"] == 0.15 and sp["submodel"]["at"] == [0.15, 0.1, 0.08]
    # X = D_ext S_ext / v_D is the exact limit of a separable error (order 2 recovered)
    assert e["extrapolated"] == pytest.approx(A_ROOT, rel=1e-9)
    for r in rows:
        assert e["rel_error"][r["label"]] == pytest.approx(
            r["scalars"]["bending_stress.ring"] / A_ROOT - 1.0, abs=1e-9
        )
    # levels 1 and 2 read their own sector on the submodel ladder: its U there
    for i in (1, 2):
        want = sp["driver"]["uncertainty"][i] + sp["submodel"]["uncertainty"][i - 1]
        assert e["uncertainty"][rows[i]["label"]] == pytest.approx(want, rel=1e-12)
    # level 0's 0.2 mm sector is coarser than the ladder: the step to the case's sector on
    # its own driver, plus the ladder's U there
    v0 = rows[0]["scalars"]["bending_stress.ring"]
    v0_f = rows[0]["fillet_scalars"]["0.15"]["bending_stress.ring"]
    want = sp["driver"]["uncertainty"][0] + abs(v0 - v0_f) / v0 + sp["submodel"]["uncertainty"][0]
    assert e["uncertainty"]["L0P1"] == pytest.approx(want, rel=1e-12)


def test_a_run_with_other_levels_sizes_is_judged_as_a_point_of_the_driver_ladder():
    """L1P1F2 reads the case level's sector like every driver-ladder reading: its U is its
    driver error (Fs |v - D_ext|) plus the sector's U there, as a ladder run's; a value that
    lands on the extrapolated X by chance (a driver error cancelling the sector's) does not
    pass with a U of zero. A run on another sector (P2 at level 0) keeps Fs |v - X|."""
    rows = _split_rows()
    h2, f_d = LEVELS[2].fine, 0.15
    on_x = {
        **rows[1],
        "label": "L1P1F2",
        "flank_level": 2,
        "fillet_scalars": {},
        "h_mm": {"fine": h2, "fillet": f_d},
        "scalars": {"bending_stress.ring": _separable(h2, f_d)},
    }
    e = scalar_table([*rows, on_x], case_level=1)["bending_stress.ring"]
    sp = e["split"]
    v = on_x["scalars"]["bending_stress.ring"]
    d_ext = sp["driver"]["extrapolated"]
    assert d_ext == pytest.approx(A_ROOT * (1 - 2 * f_d * f_d), rel=1e-9)
    u_sub = sp["submodel"]["uncertainty"][0]
    assert e["uncertainty"]["L1P1F2"] == pytest.approx(1.25 * abs(v - d_ext) / v + u_sub)
    # the same driver value as level 2's reading on the case's sector: the same driver U
    i2 = sp["driver"]["at"].index("L2P1")
    assert sp["driver"]["values"][i2] == pytest.approx(v, rel=1e-12)
    assert e["uncertainty"]["L1P1F2"] == pytest.approx(sp["driver"]["uncertainty"][i2] + u_sub)
    # a value on X: judged on v - X alone its U would be 0; here the driver's error and the
    # sector's U stay in it
    lucky = {**on_x, "scalars": {"bending_stress.ring": e["extrapolated"]}}
    e2 = scalar_table([*rows, lucky], case_level=1)["bending_stress.ring"]
    assert e2["rel_error"]["L1P1F2"] == pytest.approx(0.0, abs=1e-12)
    assert e2["uncertainty"]["L1P1F2"] > u_sub > 0.0
    # another sector (a P2 run at level 0 reads level 0's, 0.2 mm): Fs |v - X| / |v|
    p2 = {
        **rows[0],
        "label": "L0P2",
        "degree": 2,
        "fillet_scalars": {},
        "scalars": {"bending_stress.ring": 0.99 * A_ROOT},
    }
    e3 = scalar_table([*rows, p2], case_level=1)["bending_stress.ring"]
    assert e3["uncertainty"]["L0P2"] == pytest.approx(1.25 * 0.01 / 0.99)


def test_root_stress_split_of_a_run_coarser_than_the_submodel_ladder():
    """A case at level 2: the submodel ladder is 0.15 / 0.1 / 0.08 mm, and level 0 reads
    0.2 mm: its U adds the step to the case's sector on its own driver."""
    rows = _split_rows(case_level=2)
    e = scalar_table(rows, case_level=2)["bending_stress.ring"]
    sp = e["split"]
    assert e["status"] == "split" and sp["fillet_mm"] == 0.1
    assert e["extrapolated"] == pytest.approx(A_ROOT, rel=1e-9)
    v0 = rows[0]["scalars"]["bending_stress.ring"]
    v0_f = rows[0]["fillet_scalars"]["0.1"]["bending_stress.ring"]
    want = sp["driver"]["uncertainty"][0] + abs(v0 - v0_f) / v0 + sp["submodel"]["uncertainty"][1]
    assert e["uncertainty"]["L0P1"] == pytest.approx(want, rel=1e-12)


def test_root_stress_without_the_submodel_readings_keeps_the_coupled_ladder():
    e = scalar_table(_split_rows(extras=False), case_level=1)["bending_stress.ring"]
    assert e["status"] != "split" and "split" not in e


def test_report_prints_both_ladders(tmp_path):
    rows = _split_rows()
    conv = {
        "case": "x",
        "match": {"gearset": "case1", "scene": "one_branch"},
        "positions_note": "One position.",
        "ladder_degree": 1,
        "labels": [r["label"] for r in rows],
        "runs": rows,
        "skipped": [],
        "scalars": scalar_table(rows, case_level=1),
    }
    conv["recommendation"] = recommend(rows, conv["scalars"])
    text = write_report(conv, tmp_path).read_text()
    assert "## Root stress: driver and submodel" in text
    assert "| bending_stress.ring | " in text.split("## Root stress: driver and submodel")[1]


def test_the_ladder_runs_read_the_two_submodel_ladders():
    from meshing.submodel import submodel_level
    from studies.convergence.driver import submodel_levels

    study = load_study_case("1-GB")  # level 1: its sector at level 2's sizes, 0.15 mm
    assert study.model.level == 1
    assert submodel_level(1) == with_fillet(2, 0.15)
    assert submodel_levels(study, (1, 1, None, None)) == (2, 3)  # the submodel ladder, driver fixed
    driver = (1,)  # the driver ladder at the case level's sector
    assert (
        submodel_levels(study, (0, 1, None, None))
        == submodel_levels(study, (2, 1, None, None))
        == driver
    )
    # the whole sector refines along the submodel ladder, its fillet the finest part
    subs = [submodel_level(k) for k in (1, 2, 3)]
    assert [s.fillet for s in subs] == [0.15, 0.1, 0.08]
    assert subs[0].fine > subs[1].fine > subs[2].fine and subs[0].tooth > subs[2].tooth
    # a level-0 case reads the two finer sectors too; a level-2 case has one finer sector
    # (levels 3 and 4 share theirs) and reads one coarser
    at = {k: replace(study, model=replace(study.model, level=k)) for k in range(len(LEVELS))}
    assert submodel_levels(at[0], (0, 1, None, None)) == (1, 2)
    assert submodel_levels(at[2], (2, 1, None, None)) == (1, 3)
    # the finest level reads its own sizes; a case there reads the two coarser sectors
    top = len(LEVELS) - 1
    assert submodel_level(top) == submodel_level(top - 1) == with_fillet(top, 0.08)
    assert submodel_levels(at[top], (top, 1, None, None)) == (top - 3, top - 2)
    assert submodel_levels(study, (0, 2, None, None)) == ()  # off the ladder
    assert submodel_levels(study, (1, 1, 2, None)) == ()  # level 2's flanks: off the ladder
    glob = global_root_stress(study)
    assert submodel_levels(glob, (1, 1, None, None)) == ()


# ---------------------------------------------------------------- the reductions' findings
def _ladder(values: dict[str, list[float]], fillets=(0.2, 0.15, 0.1), extra: dict | None = None):
    """Three ladder rows (levels 0-2, P1, flank sizes 1.0 / 0.7 / 0.45 mm) with the given
    scalars per level, read on submodels (numerics.root_stress = submodel)."""
    rows = []
    for i, (h, hf) in enumerate(zip((1.0, 0.7, 0.45), fillets, strict=True)):
        rows.append(
            {
                "label": f"L{i}P1",
                "level": i,
                "degree": 1,
                "dofs": int(2e5 / h**3),
                "h_mm": {"fine": h, "fillet": hf, "global_fillet": hf},
                "time_s": {"total": 10.0 * (i + 1)},
                "peak_rss_mb": 1024.0,
                "numerics": {"root_stress": "submodel"},
                "scalars": {k: v[i] for k, v in values.items()},
            }
        )
    return rows


def test_a_run_is_judged_on_the_uncertainty_the_reports_print():
    """f = 100 + 6 h^6 on h 1 / 0.7 / 0.45: the observed order is 6, the GCI uses 2. L1P1 is
    0.71 % off the extrapolation but its ± is 1.39 %: judged on the error (before), it met
    the 1 % target its ± does not."""
    f = [100.0 + 6.0 * h**6 for h in (1.0, 0.7, 0.45)]
    rows = _ladder({"My_pin": f})
    table = scalar_table(rows)
    e = table["My_pin"]
    assert e["rel_error"]["L1P1"] == pytest.approx(0.0071, abs=1e-4)
    assert e["uncertainty"]["L1P1"] == pytest.approx(0.0139, abs=1e-4)
    rec = recommend(rows, table)
    verdict = {v["run"]: v for v in rec["runs"]}
    assert not verdict["L1P1"]["meets"] and verdict["L1P1"]["failing"] == ["My_pin"]
    assert verdict["L2P1"]["meets"] and rec["recommended"]["run"] == "L2P1"


def test_a_run_without_a_targeted_scalar_does_not_meet_the_targets():
    """A run that lacks a targeted key the others have (a failed stress read) fails: before,
    the key left the table and the verdict, and the run met the targets unseen."""
    rows = _ladder({"My_pin": [40.0, 40.0001, 40.0001]})
    for r in rows:
        r["scalars"]["bending_stress.sun"] = 700.0
    del rows[1]["scalars"]["bending_stress.sun"]
    verdict = {v["run"]: v for v in recommend(rows, scalar_table(rows))["runs"]}
    assert not verdict["L1P1"]["meets"] and verdict["L1P1"]["missing"] == ["bending_stress.sun"]


def test_a_two_level_study_gives_its_off_ladder_run_a_bound():
    """Two ladder levels and a P2 run: the P2 run is listed, so it must get a ± (before it
    got none, and a summary at level 0 P2 took '{}' from this study)."""
    from postprocess.convergence_record import uncertainty_for

    rows = _ladder({"My_pin": [39.0, 39.6, 40.0]})[:2]
    p2 = {**rows[0], "label": "L0P2", "degree": 2, "scalars": {"My_pin": 39.8}}
    table = scalar_table([*rows, p2])
    assert table["My_pin"]["status"] == "two-grid"
    assert table["My_pin"]["uncertainty"]["L0P2"] == pytest.approx(0.8 / 39.8)
    conv = {"labels": ["L0P1", "L1P1", "L0P2"], "scalars": table}
    assert uncertainty_for(conv, "L0P2", "x")["uncertainty"]["My_pin"] == pytest.approx(0.8 / 39.8)


def test_the_sprp_differential_is_judged_against_its_moments():
    """M_LOA_SPRP_diff = M_LOA_SP_RP + M_LOA_RP_SP, 25 of two 150-170 N m moments: its
    spread of 0.26 N m is 1.05 % of itself (its printed ±) but 0.15 % of the moments; the
    1 % target applies to the moments' scale (2B-GA failed every level on it alone)."""
    sp_rp, rp_sp = [-146.81, -146.76, -146.54], [171.71, 171.41, 171.39]
    diff = [a + b for a, b in zip(sp_rp, rp_sp, strict=True)]
    diff[1] -= 0.26  # oscillatory: the spread bound
    rows = _ladder({"M_LOA_SP_RP": sp_rp, "M_LOA_RP_SP": rp_sp, "M_LOA_SPRP_diff": diff})
    table = scalar_table(rows)
    assert table["M_LOA_SPRP_diff"]["uncertainty"]["L2P1"] > 0.01
    v = {v["run"]: v for v in recommend(rows, table)["runs"]}["L2P1"]
    assert "M_LOA_SPRP_diff" not in v["failing"]
    assert v["worst"]["moment"]["error"] < 0.01


def test_a_p1_stress_takes_the_gci_of_order_one_and_a_submodel_stress_order_two():
    """Point stresses of P1 elements converge as h: the contact pressure and the global
    fillets get the GCI with the order capped at 1 (before 2, the cap of integrals); the
    P2 submodels' root stresses keep the cap 2."""
    f = [100.0 + 6.0 * h**3 for h in (1.0, 0.7, 0.45)]
    rows = _ladder(
        {
            "contact_stress_cycle.sun_pinion.sigma_H_MPa": f,
            "bending_stress_global.sun": f,
            "bending_stress_face_end.sun": f,
        }
    )
    table = scalar_table(rows)
    assert table["contact_stress_cycle.sun_pinion.sigma_H_MPa"]["gci_order"] == 1.0
    assert table["bending_stress_global.sun"]["gci_order"] == 1.0
    assert table["bending_stress_face_end.sun"]["gci_order"] == 2.0


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_a_change_within_the_solver_noise_has_no_sign(sign):
    """[110, 100 +- 1e-6, 100] (coarse to fine) on a CG submodel: the finer pair agree
    within the solver's noise either way, so both give the spread; before, one sign was
    monotone with U ~ 0 and the other oscillatory with U 10 %."""
    vals = [110.0, 100.0 + sign * 1e-6, 100.0]
    table = scalar_table(_ladder({"bending_stress_cell.sun": vals}))
    e = table["bending_stress_cell.sun"]
    assert e["status"] == "stagnant" and e["uncertainty"]["L2P1"] == pytest.approx(0.1, rel=1e-6)


def test_zero_is_judged_within_a_unit():
    """An offset in um is not zero because an offset in mm is large (before, 0.004 um of
    f_ma beside a 5 mm ZS was 'near zero' and had no relative ±)."""
    rows = _ladder({"ZS": [5.0, 5.1, 5.15], "f_ma_SPRP_um": [0.0040, 0.0042, 0.0043]})
    e = scalar_table(rows)["f_ma_SPRP_um"]
    assert not e.get("near_zero") and e["uncertainty"]["L2P1"] is not None


def test_two_runs_reading_the_same_sector_give_no_extrapolation():
    """Levels 3 and 4 read the same 0.08 mm sector: a root stress has two grids, not three;
    it is incomplete (and fails the verdict) instead of raising in richardson."""
    rows = _ladder(
        {"bending_stress.sun": [700.0, 705.0, 706.0], "My_pin": [39.0, 39.6, 39.8]},
        fillets=(0.1, 0.08, 0.08),
    )
    table = scalar_table(rows)
    assert table["bending_stress.sun"]["status"] == "incomplete"
    verdict = {v["run"]: v for v in recommend(rows, table)["runs"]}
    assert "bending_stress.sun" in verdict["L2P1"]["no_bound"] and not verdict["L2P1"]["meets"]


def test_a_two_level_study_assumes_the_formal_order_of_where_a_stress_is_read():
    """Two levels: the GCI's assumed order is the formal one, 2 for a root stress read on
    the P2 submodels, 1 for the contact pressure of the P1 global model (before, 1 for
    every stress)."""
    sigma_h = "contact_stress_cycle.sun_pinion.sigma_H_MPa"
    rows = _ladder(
        {"bending_stress_face_end.sun": [700.0, 710.0, 0.0], sigma_h: [1500.0, 1480.0, 0.0]}
    )[:2]
    table = scalar_table(rows)
    assert table["bending_stress_face_end.sun"]["gci_order"] == 2.0
    assert table[sigma_h]["gci_order"] == 1.0


def test_compare_runs_counts_the_scalars_the_same_to_the_bit():
    from postprocess.convergence_record import reproduction_text
    from studies.convergence.reduction import compare_runs

    a = {
        "scalars": {"My_pin": 40.0, "Mz_pin": 3e-13, "ZS": None},
        "fillet_scalars": {"0.15": {"bending_stress.sun": 700.0}},
    }
    same = compare_runs(a, a)
    assert same["scalars"] == same["identical"] == 4 and same["missing"] == []
    assert same["max_rel_diff"] is None and same["worst"] is None
    assert same["targets"]["moment"] == {"max_rel_diff": 0.0, "key": "My_pin"}
    assert "every one of its 4 scalars the same to the bit" in reproduction_text(
        {"run": "L0P1", "date": "d", **same}
    )
    b = {
        "scalars": {"My_pin": 40.0 * (1 + 3e-11), "Mz_pin": -1e-13, "ZR": 1.0},
        "fillet_scalars": {"0.15": {"bending_stress.sun": 707.0}},
    }
    got = compare_runs(a, b)
    assert got["scalars"] == 3 and got["identical"] == 0  # ZS and ZR in one run only
    assert got["worst"] == "0.15 mm:bending_stress.sun"
    assert got["max_rel_diff"] == pytest.approx(0.01)
    assert got["missing"] == ["ZR", "ZS"]
    text = reproduction_text({"run": "L0P1", "date": "d", **got})
    assert "0 of 3 scalars the same to the bit, the others within 1.0e-02" in text
    assert "2 scalar(s) in one run only" in text and "another mesh" not in text
    # a run on another mesh says so: its differences are not round-off
    moved = reproduction_text(
        {"run": "L0P1", "date": "d", **compare_runs({**a, "dofs": 100}, {**b, "dofs": 111})}
    )
    assert "0 of 3 scalars the same to the bit (another mesh: 100 DOFs recorded, 111 now)" in moved
    # the targeted kinds apart: the moments within 3e-11, the stresses within 1 %
    assert got["targets"]["moment"]["key"] == "My_pin"
    assert got["targets"]["stress"] == {
        "max_rel_diff": pytest.approx(0.01),
        "key": "0.15 mm:bending_stress.sun",
    }
    assert "the targeted moments within 3.0e-11 (My_pin)" in text
    # every shared scalar the same, one in one run only: no "others within" to speak of
    more = {**a, "scalars": {**a["scalars"], "ZR": 1.0}}
    only = reproduction_text({"run": "L0P1", "date": "d", **compare_runs(a, more)})
    assert "4 of 4 scalars the same to the bit, 1 scalar(s) in one run only" in only
    # round-off of zero is judged against the zero scale of its kind (1e-3 of 40 N m), not
    # against itself: 4e-13 N m of change is 1e-11 of it, not 133 %
    b["fillet_scalars"]["0.15"]["bending_stress.sun"] = 700.0
    b["scalars"]["My_pin"] = 40.0
    got = compare_runs(a, b)
    assert got["worst"] == "Mz_pin" and got["max_rel_diff"] == pytest.approx(1e-11)


def test_reproduce_solves_a_recorded_run_again_and_the_summary_quotes_it(
    tmp_path, monkeypatch, capsys
):
    """--reproduce L solves the record's level-L run again as recorded (positions, submodel
    readings), adds the comparison of every scalar to the record, and a summary whose ± come
    from that record (solved by other code) quotes it; a changed scalar is counted, not
    hidden; a record of other inputs or without the run is refused."""
    import shutil

    import studies.convergence.driver as conv_mod
    from postprocess.convergence_record import uncertainty_note
    from studies.convergence.driver import main
    from studies.provenance import code_hash

    case = load_study_case("1-GB")
    records, out = tmp_path / "records", tmp_path / "out"
    folder = tmp_path / "study"
    _stored_runs(folder, case, "1" * 16)
    runs = [read_json(folder / "runs" / f"{r['label']}.json") for r in ROWS[:3]]
    ladder = {"runs": ["L0P1", "L1P1", "L2P1"], "positions": 1, "split_root_stress": True}
    conv = {
        "case": "1-GB",
        "match": match_key(case),
        "labels": ["L0P1", "L1P1", "L2P1"],
        "positions": 1,
        "code_hash": "1" * 16,
        "runs_code_hash": ["1" * 16],
        "ladder": ladder,
        "runs": runs,
        "case_level": 1,
        "ladder_degree": 1,
        "description": "normal bearing",
        "positions_note": "one position",
        "skipped": [],
        "machine": {"cpus": 2},
    }
    conv = reduce_study(conv)
    conv_mod.record(folder, conv, records)
    asked = []

    def child(args, study, run, where):
        level, degree = run[:2]
        asked.append((level, degree, args.positions, args.split_root_stress, args.ooc_runs))
        row = dict(runs[level])
        if len(asked) > 1:  # the second time one scalar moves
            row["scalars"] = {**row["scalars"], "My_pin": row["scalars"]["My_pin"] * 1.001}
        return row

    monkeypatch.setattr(conv_mod, "_one_run", child)
    argv = ["1-GB", "--reproduce", "0", "--records", str(records), "--out", str(out)]
    assert main(argv) == 0
    assert asked == [(0, 1, 1, True, set())]
    rec = read_json(records / "1-GB" / STUDY_FILE)
    (entry,) = rec["reproduced"]
    assert entry["run"] == "L0P1" and entry["identical"] == entry["scalars"] == 7
    assert "Solved again by later code" in (records / "1-GB" / "report.md").read_text()
    got = summary_uncertainty(case, 1, 1, tmp_path / "results", records=records)
    src = got["uncertainty_source"]
    assert src["code_changed"] is True and src["reproduced"] == entry
    assert f"its run L0P1 solved again by code {code_hash()}" in src["note"]
    assert "every one of its 7 scalars the same to the bit" in uncertainty_note({"1-GB": got})
    # again by the same code: the entry is replaced, and a moved scalar is counted
    assert main(argv) == 0
    (entry,) = read_json(records / "1-GB" / STUDY_FILE)["reproduced"]
    assert entry["identical"] == 6 and entry["worst"] == "My_pin"
    assert entry["max_rel_diff"] == pytest.approx(1e-3)
    # refused: a level the record has not, another case's inputs
    assert main(["1-GB", "--reproduce", "3", "--records", str(records), "--out", str(out)]) == 2
    assert main(["1-GC", "--reproduce", "0", "--records", str(records), "--out", str(out)]) == 2
    assert "no record of 1-GC" in capsys.readouterr().err
    # 1-GC shares 1-GB's gear set, scene and numerics (the match key), not its bearing
    shutil.copytree(records / "1-GB", records / "1-GC")
    assert main(["1-GC", "--reproduce", "0", "--records", str(records), "--out", str(out)]) == 2
    assert "1-GC's inputs changed since the record" in capsys.readouterr().err
    assert len(asked) == 2


def test_add_to_record_solves_an_off_ladder_run_and_the_record_stands_for_it(
    tmp_path, monkeypatch, capsys
):
    """--add-to-record 1:1:2 solves the run by today's code as the record's ladder was
    solved and adds it: the record's runs, its ladder (so a make asking for the same extra
    finds it), the codes of its runs, the verdict and the report; a failed run adds nothing
    (exit 1); a ladder run or a bad run is refused (exit 2)."""
    import studies.convergence.driver as conv_mod
    from studies.convergence.driver import main
    from studies.provenance import code_hash

    case = load_study_case("1-GB")
    records, out, folder = tmp_path / "records", tmp_path / "out", tmp_path / "study"
    _stored_runs(folder, case, "1" * 16)
    runs = [read_json(folder / "runs" / f"{r['label']}.json") for r in ROWS[:3]]
    lad = {"runs": ["L0P1", "L1P1", "L2P1"], "positions": 1, "split_root_stress": True}
    conv = reduce_study(
        {
            "case": "1-GB",
            "match": match_key(case),
            "labels": lad["runs"],
            "positions": 1,
            "code_hash": "1" * 16,
            "runs_code_hash": ["1" * 16],
            "ladder": lad,
            "runs": runs,
            "case_level": 1,
            "ladder_degree": 1,
            "description": "normal bearing",
            "positions_note": "one position",
            "skipped": [],
            "machine": {"cpus": 2},
        }
    )
    conv_mod.record(folder, conv, records)
    path = records / "1-GB" / STUDY_FILE
    asked, outcome = [], {}

    def child(args, study, run, where):
        asked.append((run, args.positions, args.split_root_stress, args.ooc_runs))
        key = {**conv_mod._reuse_key(study, run, 1), "code_hash": code_hash()}
        return {**_flank_row(), "reuse_key": key, "reused": False, **outcome}

    monkeypatch.setattr(conv_mod, "_one_run", child)
    argv = ["1-GB", "--records", str(records), "--out", str(out), "--add-to-record"]
    assert main([*argv, "1:1:2", "--out-of-core", "1:1:2"]) == 0
    assert asked == [((1, 1, 2, None), 1, True, {(1, 1, 2, None)})]
    rec = read_json(path)
    assert rec["labels"] == ["L0P1", "L1P1", "L2P1", "L1P1F2"]
    assert rec["ladder"]["runs"] == ["L0P1", "L1P1", "L2P1", "L1P1F2"]
    assert rec["runs_code_hash"] == sorted(["1" * 16, code_hash()])
    assert rec["added"]["L1P1F2"]["code_hash"] == code_hash()
    assert rec["recommendation"]["recommended"]["run"] == "L1P1F2"
    # the ladder's extrapolation is the record's own, not moved by the added run
    assert rec["scalars"]["My_pin"]["extrapolated"] == conv["scalars"]["My_pin"]["extrapolated"]
    text = (records / "1-GB" / "report.md").read_text()
    assert "L1P1F2 was added to the record on" in text
    assert f"The ladder's runs were solved by code {'1' * 16}" in text
    # a make asking for the ladder with this extra finds the record; without it, not
    assert recorded(case, rec["ladder"], records) == path
    assert recorded(case, lad, records) is None
    # again: replaced, not doubled
    assert main([*argv, "1:1:2"]) == 0
    assert read_json(path)["labels"].count("L1P1F2") == 1
    # a failed run adds nothing
    before = path.read_text()
    outcome = {"error": "exit code -9 (signal 9, e.g. killed out of memory)"}
    assert main([*argv, "0:2"]) == 1
    assert "L0P2 failed" in capsys.readouterr().err and path.read_text() == before
    # refused: a ladder run, the same level as flank level, a level out of range
    for bad, why in (
        ("1:1", "is a ladder run"),
        ("1:1:1", "is a ladder run"),
        ("1:1:1:1", "is a ladder run"),
        ("1:1:9", "flank level"),
        ("1:1:2:7", "fillet level"),
        ("1-1", "LEVEL:DEGREE"),
        ("1:1:2:2:2", "LEVEL:DEGREE"),
    ):
        assert main([*argv, bad]) == 2
        assert why in capsys.readouterr().err
    assert len(asked) == 3


@pytest.mark.parametrize("case", ["1-GB", "2B-GA"])
def test_a_record_carries_the_checksum_of_its_content(case):
    """Every shipped record is written with its checksum (python -m studies.convergence
    --reduce-records writes it), so an edit by hand is told from the record."""
    from postprocess.convergence_record import checksum, checksum_problem

    conv = read_json(RECORDS / case / STUDY_FILE)
    assert conv.get("checksum") == checksum(conv) and checksum_problem(conv) is None


def test_an_edited_record_gives_no_plus_minus_and_is_named(tmp_path, capsys):
    """Issue 57: a record edited by hand (one U made smaller) was read as a record. Its
    checksum no longer matches: it is skipped, named in the note and in ``skipped`` (which
    the driver turns into warnings), and the summary has no ± from it."""
    import shutil

    from studies.convergence.driver import write_study

    records = tmp_path / "records"
    shutil.copytree(RECORDS / "1-GB", records / "1-GB")
    path = records / "1-GB" / STUDY_FILE
    conv = read_json(path)
    write_study(path, conv)  # as the driver writes it
    gb = load_study_case("1-GB")
    good = summary_uncertainty(gb, 1, 1, tmp_path / "results", records=records)
    assert good["uncertainty"] and "skipped" not in good["uncertainty_source"]
    edited = read_json(path)
    edited["scalars"]["My_pin"]["uncertainty"]["L1P1"] /= 10
    write_json(path, edited)
    got = summary_uncertainty(gb, 1, 1, tmp_path / "results", records=records)
    assert got["uncertainty"] is None
    (why,) = got["uncertainty_source"]["skipped"]
    assert str(path) in why and "checksum does not match" in why
    assert "checksum does not match" in got["uncertainty_source"]["note"]
    # and --unless-recorded, which would solve the ladder again, says why
    assert recorded(gb, conv["ladder"], records) is None
    assert "a record is skipped" in capsys.readouterr().out

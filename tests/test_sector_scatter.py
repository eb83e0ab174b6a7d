"""The scatter of a root stress between equally valid sectors (studies.convergence.scatter) puts
a floor under the sector part of its U (studies.convergence.reduction.root_stress_split), and
studies.convergence.sector_scatter keeps it with a convergence record only for the record's inputs,
case level and position. Nothing here solves anything."""

import shutil

import pytest

from cases.study_case import inputs_hash, load_study_case, without_variant
from meshing.sizing import LEVELS
from meshing.submodel import submodel_level
from studies.cli import EXIT_INVALID_INPUT
from studies.convergence.driver import reduce_records, write_study
from studies.convergence.reduction import reduce_study, scalar_table
from studies.convergence.scatter import (
    carried_scatter,
    case_level_inputs,
    other_size_spreads,
    scatter_floors,
    spread,
)
from studies.convergence.sector_scatter import main, record_scatter
from studies.files import read_json, write_json
from studies.uncertainty import RECORDS


def _variant(name, fillet, sun, ring_tangent, order=1):
    return {
        "variant": name,
        "geometry_order": order,
        "sizes": {"fillet": fillet},
        "surface": {"sun": sun, "ring": 600.0},
        "tangent": {"sun": sun - 50.0, "ring": ring_tangent},
    }


ROWS = [
    _variant("2:0.15", 0.15, 867.3, 636.5),
    _variant("2:0.1", 0.1, 877.0, 634.4),
    _variant("1:0.1", 0.1, 866.4, None),  # a location whose ISO point was not read
    _variant("3:0.1", 0.1, 864.6, 633.3),
    _variant("2:0.1:c", 0.1, 700.0, 500.0, order=2),  # curved: another geometry, left out
]


def test_the_spread_is_taken_over_the_straight_variants_of_one_read_fillet():
    out = other_size_spreads(ROWS)
    assert list(out) == [0.1]  # 0.15 mm was read on one set of other sizes only
    assert out[0.1]["variants"] == ["2:0.1", "1:0.1", "3:0.1"]
    s = out[0.1]["spread"]
    sun = [877.0, 866.4, 864.6]  # (max - min) / mean, by hand: 12.4 / 869.33
    assert s["bending_stress.sun"] == pytest.approx(12.4 / (sum(sun) / 3), rel=1e-12)
    assert s["bending_stress_tangent.sun"] == pytest.approx(12.4 / (sum(sun) / 3 - 50.0))
    assert s["bending_stress.ring"] == 0.0  # the same value on every sector
    # the ring's ISO point on two of the three sectors: their spread
    assert s["bending_stress_tangent.ring"] == pytest.approx(1.1 / 633.85, rel=1e-12)
    assert spread([1.0]) is None and spread([0.0, 0.0]) is None
    assert list(other_size_spreads(ROWS, geometry_order=2)) == []


def test_the_floor_is_the_largest_spread_of_the_case_level():
    entries = [
        {"level": 1, "spread": {"a": 0.01, "b": 0.03}},
        {"level": 1, "spread": {"a": 0.02}},
        {"level": 2, "spread": {"a": 0.5, "c": 0.5}},
    ]
    assert scatter_floors(entries, 1) == {"a": 0.02, "b": 0.03}
    assert scatter_floors(entries, 2) == {"a": 0.5, "c": 0.5}
    assert scatter_floors([], 1) == {}


def _rows() -> list[dict]:
    """Ladder runs at levels 0-2 whose sector ladder (0.15 / 0.1 / 0.08 mm, read on level 1's
    driver) agrees to 0.2 % by chance: its U is far below a 3 % scatter."""
    sub = {0.15: 800.0, 0.1: 801.0, 0.08: 800.4}
    rows = []
    for level in (0, 1, 2):
        h, f = LEVELS[level].fine, submodel_level(level).fillet
        drv = 800.0 * (1.0 - 0.02 * h * h)
        extra = (0.1, 0.08) if level == 1 else (0.15,)
        rows.append(
            {
                "label": f"L{level}P1",
                "level": level,
                "degree": 1,
                "dofs": int(2e5 / h**3),
                "h_mm": {"fine": h, "fillet": f},
                "grid_points_total": 100,
                "time_s": {"total": 10.0, "factorization": 1.0, "compliance": 1.0},
                "peak_rss_mb": 1024.0,
                "scalars": {"bending_stress.ring": drv * sub.get(f, 799.0) / 800.0},
                "fillet_scalars": {
                    f"{x:g}": {"bending_stress.ring": drv * sub[x] / 800.0} for x in extra
                },
            }
        )
    return rows


def test_a_scatter_above_the_ladder_raises_the_sector_u_and_one_below_changes_nothing():
    rows, key = _rows(), "bending_stress.ring"
    bare = scalar_table(rows, case_level=1)[key]
    assert bare["split"]["sector_floor"] is None and "not measured" in bare["note"]
    u_sub = bare["split"]["submodel"]["uncertainty"]
    assert max(u_sub) < 0.01  # the three sectors agree: a small ladder U
    floored = scalar_table(rows, case_level=1, floors={key: 0.03})[key]
    assert floored["split"]["sector_floor"] == 0.03 and "sector scatter 3.00%" in floored["note"]
    assert floored["extrapolated"] == bare["extrapolated"]  # the value is not touched
    assert floored["split"]["submodel"] == bare["split"]["submodel"]  # the ladder's own U kept
    for lab in ("L1P1", "L2P1"):  # on the ladder: the driver's U + the floor
        drv = bare["uncertainty"][lab] - u_sub[("L1P1", "L2P1").index(lab)]
        assert floored["uncertainty"][lab] == pytest.approx(drv + 0.03, rel=1e-12)
    # level 0's coarser sector: the step to the case's sector + the floored U there
    assert floored["uncertainty"]["L0P1"] == pytest.approx(
        bare["uncertainty"]["L0P1"] - u_sub[0] + 0.03, rel=1e-12
    )
    low = scalar_table(rows, case_level=1, floors={key: 1e-6})[key]
    assert low["uncertainty"] == bare["uncertainty"]


def test_a_run_of_another_degree_on_the_same_sectors_takes_the_floor_too():
    rows, key = _rows(), "bending_stress.ring"
    p2 = {
        **rows[0],
        "label": "L0P2",
        "degree": 2,
        "fillet_scalars": {},
        "scalars": {key: rows[1]["scalars"][key]},
    }
    bare = scalar_table([*rows, p2], case_level=1)[key]["uncertainty"]["L0P2"]
    assert bare < 0.02  # the spread of the ladder's values with it
    floored = scalar_table([*rows, p2], case_level=1, floors={key: 0.05})[key]
    assert floored["uncertainty"]["L0P2"] == pytest.approx(0.05, rel=1e-12)


def test_a_study_is_reduced_with_the_scatter_of_its_case_level_only():
    rows = _rows()
    conv = {"case_level": 1, "ladder_degree": 1, "runs": rows}
    u = reduce_study(conv)["scalars"]["bending_stress.ring"]["uncertainty"]["L1P1"]
    other = {**conv, "sector_scatter": [{"level": 2, "spread": {"bending_stress.ring": 0.05}}]}
    assert reduce_study(other)["scalars"]["bending_stress.ring"]["uncertainty"]["L1P1"] == u
    own = {**conv, "sector_scatter": [{"level": 1, "spread": {"bending_stress.ring": 0.05}}]}
    assert reduce_study(own)["scalars"]["bending_stress.ring"]["uncertainty"]["L1P1"] > u + 0.04


# ------------------------------------------------------------ keeping it with the record
def _setup(tmp_path, **key):
    """A copy of 1-GB's record without the scatter kept with it, reduced so, and a
    sector_sizes file of its case level and roll."""
    records, out = tmp_path / "records", tmp_path / "out"
    shutil.copytree(RECORDS / "1-GB", records / "1-GB")
    path = records / "1-GB" / "convergence.json"
    write_study(path, {k: v for k, v in read_json(path).items() if k != "sector_scatter"})
    reduce_records(records)
    study = load_study_case("1-GB")
    inputs = inputs_hash(without_variant(study))  # a diagnostic sets its sizes itself
    sizes = {
        "case": "1-GB",
        "level": 1,
        "roll": 0.0,
        "key": {"inputs": inputs, "code_hash": "abc", "level": 1, "roll": 0.0},
        "variants": ROWS,
    }
    sizes.update(key)
    (out / "1-GB").mkdir(parents=True)
    write_json(out / "1-GB" / "sector_sizes_L1.json", sizes)
    return records, out


def test_the_scatter_is_kept_with_the_record_and_raises_its_root_stress_u(tmp_path):
    records, out = _setup(tmp_path)
    before = read_json(records / "1-GB" / "convergence.json")
    u0 = before["scalars"]["bending_stress.sun"]["uncertainty"]["L1P1"]
    path = record_scatter("1-GB", 1, out, records)
    rec = read_json(path)
    (entry,) = rec["sector_scatter"]
    assert (entry["level"], entry["roll"], entry["fillet_mm"]) == (1, 0.0, 0.1)
    assert entry["code_hash"] == "abc" and entry["geometry_order"] == 1
    s = entry["spread"]["bending_stress.sun"]
    sp = rec["scalars"]["bending_stress.sun"]["split"]
    assert sp["sector_floor"] == s
    # the record's sector U at its own 0.15 mm fillet was below the scatter: now the floor
    assert max(sp["submodel"]["uncertainty"]) < s
    drv = sp["driver"]["uncertainty"][sp["driver"]["at"].index("L1P1")]
    assert rec["scalars"]["bending_stress.sun"]["uncertainty"]["L1P1"] == pytest.approx(drv + s)
    assert rec["scalars"]["bending_stress.sun"]["uncertainty"]["L1P1"] > u0
    assert rec["runs"] == before["runs"] and rec.get("reproduced") == before.get("reproduced")
    report = (records / "1-GB" / "report.md").read_text()
    assert "Sector scatter measured" in report and "source hash abc" in report
    # the targeted root stresses the measurement does not hold (ROWS: the sun and the ring)
    # are named: their sector U is the ladder's alone
    bare = next(ln for ln in report.splitlines() if ln.startswith("**Targeted without"))
    assert "pinion_sun_side" in bare and "pinion_ring_side" in bare
    assert "bending_stress.sun" not in bare and "bending_stress.ring" not in bare
    # measured again: the entry of the same level, roll and fillet replaced, not added
    record_scatter("1-GB", 1, out, records)
    assert len(read_json(path)["sector_scatter"]) == 1
    # another position with a larger scatter of the sun: a second entry, and the floor
    sizes = read_json(out / "1-GB" / "sector_sizes_L1.json")
    sizes["roll"] = 0.0718
    sizes["variants"][1]["surface"]["sun"] = 900.0
    write_json(out / "1-GB" / "sector_sizes_L1.json", sizes)
    rec = read_json(record_scatter("1-GB", 1, out, records))
    assert [e["roll"] for e in rec["sector_scatter"]] == [0.0, 0.0718]
    wider = rec["sector_scatter"][1]["spread"]["bending_stress.sun"]
    assert wider > s and rec["scalars"]["bending_stress.sun"]["split"]["sector_floor"] == wider


@pytest.mark.parametrize(
    "change, words",
    [
        ({"key": {"inputs": "other", "code_hash": "abc"}}, "other inputs"),
        ({"variants": ROWS[:2]}, "more than one set of other sizes"),
    ],
)
def test_a_file_that_does_not_belong_to_the_record_is_refused(tmp_path, capsys, change, words):
    records, out = _setup(tmp_path, **change)
    rec = (records / "1-GB" / "convergence.json").read_text()
    code = main(["--case", "1-GB", "--level", "1", "--out", str(out), "--records", str(records)])
    err = capsys.readouterr().err
    assert code == EXIT_INVALID_INPUT and words in err and "Traceback" not in err
    assert (records / "1-GB" / "convergence.json").read_text() == rec  # untouched


def test_a_record_solved_from_other_inputs_is_refused(tmp_path, capsys):
    """The bearing and the load are not in a record's match key, so a case file changed
    since its record still finds it; the scatter of today's inputs does not go under it."""
    records, out = _setup(tmp_path)
    path = records / "1-GB" / "convergence.json"
    rec = read_json(path)
    for run in rec["runs"]:
        run["reuse_key"]["inputs_hash"] = "other"
    write_study(path, rec)
    argv = ["--case", "1-GB", "--out", str(out), "--records", str(records)]
    assert main(argv) == EXIT_INVALID_INPUT
    assert "level-1 run was solved from other inputs" in capsys.readouterr().err
    assert "sector_scatter" not in read_json(path)


def test_another_level_or_a_missing_file_is_refused(tmp_path, capsys):
    records, out = _setup(tmp_path)
    shutil.copy(out / "1-GB" / "sector_sizes_L1.json", out / "1-GB" / "sector_sizes_L2.json")
    argv = ["--case", "1-GB", "--out", str(out), "--records", str(records)]
    assert main([*argv, "--level", "2"]) == EXIT_INVALID_INPUT
    assert "the record of 1-GB is of case level 1" in capsys.readouterr().err
    assert main([*argv, "--level", "0"]) == EXIT_INVALID_INPUT
    err = capsys.readouterr().err
    assert "run make sector-sizes CASE=1-GB SECTOR_LEVEL=0 SECTOR_ROLL=0 first" in err


def test_a_record_solved_again_keeps_the_scatter_of_its_sectors(tmp_path):
    """Solving a ladder again and recording it (make convergence-main RECORD=1) keeps the
    scatter measured on the same inputs and case level: the record before 2026-11-30 lost
    it, and with it the floor under its root stresses' sector U, with nothing to show why
    but a smaller ±."""
    from studies.convergence.driver import record

    records = tmp_path / "records"
    shutil.copytree(RECORDS / "1-GB", records / "1-GB")
    path = records / "1-GB" / "convergence.json"
    old = read_json(path)
    entry = {
        "level": 1,
        "roll": 0.0,
        "fillet_mm": 0.1,
        "variants": ["1:0.1", "2:0.1"],
        "geometry_order": 1,
        "code_hash": "abc",
        "spread": {"bending_stress_recovered.ring": 0.2},
    }
    write_study(path, {**old, "sector_scatter": [entry]})
    new = {k: v for k, v in old.items() if k not in ("sector_scatter", "recorded")}
    assert carried_scatter(read_json(path), new) == [entry]
    # another case level, gear set or inputs of the case-level run: not the same sectors
    assert carried_scatter(read_json(path), {**new, "case_level": 2}) == []
    assert carried_scatter(read_json(path), {**new, "match": {"gearset": "x"}}) == []
    other = [
        dict(r, reuse_key={**r["reuse_key"], "inputs_hash": "other"}) if r["level"] == 1 else r
        for r in new["runs"]
    ]
    assert carried_scatter(read_json(path), {**new, "runs": other}) == []
    # recorded again: kept, and the record reduced with it (its report names it)
    study = tmp_path / "study"
    study.mkdir()
    (study / "report.md").write_text("# the study, reduced without the scatter\n")
    rec = read_json(record(study, new, records))
    assert rec["sector_scatter"] == [entry] and rec["recorded"]["date"]
    split = rec["scalars"]["bending_stress_recovered.ring"]["split"]
    assert split["sector_floor"] == 0.2
    assert "source hash abc" in (records / "1-GB" / "report.md").read_text()
    # a record of other inputs: nothing carried, the study's own report copied
    write_study(path, {**read_json(path), "runs": other})
    rec = read_json(record(study, new, records))
    assert "sector_scatter" not in rec
    assert (records / "1-GB" / "report.md").read_text().startswith("# the study, reduced")


def test_the_case_level_inputs_are_the_ladder_runs_not_the_runs_off_it():
    """The scatter is carried where the case level's ladder run (the sector ladder's driver)
    was solved from the same inputs; a run off the ladder at that level (L1P1F2, L1P2) is not
    it, and must not stop the carry (a dropped floor prints a smaller ±)."""
    rec = read_json(RECORDS / "1-GB" / "convergence.json")
    new = {k: v for k, v in rec.items() if k not in ("sector_scatter", "recorded")}
    base = [r for r in rec["runs"] if r["label"] in ("L0P1", "L1P1", "L2P1")]
    l1 = next(r for r in base if r["label"] == "L1P1")
    other = {**l1, "reuse_key": {**l1["reuse_key"], "inputs_hash": "other"}}
    for off in (
        {**other, "label": "L1P1F2", "flank_level": 2},
        {**other, "label": "L1P2", "degree": 2},
    ):
        with_off = {**new, "runs": [*base, off]}
        assert case_level_inputs(with_off) == {l1["reuse_key"]["inputs_hash"]}
        assert carried_scatter(rec, with_off) == rec["sector_scatter"]
    # the ladder run itself of other inputs: not the same sectors
    assert carried_scatter(rec, {**new, "runs": [*base[:1], other, *base[2:]]}) == []


def test_a_record_replacing_an_unreadable_one_carries_nothing_and_says_so(tmp_path, capsys):
    """A damaged record file does not stop a ladder's new record after hours of solving
    (before: exit 3 after the ladder); it carries no scatter and says so."""
    from studies.convergence.driver import record

    records = tmp_path / "records"
    shutil.copytree(RECORDS / "1-GB", records / "1-GB")
    path = records / "1-GB" / "convergence.json"
    new = {k: v for k, v in read_json(path).items() if k not in ("sector_scatter", "recorded")}
    path.write_text('{"cut off')
    study = tmp_path / "study"
    study.mkdir()
    rec = read_json(record(study, new, records))
    assert "sector_scatter" not in rec and rec["recorded"]["date"]
    assert "cannot be read" in capsys.readouterr().out


def test_a_study_of_this_machine_takes_the_scatter_kept_with_the_record(tmp_path, capsys):
    """make sector-scatter keeps the scatter with the record; the same ladder's study under
    this machine's results (the same runs, so solved by the same code) stands before the
    record in the ± lookup, which reads a study as written, so it must carry the floor when
    it is written (after the record's scatter: studies.convergence.driver.with_recorded_scatter) and
    when the scatter is kept after it (studies.convergence.sector_scatter.carry_to_this_machine)."""
    from studies.convergence.driver import with_recorded_scatter
    from studies.convergence.sector_scatter import carry_to_this_machine
    from studies.uncertainty import summary_uncertainty

    records, results = tmp_path / "records", tmp_path / "results"
    shutil.copytree(RECORDS / "1-GB", records / "1-GB")
    rec = read_json(records / "1-GB" / "convergence.json")
    assert rec["sector_scatter"]  # the record keeps its scatter
    mine = results / "convergence" / "1-GB" / "convergence.json"
    mine.parent.mkdir(parents=True)
    bare = {k: v for k, v in rec.items() if k not in ("sector_scatter", "recorded")}
    key = "bending_stress_recovered.ring"
    own = reduce_study(bare)["scalars"][key]["uncertainty"]["L1P1"]
    floored = reduce_study(rec)["scalars"][key]["uncertainty"]["L1P1"]
    assert floored > own  # 1-GB: the ring's sector scatter lies above its sector ladder's U

    def lookup():
        return summary_uncertainty(load_study_case("1-GB"), 1, 1, results, records=records)

    # written after the record's scatter: the driver carries it
    write_study(mine, reduce_study(with_recorded_scatter(bare, records)))
    got = lookup()
    src = got["uncertainty_source"]
    assert src["convergence_study"] == str(mine)  # this machine's study first
    assert got["uncertainty"][key] == pytest.approx(floored, rel=1e-12)
    assert src["sector_scatter_from"] == str(records / "1-GB" / "convergence.json")
    assert "kept with" in capsys.readouterr().out
    # written before it: keeping the scatter with the record reduces this study again
    write_study(mine, reduce_study(bare))
    assert lookup()["uncertainty"][key] == pytest.approx(own, rel=1e-12)
    carry_to_this_machine(mine, records)
    assert lookup()["uncertainty"][key] == pytest.approx(floored, rel=1e-12)
    assert (mine.parent / "report.md").is_file()
    # a record whose case-level run was solved from other inputs lends it nothing
    rec["runs"] = [
        dict(r, reuse_key={**r["reuse_key"], "inputs_hash": "other"}) if r["level"] == 1 else r
        for r in rec["runs"]
    ]
    write_study(records / "1-GB" / "convergence.json", rec)
    assert with_recorded_scatter(bare, records) is bare
    # and a study that cannot be read is named and left
    mine.write_text("{ not json")
    carry_to_this_machine(mine, records)
    assert "cannot be read" in capsys.readouterr().out

"""planetary-fe sweep (studies.sweep): a field of a case or of its gear set over several
values, every variant a case file of its own solved on the first one's bodies; and a
position whose load reaches past its zone band solved on a wider one (studies.position).

The solved tests run 1-GB's gear set at level 0, one position, the root stress on the global
fillets (about 10 s a variant)."""

import dolfinx_solver  # noqa: F401 - must precede dolfinx

# isort: split
import tomllib
from pathlib import Path

import pytest
from mpi4py import MPI

from cases.study_case import load_study_case
from solvers.body_store import BodyStore
from studies.cli import EXIT_INVALID_INPUT, EXIT_OK, InputError
from studies.files import read_json
from studies.position import solve_position
from studies.run import run_study
from studies.settings import RunSettings
from studies.sweep import CLOSED_FORM, main, parse_set, sweep_folder, sweep_record, variants

QUICK = """name = "quick"
gearset = "case1"
description = "1-GB at level 0, one position, root stress on the global fillets"
[bearing]
radial_stiffness = 2.33e6
tilting_stiffness = {tilt}
[model]
scene = "one_branch"
level = 0
positions = 1
[numerics]
root_stress = "global"
{numerics}
"""


def _case(folder: Path, tilt="8.8e7", numerics="") -> Path:
    path = folder / "quick.toml"
    path.write_text(QUICK.format(tilt=tilt, numerics=numerics))
    return path


def test_a_set_is_a_field_and_its_values():
    sw = parse_set("bearing.tilting_stiffness=8.8e6, 8.8e7,1e9")
    assert sw.field == "bearing.tilting_stiffness" and sw.labels == ("8.8e6", "8.8e7", "1e9")
    assert sw.values == (8.8e6, 8.8e7, 1e9)
    assert parse_set("numerics.contact_model=line,zone").values == ("line", "zone")
    assert parse_set("gearset.input_torque=700,1378.7").values == (700, 1378.7)
    for bad, why in (
        ("bearing.tilting_stiffness", "FIELD=V1,V2"),
        ("bearing.tilting_stiffness=", "FIELD=V1,V2"),
        ("bearing.tilting_stiffness=1,,2", "FIELD=V1,V2"),
        ("tilting_stiffness=1,2", "<table>.<key>"),
        ("bearings.tilting_stiffness=1,2", "not a table of a case file"),
        ("bearing.tilting_stiffness=1,1", "given twice"),
        ("numerics.contact_model=a b", "names its variant"),
    ):
        with pytest.raises(InputError, match=why):
            parse_set(bad)


def test_variants_set_the_field_in_the_case_or_its_gear_set(tmp_path):
    case = _case(tmp_path)
    out = tmp_path / "sweep"
    (target, data, gs), _ = variants(str(case), parse_set("bearing.tilting_stiffness=1e6,2e6"), out)
    assert target == out / "quick_1e6.toml" and data["name"] == "quick_1e6"
    assert data["bearing"]["tilting_stiffness"] == 1e6 and gs is None
    assert data["gearset"] == "case1"  # a bare name still finds the shipped gear set
    [(target, data, gs)] = variants(str(case), parse_set("gearset.gears.pinion.teeth=27"), out)
    assert gs["gears"]["pinion"]["teeth"] == 27 and gs["gears"]["sun"]["teeth"] == 35
    assert data["gearset"] == str((out / "quick_27.gearset.toml").resolve())
    with pytest.raises(InputError, match=r"has no gears\.planet \(it has: sun, pinion, ring\)"):
        variants(str(case), parse_set("gearset.gears.planet.teeth=27"), out)
    with pytest.raises(InputError, match="has 2 meshes"):
        variants(str(case), parse_set("gearset.meshes.2.centre_distance=52"), out)


def test_an_invalid_value_stops_the_sweep_before_solving(tmp_path, capsys):
    case = _case(tmp_path)
    code = main([str(case), "--set", "bearing.tilting_stiffness=8.8e7,-1", "--out", str(tmp_path)])
    assert code == EXIT_INVALID_INPUT
    err = capsys.readouterr().err
    # the variant file and the field are named; nothing is solved
    assert "quick_-1.toml" in err and "tilting_stiffness" in err
    folder = sweep_folder(tmp_path, str(case), "bearing.tilting_stiffness")
    assert not (folder / "quick_8.8e7").exists()
    assert main([str(case), "--set", "bearing=1"]) == EXIT_INVALID_INPUT


def test_a_sweep_equals_its_variants_run_one_by_one(tmp_path):
    case = _case(tmp_path)
    args = [str(case), "--set", "bearing.tilting_stiffness=8.8e7,8.8e8", "--quiet"]
    assert main([*args, "--out", str(tmp_path)]) == EXIT_OK
    folder = sweep_folder(tmp_path, str(case), "bearing.tilting_stiffness")
    record = read_json(folder / "sweep.json")
    assert [r["value"] for r in record["variants"]] == [8.8e7, 8.8e8]
    assert (folder / "sweep.md").is_file() and (folder / "sweep.png").stat().st_size > 0
    # the second variant solved on the first one's bodies: its compliance columns were kept
    second = read_json(folder / "quick_8.8e8" / "positions" / "0.json")["timings"]
    assert second["compliance_solves"] <= 0.05 * second["compliance_columns_kept"]
    for row in record["variants"]:
        alone = run_study(folder / row["case_file"], tmp_path / "alone", store=BodyStore())
        assert tomllib.loads((folder / row["case_file"]).read_text())["name"] == row["folder"]
        for q, v in row["quantities"].items():
            # the same model; the columns read instead of solved: round-off of the multi-RHS
            # blocking, amplified at most by the contact solve (1e-9 measured in
            # tests/test_body_columns.py)
            ref = alone.get(q)
            if ref is None:  # a mesh or fillet quantity: from the summary's tables
                continue
            assert v == pytest.approx(ref, rel=1e-8, abs=1e-9), q
        stress = row["quantities"]["root stress sun (MPa)"]
        assert stress == pytest.approx(alone["bending_stress_recovered"]["sun"], rel=1e-8)
        # each moment's closed form at the variant's own centroids (singh2007 Table 7)
        for k, v in alone["analytic"]["at_fe_ZS_ZR"].items():
            assert row["quantities"][k + CLOSED_FORM] == pytest.approx(v, rel=1e-8), k
    # a summary an earlier sweep left (other inputs or code) is not read as this one's
    sw = parse_set("bearing.tilting_stiffness=8.8e7,8.8e8")
    files = [folder / r["case_file"] for r in record["variants"]]
    stale = sweep_record(str(case), sw, files, folder, [("other inputs", "other code")] * 2)
    assert all(r["quantities"] is None for r in stale["variants"])
    assert all("other inputs or code" in r["missing"] for r in stale["variants"])
    # a softer bearing carries less tilting moment (the paper's Fig. 6 trend)
    my = [r["quantities"]["My_pin"] for r in record["variants"]]
    assert my[0] < my[1]


def test_a_load_past_the_band_is_solved_on_the_band_that_holds_it(tmp_path):
    """1-GC's soft bearing on the 40 um band of 1-GB: refused before; now widened to the limit
    the reach check names, and the answer is that of a case that sets that limit."""
    study = load_study_case(_case(tmp_path, tilt="8.8e6"))
    store = BodyStore()
    pos = solve_position(study, 0.0, MPI.COMM_WORLD, RunSettings(), store=store)
    w = pos["zone_gap_widened"]
    assert w["from_um"] == 40.0 and w["to_um"] > 40.0 and pos["zone_gap_limit_um"] == w["to_um"]
    # the reach check holds on the band it was solved on (solvers.zone_reach: 0.5 x limit)
    assert max(pos["zone_reach_um"].values()) <= 0.5 * w["to_um"]
    wide = load_study_case(
        _case(tmp_path, tilt="8.8e6", numerics=f"zone_gap_limit_um = {w['to_um']:g}")
    )
    ref = solve_position(wide, 0.0, MPI.COMM_WORLD, RunSettings(), store=store)
    assert ref["zone_gap_widened"] is None
    for q in ("Mx_pin", "My_pin", "ZS", "ZR"):
        assert pos[q] == pytest.approx(ref[q], rel=1e-9), q

"""The convergence study and the study driver agree (level 0, one position, serial): a run of
the study measures exactly the scalars the summary reports, and the driver writes the
uncertainty of the matching study into summary.json, which the case-1 report prints."""

from __future__ import annotations

import contextlib
import io
import json

import pytest

from cases.study_case import load_study_case
from meshing.submodel import submodel_level
from postprocess.run_scalars import summary_scalars
from solvers.body_store import BodyStore
from studies import run as study_run
from studies.case_options import CaseOptions
from studies.convergence.position_runs import FILLET_SCALARS, solve_run
from studies.convergence.reduction import scalar_table
from studies.files import write_json
from studies.paper.case1_report import write_report
from studies.progress import Progress
from studies.provenance import code_hash
from studies.uncertainty import STUDY_FILE, match_key


@pytest.fixture(scope="module")
def level0(tmp_path_factory):
    """1-GA at level 0, one position: the study driver's summary (with a convergence study of
    the gear set under the results folder) and a convergence run of the same position."""
    out = tmp_path_factory.mktemp("results")
    # the submodel ladder's reading on the run's own submodel (level 0: level 1's sizes, 0.2 mm
    # read fillets): the plumbing of fillet_scalars, checked against the run's own root stress.
    # One store for both runs: the study driver's solve then reuses the bodies and sectors
    store = BodyStore()
    row = solve_run("1-GA", 0, 1, 1, submodel_levels=(0,), store=store)
    rows = []
    for level, seconds in ((0, 10.0), (1, 20.0), (2, 110.0)):  # a ladder around the real run
        scale = {0: 1.0, 1: 0.5, 2: 0.2}[level]
        scalars = {k: v * (1.0 + 0.01 * scale) for k, v in row["scalars"].items()}
        rows.append(
            {
                **row,
                "level": level,
                "label": f"L{level}P1",
                "scalars": scalars,
                "h_mm": {"fine": 1.0 - 0.3 * level, "fillet": 0.6 - 0.15 * level},
                "dofs": row["dofs"] * 3**level,
                "time_s": {"total": seconds},
            }
        )
    table = scalar_table(rows)
    study = load_study_case("1-GB")  # the study of another case of the same gear set
    # solved by today's code, as a make's own study would be: it then stands before the
    # recorded 1-GB study (a study of other code would not, studies.uncertainty)
    conv = {
        "case": "1-GB",
        "match": match_key(study),
        "labels": ["L0P1", "L1P1", "L2P1"],
        "positions": 1,
        "code_hash": code_hash(),
        "scalars": table,
    }
    (out / "convergence" / "1-GB").mkdir(parents=True)
    write_json(out / "convergence" / "1-GB" / STUDY_FILE, conv)
    progress = Progress(out=io.StringIO(), err=io.StringIO(), quiet=True)
    stray = io.StringIO()  # what the solve itself writes to the process's stderr
    with contextlib.redirect_stderr(stray):
        summary = study_run.run_study(
            "1-GA", out, options=CaseOptions(level=0, positions=1), progress=progress, store=store
        )
    return out, summary, row, table, stray.getvalue()


def test_a_convergence_run_measures_what_the_summary_reports(level0):
    _, summary, row, _, _ = level0
    reported = summary_scalars(summary, "single_pinion")
    assert set(reported) == set(row["scalars"])
    for key, value in reported.items():
        # the same position solved twice in one process: the same numbers to round-off (the
        # root-stress sectors too: one GAMG threshold whether a sector is solved once, as
        # here, or kept for a mesh cycle, as in the case run)
        assert row["scalars"][key] == pytest.approx(value, rel=1e-9, abs=1e-9), key


def test_a_quiet_case_run_writes_nothing_to_stderr(level0):
    """``studies.run --quiet``: stderr carries warnings and errors only (studies.progress), so
    the solve below it writes no progress of its own (the root-stress sectors' lines go to a
    ladder run's log only, through ``sector_log``)."""
    *_, stray = level0
    assert stray == ""


def test_summary_carries_the_uncertainty_of_its_gear_set(level0):
    out, summary, _, table, _ = level0
    on_disk = json.loads((out / "1-GA" / "summary.json").read_text())
    assert on_disk["uncertainty"]["My_pin"] == table["My_pin"]["uncertainty"]["L0P1"] > 0
    assert on_disk["uncertainty_source"]["case"] == "1-GB"
    assert on_disk["uncertainty_source"]["run"] == "L0P1"
    assert on_disk["uncertainty_source"]["convergence_study"].endswith("1-GB/convergence.json")
    text = write_report(out).read_text()
    my = summary["My_pin"] * table["My_pin"]["uncertainty"]["L0P1"]
    assert f"{summary['My_pin']:.1f} ± {my:.1f}" in text
    assert "1-GA from" in text and "convergence study" in text


def test_a_submodel_reading_at_the_own_fillet_repeats_the_run(level0):
    _, _, row, _, _ = level0
    again = row["fillet_scalars"][f"{submodel_level(0).fillet:g}"]
    keys = [k for k in row["scalars"] if k.startswith(tuple(f"{n}." for n in FILLET_SCALARS))]
    assert keys and set(again) == set(keys)
    assert any(k.startswith("bending_stress_tangent_recovered.") for k in keys)
    for k in keys:  # the same submodel mesh, driver, loads and first guess
        assert again[k] == pytest.approx(row["scalars"][k], rel=1e-6), k
    assert row["fillet_ladder_s"] > 0.0


def test_a_run_with_the_next_levels_flanks_refines_the_flanks_and_grid_only(level0):
    """A level-0 run with level 1's flanks (``--extra 0:1:1``): its flank elements and
    contact grid are level 1's, its fillets and root-stress sectors level 0's. Level 0's
    moments move by 1.5-2 % to level 1's, most of it from the flanks
    (studies.convergence.driver_sizes):
    the run's moments differ from level 0's but stay within that step's size. Its root
    stress is not read (the moments are the same global solve without the sectors), so the
    fillet it names is the global model's, level 0's."""
    from meshing.sizing import LEVELS

    _, _, row, _, _ = level0
    fine = solve_run("1-GA", 0, 1, 1, numerics={"root_stress": "none"}, flank_level=1)
    assert fine["flank_level"] == 1 and fine["level"] == 0
    assert fine["h_mm"]["fine"] == LEVELS[1].fine
    assert fine["h_mm"]["global_fillet"] == row["h_mm"]["global_fillet"] == LEVELS[0].fillet
    assert fine["h_mm"]["fillet"] == LEVELS[0].fillet
    assert fine["dofs"] > row["dofs"] and fine["grid_points_total"] > row["grid_points_total"]
    for key in ("My_pin", "M_LOA_sun", "M_LOA_ring"):
        a, b = row["scalars"][key], fine["scalars"][key]
        assert a != b and abs(b - a) < 0.05 * abs(a), key  # 5 %: over twice the step's size

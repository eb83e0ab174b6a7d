"""The study driver: positions over one base pitch, summary contract, pictures, restart keyed
by the inputs, partial failure (a study that fails part way keeps what it finished)."""

import io
import json
import math
import re
import shutil
from pathlib import Path

import pytest
from test_docs_outputs import check_run

from cases.study_case import load_study_case
from gears.contact_stress import iso6336_pitch_contact_stress
from gears.units import n_mm
from studies import run as study_run
from studies.case_options import CaseOptions
from studies.progress import Progress
from studies.settings import RunSettings

N_POS = 2
# what the module's study printed on stderr (warnings), filled by the fixture
STDERR = io.StringIO()


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    out = tmp_path_factory.mktemp("results")
    progress = Progress(out=io.StringIO(), err=STDERR)
    summary = study_run.run_study(
        "1-GA", out, options=CaseOptions(level=0, positions=N_POS), progress=progress
    )
    return out, summary


def test_roll_angles_span_one_base_pitch():
    case = load_study_case("1-GA")
    rolls = study_run.roll_angles(case, 5)
    # equally spaced, the last one a fifth of a sun tooth pitch short of a full pitch
    assert rolls[0] == 0.0
    assert rolls[-1] + rolls[1] == pytest.approx(2 * math.pi / 35, rel=1e-12)


def test_summary_contract(study):
    out, summary = study
    on_disk = json.loads((out / "1-GA" / "summary.json").read_text())
    assert on_disk == json.loads(json.dumps(summary))
    # The summary is made of the position files this run wrote, in roll order: its records
    # and means are checked against the files on disk (an independent copy), so a summary of
    # stale, reordered or other positions fails here.
    files = [
        json.loads((out / "1-GA" / "positions" / f"{k}.json").read_text()) for k in range(N_POS)
    ]
    rolls = study_run.roll_angles(load_study_case("1-GA"), N_POS)
    assert [f["roll"] for f in files] == [p["roll"] for p in summary["positions"]] == rolls
    for key in ("Mx_pin", "My_pin", "Mz_pin", "ZS", "ZR", "M_LOA_sun", "M_LOA_ring"):
        assert summary[key] == pytest.approx(sum(f[key] for f in files) / N_POS, rel=1e-12)
    for key in ("sun", "pinion_sun_side", "pinion_ring_side", "ring"):
        # root stress: the maximum over the mesh cycle, not the mean
        peak = max(f["bending_stress"][key] for f in files)
        assert summary["bending_stress"][key] == pytest.approx(peak, rel=1e-12)
        tangent = max(f["bending_stress"]["tangent"][key] for f in files)
        assert summary["bending_stress_tangent"][key] == pytest.approx(tangent, rel=1e-12)
    assert set(summary["contact_stress"]) == {"sun_pinion", "pinion_ring"}
    assert set(summary["bending_stress_iso6336_nominal"]) == {
        "sun",
        "pinion_sun_side",
        "pinion_ring_side",
        "ring",
    }
    assert summary["level"] == 0 and summary["dofs"] == files[0]["dofs"]
    # the zone model's clipped body correction: the largest over the positions
    clipped = max(f["timings"]["correction_clipped"] for f in files)
    assert summary["contact_correction_clipped"] == clipped and 0.0 <= clipped < 1.0
    assert summary["failed_positions"] == [] and summary["warnings"] == []
    # A picture that cannot be drawn, a field write that fails or an implausible stress is a
    # warning on stderr, not an error: none here.
    assert STDERR.getvalue() == ""
    # displacement fields of the first position for ParaView, one VTX folder per body
    assert sorted(p.name for p in (out / "1-GA" / "fields").iterdir()) == [
        "pinion.bp",
        "ring.bp",
        "sun.bp",
    ]
    for name in (
        "contact_pattern_sun-pinion.png",
        "contact_pattern_pinion-ring.png",
        "contact_patterns.png",
        "loaded_scene.png",
    ):
        assert (out / "1-GA" / name).is_file()


def test_physics_of_the_rigid_bearing_case(study):
    _, s = study
    # Contact stress against an independent value: ISO 6336-2 sigma_H0 at the pitch point
    # with Z_beta = 1, which is the Hertz stress under the mean line load (the mesh force
    # over the mean total contact line length), from the torque and the gear data alone.
    # With a rigid bearing the load is nearly uniform, so the FE mean over the loaded points
    # is close: it differs by the spread of sqrt(w / rho) along the path of contact and the
    # unloaded points left out (measured +2 % sun mesh, +13 % ring mesh at level 0).
    # [0.9, 1.3] catches a 35 % bias either way.
    gs = load_study_case("1-GA").gearset
    torque = n_mm(gs.torque_per_branch)  # on the sun; the pinion drives the ring with Zp / Zs
    pinion_torque = torque * gs.gears["pinion"].teeth / gs.gears["sun"].teeth
    for mesh, (a, b), t in (
        ("sun_pinion", ("sun", "pinion"), torque),
        ("pinion_ring", ("pinion", "ring"), pinion_torque),
    ):
        iso = iso6336_pitch_contact_stress(gs.pair(a, b), t, z_beta=False)["sigma_H0"]
        assert 0.9 < s["contact_stress_mean_loaded"][mesh] / iso < 1.3, mesh
    # Rigid bearing: a nearly centred pattern (singh2007 section 7), |Z| < 1/10 face width.
    assert abs(s["ZS"]) < 2.9 and abs(s["ZR"]) < 2.9
    # My_pin within 2 % of Table 7 at the FE's own ZS, ZR (see tests/test_gear_branch.py for
    # why 2 % and why the LOA moments are looser: the ring-mesh load centroid sits off the
    # pitch point, which the analytical model does not represent).
    assert s["My_pin"] == pytest.approx(s["analytic"]["at_fe_ZS_ZR"]["My_pin"], rel=0.02)


def test_restart_reuses_finished_positions(study, monkeypatch):
    out, summary = study

    def must_not_run(*args, **kwargs):
        raise AssertionError("a finished position was solved again")

    monkeypatch.setattr(study_run, "solve_position", must_not_run)
    again = study_run.run_study("1-GA", out, options=CaseOptions(level=0, positions=N_POS))
    assert again["My_pin"] == summary["My_pin"]
    assert again["positions_reused"] == list(range(N_POS))


def test_changed_inputs_are_solved_again(study, monkeypatch, tmp_path):
    """A finished position is reused only for the inputs that produced it: the same case
    file with another tilting stiffness (a user's edit) is solved again, not read back."""
    out, _ = study
    results = tmp_path / "results"
    shutil.copytree(out / "1-GA", results / "1-GA")
    case = load_study_case("1-GA")
    text = Path(case.path).read_text()
    assert "tilting_stiffness = 8.80e9" in text
    edited = tmp_path / "1-GA.toml"
    edited.write_text(text.replace("tilting_stiffness = 8.80e9", "tilting_stiffness = 8.80e7"))
    calls = []

    def stub(study, roll, *args, **kwargs):
        calls.append((study.bearing.tilting_stiffness, roll))
        raise RuntimeError("solver stubbed (test)")

    monkeypatch.setattr(study_run, "solve_position", stub)
    again = study_run.run_study(
        case.path, results, options=CaseOptions(level=0, positions=N_POS)
    )  # unchanged
    assert calls == [] and again["positions_reused"] == list(range(N_POS))
    with pytest.raises(RuntimeError, match="2 of 2 positions failed"):
        study_run.run_study(edited, results, options=CaseOptions(level=0, positions=N_POS))
    assert [c[0] for c in calls] == [8.80e7, 8.80e7]


def _lose_all_but(kept: int, out: Path, tmp_path: Path, monkeypatch) -> dict:
    """The study run again in ``tmp_path`` with only position ``kept`` finished (copied from
    ``out``) and every other one failing: the summary it keeps."""
    (tmp_path / "1-GA" / "positions").mkdir(parents=True)
    name = f"{kept}.json"
    (tmp_path / "1-GA" / "positions" / name).write_text(
        (out / "1-GA" / "positions" / name).read_text()
    )

    def fail(*args, **kwargs):
        raise RuntimeError("active set did not converge (test)")

    monkeypatch.setattr(study_run, "solve_position", fail)
    with pytest.raises(RuntimeError, match="1 of 2 positions failed"):
        study_run.run_study("1-GA", tmp_path, options=CaseOptions(level=0, positions=N_POS))
    return json.loads((tmp_path / "1-GA" / "summary.json").read_text())


def test_failed_position_keeps_finished_ones(study, monkeypatch, tmp_path):
    out, _ = study
    kept = _lose_all_but(0, out, tmp_path, monkeypatch)
    assert [p["roll"] for p in kept["positions"]] == [0.0]
    assert kept["failed_positions"][0]["position"] == 1
    assert "did not converge" in kept["failed_positions"][0]["error"]
    # the case report says so beside its values, which are over the finished position only
    from studies.paper.case1_report import write_report

    text = write_report(tmp_path).read_text()
    # the second of two (stored from 0, named from 1 as in the run's log)
    assert "**Warning: 1-GA lost position(s) 2 of 2** (first error: " in text
    assert "active set did not converge (test)" in text and "over the 1 that finished" in text


def test_a_failed_first_position_leaves_the_others_named_by_their_cycle_index(
    study, monkeypatch, tmp_path
):
    """With position 1 of 2 lost, the finished one is the cycle's second: the summary names
    it so (its record and where the root stress peaks), not by its place among the finished
    ones (it said position 0, the failed one, until 2026-11-29)."""
    out, summary = study
    kept = _lose_all_but(1, out, tmp_path, monkeypatch)
    assert [p["position"] for p in kept["positions"]] == [1]
    assert kept["positions"][0]["roll"] == summary["positions"][1]["roll"]
    assert [f["position"] for f in kept["failed_positions"]] == [0]
    at = [a for a in (kept["bending_stress_at"] or {}).values() if a]
    assert at and all(a["position"] == 1 for a in at)


def test_case1_report(study):
    from studies.paper.case1_report import write_report

    out, summary = study
    text = write_report(out).read_text()
    assert f"| 1-GA | 0 | {N_POS} | {summary['dofs']} |" in text
    assert "Rigid bearing" in text
    # the report quotes this run's numbers beside the closed form's (with the ± of the gear
    # set's recorded convergence study, where there is one: studies.uncertainty.RECORDS)
    at_z = summary["analytic"]["at_fe_ZS_ZR"]["My_pin"]
    mine, theirs = re.escape(f"{summary['My_pin']:.1f}"), re.escape(f"{at_z:.1f}")
    row = rf"\| My_pin \| {mine}( ± [0-9.]+)? \| {theirs} \|"
    assert re.search(row, text), row


def test_global_root_stress_on_coarse_fillets_is_refused_before_any_solve(
    monkeypatch, tmp_path, capsys
):
    """numerics.root_stress = 'global' reads the global model's refined fillets; the system
    scene refines none, so the run would end without a root stress and without an error.
    It is refused as input (exit 2, the field named) before a position is solved."""
    text = Path(load_study_case("1-GA").path).read_text()
    edited = tmp_path / "1-GA.toml"
    edited.write_text(text.replace("[numerics]", '[numerics]\nroot_stress = "global"', 1))
    calls = []
    monkeypatch.setattr(study_run, "solve_position", lambda *a, **k: calls.append(a))
    code = study_run.main(
        [str(edited), "--scene", "system", "--level", "0", "--out", str(tmp_path / "results")]
    )
    err = capsys.readouterr().err
    assert code == 2 and calls == []
    assert "numerics.root_stress = 'global'" in err and "'submodel'" in err
    assert "Traceback" not in err


def test_an_invalid_case_beside_a_valid_one_stops_the_command_before_any_solve(
    monkeypatch, tmp_path, capsys
):
    """Code 2 means nothing was solved (docs/cli.md) with several cases too: every case is
    checked as input first. Before, the valid case was solved and the command still
    ended with 2, the largest code."""
    bad = tmp_path / "broken.toml"
    bad.write_text(Path(load_study_case("1-GA").path).read_text().replace("1-GA", "broken"))
    bad.write_text(bad.read_text().replace("poisson_ratio = 0.3", "poisson_ratio = 0.7"))
    calls = []
    monkeypatch.setattr(study_run, "solve_position", lambda *a, **k: calls.append(a))
    code = study_run.main(["1-GA", str(bad), "--level", "0", "--out", str(tmp_path / "res")])
    err = capsys.readouterr().err
    assert code == 2 and calls == [] and not (tmp_path / "res").exists()
    assert "broken.toml" in err and "poisson_ratio" in err and "Traceback" not in err
    assert "nothing was solved" in err


class _Meshed(Exception):
    """Raised by the stand-in mesh loader: the sizes solve_position asked for."""


def test_solve_position_takes_the_case_sizes_unless_a_level_is_given(monkeypatch):
    """No level given: the case file's sizes (1-GB: level 1 with level 2's flanks and
    fillets, cases.study_case.case_sizes); a level given: that level's own; a flank or
    fillet level given beside it: that one. Read where the meshes are asked for."""
    from meshing.sizing import with_sizes
    from studies import position

    def meshes(scene, sizes, comm, memo):
        raise _Meshed(sizes)

    monkeypatch.setattr(position, "load_body_meshes", meshes)
    gb = load_study_case("1-GB")

    def asked(**kw):
        with pytest.raises(_Meshed) as got:
            position.solve_position(gb, 0.0, None, RunSettings(**kw))
        return got.value.args[0]

    assert asked() == with_sizes(1, 2, 2)
    assert asked(level=1) == 1 and asked(level=0) == 0
    assert asked(level=1, flank_level=2) == with_sizes(1, 2)
    assert asked(fillet_level=0) == with_sizes(1, 2, 0)


def test_outputs_reference_lists_what_the_run_wrote(study):
    """docs/reference/outputs.md names every key of this summary.json and position file and
    every file of the case folder, and no key or file for every run that they lack
    (tests/test_docs_outputs.py)."""
    out, _ = study
    check_run(out / "1-GA")

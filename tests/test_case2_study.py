"""The study driver on a user's own case files (single and double pinion, written to a temporary
folder), the double-pinion summary against the closed form, the case-2 and one-page reports,
and serial == 2 ranks for a double-pinion case.

Cheap: level 0, 1-2 positions; each study runs once per module (fixtures) and is shared. The
per-position physics of the case-2 branch (torque balance, axial force signs, Table 5 at one
position) is tests/test_double_pinion_branch.py; here it is what the driver and the reports
add: the same artefacts for every case, summary means, the issue-12 keys and the SP-RP split.
"""

import io
import json
import math
import time
from dataclasses import replace
from pathlib import Path

import pytest
from mpi4py import MPI
from statics import chain_bound, off_line_share, sun_force
from test_docs_outputs import check_run

from cases.study_case import CASE_DIR, load_study_case
from postprocess.paper_report import record_wall_time, write_paper_report
from solvers.body_store import BodyStore
from studies import run as study_run
from studies.case_options import CaseOptions
from studies.case_variants import global_root_stress
from studies.paper.case2_report import collinear_check, planetary_input, write_report
from studies.position import cycle_sector_teeth, solve_position
from studies.progress import Progress
from studies.settings import RunSettings

GEARSETS = CASE_DIR / "gearsets"
TORQUE = 1000.0  # N m on the sun: the user's own load, not the paper's 1378.7
PAPER_TORQUE = 1378.7
FACE = 29.0  # mm, SP and RP face width
ISSUE12 = ("M_LOA_sun_SP", "M_LOA_SP_RP", "M_LOA_RP_SP", "M_LOA_RP_ring")
SECTION5 = ("M_LOA_SP_SUN", "M_LOA_SP_RP", "M_LOA_RP_SP", "M_LOA_RP_RING")
STDERR = io.StringIO()  # warnings of the module's studies


def user_case(
    folder: Path, gearset: str, name: str, tilt: float, positions: int, numerics: str = ""
) -> Path:
    """A gear-set file (the paper's ``gearset`` under another name and torque) and a case file
    that names it by a relative path, both written to ``folder``: a user's own design;
    ``numerics``: the body of a ``[numerics]`` table, if any."""
    text = (GEARSETS / f"{gearset}.toml").read_text()
    assert f'name = "{gearset}"' in text and "input_torque = 1378.7" in text
    text = text.replace(f'name = "{gearset}"', f'name = "my_{gearset}"')
    (folder / f"my_{gearset}.toml").write_text(
        text.replace("input_torque = 1378.7", f"input_torque = {TORQUE}")
    )
    case = folder / f"{name}.toml"
    case.write_text(
        f'name = "{name}"\ngearset = "my_{gearset}.toml"\ndescription = "a user\'s case"\n\n'
        f"[bearing]\nradial_stiffness = 2.33e6\ntilting_stiffness = {tilt}\n\n"
        f'[model]\nscene = "one_branch"\nlevel = 0\npositions = {positions}\n'
        + (f"\n[numerics]\n{numerics}\n" if numerics else "")
    )
    return case


@pytest.fixture(scope="module")
def store():
    """Bodies factorized once for the module's double-pinion studies (same gears, steel)."""
    return BodyStore()


def _run(case, out: Path, store=None, **kw) -> dict:
    progress = Progress(out=io.StringIO(), err=STDERR)
    return study_run.run_study(case, out, progress=progress, store=store, **kw)


@pytest.fixture(scope="module")
def single(tmp_path_factory):
    folder = tmp_path_factory.mktemp("user_single")
    # its root stress, which no test here checks, on the global model: the submodels would
    # be most of its time (the double-pinion studies read theirs on submodels)
    case = user_case(
        folder, "case1", "my_single", 8.80e7, positions=1, numerics='root_stress = "global"'
    )
    return folder / "results", _run(case, folder / "results")


@pytest.fixture(scope="module")
def double(tmp_path_factory, store):
    folder = tmp_path_factory.mktemp("user_double")
    # its root stress on the global model's refined fillets, as for `single`: 2B-GA (`ga`)
    # reads the same gears' on submodels through the driver
    case = user_case(
        folder, "case2", "my_double", 8.80e7, positions=2, numerics='root_stress = "global"'
    )
    return folder / "results", _run(case, folder / "results", store)


@pytest.fixture(scope="module")
def ga(tmp_path_factory, store):
    out = tmp_path_factory.mktemp("ga")
    return out, _run("2B-GA", out, store, options=CaseOptions(level=0, positions=2))


def _artefacts(folder: Path) -> set[str]:
    """What the driver wrote for a case, by kind (the names of the per-mesh charts vary)."""
    names = {p.name for p in folder.iterdir()}
    kinds = {n for n in names if not n.startswith("contact_pattern_")}
    if any(n.startswith("contact_pattern_") for n in names):
        kinds.add("contact_pattern_<mesh>.png")
    return kinds


def test_user_case_files_give_the_same_artefacts(single, double, ga):
    """A case file of one's own (any folder, its gear set beside it) runs like a built-in
    case and leaves the same artefacts, single or double pinion."""
    (out1, s1), (out2, s2), (out3, _) = single, double, ga
    expected = {
        "summary.json",
        "positions",
        "fields",
        "contact_patterns.png",
        "contact_pattern_<mesh>.png",
        "flank_patterns.png",
        "loaded_scene.png",
    }
    for folder in (out1 / "my_single", out2 / "my_double", out3 / "2B-GA"):
        assert _artefacts(folder) == expected, folder
    assert sorted(p.name for p in (out2 / "my_double" / "positions").iterdir()) == [
        "0.json",
        "1.json",
    ]
    assert sorted(p.name for p in (out2 / "my_double" / "fields").iterdir()) == [
        "RP.bp",
        "SP.bp",
        "ring.bp",
        "sun.bp",
    ]
    assert len(list((out2 / "my_double").glob("contact_pattern_*.png"))) == 3  # three meshes
    for s in (s1, s2):
        assert s["inputs"]["gearset"]["input_torque"] == TORQUE
        assert s["failed_positions"] == [] and s["warnings"] == []
    assert STDERR.getvalue() == ""


def test_user_case_closed_form_follows_its_torque(single, double):
    """The closed-form reference of a summary comes from the user's gear set: every moment
    of the concentrated-load model is linear in the torque (one axial force FA per set)."""
    (_, s1), (_, s2) = single, double
    paper1 = s1["analytic"]["concentrated"]["My_pin"] * PAPER_TORQUE / TORQUE
    assert paper1 == pytest.approx(264.2797535747209, rel=1e-9)  # Table 3 from the gear data
    t5 = s2["analytic"]["table5"]
    for key, paper in (("M_LOA_SP_SUN", 154.67885126037942), ("My_RP", 184.55349349850434)):
        assert t5[key] * PAPER_TORQUE / TORQUE == pytest.approx(paper, rel=1e-9), key
    # and the FE carries that torque: its axial forces are the closed form's (statics)
    pos = json.loads((double[0] / "my_double" / "positions" / "0.json").read_text())
    # (the zone grid: sum F_k of the sun mesh within the sun's point-arm departure of F_0,
    # tests/statics.py chain_bound; 1e-6 the round-off of the line grid's force balance)
    tol = 1e-6 + chain_bound(pos, ["sun", "SP", "RP", "ring"], 0) / sun_force(pos)
    assert pos["FzSUN_fe"] == pytest.approx(pos["analytic"]["FzSUN"], rel=tol)


def test_double_summary_keys(double):
    """The issue-12 names of the four LOA moments are the section-5 ones (same numbers), at
    the top (means) and per position, with Mx/My of both pinions, the bearing loads, the
    centroid offsets of every mesh and the SP-RP differential; means are the positions'."""
    _, s = double
    for new, old in zip(ISSUE12, SECTION5, strict=True):
        assert s[new] == s[old]
        for p in s["positions"]:
            assert p[new] == p[old]
    for key in (
        *ISSUE12,
        "Mx_SP",
        "My_SP",
        "Mx_RP",
        "My_RP",
        "ZS",
        "Z_SPRP",
        "ZR",
        "M_LOA_SPRP_diff",
        "f_ma_SPRP_um",
    ):
        assert s[key] == pytest.approx(sum(p[key] for p in s["positions"]) / 2, rel=1e-12)
    assert s["M_LOA_SPRP_diff"] == pytest.approx(s["M_LOA_SP_RP"] + s["M_LOA_RP_SP"], rel=1e-12)
    assert set(s["bearing_force_N"]) == {"SP", "RP"}
    assert {"Z_sun-SP_SP", "Z_SP-RP_SP", "Z_SP-RP_RP", "Z_RP-ring_RP"} <= set(s["mesh_offsets_mm"])
    assert set(s["bending_stress"]) - {"locations"} == {
        "sun",
        "SP_sun_side",
        "SP_RP_side",
        "RP_SP_side",
        "RP_ring_side",
        "ring",
    }
    assert set(s["contact_stress_cycle"]) == {"sun_SP", "SP_RP", "RP_ring"}


def test_one_sector_per_gear_and_side_serves_every_position(ga):
    """The root stress of every gear and side is read at both positions on one sector of the
    same size (the most teeth of the mesh cycle, studies.position.cycle_sector_teeth), set up
    at the first position and reused at the second (sized per position, RP's ring side had
    sectors of 7 and 6 teeth at level 1 and set one up again at every other position)."""
    out, _ = ga
    pos = [json.loads((out / "2B-GA" / "positions" / f"{k}.json").read_text()) for k in (0, 1)]
    subs = [p["bending_stress"]["locations"] for p in pos]
    assert set(subs[0]) == set(subs[1]) and len(subs[0]) == 6
    # both positions name 4 loaded teeth per key at level 0; the cycle's most are 5 on the
    # ring mesh (RP_ring_side, ring), the size both positions' sectors must have
    most = cycle_sector_teeth(load_study_case("2B-GA"), 0.0, pos[0]["grid_spacing_mm"])
    assert max(most.values()) > min(most.values())
    for key, rec in subs[1].items():
        first = subs[0][key]["submodel"]
        assert rec["submodel"]["teeth"] == first["teeth"] == most[key] + 2, key
        assert len(rec["teeth"]) <= rec["submodel"]["teeth"] - 2, key  # read teeth inside it
        assert rec["submodel"]["set_up_here"] is False, key


def test_rigid_bearing_moments_against_closed_form_at_fe_centroids(ga):
    """2B-GA (level 0, 2 positions, means): Mx/My and the four LOA moments against the closed
    form with each mesh force moved to the FE's own load centroid.

    Tolerance 6 N m = FA x 1 mm (FA = 5919 N). The closed form at the FE's Z still puts every
    force on the pitch point in the transverse plane; the FE centroid sits s along the line
    of action from it (``loa_offset_*``: measured 0.1-0.65 mm) and the axial force there adds
    s FA to the moments of that pinion: at most about 0.65 x 5.9 = 3.8 N m per mesh (the
    measured differences: 0.1-5 N m). We require |s| < 1 mm, which makes the bound hold.
    A centroid 0.4 mm off (14-33 N m per mm) or a sign or frame error (2 x 100-170 N m)
    fails it. The moments are 95-190 N m, so 6 N m is 3-6 %.
    """
    out, s = ga
    at = s["analytic"]["at_fe_centroids"]
    fa = json.loads((out / "2B-GA" / "positions" / "0.json").read_text())["analytic"]["FzSUN"]
    for key in s["mesh_offsets_mm"]:
        if key.startswith("loa_offset_"):
            assert abs(s["mesh_offsets_mm"][key]) < 1.0, key
    for key in (*ISSUE12, "Mx_SP", "My_SP", "Mx_RP", "My_RP"):
        assert abs(s[key] - at[key]) < fa * 1.0e-3, key
    # rigid bearings: every mesh centred within 2 % of the face width
    for key in ("ZS", "Z_SPRP", "ZR"):
        assert abs(s[key]) < 0.02 * FACE, key


def test_sp_rp_differential_split_is_exact_on_the_line_grid():
    """Line model (every force of a mesh along one direction, at its load centroid on the
    plane of action): the FE forces put back at their pitch points give Table 5's D, and
    Table 5 + Z terms + s terms closes the FE value, ``other`` and ``from_cells`` vanish
    (all to round-off: 1e-9 N m against 150 N m moments; measured 2e-13). The root stress
    is read on the global model (studies/case_variants.py)."""
    case = global_root_stress(load_study_case("2B-GA"))
    case = replace(case, numerics=replace(case.numerics, contact_model="line"))
    p = solve_position(case, 0.0, MPI.COMM_SELF, RunSettings(level=0))
    d = p["sp_rp_differential"]
    assert d["D_fe"] == pytest.approx(p["M_LOA_SPRP_diff"], abs=1e-9)
    assert d["D_pitch"] == pytest.approx(p["analytic"]["table5"]["M_LOA_SPRP_diff"], abs=1e-9)
    assert abs(d["other"]) < 1e-9 and abs(d["from_cells"]) < 1e-9
    assert d["D_pitch"] + d["from_Z"] + d["from_s"] == pytest.approx(d["D_fe"], abs=1e-9)


def test_sp_rp_differential_split_is_exact(ga, double):
    """The SP-RP differential D = M_LOA_SP_RP + M_LOA_RP_SP split over the load centroids
    (zone model, the default; the line grid's exact split: the test above). The split closes
    the FE value to round-off, D_fe = D_pitch + from_Z + from_s + other + from_cells (1e-9
    N m against 150 N m moments). The FE forces put back at their pitch points give Table
    5's D up to the FE mesh forces' departure from the closed form: each side's pitch term
    is linear in its mesh force, whose magnitude departs by at most the chain of the point
    arms' departures (tests/statics.py, within the off-line share) and whose direction
    turns by the same order, so |D_pitch - D_t5| <= share x sum |pitch terms| (measured
    0.44 N m against a bound of 1.6 N m, 2B-GA). ``other`` (the centroid a few um off the
    plane of action, on the driver's flank) and ``from_cells`` (the cells' moment about
    their centroid, their normals turned by a few degrees) stay small: below 0.5 N m, 2 %
    of D and 0.3 % of the LOA moments (measured 0.01-0.16 N m). D is the tilting stiffness
    times the relative tilt of RP against SP in the SP-RP plane of action (the bearing
    springs carry the contact moments), so the reported misalignment is D b / k_tilt (b =
    29 mm) to round-off; with rigid bearings it is far below 1 um."""
    for (out, s), name in ((ga, "2B-GA"), (double, "my_double")):
        t5 = s["analytic"]["table5"]["M_LOA_SPRP_diff"]
        assert t5 == pytest.approx(
            s["analytic"]["table5"]["M_LOA_SP_RP"] + s["analytic"]["table5"]["M_LOA_RP_SP"],
            rel=1e-12,
        )
        k = s["inputs"]["study_case"]["bearing"]["tilting_stiffness"]
        for i, p in enumerate(s["positions"]):
            d = p["sp_rp_differential"]
            p = json.loads((out / name / "positions" / f"{i}.json").read_text())  # the meshes
            assert p["sp_rp_differential"] == d
            assert d["D_fe"] == pytest.approx(p["M_LOA_SPRP_diff"], abs=1e-9)
            pitch = sum(abs(v["pitch"]) for v in d["sides"].values())
            assert abs(d["D_pitch"] - t5) <= off_line_share(p) * pitch
            assert abs(d["other"]) < 0.5 and abs(d["from_cells"]) < 0.5
            total = d["D_pitch"] + d["from_Z"] + d["from_s"] + d["other"] + d["from_cells"]
            assert total == pytest.approx(d["D_fe"], abs=1e-9)
            f_ma = d["D_fe"] * 1e3 / k * FACE * 1e3  # um
            assert d["misalignment_um"] == pytest.approx(f_ma, rel=1e-6)
    assert abs(ga[1]["f_ma_SPRP_um"]) < 0.5


def test_case2_report_of_a_user_case(double, ga, tmp_path):
    """The case-2 report takes any double-pinion cases by name (none is built in) and the
    closed form from the summaries' gear set when no analytic tables are given; the 2-A
    verdict comes from the gear data: the collinear layout needs sun-RP = 51.945 + 42.750 =
    94.695 mm, the ring puts the RP at 58.600 mm."""
    out2, _ = double
    out_ga, _ = ga
    (out2 / "2B-GA").symlink_to(out_ga / "2B-GA")
    path = write_report(
        out2, ["my_double", "2B-GA"], out=tmp_path / "case2", tables=tmp_path / "none.json"
    )
    text = path.read_text()
    assert "computed from the gear set in the summaries' inputs" in text
    assert text.index("| 2B-GA |") < text.index("| my_double |")  # rigid bearing first
    assert "94.695 mm: 36.095 mm apart" in text
    for pic in ("fig6_fe.png", "sp_rp_differential.png"):
        assert (tmp_path / "case2" / pic).stat().st_size > 10_000
    c = collinear_check(planetary_input(ga[1]))
    assert not c["buildable"] and c["z_standard"] == 135 and c["z_ring"] == 92


def test_one_page_report_and_wall_time(single, double, tmp_path):
    """results/report.md lists every case run (a user's too, named apart from the paper's
    conclusions) and the wall time of the last full make, recorded from the start stamp
    (then removed, so a report alone keeps it)."""
    out1, _ = single
    stamp = out1 / "bench" / ".make_start"
    stamp.parent.mkdir(parents=True, exist_ok=True)
    stamp.write_text(f"{time.time() - 90.0}\n")
    rec = record_wall_time(out1, stamp)
    assert 89.0 < rec["wall_s"] < 600.0 and rec["within_goal"] and not stamp.exists()
    text = write_paper_report(out1).read_text()
    assert "| my_single | [my_single](my_single) | one_branch |" in text
    # a user's case has its row but is not one of the paper's cases its conclusions check
    assert "left out of these checks: `my_single` in `my_single/` (not one of the shipped" in text
    assert f"**{rec['wall_s'] / 60:.1f} min**, within the 20-minute goal" in text
    assert record_wall_time(out1, stamp) is None  # no stamp: nothing recorded again
    assert math.isclose(
        json.loads((out1 / "bench" / "make_all.json").read_text())["wall_s"], rec["wall_s"]
    )


@pytest.mark.mpi
def test_double_pinion_study_parallel_equals_serial(tmp_path):
    """A user's double-pinion case through the driver on 2 ranks against a serial solve of the
    same position (COMM_SELF, identical cached meshes): MUMPS on another partition changes
    round-off only (measured ~1e-13 relative on the branch scenes), so 1e-6 is a wide margin.
    The parallel run goes first so a cold mesh cache is built collectively."""
    comm = MPI.COMM_WORLD
    folder = Path(comm.bcast(str(tmp_path), root=0))
    if comm.rank == 0:
        user_case(folder, "case2", "my_double", 8.80e7, positions=1)
    comm.Barrier()
    case = folder / "my_double.toml"
    progress = Progress(comm, out=io.StringIO(), err=io.StringIO())
    summary = study_run.run_study(case, folder / "results", comm=comm, progress=progress)
    # the serial reference without the root-stress submodels (every rank holds a whole
    # serial model: with six sectors each the test peaked at 21 GB of 23); the moments
    # compared here do not depend on how the root stress is read
    study = global_root_stress(load_study_case(case))
    ser = solve_position(study, 0.0, MPI.COMM_SELF, RunSettings(level=0))
    par = summary["positions"][0]
    scale = abs(ser["My_RP"])
    for key in (*ISSUE12, "Mx_SP", "My_SP", "Mx_RP", "My_RP", "M_LOA_SPRP_diff"):
        assert par[key] == pytest.approx(ser[key], rel=1e-6, abs=1e-6 * scale), key
    for key in ("ZS", "Z_SPRP", "ZR"):
        assert par[key] == pytest.approx(ser[key], abs=1e-6 * FACE), key
    assert summary["ranks"] == comm.size == 2


def test_outputs_reference_lists_what_a_double_pinion_run_wrote(ga):
    """docs/reference/outputs.md against 2B-GA's outputs: its double-pinion keys too
    (tests/test_docs_outputs.py)."""
    out, _ = ga
    check_run(out / "2B-GA")

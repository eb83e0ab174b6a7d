"""Accepted means solvable (issue 57 item 1): a case at the ends of the validator's ranges
either solves or is refused with code 2 before anything is meshed. The grid spacing's lower
end asks for a contact grid no machine holds (the cells grow as 1 / spacing^2): refused up
front with the spacing that fits (studies.contact_size). The largest helix angle with the
largest grid spacing, the case that failed in the gap operator, solves at level 0; so do
each end of each bearing stiffness's range, the narrowest face and the largest flank
modifications. The fewest teeth and the largest lead slope are refused up front, with what
to change."""

import io
import json
import math
import re
from pathlib import Path
from types import SimpleNamespace

import pytest
from test_high_helix import helix_case

from cases.gearset import MIN_FACE_MODULES, CaseError
from cases.study_case import _RANGES, GRID_SPACING_RANGE, load_study_case
from gears.microgeometry import MAX_MODIFICATION_UM
from gears.spec import HELIX_ANGLE_RANGE, MIN_TEETH
from solvers.body_store import BodyStore
from solvers.gear_train import contact_grids
from studies.contact_size import check_contact_size
from studies.position import study_scene, train_inputs
from studies.progress import Progress
from studies.run import main, run_study

GB = 1e9


def end_point_case(tmp_path: Path, beta: float, spacing: float) -> Path:
    """1-GB's data at helix angle ``beta`` (test_high_helix.helix_case: the centre distance
    of the standard sun-pinion pair, so the shifts stay valid), level 0, one position, no
    root stress, ``grid_spacing``."""
    path = helix_case(tmp_path, beta)
    case = path.read_text().replace(f'name = "helix{beta:g}"', 'name = "ends"')
    case = re.sub(r"(?m)^level = 1.*", "level = 0", case)
    case = re.sub(r"(?m)^(flank|fillet)_level = .*\n", "", case)
    case = re.sub(r"(?m)^positions = .*", "positions = 1", case)
    case = case.replace(
        "[numerics]", f'[numerics]\ngrid_spacing = {spacing!r}\nroot_stress = "none"'
    )
    path.write_text(case)
    return path


def test_the_smallest_spacing_is_refused_before_meshing_with_the_spacing_that_fits(tmp_path):
    lo = GRID_SPACING_RANGE[0]
    case = end_point_case(tmp_path, 21.0, 2 * lo)  # the open lower end's nearest allowed
    out = tmp_path / "out"
    assert main([str(case), "--out", str(out), "--quiet"]) == 2
    assert not (out / "ends").exists()  # nothing meshed, solved or written
    study = load_study_case(case)
    with pytest.raises(
        CaseError, match=r"numerics.grid_spacing = 0.02 mm .* set numerics.grid_spacing >= "
    ) as err:
        check_contact_size(study, 2 * lo, study_scene(study, 0.0), memory=int(24 * GB))
    fits = float(re.search(r">= ([0-9.]+) mm", str(err.value)).group(1))
    check_contact_size(study, fits, study_scene(study, 0.0), memory=int(24 * GB))  # it fits


def test_the_bound_counts_every_rank_and_scales_the_cells_below_the_probe():
    study = load_study_case("1-GA")
    scene = study_scene(study, 0.0)
    two = SimpleNamespace(size=2)  # what the check takes of a communicator
    check_contact_size(study, 0.45, scene, two, memory=int(24 * GB))  # 1-GA: 4216 cells
    with pytest.raises(CaseError, match=r"2 ranks\), more than 80% of this machine's 1 GB"):
        check_contact_size(study, 0.45, scene, two, memory=int(1 * GB))
    # below the probe the cells are counted at it and scaled by 1 / spacing^2: within 10 %
    # of the count (the cells across the line are capped at half the spacing, the Hertz
    # cells at the contact line are not, so the true count grows a little slower)
    fine = 0.15
    _, pairs = contact_grids(scene, train_inputs(study), fine)
    counted = sum(p.grid.n for p in pairs)
    with pytest.raises(CaseError, match=r"about (\d+) cells") as err:
        check_contact_size(study, fine, scene, memory=int(0.01 * GB))
    scaled = int(re.search(r"about (\d+) cells", str(err.value)).group(1))
    assert counted < scaled < 1.1 * counted, (scaled, counted)


def test_the_largest_helix_angle_at_the_largest_spacing_solves(tmp_path):
    case = end_point_case(tmp_path, HELIX_ANGLE_RANGE[1], GRID_SPACING_RANGE[1])
    out = tmp_path / "out"
    assert main([str(case), "--out", str(out), "--quiet"]) == 0
    summary = json.loads((out / "ends" / "summary.json").read_text())
    assert not summary.get("failed_positions")
    assert math.isfinite(summary["positions"][0]["My_pin"])


def quick_case(tmp_path: Path, gearset: str, root_stress: str, edit=lambda text: text) -> Path:
    """1-GB's case file as ``ends.toml`` in ``tmp_path``: on ``gearset`` (a path, or a name
    in cases/gearsets/), level 0, one position, ``numerics.root_stress = root_stress``,
    changed further by ``edit`` (text -> text)."""
    text = Path(load_study_case("1-GB").path).read_text()
    text = text.replace('name = "1-GB"', 'name = "ends"')
    text = text.replace('gearset = "case1"', f'gearset = "{gearset}"')
    text = re.sub(r"(?m)^level = 1.*", "level = 0", text)
    text = re.sub(r"(?m)^(flank|fillet)_level = .*\n", "", text)
    text = re.sub(r"(?m)^positions = .*", "positions = 1", text)
    text = text.replace("[numerics]", f'[numerics]\nroot_stress = "{root_stress}"', 1)
    case = tmp_path / "ends.toml"
    case.write_text(edit(text))
    return case


#: each end of each bearing stiffness's accepted range (cases.study_case)
BEARING_ENDS = [
    (name, value)
    for name in ("radial_stiffness", "tilting_stiffness", "axial_stiffness")
    for value in _RANGES[f"bearing.{name}"]
]


@pytest.fixture(scope="module")
def bearing_store():
    """The gears' bodies for every bearing end (the bearing is outside the bodies)."""
    return BodyStore()


@pytest.mark.parametrize("name, value", BEARING_ENDS)
def test_a_bearing_at_either_end_of_its_ranges_solves(tmp_path, bearing_store, name, value):
    """1-GB at level 0, one position, no root stress, one bearing stiffness at an end of
    what the case file accepts: it solves (a band the load reaches past is widened,
    studies.position), with finite moments; the radial floor is the softest needle bearing
    (below it the pinion floated past the largest zone band: refused,
    tests/test_trust_driver.py)."""

    def bearing(text):
        text = re.sub(rf"(?m)^{name} = .*", f"{name} = {value!r}", text)
        if name == "axial_stiffness":  # 1-GB leaves it at its default
            text = text.replace("[bearing]", f"[bearing]\naxial_stiffness = {value!r}", 1)
        return text

    gearset = Path(load_study_case("1-GB").gearset.path).resolve()
    case = quick_case(tmp_path, str(gearset), "none", bearing)
    study = load_study_case(case)
    assert getattr(study.bearing, name) == value  # the end itself reached the solve
    quiet = Progress(out=io.StringIO(), err=io.StringIO(), quiet=True)
    summary = run_study(case, tmp_path / "out", store=bearing_store, progress=quiet)
    assert not summary.get("failed_positions")
    for key in ("My_pin", "Mx_pin", "M_LOA_sun", "M_LOA_ring"):
        assert math.isfinite(summary["positions"][0][key]), key


def gearset_case(tmp_path: Path, edit) -> Path:
    """A case of 1-GB's bearing on case 1's gear set edited by ``edit`` (gear-set text ->
    text), level 0, one position, the root stress read on the global fillets (the sectors are
    not what an end point tests)."""
    source = Path(load_study_case("1-GB").gearset.path).read_text()
    (tmp_path / "ends_set.toml").write_text(edit(source.replace('name = "case1"', 'name = "e"')))
    return quick_case(tmp_path, "ends_set.toml", "global")


def _solves(case: Path, tmp_path: Path) -> dict:
    """The summary of ``case`` run to its end, checked for what a degenerate solution lacks:
    finite moments, a contact stress and K_Hbeta on every mesh, a root stress on every fillet."""
    out = tmp_path / "out"
    assert main([str(case), "--out", str(out), "--quiet"]) == 0
    summary = json.loads((out / "ends" / "summary.json").read_text())
    assert not summary.get("failed_positions")
    for key in ("My_pin", "Mx_pin", "M_LOA_sun", "M_LOA_ring"):
        assert math.isfinite(summary["positions"][0][key]), key
    for mesh, c in summary["contact_stress_cycle"].items():
        assert c["p_max_MPa"] > 0 and math.isfinite(c["K_Hbeta"]), mesh
    assert all(v is not None and v > 0 for v in summary["bending_stress"].values())
    return summary


def test_the_narrowest_face_solves(tmp_path):
    """Every face at the least width accepted (MIN_FACE_MODULES normal modules), the torque
    scaled with the pinion's face so the flanks carry case 1's line load (a narrow face at
    the full torque only adds the stress warnings): it solves."""
    b = MIN_FACE_MODULES * 1.59  # case 1's normal module

    def narrow(text):
        text = re.sub(r"(?m)^face_width = .*", f"face_width = {b!r}", text)
        return re.sub(r"(?m)^input_torque = .*", f"input_torque = {1378.7 * b / 29.0!r}", text)

    _solves(gearset_case(tmp_path, narrow), tmp_path)


def test_the_largest_flank_modifications_solve(tmp_path):
    """The pinion with the largest lead crown, tip relief and end relief accepted
    (MAX_MODIFICATION_UM each): it solves, its zone band widened to where the load reaches
    (measured: 40 to 160 um; studies.position), and the run warns of each amount."""
    mods = (
        "\n[gears.pinion.modifications]\n"
        f"lead_crown_um = {MAX_MODIFICATION_UM!r}\ntip_relief_um = {MAX_MODIFICATION_UM!r}\n"
        "tip_relief_diameter = 43.0\n"  # on the pinion's involute, below its tip (44.2 mm)
        f"end_relief_um = {MAX_MODIFICATION_UM!r}\nend_relief_length = 5.0\n"
    )
    summary = _solves(
        gearset_case(
            tmp_path, lambda t: t.replace("face_width = 29.00\n", f"face_width = 29.00\n{mods}", 1)
        ),
        tmp_path,
    )
    for field in ("lead_crown_um", "tip_relief_um", "end_relief_um"):
        assert any(field in w for w in summary["warnings"]), field
    assert any("was solved on a band of up to" in w for w in summary["warnings"])


def test_the_largest_lead_slope_is_refused_before_meshing(tmp_path):
    """A lead slope of MAX_MODIFICATION_UM adds half of it at one face end of each of the
    pinion's flanks, beyond case 1's 89 um backlash: the coast flanks would start inside
    each other, so the case is refused (code 2), naming the mesh and what to change."""
    slope = f"\n[gears.pinion.modifications]\nlead_slope_um = {MAX_MODIFICATION_UM!r}\n"
    case = gearset_case(
        tmp_path, lambda t: t.replace("face_width = 29.00\n", f"face_width = 29.00\n{slope}", 1)
    )
    out = tmp_path / "out"
    assert main([str(case), "--out", str(out), "--quiet"]) == 2
    assert not (out / "ends").exists()


@pytest.mark.parametrize(
    "teeth, says",
    [
        (MIN_TEETH, r"pinion.profile_shift = .*pointed tooth|undercut"),
        (8, r"gears.pinion: teeth = 8 .* too small for its pin .* more teeth or a larger module"),
    ],
)
def test_a_planet_of_few_teeth_is_refused_before_meshing_with_what_to_change(
    tmp_path, capsys, teeth, says
):
    """A planet of ``teeth`` teeth, the ring ``2 teeth`` more than the sun's 37 and the
    centre distance 0.45 modules above the standard one (a positive shift, the only way a
    planet of few teeth has a tooth): at MIN_TEETH no shift gives a valid tooth; at 8 the
    shift makes the gear (it was refused at the file's x = 0 before its centre distance was
    applied) but the paper's pin and needle bearing do not fit under its root circle. Both
    are refused (code 2) before anything is meshed, each saying what to change."""
    a = 1.59 * (37 + teeth) / (2 * math.cos(math.radians(21.0))) + 0.45 * 1.59

    def few(text):
        text = text.replace("teeth = 35", "teeth = 37").replace("teeth = 26", f"teeth = {teeth}")
        text = text.replace("teeth = 86", f"teeth = {37 + 2 * teeth}")
        return text.replace("centre_distance = 51.945", f"centre_distance = {a!r}")

    case = gearset_case(tmp_path, few)
    out = tmp_path / "out"
    assert main([str(case), "--out", str(out), "--quiet"]) == 2
    assert not (out / "ends").exists()
    assert re.search(says, capsys.readouterr().err)


@pytest.mark.parametrize(
    "field, value",
    [("youngs_modulus", _RANGES["material.youngs_modulus"][0]), ("gear_modulus_factor", 0.01)],
)
def test_gears_too_soft_for_the_torque_are_refused_before_meshing(tmp_path, capsys, field, value):
    """The softest gears accepted (1e3 MPa, or steel x 0.01) under case 1's torque: the teeth
    would bend about 4-8 mm (studies.mesh_deflection eq. (1)), beyond any zone band; the solve
    failed after the set-up in ZoneReachError (measured). Refused (code 2) before meshing,
    naming the torque and the modulus."""

    def soft(text):
        return re.sub(rf"(?m)^{field} = .*", f"{field} = {value!r}", text)

    case = quick_case(tmp_path, "case1", "none", soft)
    out = tmp_path / "out"
    assert main([str(case), "--out", str(out), "--quiet"]) == 2
    assert not (out / "ends").exists()
    err = capsys.readouterr().err
    assert "input_torque = 1378.7 N m on gears of E = " in err and "lower the torque" in err

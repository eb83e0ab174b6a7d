"""Gear-set case files: the shipped files load; bad fields fail with messages naming them."""

import tomllib

import pytest
from case_data import mutated

from cases.gearset import GEARSET_DIR, CaseError, load_gearset, parse_gearset


def _raw(name: str) -> dict:
    with (GEARSET_DIR / f"{name}.toml").open("rb") as f:
        return tomllib.load(f)


@pytest.mark.parametrize("name", ["case1", "case2"])
def test_shipped_gearsets_load(name):
    gs = load_gearset(name)
    assert gs.power_path[0] == "sun" and gs.power_path[-1] == "ring"
    assert gs.gears["ring"].internal
    # Every mesh of the power path is a valid pair at its centre distance.
    for m in gs.meshes:
        pair = gs.pair(m.gear1, m.gear2)
        assert pair.centre_distance == m.centre_distance


def test_case1_shift_split():
    """Case 1: the sun-pinion pair is standard, the ring carries the ring-mesh shift."""
    gs = load_gearset("case1")
    assert gs.gears["sun"].profile_shift == 0.0
    # The printed 51.945 mm is the standard centre distance 61 m_t / 2 = 51.94520 mm rounded
    # to 1 um, so the pinion takes the tiny shift that 0.2 um needs: |x| < 5e-4 (0.8 um).
    assert abs(gs.gears["pinion"].profile_shift) < 5e-4
    # The ring mesh runs 0.851 mm above its standard centre distance: positive ring shift.
    assert gs.gears["ring"].profile_shift > 0.0
    assert gs.torque_per_branch == pytest.approx(459.5667, abs=1e-4)  # 1378.7 / 3


def _mutated(path: list, value, base: str = "case1") -> dict:
    return mutated(_raw(base), path, value)


@pytest.mark.parametrize(
    ("path", "value", "match"),
    [
        (["kind"], "triple_pinion", "kind = 'triple_pinion'"),
        (["input_torque"], -5.0, "input_torque = -5.0: must be > 0"),
        (["planets"], 0, "planets = 0"),
        (["gears", "sun", "teeth"], 0, "gears.sun"),
        (["gears", "sun", "colour"], "red", r"gears.sun: unknown field 'colour' \(allowed: teeth"),
        (["gears", "pinion", "hand"], None, "gears.pinion"),
        (["power_path"], ["sun", "planet", "ring"], "power_path"),
        (["meshes", 0, "centre_distance"], "51", "meshes\\[0\\]: centre_distance"),
        (["meshes", 1, "gears"], ["ring", "pinion"], "meshes\\[1\\]: gears"),
    ],
)
def test_bad_fields_name_the_field(path, value, match):
    with pytest.raises(CaseError, match=match):
        parse_gearset(_mutated(path, value), "case1.toml")


def test_a_face_too_narrow_to_read_is_refused_before_solving():
    """1 mm faces used to solve to zero contact stress and no K_Hbeta (every cell within the
    edge bands, one module from each face end): refused, naming the gear, the field and
    the least width; 4 modules (the shipped module 2.5: 10 mm) is accepted."""
    import math

    from cases.gearset import MIN_FACE_MODULES
    from postprocess.mesh_stress import FACE_BAND_MODULES

    assert MIN_FACE_MODULES >= 2 * FACE_BAND_MODULES + 2  # two modules of interior at least
    m_n = load_gearset("case1").gears["pinion"].normal_module
    with pytest.raises(CaseError, match=r"case1.toml: gears.pinion: face_width = 1 mm: must be"):
        parse_gearset(_mutated(["gears", "pinion", "face_width"], 1.0), "case1.toml")
    least = MIN_FACE_MODULES * m_n
    narrow = _mutated(["gears", "pinion", "face_width"], math.nextafter(least, 0.0))
    with pytest.raises(CaseError, match=f"at least 4 normal modules \\({least:g} mm here\\)"):
        parse_gearset(narrow, "case1.toml")
    parse_gearset(_mutated(["gears", "pinion", "face_width"], least), "case1.toml")


def test_unknown_gearset_lists_available():
    with pytest.raises(CaseError, match="available: case1, case2"):
        load_gearset("case9")

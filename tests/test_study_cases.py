"""Study-case files: the paper's four case-1 cases load with the section-7 data; bad fields
fail with messages naming the field and the allowed range."""

import copy
import tomllib

import pytest

from cases.gearset import CaseError
from cases.study_case import CASE_DIR, load_study_case, parse_study_case


@pytest.mark.parametrize(
    ("name", "k_radial", "k_tilt", "factor"),
    [  # singh2007 section 7 table
        ("1-GA", 2.33e8, 8.80e9, 1.0),
        ("1-GB", 2.33e6, 8.80e7, 1.0),
        ("1-GC", 2.33e5, 8.80e6, 1.0),
        ("1-GB-R", 2.33e6, 8.80e7, 10.0),
    ],
)
def test_case1_files_match_section7(name, k_radial, k_tilt, factor):
    case = load_study_case(name)
    assert case.name == name
    assert case.gearset.name == "case1"
    assert case.bearing.radial_stiffness == k_radial
    assert case.bearing.tilting_stiffness == k_tilt
    assert case.material.gear_modulus_factor == factor
    assert case.material.gear_youngs_modulus == 206000.0 * factor


def _raw(name="1-GB"):
    with (CASE_DIR / f"{name}.toml").open("rb") as f:
        return tomllib.load(f)


@pytest.mark.parametrize(
    ("section", "key", "value", "match"),
    [
        ("bearing", "radial_stiffness", -1.0, r"bearing.radial_stiffness = -1.0: must be"),
        ("bearing", "tilting_stiffness", "soft", r"bearing.tilting_stiffness = 'soft'"),
        ("material", "poisson_ratio", 0.5, r"material.poisson_ratio = 0.5: .*\[0, 0.49\]"),
        ("model", "level", 7, r"model.level = 7: must be an integer 0..3"),
        ("model", "positions", 0, r"model.positions = 0"),
        ("model", "scene", "half", r"model.scene = 'half': must be one of"),
    ],
)
def test_bad_fields_name_the_field(section, key, value, match):
    data = copy.deepcopy(_raw())
    data[section][key] = value
    with pytest.raises(CaseError, match=match):
        parse_study_case(data, "1-GB.toml")


def test_missing_section():
    data = _raw()
    del data["bearing"]
    with pytest.raises(CaseError, match=r"\[bearing\] section is missing"):
        parse_study_case(data, "1-GB.toml")


def test_a_missing_scene_is_named_missing():
    data = copy.deepcopy(_raw())
    del data["model"]["scene"]
    with pytest.raises(CaseError, match=r"model.scene missing: must be one of one_branch"):
        parse_study_case(data, "1-GB.toml")


def test_unknown_case_lists_available():
    with pytest.raises(CaseError, match="available: 1-GA, 1-GB, 1-GB-R, 1-GC"):
        load_study_case("1-GZ")


def test_toml_syntax_error_names_the_file(tmp_path):
    bad = tmp_path / "broken.toml"
    bad.write_text('name = "x"\n[bearing\n')
    with pytest.raises(CaseError, match=r"broken\.toml: not valid TOML"):
        load_study_case(bad)


def test_a_coarse_low_rank_threshold_is_refused():
    """mumps-blr's factors serve as an exact solve: a dropping threshold of 1e-3 moved 1-GB's
    Mx_pin by 4 % at level 0 (1e-4: by 1e-4 of itself), so at most BLR_TOLERANCE_MAX; CG
    takes the whole range (its residual is checked, not assumed)."""
    from cases.study_case import BLR_TOLERANCE_MAX, LINEAR_TOLERANCE_RANGE

    data = copy.deepcopy(_raw())
    data["numerics"] |= {"linear_solver": "mumps-blr", "linear_tolerance": 1e-3}
    with pytest.raises(CaseError, match=r"linear_tolerance = 0.001: .*at most 0.0001"):
        parse_study_case(data, "1-GB.toml")
    data["numerics"]["linear_tolerance"] = BLR_TOLERANCE_MAX
    parse_study_case(data, "1-GB.toml")
    data["numerics"] |= {"linear_solver": "cg-gamg", "linear_tolerance": LINEAR_TOLERANCE_RANGE[1]}
    parse_study_case(data, "1-GB.toml")

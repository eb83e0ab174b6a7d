"""Case inputs a gear engineer can trust: unknown keys, unsafe names, impossible gear sets and
out-of-range numerics are refused with messages naming file and field; omitted optional
tables take documented defaults; the resolved inputs of a run are JSON data with a hash."""

import dataclasses
import hashlib
import json
import math
import tomllib
from pathlib import Path

import pytest
from case_data import mutated

from cases.gearset import GEARSET_DIR, CaseError, GearMeshSpec, load_gearset, parse_gearset
from cases.study_case import (
    CASE_DIR,
    DEFAULTS,
    Numerics,
    available_cases,
    case_sizes,
    inputs_hash,
    load_study_case,
    parse_study_case,
    study_inputs,
    without_variant,
)
from gears.material import STEEL
from gears.spec import GearSpec

SHIPPED = ["1-GA", "1-GB", "1-GB-R", "1-GC", "2B-GA", "2B-GB"]


def _case_raw(name: str = "1-GB") -> dict:
    return tomllib.loads((CASE_DIR / f"{name}.toml").read_text())


def _set_raw(name: str = "case1") -> dict:
    return tomllib.loads((GEARSET_DIR / f"{name}.toml").read_text())


_mutated = mutated


# ---------------------------------------------------------------------------------------
# unknown keys
# ---------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("path", "match"),
    [
        (["colour"], r"^1-GB\.toml: unknown field 'colour' \(allowed: name, gearset, descr"),
        (["bearing", "stiffnes"], r"^1-GB\.toml: bearing: unknown field 'stiffnes' \(allowed: ra"),
        (["material", "density"], r"^1-GB\.toml: material: unknown field 'density' \(allowed: y"),
        (["model", "levels"], r"^1-GB\.toml: model: unknown field 'levels' \(allowed: scene, "),
        (["numerics", "order"], r"^1-GB\.toml: numerics: unknown field 'order' \(allowed: deg"),
    ],
)
def test_study_case_unknown_keys(path, match):
    data = _mutated(_case_raw(), path, 1)
    with pytest.raises(CaseError, match=match):
        parse_study_case(data, "1-GB.toml")


def test_a_zone_gap_limit_with_the_line_model_is_refused_not_ignored():
    """The "line" model lays no zone grid, so a gap limit given with it would change nothing
    while the user believed it set; the "zone" model takes it, and an omitted one is fine."""
    data = _case_raw()
    data["numerics"].update(contact_model="line", zone_gap_limit_um=20.0)
    with pytest.raises(CaseError) as info:
        parse_study_case(data, "1-GB.toml")
    assert str(info.value).startswith(
        "1-GB.toml: numerics.zone_gap_limit_um: only for contact_model = 'zone'"
    )
    del data["numerics"]["zone_gap_limit_um"]
    assert parse_study_case(data, "1-GB.toml").numerics.contact_model == "line"
    data["numerics"].update(contact_model="zone", zone_gap_limit_um=20.0)
    assert parse_study_case(data, "1-GB.toml").numerics.zone_gap_limit_um == 20.0


def test_typo_gear_modulus_factor_is_refused_not_run_as_steel(tmp_path):
    text = (CASE_DIR / "1-GB-R.toml").read_text()
    assert "gear_modulus_factor = 10.0" in text
    bad = tmp_path / "1-GB-R.toml"
    bad.write_text(text.replace("gear_modulus_factor", "gear_modulus_facter"))
    with pytest.raises(CaseError) as info:
        load_study_case(bad)
    assert str(info.value) == (
        "1-GB-R.toml: material: unknown field 'gear_modulus_facter' "
        "(allowed: youngs_modulus, poisson_ratio, gear_modulus_factor)"
    )


@pytest.mark.parametrize(
    ("path", "match"),
    [
        (["ratio"], r"^case1\.toml: unknown field 'ratio' \(allowed: name, kind, input_torque"),
        (["common", "module"], r"^case1\.toml: common: unknown field 'module' \(allowed: normal"),
        (["gears", "ring", "x"], r"^case1\.toml: gears\.ring: unknown field 'x' \(allowed: tee"),
        (["meshes", 1, "backlash"], r"^case1\.toml: meshes\[1\]: unknown field 'backlash' \(al"),
    ],
)
def test_gearset_unknown_keys(path, match):
    with pytest.raises(CaseError, match=match):
        parse_gearset(_mutated(_set_raw(), path, 0.1), "case1.toml")


def test_several_unknown_keys_are_all_named():
    data = _mutated(_mutated(_case_raw(), ["model", "a"], 1), ["model", "b"], 2)
    with pytest.raises(CaseError, match=r"model: unknown fields 'a', 'b' \(allowed: scene, le"):
        parse_study_case(data, "1-GB.toml")


def test_table_must_be_a_table():
    with pytest.raises(CaseError, match=r"1-GB\.toml: material: must be a table, got 'steel'"):
        parse_study_case(_mutated(_case_raw(), ["material"], "steel"), "1-GB.toml")


# ---------------------------------------------------------------------------------------
# numerics and material defaults
# ---------------------------------------------------------------------------------------


def test_numerics_defaults_are_documented_once():
    assert DEFAULTS == Numerics()
    assert (DEFAULTS.degree, DEFAULTS.penalty_factor, DEFAULTS.grid_spacing) == (1, 100.0, None)
    assert DEFAULTS.contact_model == "zone"
    case = parse_study_case(_mutated(_case_raw(), ["numerics"], None), "1-GB.toml")
    assert case.numerics == DEFAULTS


@pytest.mark.parametrize("name", SHIPPED)
def test_shipped_cases_spell_out_the_numerics_defaults(name):
    raw = _case_raw(name)
    # 1-GC's own zone gap limit: its overturned pinion's tip corners (solvers.zone_reach)
    own = {"1-GC": {"zone_gap_limit_um": 120.0}}.get(name, {})
    assert raw["numerics"] == {
        "degree": 1,
        "penalty_factor": 100.0,
        "contact_model": "zone",
        **own,
    }
    case = load_study_case(name)
    assert case.numerics == dataclasses.replace(DEFAULTS, **own)
    # Spelling the defaults out or leaving them out is the same run.
    bare = parse_study_case(_mutated(raw, ["numerics"], own or None), f"{name}.toml")
    assert inputs_hash(bare) == inputs_hash(case)


def test_numerics_values_are_read():
    data = _mutated(
        _case_raw(), ["numerics"], {"degree": 2, "penalty_factor": 1000, "grid_spacing": 5}
    )
    n = parse_study_case(data, "1-GB.toml").numerics
    assert n == Numerics(degree=2, penalty_factor=1000.0, grid_spacing=5.0)
    assert isinstance(n.penalty_factor, float) and isinstance(n.grid_spacing, float)


@pytest.mark.parametrize(
    ("key", "value", "match"),
    [
        ("degree", 3, r"numerics\.degree = 3: must be one of \(1, 2\)"),
        ("degree", 0, r"numerics\.degree = 0"),
        ("degree", 1.0, r"numerics\.degree = 1\.0"),
        ("degree", True, r"numerics\.degree = True"),
        ("penalty_factor", 0, r"numerics\.penalty_factor = 0: must be a number in \[1, 1e\+06\]"),
        ("penalty_factor", 0.999, r"numerics\.penalty_factor = 0\.999"),
        ("penalty_factor", 1.1e6, r"numerics\.penalty_factor = 1100000\.0"),
        ("penalty_factor", math.nan, r"numerics\.penalty_factor = nan"),
        ("penalty_factor", "high", r"numerics\.penalty_factor = 'high'"),
        ("grid_spacing", -1, r"numerics\.grid_spacing = -1: must be a number in \(0\.01, 5\] mm"),
        ("grid_spacing", 0.01, r"numerics\.grid_spacing = 0\.01"),
        ("grid_spacing", 5.5, r"numerics\.grid_spacing = 5\.5"),
        ("grid_spacing", math.inf, r"numerics\.grid_spacing = inf"),
        (
            "root_fillets",
            "fine",
            r"numerics\.root_fillets = 'fine': must be one of 'auto', "
            r"'refined', 'coarse'",
        ),
        (
            "root_stress",
            "fine",
            r"numerics\.root_stress = 'fine': must be one of 'submodel', 'global', 'none'",
        ),
    ],
)
def test_numerics_range_errors(key, value, match):
    data = _mutated(_case_raw(), ["numerics", key], value)
    with pytest.raises(CaseError, match=r"^1-GB\.toml: " + match):
        parse_study_case(data, "1-GB.toml")


@pytest.mark.parametrize(("key", "value"), [("penalty_factor", 1), ("penalty_factor", 1e6)])
def test_numerics_range_bounds_are_inclusive(key, value):
    data = _mutated(_case_raw(), ["numerics", key], value)
    assert getattr(parse_study_case(data, "1-GB.toml").numerics, key) == value


def test_material_table_is_optional_and_defaults_to_steel():
    case = parse_study_case(_mutated(_case_raw(), ["material"], None), "1-GB.toml")
    m = case.material
    assert (m.youngs_modulus, m.poisson_ratio, m.gear_modulus_factor) == (206e3, 0.3, 1.0)
    assert (m.youngs_modulus, m.poisson_ratio) == (STEEL.youngs_modulus, STEEL.poisson_ratio)
    partial = parse_study_case(
        _mutated(_case_raw(), ["material"], {"gear_modulus_factor": 10}), "1-GB.toml"
    )
    assert partial.material.gear_youngs_modulus == 206e4


@pytest.mark.parametrize(
    ("key", "value", "match"),
    [
        ("youngs_modulus", math.nan, r"material\.youngs_modulus = nan"),
        ("gear_modulus_factor", 0.0, r"material\.gear_modulus_factor = 0\.0: .*\[0\.01, 100\]"),
        ("gear_modulus_factor", "10", r"material\.gear_modulus_factor = '10'"),
    ],
)
def test_material_range_checks_remain(key, value, match):
    with pytest.raises(CaseError, match=match):
        parse_study_case(_mutated(_case_raw(), ["material", key], value), "1-GB.toml")


# ---------------------------------------------------------------------------------------
# gear-set physics
# ---------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("value", "match"),
    [
        (math.inf, "input_torque = inf: must be a finite number"),
        (math.nan, "input_torque = nan: must be a finite number"),
        (-math.inf, "input_torque = -inf: must be a finite number"),
        (0.0, "input_torque = 0.0: must be > 0"),
        (-1378.7, "input_torque = -1378.7: must be > 0"),
        ("1378.7", "input_torque = '1378.7': must be a number"),
    ],
)
def test_input_torque_must_be_finite_and_positive(value, match):
    with pytest.raises(CaseError, match=r"^case1\.toml: " + match):
        parse_gearset(_mutated(_set_raw(), ["input_torque"], value), "case1.toml")


def test_input_torque_inf_literal_in_file(tmp_path):
    text = (GEARSET_DIR / "case1.toml").read_text().replace("1378.7 ", "inf    ")
    assert "input_torque = inf" in text
    (tmp_path / "case1.toml").write_text(text)
    with pytest.raises(CaseError, match=r"case1\.toml: input_torque = inf"):
        load_gearset(tmp_path / "case1.toml")


def test_single_pinion_centre_distances_must_agree():
    data = _mutated(_set_raw(), ["meshes", 1, "centre_distance"], 52.0)
    with pytest.raises(CaseError) as info:
        parse_gearset(data, "case1.toml")
    msg = str(info.value)
    assert msg.startswith("case1.toml: meshes[1]: centre_distance = 52.0 mm (pinion-ring)")
    assert "51.945 mm (sun-pinion)" in msg


def test_single_pinion_centre_distance_tolerance_is_1e_6_mm():
    data = _mutated(_set_raw(), ["meshes", 1, "centre_distance"], 51.945 + 2e-6)
    with pytest.raises(CaseError, match=r"meshes\[1\]: centre_distance"):
        parse_gearset(data, "case1.toml")
    ok = _mutated(_set_raw(), ["meshes", 1, "centre_distance"], 51.945 + 5e-7)
    assert parse_gearset(ok, "case1.toml").meshes[1].centre_distance == 51.945 + 5e-7


@pytest.mark.parametrize(
    ("mesh", "value"),
    [(1, 51.945 + 58.600), (2, 51.945 + 42.750), (2, 95.0), (0, 1.0e3)],
)
def test_double_pinion_triangle_inequality(mesh, value):
    data = _mutated(_set_raw("case2"), ["meshes", mesh, "centre_distance"], value)
    with pytest.raises(CaseError, match=r"^case2\.toml: meshes: .* strict triangle inequality"):
        parse_gearset(data, "case2.toml")


@pytest.mark.parametrize(
    ("base", "path", "value", "match"),
    [
        ("case1", ["kind"], "double_pinion", r"a double_pinion set has 4 gears on its power pa"),
        ("case2", ["kind"], "single_pinion", r"a single_pinion set has 3 gears on its power pa"),
        ("case1", ["gears", "ring", "internal"], False, r"gears\.ring: internal = false: the la"),
        ("case2", ["gears", "ring", "internal"], False, r"gears\.ring: internal = false"),
        (
            "case1",
            ["gears", "sun"],
            {
                "teeth": 35,
                "hand": "right",
                "face_width": 32.35,
                "internal": True,
                "shaper_teeth": 20,
            },
            r"gears\.sun: internal = true: only the last gear",
        ),
        ("case1", ["power_path"], ["sun", "pinion", "sun"], r"power_path = .*: a gear appears tw"),
        (
            "case1",
            ["gears", "idler"],
            {"teeth": 20, "hand": "right", "face_width": 10.0},
            r"gears\.idler: not on the power_path",
        ),
    ],
)
def test_power_path_checks(base, path, value, match):
    with pytest.raises(CaseError, match=rf"^{base}\.toml: .*{match}"):
        parse_gearset(_mutated(_set_raw(base), path, value), f"{base}.toml")


# ---------------------------------------------------------------------------------------
# names safe as folder names
# ---------------------------------------------------------------------------------------

UNSAFE = ["../../x", "a/b", "", "x" * 65, "..", "a..b", ".hidden", "-x", "a b", "é", 5, None]


@pytest.mark.parametrize("name", UNSAFE)
def test_unsafe_study_case_names(name):
    with pytest.raises(CaseError, match=r"^1-GB\.toml: name = .*: must be 1 to 64 characters"):
        parse_study_case(_mutated(_case_raw(), ["name"], name), "1-GB.toml")


@pytest.mark.parametrize("name", ["../../x", "a/b", "", "x" * 65])
def test_unsafe_gearset_names(name):
    with pytest.raises(CaseError, match=r"^case1\.toml: name = .*: must be 1 to 64 characters"):
        parse_gearset(_mutated(_set_raw(), ["name"], name), "case1.toml")


@pytest.mark.parametrize("name", ["x" * 64, "1-GB_v2.0+fine"])
def test_safe_names(name):
    assert parse_study_case(_mutated(_case_raw(), ["name"], name), "1-GB.toml").name == name


@pytest.mark.parametrize("value", ["../gearsets/case1", "a/b", 3])
def test_unsafe_gearset_reference_names_the_field(value):
    with pytest.raises(CaseError, match=r"^1-GB\.toml: gearset = "):
        parse_study_case(_mutated(_case_raw(), ["gearset"], value), "1-GB.toml")


# ---------------------------------------------------------------------------------------
# files: gear set by path, encodings, missing files
# ---------------------------------------------------------------------------------------


def _write_pair(tmp_path, gearset_ref: str, set_dir: str = "sets"):
    folder = tmp_path / set_dir
    folder.mkdir(exist_ok=True)
    set_text = (GEARSET_DIR / "case1.toml").read_text().replace('name = "case1"', 'name = "my_set"')
    (folder / "my_set.toml").write_text(set_text)
    case_text = (CASE_DIR / "1-GB.toml").read_text().replace('"case1"', f'"{gearset_ref}"')
    case_file = tmp_path / "study" / "my_case.toml"
    case_file.parent.mkdir(exist_ok=True)
    case_file.write_text(case_text)
    return case_file, folder / "my_set.toml"


def test_gearset_by_path_relative_to_the_case_file(tmp_path, monkeypatch):
    case_file, set_file = _write_pair(tmp_path, "../sets/my_set.toml")
    monkeypatch.chdir(GEARSET_DIR)  # not the working directory
    case = load_study_case(case_file)
    assert case.gearset.name == "my_set"
    assert case.gearset.path == str(case_file.parent / "../sets/my_set.toml")
    assert Path(case.gearset.path).resolve() == set_file.resolve()
    assert case.path == str(case_file)
    # Same data as the shipped set under another name.
    shipped = load_gearset("case1")
    assert case.gearset.gears == shipped.gears and case.gearset.meshes == shipped.meshes


def test_gearset_by_missing_path_names_the_field(tmp_path):
    case_file, _ = _write_pair(tmp_path, "nowhere.toml")
    with pytest.raises(CaseError, match=r"^my_case\.toml: gearset = 'nowhere\.toml': .*no such"):
        load_study_case(case_file)


def test_gearset_by_unknown_name_lists_available():
    data = _mutated(_case_raw(), ["gearset"], "case9")
    with pytest.raises(CaseError, match=r"1-GB\.toml: gearset = 'case9': .*available: case1, c"):
        parse_study_case(data, "1-GB.toml")


def test_non_utf8_file_names_the_file(tmp_path):
    bad = tmp_path / "latin1.toml"
    bad.write_bytes(
        'name = "1-GB"\ndescription = "Lager, Stahl 206 GPa \u00b5"\n'.encode("latin-1")
    )
    with pytest.raises(CaseError, match=r"^latin1\.toml: not UTF-8 text"):
        load_study_case(bad)


def test_unreadable_file_names_the_file(tmp_path):
    from cases.gearset import read_toml

    folder = tmp_path / "folder.toml"
    folder.mkdir()
    with pytest.raises(CaseError, match=r"^folder\.toml: cannot read"):
        read_toml(folder)


@pytest.mark.parametrize("name", ["nope", "../../etc/passwd", "sub/1-GB"])
def test_missing_case_lists_available(tmp_path, name):
    with pytest.raises(CaseError, match=r"no such case \(available: 1-GA, 1-GB, 1-GB-R, 1-GC, 2B"):
        load_study_case(name)
    with pytest.raises(CaseError, match=r"nope\.toml: no such case \(available: 1-GA"):
        load_study_case(tmp_path / "nope.toml")


# ---------------------------------------------------------------------------------------
# self-describing inputs
# ---------------------------------------------------------------------------------------


def test_rename_gear_mesh_spec():
    import cases.gearset as gearset

    assert not hasattr(gearset, "MeshSpec")
    assert all(isinstance(m, GearMeshSpec) for m in load_gearset("case1").meshes)


def test_source_and_path_are_kept_and_ignored_by_eq():
    case = load_study_case("1-GB")
    assert case.path == str(CASE_DIR / "1-GB.toml")
    assert case.source == _case_raw("1-GB")
    assert case.gearset.source == _set_raw("case1")
    assert case.gearset.path == str(GEARSET_DIR / "case1.toml")
    assert dataclasses.replace(case, source={}, path="elsewhere") == case
    assert "source" not in repr(case)


def test_study_inputs_are_json_with_resolved_data():
    inputs = study_inputs(load_study_case("1-GB"))
    assert json.loads(json.dumps(inputs, allow_nan=False)) == inputs
    sc, gs = inputs["study_case"], inputs["gearset"]
    assert sc["numerics"] == {
        "degree": 1,
        "penalty_factor": 100.0,
        "grid_spacing": None,
        "contact_model": "zone",
        "zone_gap_limit_um": 40.0,
        "linear_solver": "mumps",
        "linear_tolerance": None,
        "root_fillets": "auto",
        "root_stress": "submodel",
    }
    assert sc["material"] == {
        "youngs_modulus": 206e3,
        "poisson_ratio": 0.3,
        "gear_modulus_factor": 1.0,
    }
    assert sc["bearing"]["axial_stiffness"] == 2.33e10  # default filled in
    assert sc["model"] == {
        "scene": "one_branch",
        "level": 1,
        "flank_level": 2,
        "fillet_level": 2,
        "positions": 5,
    }
    assert (gs["kind"], gs["planets"], gs["input_torque"]) == ("single_pinion", 3, 1378.7)
    assert gs["power_path"] == ["sun", "pinion", "ring"]
    assert set(gs["gears"]["ring"]) == {f.name for f in dataclasses.fields(GearSpec)}
    assert round(gs["gears"]["ring"]["profile_shift"], 3) == 0.563
    assert gs["meshes"][1] == {"gears": ["pinion", "ring"], "centre_distance": 51.945}


def test_inputs_hash_follows_the_inputs(tmp_path):
    text = (CASE_DIR / "1-GB.toml").read_text()
    case_file = tmp_path / "1-GB.toml"
    case_file.write_text(text)
    h = inputs_hash(load_study_case(case_file))
    assert len(h) == 64 and int(h, 16) >= 0
    assert inputs_hash(load_study_case(case_file)) == h  # re-read, unchanged
    assert inputs_hash(load_study_case("1-GB")) == h  # the path is not an input
    assert inputs_hash(load_study_case("1-GB-R")) != h

    line = "tilting_stiffness = 8.80e7"
    assert line in text
    case_file.write_text(text.replace(line, "tilting_stiffness = 8.81e7"))
    assert inputs_hash(load_study_case(case_file)) != h
    nudged = math.nextafter(8.80e7, math.inf)  # 1 ulp: a relative change of 1.7e-16
    case_file.write_text(text.replace(line, f"tilting_stiffness = {nudged!r}"))
    assert inputs_hash(load_study_case(case_file)) != h
    case_file.write_text(text.replace(line, "tilting_stiffness = 88000000"))  # int: same value
    assert inputs_hash(load_study_case(case_file)) == h


def test_inputs_hash_is_sha256_of_canonical_json():
    """The documented recipe, so any tool can recompute it from a stored inputs JSON."""
    case = load_study_case("2B-GB")
    text = json.dumps(study_inputs(case), sort_keys=True, separators=(",", ":"))
    assert inputs_hash(case) == hashlib.sha256(text.encode()).hexdigest()


def test_inputs_hash_follows_the_gearset(tmp_path):
    case_file, set_file = _write_pair(tmp_path, "../sets/my_set.toml")
    h = inputs_hash(load_study_case(case_file))
    set_file.write_text(set_file.read_text().replace("1378.7 ", "1378.8 "))
    assert inputs_hash(load_study_case(case_file)) != h


def test_available_cases_list_the_shipped_ones():
    cases = available_cases()
    assert cases == sorted(cases) and set(SHIPPED) <= set(cases)


# ------------------------------------------------- gear sets that load but cannot exist
def test_teeth_that_never_meet_are_refused():
    """case1 with a 76-tooth ring: its pinion-ring mesh had eps_alpha = -0.47 (a path of
    contact of negative length, the pinion's tips short of the ring's) and passed the
    check of the total contact ratio, 1.61 with the overlap ratio of 2.08."""
    data = _mutated(_set_raw(), ["gears", "ring", "teeth"], 76)
    with pytest.raises(CaseError, match=r"transverse contact ratio eps_alpha = -0\.4\d\d must be"):
        parse_gearset(data, "case1.toml")


def test_a_transverse_contact_ratio_below_one_is_refused_at_its_bound():
    """80 teeth: eps_alpha 0.47; the shipped 86 teeth: 1.58 (both helical, eps_beta 2.08)."""
    with pytest.raises(CaseError, match=r"eps_alpha = 0\.4"):
        parse_gearset(_mutated(_set_raw(), ["gears", "ring", "teeth"], 80), "case1.toml")
    assert parse_gearset(_set_raw(), "case1.toml").gears["ring"].teeth == 86


@pytest.mark.parametrize(
    ("base", "path", "value", "what"),
    [
        # 7 pinions of 23.73 mm tip radius on a 51.945 mm circle: 44.4 mm apart, need 47.5
        ("case1", ["planets"], 7, r"pinion\d and pinion\d overlap by 3\.0\d\d mm"),
        ("case1", ["planets"], 12, r"pinion\d+ and pinion\d+ overlap"),
        # 4 SP-RP pairs: neighbouring branches' pinions overlap
        ("case2", ["planets"], 4, r"(SP|RP)\d and (SP|RP)\d overlap"),
    ],
)
def test_overlapping_planets_are_refused(base, path, value, what):
    with pytest.raises(CaseError, match=rf"^{base}\.toml: planets = {value}, .*{what}"):
        parse_gearset(_mutated(_set_raw(base), path, value), f"{base}.toml")


def test_a_double_pinion_ring_that_cuts_into_the_sp_is_refused():
    """case2 with an 84-tooth ring at a 52.5 mm RP-ring centre distance: every mesh is a good
    mesh (eps_alpha 1.46-1.51), but the RP's tips reach into the sun's and the SP's into the
    ring's teeth; the SP-ring gap of the shipped set is 1.97 mm."""
    data = _mutated(_set_raw("case2"), ["gears", "ring", "teeth"], 84)
    data = _mutated(data, ["meshes", 2, "centre_distance"], 52.5)
    with pytest.raises(CaseError, match=r"tip circles of RP and sun overlap by 1\.096 mm"):
        parse_gearset(data, "case2.toml")


@pytest.mark.parametrize(
    ("names", "match"),
    [
        ({"sun": "P1", "pinion": "P"}, r"gears\.P1: its name is gears\.P's with a number"),
        ({"pinion": "../x y"}, r"gears\.\.\./x y: a gear name must be 1 to 16 letters"),
        ({"pinion": "pin_ion"}, r"gears\.pin_ion: a gear name must be"),
        ({"pinion": "carrier"}, r"gears\.carrier: the system scene's carrier body"),
    ],
)
def test_gear_names_that_collide_or_leave_the_folder_are_refused(names, match):
    """A sun named P1 beside a pinion P: the all-planet scenes named branch 1's pinion P1
    too, and the scene's gear 'P1' was the sun; a name with '/' named files outside the
    results folder; '_' joins names in result keys (sun_pinion_side)."""
    data = _set_raw()
    for old, new in names.items():
        data["gears"][new] = data["gears"].pop(old)
        data["power_path"] = [new if p == old else p for p in data["power_path"]]
        for m in data["meshes"]:
            m["gears"] = [new if g == old else g for g in m["gears"]]
    with pytest.raises(CaseError, match=rf"^case1\.toml: {match}"):
        parse_gearset(data, "case1.toml")


def test_shaper_teeth_on_an_external_gear_is_refused():
    data = _mutated(_set_raw(), ["gears", "sun", "shaper_teeth"], 3)
    with pytest.raises(CaseError, match=r"gears\.sun: shaper_teeth: only for an internal gear"):
        parse_gearset(data, "case1.toml")


def test_a_missing_gear_field_is_named_not_a_python_error():
    data = _mutated(_set_raw(), ["gears", "sun", "teeth"], None)
    with pytest.raises(CaseError, match=r"^case1\.toml: gears\.sun: missing field\(s\) teeth$"):
        parse_gearset(data, "case1.toml")


def test_system_settings_outside_the_system_scene_are_refused():
    """1-GA (one branch) with a 200 um pin error: read by the system scene only, the run
    ignored it while the inputs' hash changed."""
    data = _case_raw("1-GA")
    data["system"] = {"pin_position_errors_um": [[200.0, 0.0], [0.0, 0.0], [0.0, 0.0]]}
    with pytest.raises(CaseError, match=r"system\.pin_position_errors_um: only for model\.scene"):
        parse_study_case(data, "1-GA.toml", CASE_DIR / "1-GA.toml")
    data["model"]["scene"] = "system"
    assert parse_study_case(data, "1-GA.toml", CASE_DIR / "1-GA.toml").system.pin_position_errors_um


@pytest.mark.parametrize("value", [5, "ab", [1.0, 2.0]])
def test_pin_errors_that_are_not_pairs_are_echoed_as_written(value):
    data = _case_raw("1-GA")
    data["model"]["scene"] = "system"
    data["system"] = {"pin_position_errors_um": value}
    with pytest.raises(CaseError) as info:
        parse_study_case(data, "1-GA.toml", CASE_DIR / "1-GA.toml")
    assert f"pin_position_errors_um = {value!r}: must be" in str(info.value)


def test_flank_and_fillet_levels_of_a_case_and_the_inputs_of_a_run_setting_its_own_sizes():
    """``[model] flank_level`` / ``fillet_level``: checked as the level is; the level's own
    is no variant; a case without them hashes as before they existed (the stored positions
    and records of such a case stand), and ``without_variant`` gives a run that sets its
    sizes itself (a convergence run) the inputs of the case without them."""
    data = tomllib.loads((CASE_DIR / "1-GB.toml").read_text())
    gb = parse_study_case(data, "1-GB.toml")
    assert gb.model.variant == {"flank_level": 2, "fillet_level": 2}
    plain = mutated(mutated(data, ["model", "flank_level"], None), ["model", "fillet_level"], None)
    own = parse_study_case(plain, "x.toml")
    assert own.model.variant == {}
    assert "flank_level" not in study_inputs(own)["study_case"]["model"]
    assert inputs_hash(without_variant(gb)) == inputs_hash(own) != inputs_hash(gb)
    same = mutated(plain, ["model", "flank_level"], 1)  # level 1's own flanks: no variant
    assert parse_study_case(same, "x.toml").model.variant == {}
    assert inputs_hash(parse_study_case(same, "x.toml")) == inputs_hash(own)
    for bad in (4, -1, 1.5, True, "2"):
        wrong = mutated(plain, ["model", "fillet_level"], bad)
        with pytest.raises(CaseError, match=r"model.fillet_level = .*: must be an integer 0..3"):
            parse_study_case(wrong, "x.toml")
    # a run's sizes: the case's with no level given, a level given is that level's own
    assert case_sizes(gb) == (1, {"flank_level": 2, "fillet_level": 2})
    assert case_sizes(gb, 0) == (0, {}) and case_sizes(gb, 1) == (1, {})
    assert case_sizes(own) == (1, {})

"""The field reference of the docs (cases.reference) against the validators: every field it
lists is accepted and checked by the validator, every field the validator accepts is listed,
and the ranges it prints are the ranges the validator enforces (probed at and beyond each
bound)."""

import copy
import re
import tomllib

import pytest

from cases.gearset import GEARSET_DIR, CaseError, parse_gearset
from cases.reference import FIELDS, ReferenceDrift, reference_markdown, table_rows
from cases.study_case import CASE_DIR, accepted_fields, parse_study_case

CASE = tomllib.loads((CASE_DIR / "1-GB.toml").read_text())
GEARSET = tomllib.loads((GEARSET_DIR / "case1.toml").read_text())
NOT_A_VALUE = {"not": "a value"}  # no field takes a table with this key


def _wrong(kind: str):
    """A value of no allowed type for a field of ``kind``: a table for a value, a number
    for a table."""
    return 5 if kind.startswith(("table", "array of tables")) else NOT_A_VALUE


def _case_with(table: str, key: str, value, context: dict | None = None) -> dict:
    data = copy.deepcopy(CASE)
    for t, fields in (context or {}).items():
        data.setdefault(t, {}).update(fields)
    (data.setdefault(table, {}) if table else data)[key] = value
    return data


# the settings a field is read under (never ignored silently elsewhere)
CONTEXT = {
    ("numerics", "linear_tolerance"): {"numerics": {"linear_solver": "cg-gamg"}},
    ("system", "sun_radial_stiffness"): {"model": {"scene": "system"}},
    ("system", "pin_position_errors_um"): {"model": {"scene": "system"}},
}


def _case_fields():
    for table, rows in table_rows("case").items():
        for key, doc, _ in rows:
            yield table, key, doc


def _gearset_paths():
    """(where in the mapping, key) of every gear-set field, on the shipped case 1 set."""
    for table, rows in table_rows("gearset").items():
        for key, doc, _ in rows:
            yield table, key, doc


def test_the_reference_lists_exactly_the_fields_the_validators_accept():
    for kind in ("case", "gearset"):
        rows = table_rows(kind)  # raises ReferenceDrift otherwise
        text = reference_markdown(kind)
        for table in rows:
            for key, _, _ in rows[table]:
                assert f"| `{key}` |" in text
    assert set(table_rows("case")) == set(accepted_fields())


def test_drift_is_an_error(monkeypatch):
    """A field added to the validator without a reference entry fails the docs build."""
    monkeypatch.setitem(FIELDS["case"], "numerics", dict(FIELDS["case"]["numerics"]))
    del FIELDS["case"]["numerics"]["degree"]
    with pytest.raises(ReferenceDrift, match=r"undocumented \['degree'\]"):
        table_rows("case")


@pytest.mark.parametrize(
    ("table", "key", "doc"), list(_case_fields()), ids=lambda v: v if isinstance(v, str) else ""
)
def test_every_case_field_is_read_and_checked(table, key, doc):
    """A value of no allowed type is refused naming the field: the validator reads it (an
    unknown field would be refused as unknown)."""
    data = _case_with(table, key, _wrong(doc.kind), CONTEXT.get((table, key)))
    with pytest.raises(CaseError) as err:
        parse_study_case(data, "c.toml")
    message = str(err.value)
    assert key in message and "unknown field" not in message


@pytest.mark.parametrize(
    ("table", "key", "doc"), list(_gearset_paths()), ids=lambda v: v if isinstance(v, str) else ""
)
def test_every_gearset_field_is_read_and_checked(table, key, doc):
    data = copy.deepcopy(GEARSET)
    target = {
        "": data,
        "common": data["common"],
        "gears.*": data["gears"]["pinion"],
        "gears.*.modifications": data["gears"]["pinion"].setdefault("modifications", {}),
        "meshes[]": data["meshes"][0],
    }[table]
    target[key] = _wrong(doc.kind)
    with pytest.raises(CaseError) as err:
        parse_gearset(data, "s.toml")
    message = str(err.value)
    assert key in message and "unknown field" not in message


_INTERVAL = re.compile(r"^([\[(])(-?[\d.e+-]+), (-?[\d.e+-]+)([\])])$")
_INTEGERS = re.compile(r"^(\d+)\.\.(\d+)$")


def _bounds():
    for table, key, doc in _case_fields():
        if m := _INTERVAL.match(doc.allowed):
            lo, hi = float(m[2]), float(m[3])
            yield table, key, lo, m[1] == "[", hi, m[4] == "]", float
        elif m := _INTEGERS.match(doc.allowed):
            yield table, key, int(m[1]), True, int(m[2]), True, int


BOUNDS = list(_bounds())


def test_the_probed_ranges_cover_the_numeric_fields():
    probed = {(t, k) for t, k, *_ in BOUNDS}
    numeric = {(t, k) for t, k, d in _case_fields() if d.kind in ("number", "integer")}
    # the rest print a bound that is not an interval (>= 0, a list of choices)
    assert numeric - probed == {("system", "sun_radial_stiffness"), ("numerics", "degree")}


@pytest.mark.parametrize(
    ("table", "key", "lo", "lo_in", "hi", "hi_in", "kind"),
    BOUNDS,
    ids=lambda v: v if isinstance(v, str) else "",
)
def test_the_printed_range_is_the_enforced_range(table, key, lo, lo_in, hi, hi_in, kind):
    """At a closed bound the value is accepted; just beyond either bound it is refused with
    the field named (1e-9 relative: far below any printed digit, far above round-off)."""
    context = CONTEXT.get((table, key))
    step = 1 if kind is int else None

    def beyond(bound, sign):
        return bound + sign * (step or max(abs(bound) * 1e-9, 1e-12))

    for value, inside in ((lo, lo_in), (hi, hi_in)):
        if inside:
            parse_study_case(_case_with(table, key, value, context), "c.toml")
    for value in ((beyond(lo, -1) if lo_in else lo), (beyond(hi, +1) if hi_in else hi)):
        with pytest.raises(CaseError, match=re.escape(f"{table}.{key} = ")):
            parse_study_case(_case_with(table, key, value, context), "c.toml")

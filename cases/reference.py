"""The field reference of the study-case file and the gear-set file, as Markdown for the docs
site (``docs/reference/*-file.md``, written at the start of ``make docs``).

The fields listed are the ones the validators accept (``accepted_fields()`` of
:mod:`cases.study_case` and :mod:`cases.gearset`), the defaults are the dataclasses' and the
allowed ranges are the constants the validators check against; only the meaning and the unit
of each field are written here. A field the validator accepts without an entry below, or an
entry for a field it refuses, raises :class:`ReferenceDrift`: the docs build fails instead of
going stale (and ``tests/test_case_reference.py`` checks the ranges by probing the validators).
"""

from __future__ import annotations

import math
from dataclasses import MISSING, dataclass, fields

from cases import gearset as gs
from cases import study_case as sc
from gears import microgeometry as mg
from gears import spec as gspec

__all__ = ["FIELDS", "FieldDoc", "ReferenceDrift", "reference_markdown", "table_rows"]


class ReferenceDrift(RuntimeError):
    """The reference and the validator disagree on which fields exist."""


@dataclass(frozen=True)
class FieldDoc:
    """What a user needs to know of one field beyond its name."""

    kind: str  # TOML type: number, integer, string, boolean, table, array
    unit: str  # "" for none
    allowed: str  # the allowed values, from the validator's constants
    meaning: str
    default: str | None = None  # None: read from the dataclass the field fills (or required)


def _interval(lo: float, hi: float, lo_open: bool = False, hi_open: bool = False) -> str:
    if hi == math.inf:
        return f"> {lo:g}" if lo_open else f">= {lo:g}"
    return f"{'(' if lo_open else '['}{lo:g}, {hi:g}{')' if hi_open else ']'}"


def _choices(values) -> str:
    return ", ".join(f'`"{v}"`' for v in values)


def _range(name: str) -> str:
    return _interval(*sc._RANGES[name])


_MAX_LEVEL = f"0..{sc.MAX_LEVEL}"
_AN20 = math.radians(20.0)
_DEDENDUM_MAX_20 = math.pi / (4.0 * math.tan(_AN20))
_RHO_MAX_20 = (math.pi / 4.0 - 1.25 * math.tan(_AN20)) * math.cos(_AN20) / (1.0 - math.sin(_AN20))

#: the study-case file (``cases/<name>.toml``), by table ("" the top level)
CASE_FIELDS: dict[str, dict[str, FieldDoc]] = {
    "": {
        "name": FieldDoc(
            "string",
            "",
            f"1-{gs.MAX_NAME_LENGTH} of `A-Z a-z 0-9 _ . + -`, starting with a letter or digit",
            "The case's name; names its output folder `results/<name>/`.",
            "required",
        ),
        "gearset": FieldDoc(
            "string",
            "",
            "a name in `cases/gearsets/`, or a path ending in "
            "`.toml` (relative to this file's folder)",
            "The gear-set file: gears, meshes, torque.",
            "required",
        ),
        "description": FieldDoc(
            "string",
            "",
            "any text",
            "Free text; not an input of the run (changing it solves nothing again).",
            '`""`',
        ),
        "bearing": FieldDoc("table", "", "", "The needle bearing of each pinion.", "required"),
        "material": FieldDoc("table", "", "", "The elastic material of every body.", "steel"),
        "model": FieldDoc(
            "table", "", "", "Scene, mesh resolution and mesh positions.", "required"
        ),
        "numerics": FieldDoc(
            "table", "", "", "Numerical settings; every field optional.", "every field's default"
        ),
        "system": FieldDoc(
            "table",
            "",
            'only with `model.scene = "system"`',
            "Settings of the system scene; every field optional.",
            "every field's default",
        ),
    },
    "bearing": {
        "radial_stiffness": FieldDoc(
            "number",
            "N/mm",
            _range("bearing.radial_stiffness"),
            "Radial stiffness of the bearing between pinion and pin, in both radial directions.",
        ),
        "tilting_stiffness": FieldDoc(
            "number",
            "N mm/rad",
            _range("bearing.tilting_stiffness"),
            "Tilting stiffness about both axes normal to the pin: "
            "what the paper's bearing cases vary.",
        ),
        "axial_stiffness": FieldDoc(
            "number",
            "N/mm",
            _range("bearing.axial_stiffness"),
            'Axial stiffness ("stiff" in the paper: 100x the rigid '
            "bearing's radial stiffness). The spin is free.",
        ),
    },
    "material": {
        "youngs_modulus": FieldDoc(
            "number", "MPa", _range("material.youngs_modulus"), "Young's modulus of every body."
        ),
        "poisson_ratio": FieldDoc(
            "number",
            "",
            _range("material.poisson_ratio"),
            "Poisson's ratio of every body. Above 0.45 set `numerics.degree = 2`: "
            "linear tetrahedra lock as it nears 0.5 (the run warns).",
        ),
        "gear_modulus_factor": FieldDoc(
            "number",
            "",
            _range("material.gear_modulus_factor"),
            "Multiplies the Young's modulus of the gear bodies "
            "(not the bearing): 10 gives the near-rigid gears of "
            "case 1-GB-R.",
        ),
    },
    "model": {
        "scene": FieldDoc(
            "string",
            "",
            _choices(sc.SCENES),
            '`"one_branch"`: one pinion '
            "(or pinion pair) with sun and ring, equal load sharing on a rigid "
            'carrier; `"all_planets"`: every planet; `"system"`: every planet '
            "on its pin of the elastic carrier.",
        ),
        "level": FieldDoc(
            "integer",
            "",
            _MAX_LEVEL,
            "Mesh resolution level of the ladder "
            "(element sizes of `meshing.sizing.LEVELS`); 1 is the shipped "
            "cases'.",
        ),
        "positions": FieldDoc(
            "integer",
            "",
            f"1..{sc.MAX_POSITIONS}",
            "Mesh positions solved "
            "over one base pitch (the mesh cycle); means and cycle maxima "
            "are taken over them.",
        ),
        "flank_level": FieldDoc(
            "integer",
            "",
            _MAX_LEVEL,
            "The active flanks and the contact "
            "grid at this level's element size; omitted: `level`'s.",
        ),
        "fillet_level": FieldDoc(
            "integer",
            "",
            _MAX_LEVEL,
            "The refined root fillets at this level's size; omitted: `level`'s.",
        ),
    },
    "numerics": {
        "degree": FieldDoc(
            "integer",
            "",
            ", ".join(map(str, sc.DEGREES)),
            "Lagrange element degree of the displacement.",
        ),
        "penalty_factor": FieldDoc(
            "number",
            "",
            _interval(*sc.PENALTY_FACTOR_RANGE),
            "Contact penalty relative to the body stiffness "
            '(eps = factor E* / h); used by the `"line"` contact model '
            "(and where a zone grid finds no cell on a coast flank).",
        ),
        "grid_spacing": FieldDoc(
            "number",
            "mm",
            _interval(*sc.GRID_SPACING_RANGE, lo_open=True),
            "Contact grid spacing along the contact line. The grid's cells grow as "
            "1 / spacing^2 and its compliance is dense: a spacing whose grid would not fit "
            "in the machine's memory is refused before meshing, with the spacing that fits.",
            "the flank element size of the level",
        ),
        "contact_model": FieldDoc(
            "string",
            "",
            _choices(sc.CONTACT_MODELS),
            '`"zone"`: a '
            "grid over the whole potential contact zone of drive and "
            "coast flanks, half-space near field, exact contact; "
            '`"line"`: a penalty spring per point on the theoretical '
            "contact lines.",
        ),
        "zone_gap_limit_um": FieldDoc(
            "number",
            "um",
            _interval(*sc.ZONE_GAP_RANGE),
            '`"zone"` only: grid cells are laid where the unloaded '
            "separation (modifications included) is within this of the "
            "smallest in its transverse section; a position whose load reaches "
            "cells more than half of it above is solved again on the band the "
            "check names, and the summary warns (`zone_reach_um`, "
            "`zone_gap_widened` in the position files).",
        ),
        "linear_solver": FieldDoc(
            "string",
            "",
            _choices(sc.LINEAR_SOLVERS),
            "Solver of each "
            'body: `"mumps"` exact sparse LU, `"mumps-blr"` block '
            'low-rank LU, `"cg-gamg"` iterative.',
        ),
        "linear_tolerance": FieldDoc(
            "number",
            "",
            _interval(*sc.LINEAR_TOLERANCE_RANGE),
            "BLR dropping threshold (at most "
            f"{sc.BLR_TOLERANCE_MAX:g}: its factors serve as an exact solve) or CG "
            'relative residual; not for `"mumps"`.',
            "the solver's (1e-6 BLR, 1e-8 CG)",
        ),
        "out_of_core": FieldDoc(
            "boolean",
            "",
            "true, false; not with `cg-gamg`",
            "Keep the "
            "LU factors on disk (`$PLANETARY_OOC_DIR`, else the temporary "
            "folder): the same answer, a fraction of the memory.",
        ),
        "root_fillets": FieldDoc(
            "string",
            "",
            _choices(sc.ROOT_FILLETS),
            "Which root "
            'fillets the global mesh refines: `"auto"` refines the '
            "loaded fillets in the one-branch scene and none in the "
            "all-planet and system scenes.",
        ),
        "root_stress": FieldDoc(
            "string",
            "",
            _choices(sc.ROOT_STRESS_METHODS),
            "Where the "
            'root stress is read: `"submodel"` on P2 submodels of the '
            'loaded teeth, `"global"` on the global mesh (a check), '
            '`"none"` not read.',
        ),
    },
    "system": {
        "sun_radial_stiffness": FieldDoc(
            "number",
            "N/mm",
            ">= 0",
            "Radial support of the sun at its bore; 0 lets the sun float (centred by the meshes).",
        ),
        "pin_position_errors_um": FieldDoc(
            "array",
            "um",
            "empty, or one `[tangential, "
            f"radial]` pair per branch, each within "
            f"+-{sc.MAX_PIN_ERROR_UM:g}",
            "Pin-hole position "
            "error of each pinion's pin in the carrier, in "
            "carrier order; tangential along the sun's sense of "
            "rotation.",
            "`[]` (none)",
        ),
    },
}

_GEAR = {
    "teeth": FieldDoc("integer", "", f">= {gspec.MIN_TEETH}", "Number of teeth."),
    "normal_module": FieldDoc("number", "mm", "> 0", "Normal module m_n."),
    "normal_pressure_angle": FieldDoc(
        "number", "deg", _interval(*gspec.PRESSURE_ANGLE_RANGE), "Normal pressure angle alpha_n."
    ),
    "helix_angle": FieldDoc(
        "number",
        "deg",
        _interval(*gspec.HELIX_ANGLE_RANGE),
        "Helix angle beta (magnitude; the hand gives its sense).",
    ),
    "hand": FieldDoc(
        "string",
        "",
        '`"right"`, `"left"` (`"R"`, `"L"`, any case)',
        "Hand of the helix; either for a spur gear.",
    ),
    "face_width": FieldDoc(
        "number",
        "mm",
        f">= {gs.MIN_FACE_MODULES:g} normal modules",
        "Face width b; the stresses are read one module in from each face end.",
    ),
    "internal": FieldDoc(
        "boolean",
        "",
        "true only for the last gear of the power path",
        "An internal gear (the ring).",
    ),
    "addendum_coef": FieldDoc("number", "", "(0, 2]", "Addendum h_a* = h_a / m_n."),
    "dedendum_coef": FieldDoc(
        "number",
        "",
        f"up to a pointed tool tooth, pi / (4 tan alpha_n) ({_DEDENDUM_MAX_20:.3f} at 20 deg)",
        "Dedendum h_f* = h_f / m_n, also the generating tool's addendum.",
    ),
    "hob_tip_radius_coef": FieldDoc(
        "number",
        "",
        f"up to the tool's full-round tip ({_RHO_MAX_20:.3f} at 20 deg with h_f* 1.25)",
        "Tip radius of the generating tool / m_n (ISO 53 profile A: 0.38); sets the root fillet.",
    ),
    "shaper_teeth": FieldDoc(
        "integer",
        "",
        f">= {gspec.MIN_SHAPER_TEETH} and < teeth; internal gears only",
        "Teeth of the pinion-type shaper that cuts the ring (external gears are hobbed).",
    ),
    "modifications": FieldDoc("table", "", "", "Flank modifications of this gear (below).", "none"),
}

#: the gear-set file (``cases/gearsets/<name>.toml``), by table
GEARSET_FIELDS: dict[str, dict[str, FieldDoc]] = {
    "": {
        "name": FieldDoc(
            "string",
            "",
            f"1-{gs.MAX_NAME_LENGTH} of `A-Z a-z 0-9 _ . + -`",
            "The gear set's name.",
            "required",
        ),
        "kind": FieldDoc(
            "string",
            "",
            _choices(gs.KINDS),
            "Single pinion (sun, pinion, ring) or double pinion (sun, SP, RP, ring).",
            "required",
        ),
        "input_torque": FieldDoc(
            "number", "N m", "> 0", "Torque on the sun, shared equally by the planets.", "required"
        ),
        "planets": FieldDoc(
            "integer",
            "",
            "1..12; the tip circles must clear",
            "Pinions (single) or pinion pairs (double) on the carrier.",
            "required",
        ),
        "power_path": FieldDoc(
            "array",
            "",
            "the gear names, sun first, ring last: "
            f"{gs.PATH_LENGTH['single_pinion']} (single) or "
            f"{gs.PATH_LENGTH['double_pinion']} (double)",
            "The gears in mesh order from the sun to the ring.",
            "required",
        ),
        "common": FieldDoc(
            "table",
            "",
            "",
            "Gear fields shared by every gear (a gear's own table overrides them).",
            "none",
        ),
        "gears": FieldDoc(
            "table",
            "",
            "one `[gears.<name>]` per gear on the power path; a "
            "name is letters and digits, starting with a letter",
            "The gears.",
            "required",
        ),
        "meshes": FieldDoc(
            "array of tables",
            "",
            "one `[[meshes]]` per step of the power path, in order",
            "The meshes.",
            "required",
        ),
    },
    "common": {k: v for k, v in _GEAR.items() if k in gs._COMMON_FIELDS},
    "gears.*": _GEAR,
    "gears.*.modifications": {
        "lead_crown_um": FieldDoc(
            "number",
            "um",
            f"[0, {mg.MAX_MODIFICATION_UM:g}]",
            "Parabolic lead crown C_b, reached at both face ends.",
        ),
        "lead_slope_um": FieldDoc(
            "number",
            "um",
            f"[-{mg.MAX_MODIFICATION_UM:g}, {mg.MAX_MODIFICATION_UM:g}]",
            "Helix angle modification f_Hb across the face width.",
        ),
        "tip_relief_um": FieldDoc(
            "number",
            "um",
            f"[0, {mg.MAX_MODIFICATION_UM:g}]",
            "Tip relief C_a at the tip circle, linear in roll length.",
        ),
        "tip_relief_diameter": FieldDoc(
            "number",
            "mm",
            "> 0; required with tip_relief_um",
            "Diameter d_Ca where the tip relief starts.",
        ),
        "end_relief_um": FieldDoc(
            "number", "um", f"[0, {mg.MAX_MODIFICATION_UM:g}]", "End relief C_I at each face end."
        ),
        "end_relief_length": FieldDoc(
            "number",
            "mm",
            "> 0; required with end_relief_um",
            "Length l_I of the end relief from each face end.",
        ),
    },
    "meshes[]": {
        "gears": FieldDoc(
            "array",
            "",
            "the two gears of this step of the power path, in order",
            "The meshing pair.",
            "required",
        ),
        "centre_distance": FieldDoc(
            "number",
            "mm",
            "> 0; equal at both meshes of a single pinion set; a triangle for a double pinion set",
            "Operating centre distance; the profile shifts follow from it (the sun's is 0).",
            "required",
        ),
        "normal_backlash_um": FieldDoc(
            "number",
            "um",
            f"[0, {gs.MAX_BACKLASH_UM:g}]",
            "Normal backlash, made by tooth thickness allowances.",
            "the ISO/TR 10064-2 minimum for the centre distance and module",
        ),
    },
}

FIELDS = {"case": CASE_FIELDS, "gearset": GEARSET_FIELDS}

#: the dataclass each table fills, for the defaults
_DATACLASSES = {
    ("case", "bearing"): sc.Bearing,
    ("case", "material"): sc.Material,
    ("case", "model"): sc.Model,
    ("case", "numerics"): sc.Numerics,
    ("case", "system"): sc.System,
    ("gearset", "common"): gspec.GearSpec,
    ("gearset", "gears.*"): gspec.GearSpec,
    ("gearset", "gears.*.modifications"): mg.FlankModifications,
}

_ACCEPTED = {"case": sc.accepted_fields, "gearset": gs.accepted_fields}


def _default(kind: str, table: str, key: str, doc: FieldDoc) -> str:
    if doc.default is not None:
        return doc.default
    cls = _DATACLASSES.get((kind, table))
    f = {f.name: f for f in fields(cls)}.get(key) if cls else None
    if f is None or f.default is MISSING:
        return {
            "gears.*": "required (here or in `[common]`)",
            "common": "none (each gear gives it)",
        }.get(table, "required")
    if f.default is None:
        return "omitted"
    value = f.default
    if isinstance(value, bool):
        return f"`{str(value).lower()}`"
    if isinstance(value, str):
        return f'`"{value}"`'
    return f"`{value:g}`" if isinstance(value, float) else f"`{value}`"


def table_rows(kind: str) -> dict[str, list[tuple[str, FieldDoc, str]]]:
    """Per table of the ``kind`` file ("case" or "gearset"): (field, doc, default) in the
    validator's order; :class:`ReferenceDrift` where the reference and the validator differ."""
    accepted = _ACCEPTED[kind]()
    docs = FIELDS[kind]
    if set(accepted) != set(docs):
        raise ReferenceDrift(f"{kind} file: tables {sorted(accepted)} vs {sorted(docs)}")
    rows = {}
    for table, keys in accepted.items():
        missing = [k for k in keys if k not in docs[table]]
        extra = [k for k in docs[table] if k not in keys]
        if missing or extra:
            raise ReferenceDrift(
                f"{kind} file, table {table!r}: undocumented {missing}, refused {extra}"
            )
        rows[table] = [(k, docs[table][k], _default(kind, table, k, docs[table][k])) for k in keys]
    return rows


_TITLES = {
    "case": ("The study-case file", "cases/<name>.toml", "cases/1-GB.toml"),
    "gearset": ("The gear-set file", "cases/gearsets/<name>.toml", "cases/gearsets/case1.toml"),
}
_INTRO = {
    "case": "A study case names a gear set and adds what the run needs: the pinion needle "
    "bearing, the material, the scene and mesh resolution, and the numerics. Every table "
    "refuses keys it does not know, and every error names the file, the field and what is "
    "allowed (`planetary-fe check CASE` validates a file without solving).",
    "gearset": "A gear set holds the data a gear drawing or a paper prints: tooth numbers, "
    "module, pressure and helix angles, hands, face widths, centre distances and the torque. "
    "The profile shifts are not entered: they follow from the centre distances along the "
    "power path, with the sun at x = 0. Backlash and flank modifications are optional.",
}


def _heading(table: str) -> str:
    if table == "":
        return "Top level"
    return {
        "gears.*": "[gears.<name>]",
        "gears.*.modifications": "[gears.<name>.modifications]",
        "meshes[]": "[[meshes]]",
    }.get(table, f"[{table}]")


def reference_markdown(kind: str) -> str:
    """The reference page of the ``kind`` file ("case" or "gearset") as MyST Markdown."""
    title, where, example = _TITLES[kind]
    lines = [
        f"# {title}",
        "",
        "<!-- written by cases/reference.py at the start of `make docs`: do not edit -->",
        "",
        f"`{where}`. {_INTRO[kind]} A shipped example: `{example}`.",
        "",
    ]
    for table, rows in table_rows(kind).items():
        header = "| field | type | unit | default | allowed | meaning |"
        lines += [f"## {_heading(table)}", "", header, "|---|---|---|---|---|---|"]
        for key, doc, default in rows:
            cells = (f"`{key}`", doc.kind, doc.unit, default, doc.allowed or "", doc.meaning)
            lines.append("| " + " | ".join(c.replace("|", "\\|") for c in cells) + " |")
        lines.append("")
    return "\n".join(lines)

"""Finite element study cases (``cases/<name>.toml``) read into frozen, validated dataclasses.

A study case names a gear set (``cases/gearsets/``), the pinion needle bearing (singh2007
section 7: a 6x6 diagonal stiffness between pinion and pin, radial and tilting given, axial
stiff, spin free), the material, the model resolution and the numerical settings. Every
table refuses keys it does not know; every error names the file and the field with the
allowed range. Omitted optional fields take the defaults of the dataclasses below, the one
place they are defined: ``[material]`` defaults to :data:`gears.material.STEEL`,
``[numerics]`` to :data:`DEFAULTS`.

:func:`study_inputs` gives everything that defines a run as JSON-ready data and
:func:`inputs_hash` its sha256, for outputs that say what produced them.
"""

from __future__ import annotations

import hashlib
import json
import math
from dataclasses import asdict, dataclass, field, fields, replace
from pathlib import Path
from typing import Any

from cases.gearset import (
    NAME_PATTERN,
    CaseError,
    GearSet,
    check_keys,
    check_name,
    load_gearset,
    read_toml,
)
from gears.material import STEEL

CASE_DIR = Path(__file__).parent
SCENES = ("one_branch", "all_planets", "system")
MAX_LEVEL = 3
#: ``[model]`` fields that take one kind of element size from another level (Model)
VARIANT_FIELDS = ("flank_level", "fillet_level")
MAX_POSITIONS = 50
# The paper leaves the axial bearing stiffness out ("stiff"): 100x the radial rigid bearing.
DEFAULT_AXIAL_STIFFNESS = 2.33e10
DEGREES = (1, 2)
PENALTY_FACTOR_RANGE = (1.0, 1e6)  # inclusive
GRID_SPACING_RANGE = (0.01, 5.0)  # mm, open below, closed above
CONTACT_MODELS = ("line", "zone")
ZONE_GAP_RANGE = (1.0, 500.0)  # um, inclusive
# the body solvers of solvers.elastic_body.LinearSolver (a test checks the two agree)
LINEAR_SOLVERS = ("mumps", "mumps-blr", "cg-gamg")
# Which root fillets of the global model a scene refines to the level's fillet size
# (meshing.sizing.Level): "auto" = "refined" in the one-branch scene, "coarse" in the
# all-planet and system scenes (refining every planet's loaded fillets would double their
# DOFs); "coarse" = every fillet at fillet_far. Finer fillets make the teeth more compliant
# (the moments move by 1-3 %); the submodels read the root stress on either.
ROOT_FILLETS = ("auto", "refined", "coarse")
# How the root stress is read (solvers.root_submodel): "submodel" = on a P2 submodel of the
# loaded teeth with finer fillets, driven by the global solution, in every scene (with
# several planets, on the most loaded mesh of each gear and side); "global" = on the global
# model's own fillets where the scene refines them (P1 there is not converged: a check
# only); "none" = not read (studies of moments or stiffness alone).
ROOT_STRESS_METHODS = ("submodel", "global", "none")
LINEAR_TOLERANCE_RANGE = (1e-14, 1e-3)  # inclusive; BLR threshold or CG relative residual
# the largest BLR dropping threshold: its factors are used as an exact solve (no refinement);
# 1-GB at level 0 moved Mx_pin by 1e-4 of itself at 1e-5 and 1e-4, by 4 % at 1e-3
BLR_TOLERANCE_MAX = 1e-4


def _real(value) -> bool:
    """A finite int or float (not a bool)."""
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


@dataclass(frozen=True)
class Bearing:
    """Needle bearing of one pinion: diagonal stiffness to the pin (carrier)."""

    radial_stiffness: float  # N/mm, both radial directions
    tilting_stiffness: float  # N mm/rad, both tilting axes
    axial_stiffness: float = DEFAULT_AXIAL_STIFFNESS  # N/mm; "stiff" in the paper


@dataclass(frozen=True)
class Material:
    """Isotropic elastic material of the bodies; defaults: :data:`gears.material.STEEL`."""

    youngs_modulus: float = STEEL.youngs_modulus  # MPa
    poisson_ratio: float = STEEL.poisson_ratio
    gear_modulus_factor: float = 1.0  # multiplies E of every gear body (case 1-GB-R: 10)

    @property
    def gear_youngs_modulus(self) -> float:
        return self.youngs_modulus * self.gear_modulus_factor


@dataclass(frozen=True)
class Model:
    scene: str  # one of SCENES
    level: int  # mesh resolution ladder level, 0..MAX_LEVEL
    positions: int  # mesh positions over one base pitch, 1..MAX_POSITIONS
    # The active teeth's flank elements (and so the default contact grid) at this level's
    # size, and the refined root fillets at this level's, every other size and the
    # root-stress sectors those of ``level`` (meshing.sizing.with_sizes; run label
    # L<level>P<degree>F<flank_level>R<fillet_level>). None, or ``level`` itself: the level's
    # own. The case's sizes, used where a run takes the case's level (no --level given).
    flank_level: int | None = None
    fillet_level: int | None = None

    @property
    def variant(self) -> dict[str, int]:
        """The sizes the case's runs take from other levels ({} for the level's own)."""
        pairs = (("flank_level", self.flank_level), ("fillet_level", self.fillet_level))
        return {k: v for k, v in pairs if v is not None}


@dataclass(frozen=True)
class Numerics:
    """Numerical settings of the finite element model (``[numerics]``, every field
    optional). The defaults below are the only definition; validated on construction."""

    degree: int = 1  # Lagrange element degree of the displacement, one of DEGREES
    # Contact penalty relative to the body stiffness (eps = factor E* / h), PENALTY_FACTOR_RANGE;
    # used by the "line" contact model. The "zone" model's contact is exact (no penalty) except
    # on a coast view its grid finds no cell on, which keeps its contact-line grid with this
    # penalty and says so (solvers.flank_grid.contact_grids, FlankGridInfo.fallback).
    penalty_factor: float = 100.0
    # Contact grid point spacing along the contact line, mm, in GRID_SPACING_RANGE;
    # None: the flank element size of the mesh level.
    grid_spacing: float | None = None
    # Contact model, one of CONTACT_MODELS: "line" (one row of points on the theoretical
    # contact lines, a penalty spring each, every point one FE column) or "zone" (a grid over
    # the whole potential contact zone of the drive and coast flanks, the FE compliance on one
    # point per section, the local compliance from Boussinesq half-space coefficients, exact
    # contact; solvers.flank_grid.zone_grid, solvers.contact eq. (5)).
    contact_model: str = "zone"
    # "zone": grid points are laid where the unloaded separation (modifications included) is
    # within this (um) of its section's smallest, ZONE_GAP_RANGE: twice the largest approach
    # under load at least (Hertz + bending + mismatch, 10-20 um for these gears; more at an
    # overturned pinion's tip corners), which solvers.zone_reach checks on every solve; a
    # position whose load reaches past half of it is solved again on the band the check names.
    zone_gap_limit_um: float = 40.0
    # Solver of each body's stiffness, one of LINEAR_SOLVERS: "mumps" (exact sparse LU),
    # "mumps-blr" (block low-rank LU: less memory, faster factorization) or "cg-gamg"
    # (iterative, no factor in memory, slow per right-hand side); solvers.elastic_body.
    linear_solver: str = "mumps"
    # BLR dropping threshold or CG relative residual, LINEAR_TOLERANCE_RANGE; None: the
    # solver's default (1e-6 BLR, 1e-8 CG); "mumps" takes none.
    linear_tolerance: float | None = None
    # The LU factors ("mumps", "mumps-blr") on disk, read back for every block of solves: the
    # same answer (to round-off), memory of about the largest front instead of all factors,
    # slower solves; for a level whose factors do not fit in memory. Folder:
    # $PLANETARY_OOC_DIR, else the system's temporary folder.
    out_of_core: bool = False
    # Root fillets refined where the root stress is read, one of ROOT_FILLETS.
    root_fillets: str = "auto"
    # Where the root stress is read, one of ROOT_STRESS_METHODS.
    root_stress: str = "submodel"

    def __post_init__(self):
        d = self.degree
        if isinstance(d, bool) or not isinstance(d, int) or d not in DEGREES:
            raise CaseError(f"numerics.degree = {d!r}: must be one of {DEGREES} (element degree)")
        p = self.penalty_factor
        lo, hi = PENALTY_FACTOR_RANGE
        if not _real(p) or not lo <= p <= hi:
            raise CaseError(
                f"numerics.penalty_factor = {p!r}: must be a number in [{lo:g}, {hi:g}]"
            )
        object.__setattr__(self, "penalty_factor", float(p))
        s = self.grid_spacing
        lo, hi = GRID_SPACING_RANGE
        if s is not None:
            if not _real(s) or not lo < s <= hi:
                raise CaseError(
                    f"numerics.grid_spacing = {s!r}: must be a number in ({lo:g}, {hi:g}] mm, "
                    "or omitted for the flank element size of the mesh level"
                )
            object.__setattr__(self, "grid_spacing", float(s))
        if self.contact_model not in CONTACT_MODELS:
            raise CaseError(
                f"numerics.contact_model = {self.contact_model!r}: must be one of "
                f"{', '.join(repr(m) for m in CONTACT_MODELS)}"
            )
        g = self.zone_gap_limit_um
        lo, hi = ZONE_GAP_RANGE
        if not _real(g) or not lo <= g <= hi:
            raise CaseError(
                f"numerics.zone_gap_limit_um = {g!r}: must be a number in [{lo:g}, {hi:g}] um"
            )
        object.__setattr__(self, "zone_gap_limit_um", float(g))
        if self.root_fillets not in ROOT_FILLETS:
            raise CaseError(
                f"numerics.root_fillets = {self.root_fillets!r}: must be one of "
                f"{', '.join(repr(m) for m in ROOT_FILLETS)}"
            )
        if self.root_stress not in ROOT_STRESS_METHODS:
            raise CaseError(
                f"numerics.root_stress = {self.root_stress!r}: must be one of "
                f"{', '.join(repr(m) for m in ROOT_STRESS_METHODS)}"
            )
        if self.linear_solver not in LINEAR_SOLVERS:
            raise CaseError(
                f"numerics.linear_solver = {self.linear_solver!r}: must be one of "
                f"{', '.join(repr(m) for m in LINEAR_SOLVERS)}"
            )
        t = self.linear_tolerance
        lo, hi = LINEAR_TOLERANCE_RANGE
        if t is not None:
            if self.linear_solver == "mumps":
                raise CaseError(
                    f"numerics.linear_tolerance = {t!r}: linear_solver 'mumps' is exact and "
                    "takes no tolerance (omit it, or choose 'mumps-blr' or 'cg-gamg')"
                )
            if not _real(t) or not lo <= t <= hi:
                raise CaseError(
                    f"numerics.linear_tolerance = {t!r}: must be a number in [{lo:g}, {hi:g}], "
                    "or omitted for the solver's default"
                )
            if self.linear_solver == "mumps-blr" and t > BLR_TOLERANCE_MAX:
                raise CaseError(
                    f"numerics.linear_tolerance = {t!r}: linear_solver 'mumps-blr' drops "
                    f"low-rank blocks below it, used as an exact solve: at most "
                    f"{BLR_TOLERANCE_MAX:g} (1e-3 moved 1-GB's Mx_pin by 4 % at level 0)"
                )
            object.__setattr__(self, "linear_tolerance", float(t))
        if not isinstance(self.out_of_core, bool):
            raise CaseError(f"numerics.out_of_core = {self.out_of_core!r}: must be true or false")
        if self.out_of_core and self.linear_solver == "cg-gamg":
            raise CaseError(
                "numerics.out_of_core = true: linear_solver 'cg-gamg' has no factors to keep "
                "on disk (choose 'mumps' or 'mumps-blr', or omit out_of_core)"
            )


DEFAULTS = Numerics()

MAX_PIN_ERROR_UM = 1000.0  # a pin-hole position error beyond 1 mm is a drawing error


@dataclass(frozen=True)
class System:
    """Settings of the system scene (``[system]``, every field optional; ``model.scene =
    "system"``: every pinion on its pin of the elastic carrier)."""

    # Radial support of the sun at its bore, N/mm in x and y; 0: floating (the usual
    # planetary, centred by the meshes). The one-branch and all-planets scenes hold the sun.
    sun_radial_stiffness: float = 0.0
    # Pin-hole position error of each pinion's pin in the carrier, um, [tangential, radial]
    # per pinion in carrier order (tangential along the sun's sense of rotation); empty: none.
    pin_position_errors_um: tuple[tuple[float, float], ...] = ()

    def check(self, planets: int, source: str) -> None:
        k = self.sun_radial_stiffness
        if not _real(k) or k < 0:
            raise CaseError(f"{source}: system.sun_radial_stiffness = {k!r}: must be >= 0 N/mm")
        e = self.pin_position_errors_um
        ok = all(
            len(pe) == 2 and all(_real(v) and abs(v) <= MAX_PIN_ERROR_UM for v in pe) for pe in e
        )
        if not ok or len(e) not in (0, planets):
            raise CaseError(
                f"{source}: system.pin_position_errors_um = {list(map(list, e))!r}: must be "
                f"empty or {planets} pairs [tangential, radial] of numbers within "
                f"+-{MAX_PIN_ERROR_UM:g} um (one per branch: a double pinion's SP pin)"
            )


@dataclass(frozen=True)
class StudyCase:
    name: str  # safe as a folder name (cases.gearset.NAME_PATTERN)
    description: str  # free text; not an input of the run (left out of study_inputs)
    gearset: GearSet
    bearing: Bearing
    material: Material
    model: Model
    numerics: Numerics
    system: System = System()
    path: str = field(default="", compare=False)  # the file read ("" if parsed from a mapping)
    source: dict = field(default_factory=dict, compare=False, repr=False)  # its TOML mapping


_TOP_FIELDS = (
    "name",
    "gearset",
    "description",
    "bearing",
    "material",
    "model",
    "numerics",
    "system",
)


def _names(cls) -> tuple[str, ...]:
    return tuple(f.name for f in fields(cls))


def accepted_fields() -> dict[str, tuple[str, ...]]:
    """The keys :func:`parse_study_case` accepts, per table ("" the top level): what the
    field reference (:mod:`cases.reference`) lists."""
    tables = {"bearing": Bearing, "material": Material, "model": Model, "numerics": Numerics}
    return {"": _TOP_FIELDS, **{t: _names(c) for t, c in tables.items()}, "system": _names(System)}


# Range checks: field -> (low, high, inclusive bounds), in the units of the dataclasses.
# The radial stiffness's floor is the softest needle bearing: k_r = F / (0.9 delta) with the
# line-contact approach delta = 3.84e-5 Q^0.9 / l^0.8 (mm, N; Harris & Kotzalas) gives about
# 2e6 N/mm for 15 rollers of 15 mm under 5 kN (the paper's 2.33e6, its flexible 2.33e5). Softer,
# the pinion floats beyond the contact zone a grid represents (case 1 at level 0: 1e4 N/mm
# loads gaps past the largest zone band, 3e4 solves on it). A rigid bearing is accepted.
_RANGES = {
    "bearing.radial_stiffness": (1e5, 1e12),
    "bearing.tilting_stiffness": (1e3, 1e14),
    "bearing.axial_stiffness": (1e2, 1e12),
    "material.youngs_modulus": (1e3, 1e7),
    "material.poisson_ratio": (0.0, 0.49),
    "material.gear_modulus_factor": (0.01, 100.0),
}


# What a value beyond a range's end would do, said with the refusal.
_RANGE_REASONS = {
    "bearing.radial_stiffness": (
        " (a softer bearing lets the pinion float under load beyond the contact zone the"
        " grid represents; needle bearings are 1e5-1e7 N/mm)"
    ),
}


def _section(data: dict, key: str, source: str) -> dict:
    value = data.get(key)
    if not isinstance(value, dict):
        raise CaseError(f"{source}: [{key}] section is missing")
    return check_keys(value, _names({"bearing": Bearing, "model": Model}[key]), source, key)


def _ranged(section: dict, key: str, prefix: str, source: str, default=None) -> float:
    field_name = f"{prefix}.{key}"
    value = section.get(key, default)
    lo, hi = _RANGES[field_name]
    if not _real(value) or not lo <= value <= hi:
        why = _RANGE_REASONS.get(field_name, "")
        raise CaseError(
            f"{source}: {field_name} = {value!r}: must be a number in [{lo:g}, {hi:g}]{why}"
        )
    return float(value)


def _integer(section: dict, key: str, prefix: str, source: str, lo: int, hi: int) -> int:
    value = section.get(key)
    if isinstance(value, bool) or not isinstance(value, int) or not lo <= value <= hi:
        raise CaseError(f"{source}: {prefix}.{key} = {value!r}: must be an integer {lo}..{hi}")
    return value


def _load_case_gearset(value: Any, source: str, path: str | Path) -> GearSet:
    """``gearset``: a bare name (``cases/gearsets/<name>.toml``) or a path ending in .toml,
    relative to the study-case file's folder (``CASE_DIR`` for a mapping without a file)."""
    if isinstance(value, str) and value.endswith(".toml"):
        target = Path(value)
        if not target.is_absolute():
            target = (Path(path).parent if path else CASE_DIR) / target
    else:
        if not isinstance(value, str):
            raise CaseError(
                f"{source}: gearset = {value!r}: must be a gear-set name (cases/gearsets/) or "
                "a path ending in .toml"
            )
        target = check_name(value, source, "gearset")
    try:
        return load_gearset(target)
    except CaseError as exc:
        raise CaseError(f"{source}: gearset = {value!r}: {exc}") from exc


def parse_study_case(
    data: dict[str, Any], source: str = "<case>", path: str | Path = ""
) -> StudyCase:
    """Validate a parsed TOML mapping into a :class:`StudyCase`; ``source`` names the file
    in messages, ``path`` (the file) is recorded and anchors a relative gear-set path."""
    check_keys(data, _TOP_FIELDS, source)
    name = check_name(data.get("name"), source)
    description = data.get("description", "")
    if not isinstance(description, str):
        raise CaseError(f"{source}: description = {description!r}: must be a string")
    gearset = _load_case_gearset(data.get("gearset"), source, path)

    b = _section(data, "bearing", source)
    bearing = Bearing(
        _ranged(b, "radial_stiffness", "bearing", source),
        _ranged(b, "tilting_stiffness", "bearing", source),
        _ranged(b, "axial_stiffness", "bearing", source, DEFAULT_AXIAL_STIFFNESS),
    )
    m = check_keys(data.get("material", {}), _names(Material), source, "material")
    steel = Material()
    material = Material(
        *(_ranged(m, k, "material", source, getattr(steel, k)) for k in _names(Material))
    )
    mod = _section(data, "model", source)
    scene = mod.get("scene")
    if scene not in SCENES:
        given = "missing" if scene is None else f"= {scene!r}"
        raise CaseError(f"{source}: model.scene {given}: must be one of {', '.join(SCENES)}")
    level = _integer(mod, "level", "model", source, 0, MAX_LEVEL)
    # another level's sizes; the level's own is no variant (L1P1 with flank_level 1 is L1P1)
    other = {k: _integer(mod, k, "model", source, 0, MAX_LEVEL) for k in VARIANT_FIELDS if k in mod}
    model = Model(
        scene,
        level,
        _integer(mod, "positions", "model", source, 1, MAX_POSITIONS),
        **{k: None if v == level else v for k, v in other.items()},
    )
    n = check_keys(data.get("numerics", {}), _names(Numerics), source, "numerics")
    try:
        numerics = Numerics(**n)
    except CaseError as exc:
        raise CaseError(f"{source}: {exc}") from exc
    if "zone_gap_limit_um" in n and numerics.contact_model != "zone":  # never ignored silently
        raise CaseError(
            f"{source}: numerics.zone_gap_limit_um: only for contact_model = 'zone' (where its "
            f"grid is laid); the {numerics.contact_model!r} model lays its points on the "
            "theoretical contact lines: remove it or choose 'zone'"
        )
    s = check_keys(data.get("system", {}), _names(System), source, "system")
    if s and model.scene != "system":  # read by the system scene only: never ignored silently
        raise CaseError(
            f"{source}: system.{', system.'.join(s)}: only for model.scene = 'system' (the "
            f"carrier as a body), not {model.scene!r}: remove [system] or change the scene"
        )
    raw_errors = s.get("pin_position_errors_um", [])
    if not isinstance(raw_errors, list) or not all(isinstance(pe, list) for pe in raw_errors):
        raise CaseError(
            f"{source}: system.pin_position_errors_um = {raw_errors!r}: must be a list of "
            "[tangential, radial] pairs of numbers (um), one per branch"
        )
    errors = tuple(tuple(pe) for pe in raw_errors)
    system = System(s.get("sun_radial_stiffness", 0.0), errors)
    system.check(gearset.planets, source)
    errors = tuple((float(a), float(b)) for a, b in system.pin_position_errors_um)
    system = System(float(system.sun_radial_stiffness), errors)
    return StudyCase(
        name, description, gearset, bearing, material, model, numerics, system, str(path), data
    )


def available_cases() -> list[str]:
    return sorted(p.stem for p in CASE_DIR.glob("*.toml"))


def load_study_case(name_or_path: str | Path) -> StudyCase:
    """Load ``cases/<name>.toml`` (a bare name) or a study-case file (a path ending in
    ``.toml``)."""
    path = Path(name_or_path)
    available = ", ".join(available_cases())
    if path.suffix != ".toml":
        name = str(name_or_path)
        if not NAME_PATTERN.fullmatch(name) or ".." in name:
            raise CaseError(f"{name!r}: no such case (available: {available})")
        path = CASE_DIR / f"{name}.toml"
    if not path.is_file():
        raise CaseError(f"{path}: no such case (available: {available})")
    return parse_study_case(read_toml(path), path.name, path)


def study_inputs(study: StudyCase) -> dict[str, Any]:
    """Everything that defines the run of ``study``, resolved (defaults filled in, profile
    shifts computed) and JSON-ready: the study case's name, bearing, material, model and
    numerics; the gear set's name, kind, input torque, planets, power path, every
    :class:`~gears.spec.GearSpec` field of every gear and the meshes. File paths and the
    description are left out: moving a file or rewording it does not change the run; so is
    ``numerics.out_of_core``, where the factors are kept (the same answer to round-off)."""
    gs = study.gearset
    numerics = {k: v for k, v in asdict(study.numerics).items() if k != "out_of_core"}
    # a level's own sizes leave the variant fields out: the hash of a case without them stays
    model = {k: v for k, v in asdict(study.model).items() if v is not None}
    return {
        "study_case": {
            "name": study.name,
            "bearing": asdict(study.bearing),
            "material": asdict(study.material),
            "model": model,
            "numerics": numerics,
            "system": {
                "sun_radial_stiffness": study.system.sun_radial_stiffness,
                "pin_position_errors_um": [list(e) for e in study.system.pin_position_errors_um],
            },
        },
        "gearset": {
            "name": gs.name,
            "kind": gs.kind,
            "input_torque": gs.input_torque,
            "planets": gs.planets,
            "power_path": list(gs.power_path),
            "gears": {n: asdict(g) for n, g in gs.gears.items()},
            "meshes": [
                {"gears": [m.gear1, m.gear2], "centre_distance": m.centre_distance}
                for m in gs.meshes
            ],
            # flank modifications are contact gaps outside the gears: hashed here too
            "modifications": {n: asdict(m) for n, m in sorted(gs.modifications.items())},
        },
    }


def case_sizes(study: StudyCase, level: int | None = None) -> tuple[int, dict[str, int]]:
    """The level a run of ``study`` takes and the sizes it takes from other levels: the
    case's (``model.level`` with ``model.flank_level`` / ``fillet_level``) unless ``level``
    is given, which is that level's own sizes (the one place that decides it: the driver,
    :func:`studies.position.solve_position`, the lead correction, the phasing study)."""
    if level is None:
        return study.model.level, study.model.variant
    return level, {}


def without_variant(study: StudyCase) -> StudyCase:
    """``study`` with its level's own sizes (``model.flank_level`` / ``fillet_level`` None):
    the inputs of a run that sets its sizes itself (a convergence run, a size diagnostic), so
    its stored runs stand when a case file gains or changes its sizes."""
    model = replace(study.model, flank_level=None, fillet_level=None)
    return replace(study, model=model)


def inputs_hash(study: StudyCase) -> str:
    """sha256 (hex) of the canonical JSON of :func:`study_inputs`: sorted keys, no spaces,
    floats as ``repr`` (shortest round trip, so any change of a float's value counts)."""
    text = json.dumps(study_inputs(study), sort_keys=True, separators=(",", ":"), allow_nan=False)
    return hashlib.sha256(text.encode("utf-8")).hexdigest()

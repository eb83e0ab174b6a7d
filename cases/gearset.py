"""Gear-set case files (TOML) read into frozen, validated dataclasses.

A gear-set file holds the data a paper prints and nothing derived: tooth numbers, module,
pressure and helix angle, hands, face widths, centre distances, torque. Profile shifts are
resolved from the centre distances along the power path (sun -> ... -> ring) by
:func:`gears.pair.assign_chain_shifts`.

Backlash and microgeometry, both optional. ``[[meshes]] normal_backlash_um`` is the mesh's
normal backlash (um; default :func:`gears.pair.default_normal_backlash`, the ISO/TR 10064-2
minimum for the centre distance and module, 89.1 um for case 1), made by tooth thickness
allowances along the power path (:func:`gears.pair.assign_chain_backlash`): the gears (and
their meshes) get thinner teeth, the drive flanks stay in contact and the centre distances
as given. ``[gears.X.modifications]`` holds the flank modifications of gear X
(:class:`gears.microgeometry.FlankModifications`: lead crown, lead slope, tip relief, end
relief), kept in :attr:`GearSet.modifications`, outside the gears: they are contact gaps,
not mesh geometry.

Every error names the file and the field (``case1.toml: gears.sun.teeth = 0: ...``); every
table refuses keys it does not know. Beyond the single gears and meshes (checked by
:mod:`gears`), the set must be buildable: a single-pinion set meshes the pinion with sun and
ring at one centre distance (sun and ring are coaxial), a double-pinion set places the
sun, SP and RP axes on a triangle.
"""

from __future__ import annotations

import math
import re
import tomllib
from dataclasses import MISSING, dataclass, field, fields
from pathlib import Path
from typing import Any

from gears.analytic.phasing import assemblable_angles
from gears.analytic.planetary import PlanetaryInput
from gears.layout import layout_clearances
from gears.microgeometry import FIELDS as MODIFICATION_FIELDS
from gears.microgeometry import FlankModifications
from gears.pair import (
    GearPair,
    assign_chain_backlash,
    assign_chain_shifts,
    default_normal_backlash,
)
from gears.spec import GearSpec, GeometryError

GEARSET_DIR = Path(__file__).parent / "gearsets"
KINDS = ("single_pinion", "double_pinion")
# Gears on the power path sun -> ... -> ring, per kind.
PATH_LENGTH = {"single_pinion": 3, "double_pinion": 4}
# Tolerance on the two centre distances of a single-pinion set (mm).
CENTRE_DISTANCE_TOL = 1e-6
# Names of cases and gear sets: also folder names of their outputs.
NAME_PATTERN = re.compile(r"[A-Za-z0-9][A-Za-z0-9_.+-]*")
MAX_NAME_LENGTH = 64
# Names of gears: they name bodies, files and keys. The all-planet scenes name branch k's
# pinion <name><k>, and keys join names with "_" (sun_pinion_side), so a letter first, then
# letters and digits only.
GEAR_NAME_PATTERN = re.compile(r"[A-Za-z][A-Za-z0-9]*")
MAX_GEAR_NAME_LENGTH = 16
# body names the scenes give to what is not a gear (meshing.scene_bodies)
RESERVED_GEAR_NAMES = ("carrier",)

_TOP_FIELDS = ("name", "kind", "input_torque", "planets", "power_path", "common", "gears", "meshes")
_GEAR_FIELDS = (
    "teeth",
    "normal_module",
    "normal_pressure_angle",
    "helix_angle",
    "hand",
    "face_width",
    "internal",
    "addendum_coef",
    "dedendum_coef",
    "hob_tip_radius_coef",
    "shaper_teeth",
    "modifications",
)
_COMMON_FIELDS = tuple(
    f for f in _GEAR_FIELDS if f not in {"teeth", "hand", "face_width", "internal", "modifications"}
)
_MESH_FIELDS = ("gears", "centre_distance", "normal_backlash_um")
# fields without a default in GearSpec (in [gears.X] or [common]); the name is the table's
_REQUIRED_GEAR_FIELDS = tuple(
    f.name for f in fields(GearSpec) if f.default is MISSING and f.name != "name"
)
UM = 1e-3  # mm per um
#: largest normal backlash a gear-set file may ask for (um)
MAX_BACKLASH_UM = 1000.0


def accepted_fields() -> dict[str, tuple[str, ...]]:
    """The keys :func:`parse_gearset` accepts, per table ("" the top level; ``gears.*`` any
    gear, ``meshes[]`` each mesh): what the field reference (:mod:`cases.reference`) lists."""
    return {
        "": _TOP_FIELDS,
        "common": _COMMON_FIELDS,
        "gears.*": _GEAR_FIELDS,
        "gears.*.modifications": MODIFICATION_FIELDS,
        "meshes[]": _MESH_FIELDS,
    }


class CaseError(ValueError):
    """A case file is malformed: the message names the file, the field and what is allowed."""


@dataclass(frozen=True)
class GearMeshSpec:
    """One gear mesh of the set: ``gear1`` is the external gear nearer the sun."""

    gear1: str
    gear2: str
    centre_distance: float  # mm
    normal_backlash: float = 0.0  # mm, as resolved (the file's or the default)


@dataclass(frozen=True)
class GearSet:
    name: str  # safe as a folder name (NAME_PATTERN)
    kind: str  # one of KINDS
    input_torque: float  # N m on the sun, finite and > 0
    planets: int  # pinions (single) or pinion pairs (double) sharing the torque
    power_path: tuple[str, ...]  # sun -> ... -> ring, PATH_LENGTH[kind] gears
    gears: dict[str, GearSpec]  # profile shifts resolved
    meshes: tuple[GearMeshSpec, ...]  # one per step of the power path, in order
    path: str = field(default="", compare=False)  # the file read ("" if parsed from a mapping)
    source: dict = field(default_factory=dict, compare=False, repr=False)  # its TOML mapping
    # flank modifications per gear (gears without any are left out)
    modifications: dict[str, FlankModifications] = field(default_factory=dict)

    @property
    def torque_per_branch(self) -> float:
        """Sun torque carried by one branch, N m (equal load sharing)."""
        return self.input_torque / self.planets

    def pair(self, gear1: str, gear2: str) -> GearPair:
        """The mesh between two named gears, as a :class:`GearPair`."""
        for m in self.meshes:
            if (m.gear1, m.gear2) == (gear1, gear2):
                return GearPair(self.gears[gear1], self.gears[gear2], m.centre_distance)
        known = ", ".join(f"{m.gear1}-{m.gear2}" for m in self.meshes)
        raise KeyError(f"{self.name}: no mesh {gear1}-{gear2}; meshes are {known}")

    def planetary_input(self) -> PlanetaryInput:
        """The closed-form inputs (:mod:`gears.analytic.planetary`) of this set."""
        return PlanetaryInput(
            name=self.name,
            gears=tuple(self.gears[p] for p in self.power_path),
            centre_distances=tuple(m.centre_distance for m in self.meshes),
            input_torque=self.input_torque,
            planets=self.planets,
        )


def _require(cond: bool, where: str, msg: str) -> None:
    if not cond:
        raise CaseError(f"{where}: {msg}")


def check_keys(table: Any, allowed: tuple[str, ...], where: str, table_name: str = "") -> dict:
    """``table`` as a dict whose keys are all in ``allowed``; else a :class:`CaseError`
    naming the file (``where``), the table and the allowed keys."""
    prefix = f"{where}: {table_name}" if table_name else where
    _require(isinstance(table, dict), prefix, f"must be a table, got {table!r}")
    unknown = [k for k in table if k not in allowed]
    if unknown:
        what = "unknown field" if len(unknown) == 1 else "unknown fields"
        listed = ", ".join(repr(k) for k in unknown)
        raise CaseError(f"{prefix}: {what} {listed} (allowed: {', '.join(allowed)})")
    return table


def check_name(value: Any, where: str, key: str = "name") -> str:
    """A case or gear-set name that is safe as a folder name: ``NAME_PATTERN``, at most
    ``MAX_NAME_LENGTH`` characters, no ``..``."""
    ok = (
        isinstance(value, str)
        and len(value) <= MAX_NAME_LENGTH
        and NAME_PATTERN.fullmatch(value) is not None
        and ".." not in value
    )
    _require(
        ok,
        where,
        f"{key} = {value!r}: must be 1 to {MAX_NAME_LENGTH} characters from A-Z a-z 0-9 _ . + -"
        ", starting with a letter or digit, without '..' (it names output folders)",
    )
    return value


def _number(data: dict, key: str, where: str, *, positive: bool = True) -> float:
    value = data.get(key)
    _require(
        isinstance(value, (int, float)) and not isinstance(value, bool),
        where,
        f"{key} = {value!r}: must be a number",
    )
    _require(math.isfinite(value), where, f"{key} = {value!r}: must be a finite number")
    if positive:
        _require(value > 0, where, f"{key} = {value!r}: must be > 0")
    return float(value)


#: the narrowest face (normal modules) a gear may have: the contact and root stresses are
#: quoted on the interior of the face, read one module in from each face end (the edge bands
#: of postprocess.mesh_stress, FACE_BAND_MODULES); below 4 modules that interior is two
#: modules or less, a section or two of the contact grid, and at about 2 nothing is left to
#: read (1 mm faces solved to zero contact stress and no K_Hbeta). Real gears have b / m_n of
#: 6-30.
MIN_FACE_MODULES = 4.0


#: shifts (x) a gear whose shift follows from its centre distance is first built at when it
#: is not a valid gear at x = 0 (a planet of few teeth is undercut there), nearest 0 first:
#: what is read of it before its shift is known (teeth, module, angles) does not depend on
#: x. Steps of 0.05: a 6-tooth gear of the ISO 53 rack is valid for x in 0.30-0.35 only
_PROVISIONAL_SHIFTS = tuple(sorted((0.05 * k for k in range(-10, 31) if k), key=abs))


def _gear_spec(name: str, fields: dict, where: str, shifted_later: bool) -> GearSpec:
    """The gear ``name`` of a gear-set file. A gear whose profile shift follows from the
    centre distances (every gear after the first of the power path) is judged at that shift
    (:func:`gears.pair.assign_chain_shifts`), not at the file's x = 0: where x = 0 does not
    make a valid tooth it is built at a provisional shift until then."""
    try:
        return GearSpec(name=name, **fields)
    except GeometryError as exc:
        for x in _PROVISIONAL_SHIFTS if shifted_later else ():
            try:
                return GearSpec(name=name, **fields, profile_shift=x)
            except GeometryError:
                continue
        raise CaseError(f"{where}: {exc}") from exc


def _check_face_width(gear: GearSpec, where: str) -> None:
    least = MIN_FACE_MODULES * gear.normal_module
    _require(
        gear.face_width >= least,
        where,
        f"face_width = {gear.face_width:g} mm: must be at least {MIN_FACE_MODULES:g} normal "
        f"modules ({least:g} mm here); the stresses are read one module in from each face end",
    )


def _check_kind_geometry(kind: str, meshes: list[GearMeshSpec], source: str) -> None:
    """Centre distances a carrier can hold: single pinion, sun-pinion = pinion-ring (the
    pinion axis is shared, sun and ring coaxial); double pinion, the sun, SP and RP axes form
    a triangle with sides sun-SP, SP-RP and RP-ring (= sun-RP, sun and ring coaxial)."""
    a = [m.centre_distance for m in meshes]
    names = [f"{m.gear1}-{m.gear2}" for m in meshes]
    if kind == "single_pinion":
        _require(
            abs(a[1] - a[0]) <= CENTRE_DISTANCE_TOL,
            f"{source}: meshes[1]",
            f"centre_distance = {a[1]!r} mm ({names[1]}) must equal meshes[0].centre_distance"
            f" = {a[0]!r} mm ({names[0]}) to {CENTRE_DISTANCE_TOL:g} mm: both meshes share the"
            " pinion axis and sun and ring are coaxial",
        )
    else:
        sides = sorted(a)
        _require(
            sides[2] < sides[0] + sides[1],
            f"{source}: meshes",
            f"centre distances {names[0]} = {a[0]!r}, {names[1]} = {a[1]!r}, {names[2]} = "
            f"{a[2]!r} mm (= sun-{meshes[2].gear1}, sun and ring coaxial) violate the strict "
            "triangle inequality: the sun, SP and RP axes cannot be placed",
        )


def _check_gear_names(names: list[str], source: str) -> None:
    """Gear names: ``GEAR_NAME_PATTERN``, and none another's name with a number after it
    (branch 1 of a pinion ``P`` is ``P1`` in the all-planet scenes)."""
    for n in names:
        _require(
            len(n) <= MAX_GEAR_NAME_LENGTH and GEAR_NAME_PATTERN.fullmatch(n) is not None,
            source,
            f"gears.{n}: a gear name must be 1 to {MAX_GEAR_NAME_LENGTH} letters and digits, "
            "starting with a letter (it names bodies, files and result keys)",
        )
        _require(
            n not in RESERVED_GEAR_NAMES,
            source,
            f"gears.{n}: the system scene's carrier body has this name: rename the gear",
        )
    for n in names:
        for m in names:
            _require(
                m == n or not (m.startswith(n) and m[len(n) :].isdigit()),
                source,
                f"gears.{m}: its name is gears.{n}'s with a number after it, the name the "
                f"all-planet scenes give a branch's {n}: rename one",
            )


def first_overlap(gs: GearSet, angles) -> tuple[str, float] | None:
    """The first two gears that do not mesh whose tip circles overlap, with the branches at
    carrier angles ``angles`` (rad): (which, overlap mm), or None (:mod:`gears.layout`)."""
    path = [gs.gears[p] for p in gs.power_path]
    clear = layout_clearances(
        gs.power_path, [g.tip_radius for g in path], [m.centre_distance for m in gs.meshes], angles
    )
    return next(((what, -c) for what, c in clear if c <= 0.0), None)


def _check_layout(gs: GearSet, source: str) -> None:
    """The gears of ``gs`` clear each other at its default carrier angles
    (:func:`gears.analytic.phasing.assemblable_angles`)."""
    path = gs.power_path
    angles = assemblable_angles(
        gs.gears[path[0]].teeth, gs.gears[path[-1]].teeth, gs.planets, len(path) == 4
    )
    hit = first_overlap(gs, angles)
    if hit is not None:
        what, mm = hit
        raise CaseError(
            f"{source}: planets = {gs.planets}, meshes' centre_distance = "
            f"{[m.centre_distance for m in gs.meshes]}: the tip circles of {what} overlap by "
            f"{mm:.3f} mm (at carrier angles {[round(math.degrees(a), 2) for a in angles]} "
            "deg): fewer planets, other centre distances or smaller gears"
        )


def parse_gearset(
    data: dict[str, Any], source: str = "<gearset>", path: str | Path = ""
) -> GearSet:
    """Validate a parsed TOML mapping into a :class:`GearSet`; ``source`` names the file in
    messages, ``path`` is recorded as :attr:`GearSet.path`."""
    check_keys(data, _TOP_FIELDS, source)
    name = check_name(data.get("name"), source)
    kind = data.get("kind")
    _require(kind in KINDS, source, f"kind = {kind!r}: must be one of {', '.join(KINDS)}")
    torque = _number(data, "input_torque", source)
    planets = data.get("planets")
    _require(
        isinstance(planets, int) and not isinstance(planets, bool) and 1 <= planets <= 12,
        source,
        f"planets = {planets!r}: must be an integer from 1 to 12",
    )

    common = check_keys(data.get("common", {}), _COMMON_FIELDS, source, "common")
    raw_gears = data.get("gears")
    _require(isinstance(raw_gears, dict) and raw_gears, source, "gears: at least one [gears.X]")
    gears: dict[str, GearSpec] = {}
    modifications: dict[str, FlankModifications] = {}
    _check_gear_names(list(raw_gears), source)
    named_path = data.get("power_path")  # validated below, once the gears are known
    shifted_later = set(named_path[1:]) if isinstance(named_path, list) else set()
    for gname, g in raw_gears.items():
        where = f"{source}: gears.{gname}"
        check_keys(g, _GEAR_FIELDS, source, f"gears.{gname}")
        g = dict(g)
        if "modifications" in g:
            modifications[gname] = _modifications(g.pop("modifications"), source, gname)
        missing = [f for f in _REQUIRED_GEAR_FIELDS if f not in {**common, **g}]
        _require(not missing, where, f"missing field(s) {', '.join(missing)}")
        _require(
            "shaper_teeth" not in g or g.get("internal") is True,
            where,
            "shaper_teeth: only for an internal gear (the ring, cut by a pinion-type shaper); "
            "external gears are hobbed",
        )
        gears[gname] = _gear_spec(gname, {**common, **g}, where, gname in shifted_later)
        _check_face_width(gears[gname], where)

    power_path = data.get("power_path")
    _require(
        isinstance(power_path, list)
        and len(power_path) >= 2
        and all(isinstance(p, str) and p in gears for p in power_path),
        source,
        f"power_path = {power_path!r}: must list at least two of the gears {sorted(gears)}",
    )
    n_path = PATH_LENGTH[kind]
    _require(
        len(power_path) == n_path,
        source,
        f"power_path = {power_path!r}: a {kind} set has {n_path} gears on its power path "
        f"({'sun, pinion, ring' if n_path == 3 else 'sun, SP, RP, ring'})",
    )
    _require(
        len(set(power_path)) == len(power_path),
        source,
        f"power_path = {power_path!r}: a gear appears twice",
    )
    unused = [g for g in gears if g not in power_path]
    _require(not unused, source, f"gears.{', gears.'.join(unused)}: not on the power_path")
    for p in power_path[:-1]:
        _require(
            not gears[p].internal,
            f"{source}: gears.{p}",
            "internal = true: only the last gear of the power path (the ring) may be internal",
        )
    last = power_path[-1]
    _require(
        gears[last].internal,
        f"{source}: gears.{last}",
        "internal = false: the last gear of the power path must be internal (the ring)",
    )

    raw_meshes = data.get("meshes", [])
    _require(
        isinstance(raw_meshes, list) and len(raw_meshes) == len(power_path) - 1,
        source,
        f"meshes: need one [[meshes]] per step of the power path ({len(power_path) - 1})",
    )
    meshes = []
    for i, (m, a, b) in enumerate(zip(raw_meshes, power_path[:-1], power_path[1:], strict=True)):
        where = f"{source}: meshes[{i}]"
        check_keys(m, _MESH_FIELDS, source, f"meshes[{i}]")
        _require(
            m.get("gears") == [a, b],
            where,
            f"gears = {m.get('gears')!r}: must be {[a, b]!r} (the power path, in order)",
        )
        a_w = _number(m, "centre_distance", where)
        if "normal_backlash_um" in m:
            j_n = _number(m, "normal_backlash_um", where, positive=False)
            _require(
                0.0 <= j_n <= MAX_BACKLASH_UM,
                where,
                f"normal_backlash_um = {j_n!r}: must be in [0, {MAX_BACKLASH_UM:g}] um",
            )
            j_n *= UM
        else:
            j_n = default_normal_backlash(a_w, gears[a].normal_module)
        meshes.append(GearMeshSpec(a, b, a_w, j_n))
    _check_kind_geometry(kind, meshes, source)

    centre_distances = [m.centre_distance for m in meshes]
    try:
        shifted = assign_chain_shifts([gears[p] for p in power_path], centre_distances)
    except GeometryError as exc:
        raise CaseError(f"{source}: {exc}") from exc
    try:
        thinned = assign_chain_backlash(
            shifted, centre_distances, [m.normal_backlash for m in meshes]
        )
    except GeometryError as exc:
        raise CaseError(
            f"{source}: meshes: normal_backlash_um = "
            f"{[round(m.normal_backlash / UM, 6) for m in meshes]}: needs tooth thickness "
            f"allowances the gears cannot take: {exc}"
        ) from exc
    gears.update({g.name: g for g in thinned})
    for gname, mods in modifications.items():
        try:
            mods.check(gears[gname])
        except GeometryError as exc:
            raise CaseError(f"{source}: gears.{gname}: {exc}") from exc
    modifications = {k: v for k, v in modifications.items() if not v.is_zero}
    gs = GearSet(
        name,
        kind,
        torque,
        planets,
        tuple(power_path),
        gears,
        tuple(meshes),
        str(path),
        data,
        modifications,
    )
    _check_layout(gs, source)
    return gs


def _modifications(table: Any, source: str, gear: str) -> FlankModifications:
    """``[gears.<gear>.modifications]`` as :class:`FlankModifications` (errors name the file
    and the field)."""
    name = f"gears.{gear}.modifications"
    check_keys(table, MODIFICATION_FIELDS, source, name)
    try:
        return FlankModifications(**table)
    except GeometryError as exc:
        raise CaseError(f"{source}: gears.{gear}.{exc}") from exc


def load_gearset(name_or_path: str | Path) -> GearSet:
    """Load ``cases/gearsets/<name>.toml`` (a bare name) or a gear-set file (a path ending
    in ``.toml``; a relative path is taken from the working directory)."""
    path = Path(name_or_path)
    available = ", ".join(sorted(p.stem for p in GEARSET_DIR.glob("*.toml")))
    if path.suffix != ".toml":
        name = str(name_or_path)
        if not (NAME_PATTERN.fullmatch(name) and ".." not in name):
            raise CaseError(
                f"gear set {name!r}: not a gear-set name (available: {available}) nor a path "
                "ending in .toml"
            )
        path = GEARSET_DIR / f"{name}.toml"
    if not path.is_file():
        raise CaseError(f"{path}: no such gear-set file (available: {available})")
    return parse_gearset(read_toml(path), path.name, path)


def read_toml(path: Path) -> dict[str, Any]:
    """Parse a case file; an unreadable file, one not in UTF-8 or not valid TOML becomes a
    :class:`CaseError` naming the file."""
    path = Path(path)
    try:
        raw = path.read_bytes()
    except OSError as exc:
        raise CaseError(f"{path.name}: cannot read {path}: {exc.strerror or exc}") from exc
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise CaseError(
            f"{path.name}: not UTF-8 text (byte {exc.start}: {raw[exc.start : exc.end]!r})"
        ) from exc
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise CaseError(f"{path.name}: not valid TOML: {exc}") from exc

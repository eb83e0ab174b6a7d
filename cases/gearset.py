"""Gear-set case files (TOML) read into frozen, validated dataclasses.

A gear-set file holds the data a paper prints and nothing derived: tooth numbers, module,
pressure and helix angle, hands, face widths, centre distances, torque. Profile shifts are
resolved from the centre distances along the power path (sun -> ... -> ring) by
:func:`meshing.gear_geometry.assign_chain_shifts`.

Every error names the file and the field (``case1.toml: gears.sun.teeth = 0: ...``).
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from meshing.gear_geometry import GearPair, GearSpec, GeometryError, assign_chain_shifts

GEARSET_DIR = Path(__file__).parent / "gearsets"
KINDS = ("single_pinion", "double_pinion")
_GEAR_FIELDS = {
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
}
_COMMON_FIELDS = _GEAR_FIELDS - {"teeth", "hand", "face_width", "internal"}


class CaseError(ValueError):
    """A case file is malformed: the message names the file, the field and what is allowed."""


@dataclass(frozen=True)
class MeshSpec:
    """One gear mesh of the set: ``gear1`` is the external gear nearer the sun."""

    gear1: str
    gear2: str
    centre_distance: float  # mm


@dataclass(frozen=True)
class GearSet:
    name: str
    kind: str  # one of KINDS
    input_torque: float  # N m on the sun
    planets: int  # pinions (single) or pinion pairs (double) sharing the torque
    power_path: tuple[str, ...]
    gears: dict[str, GearSpec]  # profile shifts resolved
    meshes: tuple[MeshSpec, ...]

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


def _require(cond: bool, where: str, msg: str) -> None:
    if not cond:
        raise CaseError(f"{where}: {msg}")


def _number(data: dict, key: str, where: str, *, positive: bool = True) -> float:
    value = data.get(key)
    _require(
        isinstance(value, (int, float)) and not isinstance(value, bool),
        where,
        f"{key} = {value!r}: must be a number",
    )
    if positive:
        _require(value > 0, where, f"{key} = {value!r}: must be > 0")
    return float(value)


def parse_gearset(data: dict[str, Any], source: str = "<gearset>") -> GearSet:
    """Validate a parsed TOML mapping into a :class:`GearSet`."""
    name = data.get("name")
    _require(isinstance(name, str) and name, source, f"name = {name!r}: must be a non-empty string")
    kind = data.get("kind")
    _require(kind in KINDS, source, f"kind = {kind!r}: must be one of {', '.join(KINDS)}")
    torque = _number(data, "input_torque", source)
    planets = data.get("planets")
    _require(
        isinstance(planets, int) and not isinstance(planets, bool) and 1 <= planets <= 12,
        source,
        f"planets = {planets!r}: must be an integer from 1 to 12",
    )

    common = data.get("common", {})
    unknown = set(common) - _COMMON_FIELDS
    _require(not unknown, source, f"common: unknown field(s) {sorted(unknown)}")
    raw_gears = data.get("gears")
    _require(isinstance(raw_gears, dict) and raw_gears, source, "gears: at least one [gears.X]")
    gears: dict[str, GearSpec] = {}
    for gname, g in raw_gears.items():
        where = f"{source}: gears.{gname}"
        unknown = set(g) - _GEAR_FIELDS
        _require(not unknown, where, f"unknown field(s) {sorted(unknown)}")
        try:
            gears[gname] = GearSpec(name=gname, **{**common, **g})
        except TypeError as exc:  # a required field is missing
            raise CaseError(f"{where}: {exc}") from exc
        except GeometryError as exc:
            raise CaseError(f"{where}: {exc}") from exc

    path = data.get("power_path")
    _require(
        isinstance(path, list) and len(path) >= 2 and all(p in gears for p in path),
        source,
        f"power_path = {path!r}: must list at least two of the gears {sorted(gears)}",
    )
    raw_meshes = data.get("meshes", [])
    _require(
        isinstance(raw_meshes, list) and len(raw_meshes) == len(path) - 1,
        source,
        f"meshes: need one [[meshes]] per step of the power path ({len(path) - 1})",
    )
    meshes = []
    for i, (m, a, b) in enumerate(zip(raw_meshes, path[:-1], path[1:], strict=True)):
        where = f"{source}: meshes[{i}]"
        _require(
            m.get("gears") == [a, b],
            where,
            f"gears = {m.get('gears')!r}: must be {[a, b]!r} (the power path, in order)",
        )
        meshes.append(MeshSpec(a, b, _number(m, "centre_distance", where)))

    try:
        shifted = assign_chain_shifts([gears[p] for p in path], [m.centre_distance for m in meshes])
    except GeometryError as exc:
        raise CaseError(f"{source}: {exc}") from exc
    gears.update({g.name: g for g in shifted})
    return GearSet(name, kind, torque, planets, tuple(path), gears, tuple(meshes))


def load_gearset(name_or_path: str | Path) -> GearSet:
    """Load ``cases/gearsets/<name>.toml`` (or a path to any gear-set file)."""
    path = Path(name_or_path)
    if not path.suffix:
        path = GEARSET_DIR / f"{name_or_path}.toml"
    if not path.is_file():
        available = ", ".join(sorted(p.stem for p in GEARSET_DIR.glob("*.toml")))
        raise CaseError(f"{path}: no such gear-set file (available: {available})")
    return parse_gearset(read_toml(path), path.name)


def read_toml(path: Path) -> dict[str, Any]:
    """Parse a case file; a syntax error becomes a :class:`CaseError` naming the file."""
    with path.open("rb") as f:
        try:
            return tomllib.load(f)
        except tomllib.TOMLDecodeError as exc:
            raise CaseError(f"{path.name}: not valid TOML: {exc}") from exc

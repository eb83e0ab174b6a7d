"""Finite element study cases (``cases/<name>.toml``) read into frozen, validated dataclasses.

A study case names a gear set (``cases/gearsets/``), the pinion needle bearing (singh2007
section 7: a 6x6 diagonal stiffness between pinion and pin, radial and tilting given, axial
stiff, spin free), the material, and the model resolution. Every error names the file and
the field with the allowed range.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

from cases.gearset import CaseError, GearSet, load_gearset, read_toml

CASE_DIR = Path(__file__).parent
SCENES = ("one_branch", "all_planets")
MAX_LEVEL = 3


@dataclass(frozen=True)
class Bearing:
    """Needle bearing of one pinion: diagonal stiffness to the pin (carrier)."""

    radial_stiffness: float  # N/mm, both radial directions
    tilting_stiffness: float  # N mm/rad, both tilting axes
    axial_stiffness: float  # N/mm; "stiff" in the paper


@dataclass(frozen=True)
class Material:
    youngs_modulus: float  # MPa
    poisson_ratio: float
    gear_modulus_factor: float  # multiplies E of every gear body (case 1-GB-R: 10)

    @property
    def gear_youngs_modulus(self) -> float:
        return self.youngs_modulus * self.gear_modulus_factor


@dataclass(frozen=True)
class Model:
    scene: str  # one of SCENES
    level: int  # mesh resolution ladder level, 0..MAX_LEVEL
    positions: int  # mesh positions over one base pitch


@dataclass(frozen=True)
class StudyCase:
    name: str
    description: str
    gearset: GearSet
    bearing: Bearing
    material: Material
    model: Model


# Range checks: field -> (low, high, inclusive bounds), in the units of the dataclasses.
_RANGES = {
    "bearing.radial_stiffness": (1e2, 1e12),
    "bearing.tilting_stiffness": (1e3, 1e14),
    "bearing.axial_stiffness": (1e2, 1e12),
    "material.youngs_modulus": (1e3, 1e7),
    "material.poisson_ratio": (0.0, 0.49),
    "material.gear_modulus_factor": (0.01, 100.0),
}
# The paper leaves the axial bearing stiffness out ("stiff"): 100x the radial rigid bearing.
DEFAULT_AXIAL_STIFFNESS = 2.33e10


def _section(data: dict, key: str, source: str) -> dict:
    value = data.get(key)
    if not isinstance(value, dict):
        raise CaseError(f"{source}: [{key}] section is missing")
    return value


def _ranged(section: dict, key: str, prefix: str, source: str, default=None) -> float:
    field = f"{prefix}.{key}"
    value = section.get(key, default)
    lo, hi = _RANGES[field]
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not lo <= value <= hi:
        raise CaseError(f"{source}: {field} = {value!r}: must be a number in [{lo:g}, {hi:g}]")
    return float(value)


def _integer(section: dict, key: str, prefix: str, source: str, lo: int, hi: int) -> int:
    value = section.get(key)
    if isinstance(value, bool) or not isinstance(value, int) or not lo <= value <= hi:
        raise CaseError(f"{source}: {prefix}.{key} = {value!r}: must be an integer {lo}..{hi}")
    return value


def parse_study_case(data: dict[str, Any], source: str = "<case>") -> StudyCase:
    """Validate a parsed TOML mapping into a :class:`StudyCase`."""
    name = data.get("name")
    if not isinstance(name, str) or not name:
        raise CaseError(f"{source}: name = {name!r}: must be a non-empty string")
    gearset = load_gearset(str(data.get("gearset", "")) or "<missing gearset>")
    b = _section(data, "bearing", source)
    bearing = Bearing(
        _ranged(b, "radial_stiffness", "bearing", source),
        _ranged(b, "tilting_stiffness", "bearing", source),
        _ranged(b, "axial_stiffness", "bearing", source, DEFAULT_AXIAL_STIFFNESS),
    )
    m = _section(data, "material", source)
    material = Material(
        _ranged(m, "youngs_modulus", "material", source),
        _ranged(m, "poisson_ratio", "material", source),
        _ranged(m, "gear_modulus_factor", "material", source, 1.0),
    )
    mod = _section(data, "model", source)
    scene = mod.get("scene")
    if scene not in SCENES:
        raise CaseError(f"{source}: model.scene = {scene!r}: must be one of {', '.join(SCENES)}")
    model = Model(
        scene,
        _integer(mod, "level", "model", source, 0, MAX_LEVEL),
        _integer(mod, "positions", "model", source, 1, 50),
    )
    return StudyCase(name, str(data.get("description", "")), gearset, bearing, material, model)


def available_cases() -> list[str]:
    return sorted(p.stem for p in CASE_DIR.glob("*.toml"))


def load_study_case(name_or_path: str | Path) -> StudyCase:
    """Load ``cases/<name>.toml`` (or a path to any study-case file)."""
    path = Path(name_or_path)
    if path.suffix != ".toml":
        path = CASE_DIR / f"{name_or_path}.toml"
    if not path.is_file():
        raise CaseError(f"{path}: no such case (available: {', '.join(available_cases())})")
    return parse_study_case(read_toml(path), path.name)

"""The analytical study's input file (``cases/analytic/<name>.toml``): which gear sets and
study cases the closed-form tables are computed for. Errors name the file and the field."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from cases.gearset import CaseError, GearSet, load_gearset, read_toml
from cases.study_case import load_study_case

ANALYTIC_DIR = Path(__file__).parent / "analytic"
_FIELDS = {"single_pinion", "double_pinion", "bearing_cases"}


@dataclass(frozen=True)
class AnalyticStudy:
    single_pinion: GearSet
    double_pinion: GearSet
    bearing_radial_stiffness: dict[str, float]  # study case -> radial pin-bearing N/mm


def _beside(value: str, path: Path) -> str | Path:
    """A name as it is; a path ending in .toml relative to the study file's folder (as a
    study case's ``gearset``), not the working directory."""
    target = Path(value)
    if value.endswith(".toml") and not target.is_absolute():
        return path.parent / target
    return value


def load_analytic_study(name_or_path: str | Path = "singh2007") -> AnalyticStudy:
    """Load ``cases/analytic/<name>.toml`` (or a path to such a file). Its gear sets and
    study cases: names, or paths ending in .toml relative to the file's folder."""
    path = Path(name_or_path)
    if path.suffix != ".toml":
        path = ANALYTIC_DIR / f"{name_or_path}.toml"
    if not path.is_file():
        raise CaseError(f"{path}: no such analytic study file")
    data = read_toml(path)
    src = path.name
    unknown = set(data) - _FIELDS
    if unknown:
        raise CaseError(f"{src}: unknown field(s) {sorted(unknown)}; allowed: {sorted(_FIELDS)}")
    sets = {}
    for key, kind in (("single_pinion", "single_pinion"), ("double_pinion", "double_pinion")):
        name = data.get(key)
        if not isinstance(name, str) or not name:
            raise CaseError(f"{src}: {key} = {name!r}: must name a gear set (cases/gearsets/)")
        try:
            gs = load_gearset(_beside(name, path))
        except CaseError as exc:
            raise CaseError(f"{src}: {key} = {name!r}: {exc}") from exc
        if gs.kind != kind:
            raise CaseError(f"{src}: {key} = {name!r} is a {gs.kind} set; must be {kind}")
        sets[key] = gs
    names = data.get("bearing_cases")
    if not isinstance(names, list) or not names or not all(isinstance(n, str) for n in names):
        raise CaseError(f"{src}: bearing_cases = {names!r}: must be a list of study-case names")
    radial = {}
    for n in names:
        try:
            radial[n] = load_study_case(_beside(n, path)).bearing.radial_stiffness
        except CaseError as exc:
            raise CaseError(f"{src}: bearing_cases: {n!r}: {exc}") from exc
    return AnalyticStudy(sets["single_pinion"], sets["double_pinion"], radial)

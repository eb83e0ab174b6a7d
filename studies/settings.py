"""The settings of one run of a case: sizes, degree, contact numerics and positions, resolved
once from the case file and the command line (or a study's own choice) and passed down.

:class:`RunSettings` holds what a run changes of the case's own settings; a field left None
is the case's. :meth:`RunSettings.resolved` merges the two in the one place that decides it:

- no ``level``: the case's ``model.level`` with its ``model.flank_level`` and
  ``fillet_level`` (the case file's sizes, e.g. L1P1F2R2);
- a ``level``: that level's own sizes (the case's flank and fillet levels go with the case's
  level);
- a ``flank_level`` / ``fillet_level`` given beside either: that one;
- ``degree``, ``grid_spacing``, ``penalty_factor``: the case's ``[numerics]`` unless given;
  ``positions``: the case's ``model.positions`` unless given.

A resolved settings object has every field but ``grid_spacing`` set (None there: the flank
element size of the sizes) and resolves to itself.

What a run asks beyond the case file (the options of ``planetary-fe run``) is
:class:`studies.case_options.CaseOptions`, kept apart so the command line's errors stay out
of the code hash.
"""

from __future__ import annotations

from dataclasses import dataclass

from cases.study_case import case_sizes
from meshing import sizing
from meshing.sizing import Level
from postprocess.run_scalars import run_label

__all__ = ["RunSettings"]


@dataclass(frozen=True)
class RunSettings:
    level: int | Level | None = None  # a ladder index, or explicit sizes (a size diagnostic)
    flank_level: int | None = None  # active flanks and contact grid at this level's size
    fillet_level: int | None = None  # refined root fillets at this level's size
    degree: int | None = None  # Lagrange degree of the displacement
    grid_spacing: float | None = None  # mm; None: the flank element size of the sizes
    penalty_factor: float | None = None  # contact penalty / body stiffness
    positions: int | None = None  # mesh positions over one base pitch
    is_resolved: bool = False

    def resolved(self, study) -> RunSettings:
        """These settings with the case's where they leave one open (module docstring)."""
        if self.is_resolved:
            return self
        level, case = case_sizes(study, self.level)
        num = study.numerics
        return RunSettings(
            level=level,
            flank_level=case.get("flank_level") if self.flank_level is None else self.flank_level,
            fillet_level=(
                case.get("fillet_level") if self.fillet_level is None else self.fillet_level
            ),
            degree=num.degree if self.degree is None else self.degree,
            grid_spacing=num.grid_spacing if self.grid_spacing is None else self.grid_spacing,
            penalty_factor=(
                num.penalty_factor if self.penalty_factor is None else self.penalty_factor
            ),
            positions=study.model.positions if self.positions is None else self.positions,
            is_resolved=True,
        )

    @property
    def variant(self) -> dict[str, int]:
        """The sizes taken from other levels (``flank_level``, ``fillet_level``; {} for the
        level's own): how results and records name them."""
        pairs = (("flank_level", self.flank_level), ("fillet_level", self.fillet_level))
        return {k: v for k, v in pairs if v is not None}

    @property
    def sizes(self) -> int | Level:
        """The mesh sizes: the level's index for its own sizes, else a :class:`Level`."""
        if isinstance(self.level, Level):
            return sizing.check_level(self.level)
        return sizing.run_sizes(self.level, self.flank_level, self.fillet_level)

    @property
    def spacing(self) -> float:
        """The contact grid spacing, mm: ``grid_spacing``, else the flank element size."""
        if self.grid_spacing is not None:
            return self.grid_spacing
        return sizing.check_level(self.sizes).fine

    @property
    def label(self) -> str:
        """``L<level>P<degree>[F<flank_level>][R<fillet_level>]``."""
        return run_label(self.level, self.degree, self.flank_level, self.fillet_level)

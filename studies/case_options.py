"""What one run of a case asks beyond its file: the options of ``planetary-fe run`` (level,
positions, scene, root fillets, out of core), checked and applied in one place
(:meth:`CaseOptions.applied`), which returns the case as it is solved and its resolved
:class:`studies.settings.RunSettings`. A bad option is an :class:`~studies.cli.InputError`
naming it and what is allowed. Apart from :mod:`studies.settings` because the settings are
under the code hash and the command line's errors are not."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

from cases.study_case import MAX_LEVEL, MAX_POSITIONS, ROOT_FILLETS, SCENES, StudyCase
from studies.cli import InputError
from studies.settings import RunSettings

__all__ = ["CaseOptions"]


@dataclass(frozen=True)
class CaseOptions:
    """What one run asks of a case beyond its file; None keeps the case file's."""

    level: int | None = None  # mesh level: that level's own sizes (--level)
    positions: int | None = None  # mesh positions over one base pitch (--positions)
    scene: str | None = None  # instead of model.scene (--scene)
    root_fillets: str | None = None  # instead of numerics.root_fillets (--root-fillets)
    out_of_core: bool | None = None  # instead of numerics.out_of_core (--out-of-core)

    def applied(self, study: StudyCase) -> tuple[StudyCase, RunSettings]:
        """``study`` as this run solves it (the scene, root fillets and out-of-core given
        replace the case's, and are then in the summary's inputs; a level given takes that
        level's own sizes) and its resolved :class:`RunSettings`.
        :class:`~studies.cli.InputError` names the option and what is allowed."""
        model, num = study.model, study.numerics
        if self.scene is not None:
            if self.scene not in SCENES:
                raise InputError(f"scene = {self.scene!r}: must be one of {', '.join(SCENES)}")
            model = dataclasses.replace(model, scene=self.scene)
        if self.root_fillets is not None:
            if self.root_fillets not in ROOT_FILLETS:
                raise InputError(
                    f"root_fillets = {self.root_fillets!r}: must be one of "
                    f"{', '.join(ROOT_FILLETS)}"
                )
            num = dataclasses.replace(num, root_fillets=self.root_fillets)
        if self.out_of_core is not None:
            num = dataclasses.replace(num, out_of_core=bool(self.out_of_core))
        study = dataclasses.replace(study, model=model, numerics=num)
        settings = self._settings(study)
        if self.level is not None:  # the inputs (and their hash) say which sizes run
            model = dataclasses.replace(
                study.model, level=settings.level, flank_level=None, fillet_level=None
            )
            study = dataclasses.replace(study, model=model)
        return study, settings

    def _settings(self, study: StudyCase) -> RunSettings:
        """The run's resolved settings, checked (the number of positions stays out of the
        inputs: a position is keyed by its roll)."""
        lv = self.level
        if lv is not None and (
            isinstance(lv, bool) or not isinstance(lv, int) or not 0 <= lv <= MAX_LEVEL
        ):  # the case file's range: a finer global level does not fit a machine's memory
            raise InputError(
                f"{study.name}: --level {lv!r}: must be an integer from 0 to {MAX_LEVEL} "
                "(the range of the case file's [model] level)"
            )
        n = self.positions
        if n is not None and (
            isinstance(n, bool) or not isinstance(n, int) or not 1 <= n <= MAX_POSITIONS
        ):
            raise InputError(
                f"{study.name}: --positions {n!r}: must be an integer from 1 to "
                f"{MAX_POSITIONS} (mesh positions over one base pitch)"
            )
        return RunSettings(level=self.level, positions=n).resolved(study)

"""Errors raised by the solver layer.

Every error names what failed (the body, the rigid mode, the rigid unknown, the contact pair)
and carries what had been computed before it stopped in ``partial`` (a dict, possibly empty),
so a caller can still write out or inspect the iteration history.
"""

from __future__ import annotations

from typing import Any


class SolverError(RuntimeError):
    """Base class: a solve that cannot give a trustworthy answer."""

    def __init__(self, message: str, partial: dict[str, Any] | None = None):
        super().__init__(message)
        self.partial: dict[str, Any] = dict(partial or {})


class SingularBodyError(SolverError):
    """A body's stiffness is singular: a rigid-body mode is not restrained.

    ``body`` is the body's name and ``modes`` lists the unrestrained rigid modes in words,
    e.g. ``["rotation about z"]``.
    """

    def __init__(self, body: str, modes: list[str], detail: str = ""):
        msg = (
            f"body '{body}' is not restrained against rigid-body motion: free mode(s) "
            f"{', '.join(modes)}. Add a support (Dirichlet surface, coupling DOF fixed or a "
            f"spring), or declare the mode a rigid unknown balanced by contact."
        )
        if detail:
            msg += f" ({detail})"
        super().__init__(msg)
        self.body = body
        self.modes = modes


class FactorizationError(SolverError):
    """The sparse direct factorization (MUMPS) failed or found null pivots."""


class GapOperatorError(SolverError):
    """Contact grid points could not be located in the body they should lie on."""


class NoContactError(SolverError):
    """No grid point is in contact: the flanks do not touch under this load."""


class ActiveSetError(SolverError):
    """The contact active set did not converge; ``partial['history']`` has every iteration."""


class PenaltyConditioningError(SolverError):
    """The penalty is so stiff that the condensed contact system is ill-conditioned."""


class RigidUnknownError(SolverError):
    """A rigid unknown (sun rotation, pinion spin, rigid approach) is not determined."""


class ZoneReachError(SolverError):
    """The solved load reaches the edge of a zone grid's band: cells beyond its gap limit may
    be in contact (:mod:`solvers.zone_reach`)."""

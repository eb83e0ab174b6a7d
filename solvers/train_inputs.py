"""What the gear-train model takes of a case (:class:`TrainInputs`): materials, bearing,
torque, the bodies' linear solver, the contact settings, the flank modifications and the
system scene's supports. The solvers read no case file; the driver makes this from the study
case (:func:`studies.position.train_inputs`)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

from solvers.elastic_body import LinearSolver

__all__ = ["TrainInputs"]


@dataclass(frozen=True)
class TrainInputs:
    youngs_modulus: float  # MPa, the carrier's (no gear modulus factor)
    poisson_ratio: float
    gear_youngs_modulus: float  # MPa, every gear body's
    # the needle bearing, pinion to pin: N/mm along x, y, z, N mm/rad about x, y; spin free (0)
    bearing_stiffness: tuple[float, float, float, float, float, float]
    torque_per_branch_Nm: float  # the sun torque one branch carries (equal load sharing)
    linear_solver: LinearSolver  # of every body; part of every body's store key
    contact_model: str  # "zone" or "line" (solvers.flank_grid.flank_contact_pairs)
    zone_gap_limit_mm: float  # "zone": grid cells where the unloaded separation is below this
    modifications: Mapping = field(default_factory=dict)  # flank modifications by gear name
    sun_radial_stiffness: float = 0.0  # N/mm at the sun bore in the system scene; 0 floating
    pin_position_errors_um: tuple = ()  # system scene: [tangential, radial] per branch

"""Rigid coupling of a tagged surface (a bore) to a reference point, by elimination.

A reference point ``x_ref`` carries ``nr`` rigid DOFs q (3D: U_1, U_2, U_3, Theta_1,
Theta_2, Theta_3 along/about the coupling's ``axes``; 2D: U_1, U_2, Theta_z). Every FE DOF
on the coupled surface S is slaved to it:

    u(x) = sum_j q_j psi_j(x),   psi_j = a_j (translation),  psi_j = a_j x (x - x_ref) (rotation)

Elimination, not penalty: with the reduced unknowns u_red = [FE DOFs | q] the full field is
u = P u_red, where P is the identity on every FE DOF and adds the columns psi(x_i) on the rows
of the slaved DOFs; the slaved DOFs' own reduced entries are then constrained to zero. The
reduced stiffness is K_red = P^T K P (PETSc PtAP) plus the coupling's spring diagonal
diag(k_j) to ground on q, and a load on q is a generalized force (force or moment about
x_ref along a_j). A needle bearing is such a coupling with k = (k_r, k_r, k_ax, k_tilt,
k_tilt, 0) in the pinion frame (radial, axial, tilting; spin free).

Per DOF the stiffness says what the reference point is tied to: ``math.inf`` fixed (the
reaction is read from the residual), a positive number a spring to ground, 0 free.
A free DOF must be restrained by something else (a rigid unknown balanced by contact),
or the body is reported singular.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np


def n_rigid(gdim: int) -> int:
    """Number of rigid-body DOFs of a body in ``gdim`` dimensions (3 in 2D, 6 in 3D)."""
    return 3 if gdim == 2 else 6


def global_mode_names(gdim: int) -> list[str]:
    """Names of the global rigid modes (identity frame) in the order of :func:`rigid_modes`."""
    if gdim == 2:
        return ["translation x", "translation y", "rotation about z"]
    return [f"translation {c}" for c in "xyz"] + [f"rotation about {c}" for c in "xyz"]


def rigid_modes(x: np.ndarray, x_ref: np.ndarray, axes: np.ndarray | None = None) -> np.ndarray:
    """Rigid-body displacement fields psi_j evaluated at points x.

    Args:
        x: points, shape (n, gdim).
        x_ref: reference point, shape (gdim,).
        axes: orthonormal frame, rows are a_j (gdim x gdim); identity if None.

    Returns:
        array (n, gdim, nr) with psi_j(x_i)[c] at [i, c, j]; translations along a_j first,
        then rotations about a_j through x_ref (2D: about z).
    """
    x = np.asarray(x, dtype=float)
    n, gdim = x.shape
    a = np.eye(gdim) if axes is None else np.asarray(axes, dtype=float)
    d = x - np.asarray(x_ref, dtype=float)[None, :gdim]
    out = np.zeros((n, gdim, n_rigid(gdim)))
    for j in range(gdim):
        out[:, :, j] = a[j][None, :]
    if gdim == 2:
        out[:, 0, 2] = -d[:, 1]
        out[:, 1, 2] = d[:, 0]
    else:
        for j in range(3):
            out[:, :, 3 + j] = np.cross(a[j][None, :], d)
    return out


def reference_motion(
    x_ref: np.ndarray, centre: np.ndarray, axes: np.ndarray | None = None
) -> np.ndarray:
    """Generalized coordinates q (in the coupling frame) of each global rigid mode.

    The global rigid modes are the ones of :func:`rigid_modes` with the identity frame about
    ``centre``; column m of the result is q for mode m (nr x nr).
    """
    gdim = len(centre)
    a = np.eye(gdim) if axes is None else np.asarray(axes, dtype=float)
    nr = n_rigid(gdim)
    q = np.zeros((nr, nr))
    disp = rigid_modes(np.asarray(x_ref, dtype=float)[None, :gdim], centre)[0]  # (gdim, nr)
    q[:gdim, :] = a @ disp
    if gdim == 2:
        q[2, 2] = 1.0
    else:
        q[3:, 3:] = a  # rotation vector e_m expressed in the frame: a @ e_m
    return q


@dataclass(frozen=True)
class RigidCoupling:
    """A surface of a body moving as a rigid body with a reference point.

    Attributes:
        name: unique within the body.
        surface: facet tag name of the coupled surface (e.g. "bore").
        x_ref: the reference point (mm).
        stiffness: per rigid DOF, ``math.inf`` fixed, > 0 spring to ground, 0 free.
        load: generalized force on each rigid DOF (N along a_j, N mm about a_j).
        axes: frame rows a_j (orthonormal); identity if None. For a pinion, a_3 = its axis.
    """

    name: str
    surface: str
    x_ref: Sequence[float]
    stiffness: Sequence[float]
    load: Sequence[float] | None = None
    axes: np.ndarray | None = field(default=None, compare=False)

    def __post_init__(self):
        k = np.asarray(self.stiffness, dtype=float)
        if k.ndim != 1 or len(k) not in (3, 6):
            raise ValueError(f"coupling '{self.name}': stiffness needs 3 (2D) or 6 (3D) values")
        if np.any(k < 0) or np.any(np.isnan(k)):
            raise ValueError(f"coupling '{self.name}': stiffness must be >= 0 or math.inf")
        if self.load is not None and len(self.load) != len(k):
            raise ValueError(f"coupling '{self.name}': load needs {len(k)} values")
        if self.axes is not None:
            a = np.asarray(self.axes, dtype=float)
            gd = 2 if len(k) == 3 else 3
            if a.shape != (gd, gd) or not np.allclose(a @ a.T, np.eye(gd), atol=1e-12):
                raise ValueError(f"coupling '{self.name}': axes must be orthonormal {gd}x{gd}")

    @property
    def nr(self) -> int:
        return len(self.stiffness)

    def frame(self, gdim: int) -> np.ndarray:
        return np.eye(gdim) if self.axes is None else np.asarray(self.axes, dtype=float)

    def loads(self) -> np.ndarray:
        return np.zeros(self.nr) if self.load is None else np.asarray(self.load, dtype=float)

    def fixed(self) -> np.ndarray:
        return np.array([math.isinf(k) for k in self.stiffness])

    def springs(self) -> np.ndarray:
        k = np.asarray(self.stiffness, dtype=float)
        return np.where(np.isinf(k), 0.0, k)


def bearing(
    name: str,
    surface: str,
    x_ref: Sequence[float],
    axis: Sequence[float],
    k_radial: float,
    k_tilt: float,
    k_axial: float,
    load: Sequence[float] | None = None,
) -> RigidCoupling:
    """Needle bearing between a pinion bore and its pin (pin and carrier rigid, fixed).

    6x6 diagonal in the pinion frame (a_1, a_2 radial, a_3 = axis):
    k = (k_radial, k_radial, k_axial, k_tilt, k_tilt, 0): spin free.
    """
    a3 = np.asarray(axis, dtype=float)
    a3 = a3 / np.linalg.norm(a3)
    trial = np.array([1.0, 0.0, 0.0]) if abs(a3[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    a1 = trial - a3 * (trial @ a3)
    a1 /= np.linalg.norm(a1)
    a2 = np.cross(a3, a1)
    return RigidCoupling(
        name,
        surface,
        tuple(x_ref),
        (k_radial, k_radial, k_axial, k_tilt, k_tilt, 0.0),
        load=load,
        axes=np.vstack([a1, a2, a3]),
    )

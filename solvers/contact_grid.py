"""The contact grid: where the exact flank surfaces are close, independent of the FE mesh.

The grid arrives as arrays (for gears from the exact flank geometry, in the tests from
analytic cylinders and planes). Grid point k has a point on each surface, x_a[k] on body A
and x_b[k] on body B, a unit normal n[k] pointing from A to B, the exact initial separation
g0[k] along n (including microgeometry and rigid misalignment; negative = interference) and
the area it stands for, w[k] (mm^2 in 3D; in 2D, length per unit thickness, mm).

The gap at k after deformation is

    g_k = g0_k + n_k . (u_B(x_b,k) - u_A(x_a,k))                             (1)

evaluated from the FE fields by :mod:`solvers.gap_operator`, not from the faceted mesh.

Spreading (the point-load issue): a grid force applied at a single point is a point load on
the FE mesh; its self-compliance is of order 1/(E h) in 3D (log(1/h) in 2D) and grows
without bound as the mesh is refined, so C_kk would depend on the mesh instead of on the
contact. Each row of (1) is therefore the *mean* of n . u over the grid cell of point k: a
tensor Gauss rule of ``n_spread`` points per tangent direction over the patch
x_k + sum_i s_i t_i, |s_i| <= half_size_i (the grid cell). The force F_k is then spread over
the same patch (G^T is the consistent load of a uniform traction on the patch), and C_kk
stays bounded as h -> 0. Without tangents the rows are point evaluations.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True, eq=False)
class ContactGrid:
    """Grid points of one flank pair (arrays replicated on every rank).

    Attributes:
        name: pair name used in messages.
        x_a, x_b: (n, gdim) points on the exact surfaces of body A and body B.
        normals: (n, gdim) unit normals from A to B.
        gap0: (n,) exact initial separation along the normal (mm).
        weights: (n,) area per point (mm^2, or mm per unit thickness in 2D).
        tangents: optional (n, gdim - 1, gdim) unit tangents spanning the grid cell.
        half_sizes: optional (n, gdim - 1) half-extent of the grid cell along each tangent.
        stations: optional (n,) integer station along a contact line (for line loads).
        station_length: optional (n_stations,) length of each station (mm).
        n_spread: Gauss points per tangent direction when spreading (>= 1).
        nominal_normal: optional (gdim,) unit vector, the one direction that stands for the
            pair (a gear mesh: the normal of its plane of action, A -> B, which readers
            project forces on). The point normals may differ from it (a zone grid's points
            off the contact line carry the exact flank normal there); the force the grid
            transmits to body B is sum_k F_k n_k, not (sum_k F_k) times it. None: not given.
    """

    name: str
    x_a: np.ndarray
    x_b: np.ndarray
    normals: np.ndarray
    gap0: np.ndarray
    weights: np.ndarray
    tangents: np.ndarray | None = None
    half_sizes: np.ndarray | None = None
    stations: np.ndarray | None = None
    station_length: np.ndarray | None = None
    n_spread: int = 2
    nominal_normal: np.ndarray | None = None

    def __post_init__(self):
        n, gdim = np.shape(self.x_a)
        if np.shape(self.x_b) != (n, gdim) or np.shape(self.normals) != (n, gdim):
            raise ValueError(f"grid '{self.name}': x_a, x_b, normals must all be (n, gdim)")
        if np.shape(self.gap0) != (n,) or np.shape(self.weights) != (n,):
            raise ValueError(f"grid '{self.name}': gap0 and weights must be (n,)")
        if n == 0:
            raise ValueError(f"grid '{self.name}' has no points")
        norms = np.linalg.norm(self.normals, axis=1)
        if not np.allclose(norms, 1.0, atol=1e-9):
            raise ValueError(f"grid '{self.name}': normals must be unit vectors")
        if np.any(np.asarray(self.weights) <= 0):
            raise ValueError(f"grid '{self.name}': weights (areas) must be > 0")
        if (self.tangents is None) != (self.half_sizes is None):
            raise ValueError(f"grid '{self.name}': give both tangents and half_sizes, or none")
        if self.tangents is not None:
            if np.shape(self.tangents) != (n, gdim - 1, gdim):
                raise ValueError(f"grid '{self.name}': tangents must be (n, gdim - 1, gdim)")
            if np.shape(self.half_sizes) != (n, gdim - 1):
                raise ValueError(f"grid '{self.name}': half_sizes must be (n, gdim - 1)")
        if self.stations is not None and self.station_length is None:
            raise ValueError(f"grid '{self.name}': stations need station_length")
        if self.nominal_normal is not None:
            nn = np.asarray(self.nominal_normal, dtype=float)
            if np.shape(nn) != (gdim,) or not abs(np.linalg.norm(nn) - 1.0) < 1e-9:
                raise ValueError(f"grid '{self.name}': nominal_normal must be a unit (gdim,)")

    @property
    def n(self) -> int:
        return len(self.gap0)

    @property
    def gdim(self) -> int:
        return np.shape(self.x_a)[1]

    def spread_points(self, side: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Quadrature points of every grid cell on one side ("a" or "b").

        Returns:
            (points (m, gdim), parent grid index (m,), weight (m,) summing to 1 per parent).
        """
        x = np.asarray(self.x_a if side == "a" else self.x_b, dtype=float)
        if self.tangents is None:
            return x, np.arange(self.n), np.ones(self.n)
        s, w = np.polynomial.legendre.leggauss(self.n_spread)
        w = w / 2.0
        t = np.asarray(self.tangents, dtype=float)
        h = np.asarray(self.half_sizes, dtype=float)
        if self.gdim == 2:
            offs = [(si,) for si in s]
            wts = list(w)
        else:
            offs = [(si, sj) for si in s for sj in s]
            wts = [wi * wj for wi in w for wj in w]
        pts, parent, weight = [], [], []
        for off, wt in zip(offs, wts, strict=True):
            d = sum(off[i] * h[:, i, None] * t[:, i, :] for i in range(self.gdim - 1))
            pts.append(x + d)
            parent.append(np.arange(self.n))
            weight.append(np.full(self.n, wt))
        return np.vstack(pts), np.concatenate(parent), np.concatenate(weight)


def line_grid_2d(
    name: str,
    x_a: np.ndarray,
    x_b: np.ndarray,
    normals: np.ndarray,
    gap0: np.ndarray,
    spacing: float,
    n_spread: int = 2,
) -> ContactGrid:
    """A 2D grid of equally spaced points along a contact (per unit thickness).

    Tangent t = n rotated by +90 degrees; each point stands for a length ``spacing``.
    """
    n = len(gap0)
    normals = np.asarray(normals, dtype=float)
    t = np.stack([-normals[:, 1], normals[:, 0]], axis=1)[:, None, :]
    return ContactGrid(
        name,
        np.asarray(x_a, dtype=float),
        np.asarray(x_b, dtype=float),
        normals,
        np.asarray(gap0, dtype=float),
        np.full(n, spacing),
        tangents=t,
        half_sizes=np.full((n, 1), spacing / 2),
        n_spread=n_spread,
    )


@dataclass(frozen=True, eq=False)
class ZoneLink:
    """How a fine zone grid (:func:`solvers.flank_grid.zone_grid`) couples to the FE.

    The FE compliance is formed only on the ``coarse`` grid (one point per section and tooth
    pair, on the closest-approach curve) and carried to the fine points by ``parent`` (fine
    row -> coarse row, piecewise constant: every fine point of a section takes its section's
    coarse column). The near field comes from Boussinesq coefficients
    (:mod:`solvers.halfspace`) in the flank's developed plane: ``plane`` (n, 2) = (u along the
    contact line, v across it along the profile, mm) with half sizes ``half`` (n, 2) for the
    fine patches, ``plane_coarse`` / ``half_coarse`` for the coarse ones, and half-space
    coupling only inside one tooth pair (``group`` / ``group_coarse``). The FE and the
    half-space are matched at the depths ``depth_a`` / ``depth_b`` below each coarse point
    inside body A / B (x_a - d_a n, x_b + d_b n), where the FE resolves the field of a coarse
    patch; see eq. (5) of :mod:`solvers.contact`.
    """

    coarse: ContactGrid
    parent: np.ndarray  # (n,) int, coarse row of each fine point
    plane: np.ndarray  # (n, 2)
    half: np.ndarray  # (n, 2)
    plane_coarse: np.ndarray  # (n_c, 2)
    half_coarse: np.ndarray  # (n_c, 2)
    group: np.ndarray  # (n,) tooth pair of each fine point
    group_coarse: np.ndarray  # (n_c,)
    depth_a: np.ndarray  # (n_c,) matching depth below the coarse point in body A (mm)
    depth_b: np.ndarray  # (n_c,) the same in body B

    def __post_init__(self):
        n, nc = len(self.parent), self.coarse.n
        ok = (
            np.shape(self.plane) == (n, 2)
            and np.shape(self.half) == (n, 2)
            and np.shape(self.plane_coarse) == (nc, 2)
            and np.shape(self.half_coarse) == (nc, 2)
            and np.shape(self.group) == (n,)
            and np.shape(self.group_coarse) == (nc,)
            and np.shape(self.depth_a) == (nc,)
            and np.shape(self.depth_b) == (nc,)
        )
        if not ok:
            raise ValueError(f"zone link of '{self.coarse.name}': array shapes disagree")
        p = np.asarray(self.parent)
        if n and (p.min() < 0 or p.max() >= nc):
            raise ValueError(f"zone link of '{self.coarse.name}': parent out of range")
        if np.any(np.asarray(self.group_coarse)[p] != np.asarray(self.group)):
            raise ValueError(f"zone link of '{self.coarse.name}': parent in another tooth pair")

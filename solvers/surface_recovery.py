"""Moving least-squares recovery of the stress on a root fillet, in the fillet's own
coordinates.

The nodal surface tensors of :func:`solvers.root_stress.surface_values` (at each fillet vertex
the mean over its fillet cells of each cell's own stress there) scatter from node to node at
the element scale. A largest value over nodes, or along a line across them, picks that
scatter up: 1-GB's ring at mid-cycle (roll 0.0718, level-1 driver) reads ISO's
60 deg line 737.3 / 746.4 / 772.1 MPa on sectors of levels 1 / 2 / 3's sizes at one 0.1 mm
read fillet, while the three surface maxima agree within 0.9 %; along the line the nodal
values rise 4.5 % over a single axial node of the level-3 sector (747 / 760 / 772 / 758 /
741 MPa at 0.06 mm steps).

A fillet strip (one tooth side, :func:`meshing.body_mesh.structure_fillets`) is mapped to
coordinates (s, z): each node is screwed back along the helix to the transverse section,
turned to tooth 0 (mirrored for a ``neg`` fillet) and projected on the generated fillet
curve (:func:`gears.profile.tooth_profile`, ``fillet_pos``); s is the arc length of its
foot point from the root circle, z its axial position. The recovered tensor at (s0, z0) is
the constant c_0 of the weighted least-squares fit, per tensor component, of the nodes'
tensors S_i:

    S(s, z) ~ c_0 + c_1 (s - s0) + c_2 (z - z0) + c_3 (s - s0)^2,
    w_i = (1 - rho_i^2)^2,  rho_i^2 = ((s_i - s0) / (A h_s))^2 + ((z_i - z0) / (B h_z))^2 < 1,

h_s and h_z the strip's node spacings across and along (the medians of its facet edges'
projections), A = :data:`ACROSS` and B = :data:`ALONG`. Quadratic across the profile, where
the stress peaks within a few nodes (the ring above: 729 / 767 / 767 / 665 MPa at 0.13 mm
steps; a linear fit cut such peaks by 2-5 %); linear and wider along the face width, where
the stress changes over millimetres and what varies from node to node is the scatter. The
windows shrink with the mesh, so the recovery converges to the surface field as the nodal
values do (it reproduces any field of the basis exactly, :func:`recover`).

Where the window holds fewer than two nodes beyond 0.3 h_s on either side of s0 (the strip's
edges), the quadratic term is dropped (a one-sided quadratic extrapolates); a fit that is
still underdetermined or ill-conditioned gives NaN, and the caller keeps the nodal value.

Measured (``make sector-sizes``, the spreads 1-GB's record keeps; docs/validation.md): over
equally valid sectors the recovery takes the ISO line's scatter that the nodal values pick
up (1-GB's ring above) down to that of the other values, and leaves the surface maxima's
within their scatter; windows of 1.5-3 spacings across and 3-6 along read within about 1 %
of the defaults, and a fit linear across the profile cut the peaks by 2-5 %. The recovered
surface maxima lie 0.3-2.8 % below the nodal ones (the nodal maxima are maxima of scattered
values and carry the scatter's upper half); the ISO-line values from 4.0 % below to 0.9 %
above them (the line's points fall between nodes, where the fit may pass above the nodal
values' linear interpolation).

Pure numpy; the same inputs give the same values on every rank.
"""

from __future__ import annotations

import math

import numpy as np

from gears.profile import polyline_foot, tooth_profile

#: window half-widths in node spacings: across the fillet profile (the quadratic fit needs
#: at least five nodes, two either side) and along the face width
ACROSS = 2.0
ALONG = 4.0
#: largest condition number of the weighted fit's matrix (the basis is scaled by h_s, h_z)
MAX_CONDITION = 1e6
#: samples of the generated fillet curve (chord error well below 1e-4 mm for fillets of
#: 0.3-1 mm radius)
CURVE_SAMPLES = 801


def fillet_curve(gear) -> tuple[np.ndarray, np.ndarray]:
    """Tooth 0's ``pos`` fillet of ``gear`` in the transverse section, root circle to form
    circle, sampled at :data:`CURVE_SAMPLES` points (m, 2), and the arc length (mm) at each."""
    pts = tooth_profile(gear, n_fillet=CURVE_SAMPLES).fillet_pos
    arc = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(pts, axis=0), axis=1))]
    return pts, arc


def fillet_coordinates(gear, tooth: int, side: str, xyz: np.ndarray, curve=None) -> np.ndarray:
    """(s, z) (n, 2) of body-frame points ``xyz`` (n, 3) on the fillet of ``tooth`` /
    ``side``: s the arc length (mm) of the point's foot on the generated fillet curve
    (:func:`fillet_curve`), after screwing it back to z = 0 and turning it to tooth 0
    (mirrored for ``neg``), z its axial position."""
    pts, arc = fillet_curve(gear) if curve is None else curve
    x = np.asarray(xyz, float).reshape(-1, 3)
    ang = np.arctan2(x[:, 1], x[:, 0]) - 2.0 * math.pi * tooth / gear.teeth
    ang = ang - np.asarray(gear.helix_rotation(x[:, 2]), float)
    ang = (ang + math.pi) % (2.0 * math.pi) - math.pi
    if side == "neg":
        ang = -ang
    r = np.hypot(x[:, 0], x[:, 1])
    q = np.c_[r * np.cos(ang), r * np.sin(ang)]
    j, w = polyline_foot(pts, q)
    s = arc[j] + w * (arc[j + 1] - arc[j])
    return np.c_[s, x[:, 2]]


def strip_spacings(sz: np.ndarray, triangles: np.ndarray) -> tuple[float, float]:
    """Node spacings (h_s, h_z) (mm) of a fillet strip: the medians of the facet edges'
    |ds| over the edges running more across than along, and of |dz| over the others.
    ``sz``: (n, 2) node coordinates, ``triangles``: (m, 3) node indices."""
    tri = np.asarray(triangles, np.int64)
    d = np.abs(sz[tri] - sz[np.roll(tri, 1, axis=1)]).reshape(-1, 2)
    across, along = d[d[:, 0] > d[:, 1], 0], d[d[:, 1] >= d[:, 0], 1]
    h_s = float(np.median(across)) if across.size else float(np.median(d[:, 0]))
    h_z = float(np.median(along)) if along.size else float(np.median(d[:, 1]))
    return h_s, h_z


def recover(
    sz: np.ndarray,
    tensors: np.ndarray,
    at: np.ndarray,
    h_s: float,
    h_z: float,
    across: float = ACROSS,
    along: float = ALONG,
) -> np.ndarray:
    """Recovered tensors (p, 3, 3) at the points ``at`` (p, 2) in (s, z) from the nodes
    ``sz`` (n, 2) with tensors (n, 3, 3) (module docstring); NaN where the fit is not
    posed."""
    order = np.argsort(sz[:, 1], kind="stable")
    s, z = sz[order, 0], sz[order, 1]
    vals = np.asarray(tensors, float).reshape(-1, 9)[order]
    ws, wz = across * h_s, along * h_z
    lo = np.searchsorted(z, at[:, 1] - wz, side="left")
    hi = np.searchsorted(z, at[:, 1] + wz, side="right")
    out = np.full((len(at), 9), np.nan)
    for p, (s0, z0) in enumerate(at):
        ds, dz = s[lo[p] : hi[p]] - s0, z[lo[p] : hi[p]] - z0
        rho2 = (ds / ws) ** 2 + (dz / wz) ** 2
        m = rho2 < 1.0
        if not m.any():
            continue
        a, b = ds[m] / h_s, dz[m] / h_z
        sw = 1.0 - rho2[m]  # sqrt of the weight (1 - rho^2)^2
        both = np.count_nonzero(a > 0.3) >= 2 and np.count_nonzero(a < -0.3) >= 2
        cols = [np.ones_like(a), a, b] + ([a * a] if both else [])
        A = np.stack(cols, axis=1) * sw[:, None]
        if len(a) < 2 * A.shape[1]:
            continue
        coef, _, rank, sv = np.linalg.lstsq(A, vals[lo[p] : hi[p]][m] * sw[:, None], rcond=None)
        if rank < A.shape[1] or sv[0] > MAX_CONDITION * sv[-1]:
            continue  # the condition number sv_max / sv_min of the weighted fit
        out[p] = coef[0]
    return out.reshape(-1, 3, 3)

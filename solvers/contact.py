"""Penalty contact between elastic bodies, condensed exactly onto the contact grid.

Unknowns: the bodies' reduced displacements u_b (each body its own factorized system), the
grid forces F_k >= 0 (N; F_k = p_k w_k) and the rigid unknowns r_j (sun rotation, pinion
spin, a rigid approach: motions held in the FE system and superposed explicitly).

Gap at grid point k (see :mod:`solvers.contact_grid`, :mod:`solvers.gap_operator`):

    g = g0 + sum_b G_b u_b + R r,     R_kj = sigma_k n_k . psi_j(x_k)                (1)

with psi_j the rigid field of unknown j on its body and sigma = +1 (side B) / -1 (side A).
Penalty: F_k = eps_k w_k max(0, -g_k) with eps_k = factor * E*_k / h_k (N/mm^3), E*_k the
Hertz contact modulus of the pair (1/E* = (1 - nu_a^2)/E_a + (1 - nu_b^2)/E_b, a rigid
obstacle contributing 0) and h_k the size of the cells holding point k (the finer side). So
the penalty layer is ``factor`` times stiffer than an elastic layer of thickness h, and its
penetration p/eps = p h / (factor E*) is a fraction 1/factor of the local elastic
deformation scale.

Each body is in equilibrium with its load and the contact forces,

    K_b u_b = f_b + G_b^T F,                                                      (2)

and each rigid unknown balances its generalized load (torque, force) against contact and
the springs between rigid unknowns (a needle bearing between a pinion and its pin, a support
to ground, the condensed stiffness of an elastic carrier at its pins), K_r the small
symmetric matrix they assemble and f_d the forces of springs with a rest offset d (a pin
position error: energy k (r_a - r_b - d)^2 / 2 gives f_d = +k d on a, -k d on b):

    R^T F + f_r + f_d - K_r r = 0.                                                 (3)

Springs act on rigid unknowns, never inside a body's K: a pinion whose bore reference DOFs
are all rigid unknowns is clamped at the bore in its FE system, so its factorization does not
depend on the bearing and serves every case that differs only in bearing stiffness.

Condensation (exact for the penalty method, no approximation): with the compliance
C = sum_b G_b K_b^{-1} G_b^T (dense, n x n, from ONE factorization per body, multi-RHS
solves) and the no-contact gaps g_f = sum_b G_b K_b^{-1} f_b, on the active set A
(F = 0 off A) eqs. (1)-(3) become the small symmetric saddle-point system

    [ C_AA + D_A   R_A  ] [F_A]   [ -(g0 + g_f)_A ]
    [ R_A^T       -K_r ] [ r ] = [ -f_r - f_d    ],   D = diag(1 / (eps_k w_k)),    (4)

(prescribed rigid unknowns move to the right-hand side). This is K + G_A^T E_A G_A condensed
exactly, so the penalty sweep converges to the eps -> inf limit of the same discrete model.
The active set is iterated on (4) alone (primal-dual / semismooth Newton for the piecewise
linear penalty law): A_{i+1} = {k : g_k(F_i, r_i) < 0}, stopping when A repeats; no
refactorization of any K_b is needed, whatever the number of active-set changes.

Only the columns C[:, A] of points that are or were active are ever used (in (4) and in the
gaps g = g0 + g_f + C[:, A] F_A + R r), so they are formed on demand, in batches, by MUMPS
multi-RHS solves with each body's one factorization (``ensure_columns``). A body keeps its
share of every column it formed, keyed by the rows' geometry in its own frame
(:mod:`solvers.body_columns`): a later problem placing the same rows on the body (another
case at the same mesh position, a sweep) reads them instead of solving.

Zone grids: near field / far field split (a pair with a ``link``,
:func:`solvers.flank_grid.zone_grid`). A fine grid over the whole potential contact zone
would cost one FE solve per point, and the FE cannot resolve the Hertz field of a patch far
smaller than its elements anyway. Its compliance is therefore

    C_ij = H_f,ij + P (D_FE - H_d) P^T |_ij          (i, j in one tooth pair)
    C_ij = P C_FE P^T |_ij                          (otherwise),                    (5)

H_f the Boussinesq half-space compliance of the fine patches (:mod:`solvers.halfspace`,
Love's rectangles, contact modulus E*), P the piecewise-constant map fine -> coarse (every
fine point of a section takes its section's coarse column; ``ZoneLink.parent``; one coarse
point per section and tooth pair, patch of the element size), C_FE = G_c K^{-1} G_c^T the
FE compliance on the coarse points. The FE cannot be matched to the half-space at the
surface: a P1 mesh of size h is too stiff under an h-sized patch (a steel roller at
h = 1 mm: the patch's FE self-compliance is 0.6 of Love's for the same patch, so
C_FE - H_c is indefinite and the active set cycles). It is matched at depth, as in the
combined surface-integral / FE method of Vijayakar (1991): D_FE = G_d K^{-1} G_c^T is the
FE's normal approach of the two bodies at the matching points d below each coarse point
inside each body (``ZoneLink.depth_a``/``depth_b``, one coarse width), where the FE
resolves the field of a patch load, and H_d the half-space's there (Boussinesq's subsurface
solution per body, its own E and nu, eq. (3) of :mod:`solvers.halfspace`). D_FE - H_d is
the body correction (bending, shear, finite body, support); the near field, down to the
fine cells, is the half-space's. For a half-space body the correction vanishes and C = H_f.
D_FE is observed at depth but loaded at the surface, so (5) is not exactly symmetric (the
saddle system is solved as a general one). Different tooth pairs and different meshes
interact through the surface FE compliance C_FE alone. The gaps use exact fine geometry
(g0, normals, R of eq. (1) at the fine points), the no-contact gaps and the final
displacements the fine gap operator G (the forces applied where they act); only the
compliance columns go through the coarse points. The zone points need no penalty: their
local compliance is the half-space's, H_f makes C_AA well conditioned, and contact is
enforced exactly there (D = 0 in eq. (4); F >= 0, g >= 0, F g = 0 by the same active-set
iteration, as semi-analytic gear solvers do); the penalty factor then acts only on the line
pairs of the problem (the coast flanks). With a penalty D = H_f,kk / factor instead, the
1-GC level-0 moments moved 0.85 % from factor 10 to 10^4 and 0.09 % from 100 to 10^4 (the
line grid: 2.5 % and 0.26 %), converging like 1 / factor to this exact limit.

The body correction M = D_FE - H_d of a tooth pair is what bending, shear and the finite
body add to the half-space; observed a coarse width below P1 patch loads it carries the
FE's discretisation error, and its symmetric part can have negative eigenvalues (the P1
mesh stiffer than the half-space it should approach there). Then C_AA can be indefinite and
the active set cycles: 1-GB at level 2 (pinion-ring mesh: eigenvalues down to -1.5e-5 mm/N
against +6e-5; the iterates carried cell forces of -20 kN). Per tooth pair, M is replaced by

    M' = M - V min(Lambda, 0) V^T,        (M + M^T) / 2 = V Lambda V^T,                 (6)

(the nearest positive semidefinite symmetric part in the Frobenius norm, the skew part
kept: :func:`psd_projection`), so each tooth pair's block H_f + P M' P^T has a symmetric
part at least H_f's, positive definite. All coarse columns of a tooth pair are formed when
the first of its points is needed. The largest clipped eigenvalue over the largest kept one
is recorded (``timings["correction_clipped"]``): 0.36 on the steel roller, 0.06 / 0.25 on
1-GB at levels 0 / 2; the clip moves 1-GB's My_pin by 1e-5 (level 0) and 3e-5 (level 1).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import dolfinx_solver  # noqa: F401 - orders MPI ahead of the bindings

# isort: split
import numpy as np
from mpi4py import MPI
from petsc4py import PETSc

from solvers.body_columns import body_columns, node_keys
from solvers.contact_grid import ContactGrid, ZoneLink
from solvers.elastic_body import ElasticBody
from solvers.errors import (
    ActiveSetError,
    NoContactError,
    PenaltyConditioningError,
    RigidUnknownError,
)
from solvers.gap_operator import gap_matrix
from solvers.halfspace import influence_matrix, subsurface_matrix
from solvers.rigid_coupling import rigid_modes

#: the penalty is refused when max(eps w) * ||C||_inf exceeds this (cond(C + D) bound)
MAX_PENALTY_CONDITION = 1e12


def psd_projection(M: np.ndarray) -> tuple[np.ndarray, float]:
    """``(M', ratio)``: M with the negative eigenvalues of its symmetric part S = (M + M^T)/2
    set to zero, M' = M - V min(Lambda, 0) V^T (S = V Lambda V^T; the skew part is kept, and
    S' is the nearest positive semidefinite matrix to S in the Frobenius norm, Higham 1988),
    and ``ratio`` = the largest clipped |eigenvalue| over the largest eigenvalue (0 if none)."""
    S = 0.5 * (M + M.T)
    w, V = np.linalg.eigh(S)
    neg = np.minimum(w, 0.0)
    if not neg.any():
        return M, 0.0
    return M - (V * neg) @ V.T, float(-neg.min() / max(w.max(), 1e-300))


@dataclass(frozen=True)
class ContactPair:
    """A flank pair: grid + the two bodies (FE body or rigid obstacle names). ``standby``:
    open when the solve starts (coast flanks, open by the backlash): the active set starts
    with only its penetrating points and it takes load where it closes. ``link``: a zone
    grid's coupling to the FE (coarse FE points + half-space near field, eq. (5)); None: every
    grid point is an FE point."""

    grid: ContactGrid
    body_a: str
    body_b: str
    standby: bool = False
    link: ZoneLink | None = None


@dataclass(frozen=True)
class RigidUnknown:
    """A rigid motion solved as an explicit scalar, balanced by contact, eq. (3).

    On an FE body: ``coupling`` and ``dof`` name the reference DOF that is held in the FE
    system; the superposed field is that DOF's rigid mode about the coupling's x_ref.
    On a rigid obstacle: ``x_ref`` and ``direction`` (translation) or ``axis`` (rotation).
    ``load`` is the generalized force (N or N mm) on the mode; ``prescribed`` fixes r instead
    (displacement control, no balance equation). ``axes``: rows a_j of the frame the FE
    body's mode is taken in, scene frame (default: the coupling's axes, placed with the body).
    """

    name: str
    body: str
    coupling: str | None = None
    dof: int | None = None
    x_ref: Sequence[float] | None = None
    direction: Sequence[float] | None = None
    axis: Sequence[float] | None = None
    load: float = 0.0
    prescribed: float | None = None
    axes: Sequence[Sequence[float]] | None = None


@dataclass(frozen=True)
class Spring:
    """A linear spring between two rigid unknowns (``b`` None: to ground), stiffness ``k``
    (N/mm or N mm/rad) and rest offset ``offset`` (mm or rad): energy
    k (r_a - r_b - offset)^2 / 2."""

    a: str
    b: str | None
    k: float
    offset: float = 0.0

    def __post_init__(self):
        if not (self.k >= 0 and np.isfinite(self.k)):
            raise ValueError(f"spring {self.a}-{self.b}: k = {self.k!r} must be finite, >= 0")
        if not np.isfinite(self.offset):
            raise ValueError(f"spring {self.a}-{self.b}: offset {self.offset!r} must be finite")


@dataclass(frozen=True, eq=False)
class StiffnessBlock:
    """A symmetric stiffness matrix ``K`` acting on the rigid unknowns ``names`` (the
    condensed stiffness of an elastic body at its reference points, e.g. a carrier at its
    pins; :mod:`solvers.superelement`)."""

    names: tuple[str, ...]
    K: np.ndarray

    def __post_init__(self):
        k = np.asarray(self.K, dtype=float)
        if k.shape != (len(self.names), len(self.names)) or not np.all(np.isfinite(k)):
            raise ValueError(f"stiffness block on {self.names}: K must be finite and square")


@dataclass
class ContactResult:
    """Everything the contact solve produced (arrays replicated on every rank)."""

    forces: np.ndarray  # F_k (N)
    gaps: np.ndarray  # g_k after deformation (mm), eq. (1)
    active: np.ndarray  # bool
    rigid: dict[str, float]  # r_j
    history: list[dict]
    pairs: list[tuple[str, slice]]  # grid name -> rows
    penalty: np.ndarray  # eps_k (N/mm^3)
    displacements: dict[str, PETSc.Vec]  # full displacement per FE body (rigid part included)
    reduced: dict[str, PETSc.Vec]
    timings: dict[str, float] = field(default_factory=dict)

    def pressure(self, problem: ContactProblem) -> np.ndarray:
        return self.forces / problem.weights


class ContactProblem:
    """Bodies + flank pairs + rigid unknowns; see the module docstring for the equations.

    Args:
        bodies: the FE bodies (set up here if not yet).
        pairs: flank pairs.
        rigid_unknowns: explicit rigid motions with their balance equations.
        springs: springs between rigid unknowns or to ground (K_r, f_d of eq. (3)).
        blocks: stiffness matrices on groups of rigid unknowns (added to K_r).
        obstacles: names of rigid, FE-free counterparts (fixed unless a rigid unknown moves them).
        penalty_factor: eps = penalty_factor * E* / h.
        block_size: right-hand sides per MUMPS multi-RHS solve when forming C.
        eager: form every column of C up front (default: only the columns of points that
            become active, which is all the active-set loop and the gaps ever use).
    """

    def __init__(
        self,
        bodies: Sequence[ElasticBody],
        pairs: Sequence[ContactPair],
        rigid_unknowns: Sequence[RigidUnknown] = (),
        springs: Sequence[Spring] = (),
        *,
        penalty_factor: float,
        obstacles: Sequence[str] = (),
        blocks: Sequence[StiffnessBlock] = (),
        block_size: int | None = None,
        eager: bool = False,
    ):
        self.bodies = {b.name: b for b in bodies}
        self.comm: MPI.Comm = bodies[0].comm
        self.pairs = list(pairs)
        self.rigid_unknowns = list(rigid_unknowns)
        self.springs = list(springs)
        self.blocks = list(blocks)
        self._rigid_stiffness()  # checks the names now
        self.obstacles = set(obstacles)
        self.penalty_factor = float(penalty_factor)
        self.block_size = block_size
        self.eager = eager
        for p in self.pairs:
            for nm in (p.body_a, p.body_b):
                if nm not in self.bodies and nm not in self.obstacles:
                    raise KeyError(f"pair '{p.grid.name}': unknown body or obstacle '{nm}'")
        self.gdim = bodies[0].gdim
        self.offsets = np.cumsum([0] + [p.grid.n for p in self.pairs])
        self.n = int(self.offsets[-1])
        # FE points (eq. (5)): a zone pair's coarse grid, a line pair's own points
        self.zoned = any(p.link is not None for p in self.pairs)
        self.coarse_offsets = np.cumsum(
            [0] + [p.grid.n if p.link is None else p.link.coarse.n for p in self.pairs]
        )
        self.n_fe = int(self.coarse_offsets[-1])
        # zone points: exact contact (no penalty, D = 0 in eq. (4)), see eq. (5)
        self.exact = np.concatenate([np.full(p.grid.n, p.link is not None) for p in self.pairs])
        self.parent = np.concatenate(
            [
                (np.arange(p.grid.n) if p.link is None else np.asarray(p.link.parent, int))
                + self.coarse_offsets[i]
                for i, p in enumerate(self.pairs)
            ]
        )
        self.weights = np.concatenate([np.asarray(p.grid.weights, float) for p in self.pairs])
        self.gap0 = np.concatenate([np.asarray(p.grid.gap0, float) for p in self.pairs])
        self.timings: dict[str, float] = {}
        self._prepared = False

    def _rigid_stiffness(self) -> tuple[np.ndarray, np.ndarray]:
        """K_r and f_d of eq. (3) from the springs and stiffness blocks (checked by name)."""
        index = {ru.name: j for j, ru in enumerate(self.rigid_unknowns)}
        K_r = np.zeros((len(index), len(index)))
        f_d = np.zeros(len(index))
        for s in self.springs:
            for nm in (s.a, s.b):
                if nm is not None and nm not in index:
                    raise KeyError(f"spring {s.a}-{s.b}: no rigid unknown '{nm}'")
            i = index[s.a]
            K_r[i, i] += s.k
            f_d[i] += s.k * s.offset
            if s.b is not None:
                j = index[s.b]
                K_r[j, j] += s.k
                K_r[i, j] -= s.k
                K_r[j, i] -= s.k
                f_d[j] -= s.k * s.offset
        for blk in self.blocks:
            missing = [nm for nm in blk.names if nm not in index]
            if missing:
                raise KeyError(f"stiffness block: no rigid unknown(s) {missing}")
            ids = [index[nm] for nm in blk.names]
            K_r[np.ix_(ids, ids)] += np.asarray(blk.K, dtype=float)
        return K_r, f_d

    # ------------------------------------------------------------------ building blocks
    def _blocks(self, name: str, fe: bool = False, grids=None):
        """(row offset, grid, side) of the grids touching body ``name``: the contact grids,
        or (``fe``) the FE points of eq. (5) (a zone pair's coarse grid, or ``grids``)."""
        out = []
        offsets = self.coarse_offsets if fe else self.offsets
        for i, p in enumerate(self.pairs):
            grid = p.link.coarse if fe and p.link is not None else p.grid
            if grids is not None:
                grid = grids[i]
            if p.body_a == name:
                out.append((int(offsets[i]), grid, "a"))
            if p.body_b == name:
                out.append((int(offsets[i]), grid, "b"))
        return out

    def _near_field(self) -> list[dict]:
        """The tooth pairs (groups) of the zone pairs, each a dict: ``fine`` (global rows),
        ``coarse`` (global FE points), ``loc`` (each fine point's position in ``coarse``),
        ``h_f`` (the fine half-space block H_f of eq. (5)) and ``h_d`` (the half-space
        approach at the matching depths, coarse, both bodies)."""
        out = []
        for i, p in enumerate(self.pairs):
            lk = p.link
            if lk is None:
                continue
            e_star = float(self.estar[self.offsets[i]])
            par = np.asarray(lk.parent, int)
            sides = [
                (self.bodies[nm].material, d)
                for nm, d in ((p.body_a, lk.depth_a), (p.body_b, lk.depth_b))
                if nm in self.bodies
            ]
            for grp in np.unique(lk.group):
                f = np.flatnonzero(lk.group == grp)
                c = np.flatnonzero(lk.group_coarse == grp)
                uv, hc = lk.plane_coarse[c], lk.half_coarse[c]
                out.append(
                    {
                        "fine": f + int(self.offsets[i]),
                        "coarse": c + int(self.coarse_offsets[i]),
                        "loc": np.searchsorted(c, par[f]),
                        "h_f": influence_matrix(lk.plane[f], lk.half[f], e_star),
                        "h_d": sum(
                            subsurface_matrix(uv, d[c], uv, hc, m.E, m.nu) for m, d in sides
                        ),
                        "correction": None,
                    }
                )
        return out

    def _body_correction(self, grp: dict) -> np.ndarray:
        """The body correction D_FE - H_d of eq. (5) on one tooth pair's coarse points, its
        symmetric part projected onto the positive semidefinite matrices (eq. (6)); keeps
        the largest clipped ratio in ``timings["correction_clipped"]``."""
        c = grp["coarse"]
        raw = self.C_depth[np.ix_(c, c)] - grp["h_d"]
        M, ratio = psd_projection(raw)
        self.timings["correction_clipped"] = max(self.timings["correction_clipped"], ratio)
        grp["clip"] = M - raw if ratio > 0.0 else None  # what eq. (6) added, for clip_effect
        return M

    def _kind(self, ru: RigidUnknown) -> str:
        """ "translation" or "rotation": what a rigid unknown moves (its unit)."""
        if ru.body in self.bodies:
            return "rotation" if ru.dof >= self.gdim else "translation"
        return "rotation" if ru.axis is not None else "translation"

    def _clip_effect(self, idx, free, M, rhs, F, r) -> tuple[float, float]:
        """What the projection of eq. (6) moved in this solve, to first order: the saddle
        system of the converged active set ``idx`` (matrix ``M``, right-hand side ``rhs``)
        solved again with each tooth pair's correction as the FE gave it (the clip taken
        back out of its active block). Returns ``(effect, redistribution)``: ``effect`` the
        larger of the change of each pair's resultant force over the largest pair's (the
        load shares) and the relative change of the free rigid unknowns, max_j |dr_j| /
        max_k |r_k| over the unknowns of the same body and kind (translation or rotation: a
        bearing moment is a tilt times a stiffness, a centroid follows the moments);
        ``redistribution`` the change of the cell forces, ||dF||_1 / ||F||_1, which also holds
        their shift between neighbouring cells.
        (0, 0) where nothing was clipped; inf where the unclipped system is singular. The
        active set is kept, so a clip that would change which cells touch is seen only
        through the forces it moves."""
        nA = len(idx)
        dM = np.zeros_like(M)
        pos = np.full(self.n, -1)
        pos[idx] = np.arange(nA)
        for g in getattr(self, "near", []):
            if g.get("clip") is None:
                continue
            f = g["fine"]
            on = pos[f] >= 0
            if on.any():
                li = g["loc"][on]
                dM[np.ix_(pos[f[on]], pos[f[on]])] = g["clip"][np.ix_(li, li)]
        if not dM.any():
            return 0.0, 0.0
        out = (0.0, 0.0)
        if self.comm.rank == 0:
            try:
                sol = np.linalg.solve(M - dM, rhs)
            except np.linalg.LinAlgError:
                sol = None
            if sol is None or not np.all(np.isfinite(sol)):
                out = (float("inf"), float("inf"))
            else:
                F_u = np.zeros(self.n)
                F_u[idx] = sol[:nA]
                sl = [slice(self.offsets[i], self.offsets[i + 1]) for i in range(len(self.pairs))]
                totals = np.array([F[s].sum() for s in sl])
                shifts = np.array([abs(F_u[s].sum() - F[s].sum()) for s in sl])
                # against the largest pair's load: a lightly loaded coast pair's own share
                # would read a tiny shift as a large one
                moved = float(shifts.max() / max(totals.max(), 1e-300))
                for j, v in zip(free, sol[nA:], strict=True):
                    ru = self.rigid_unknowns[j]
                    scale = max(
                        abs(r[k])
                        for k in free
                        if self.rigid_unknowns[k].body == ru.body
                        and self._kind(self.rigid_unknowns[k]) == self._kind(ru)
                    )
                    moved = max(moved, abs(v - r[j]) / max(scale, 1e-300))
                spread = np.abs(F_u - F).sum() / max(np.abs(F).sum(), 1e-300)
                out = (float(moved), float(spread))
        return self.comm.bcast(out, root=0)

    def _depth_grids(self):
        """Per pair, the grid whose rows observe the FE at the matching depths of eq. (5)
        (point rows x_a - d_a n, x_b + d_b n of a zone pair's coarse points; a line pair's
        own points, unused)."""
        out = []
        for p in self.pairs:
            lk = p.link
            if lk is None:
                out.append(p.grid)
                continue
            c = lk.coarse
            nrm = np.asarray(c.normals, float)
            x_a = np.asarray(c.x_a) - lk.depth_a[:, None] * nrm
            x_b = np.asarray(c.x_b) + lk.depth_b[:, None] * nrm
            out.append(ContactGrid(f"{c.name}#depth", x_a, x_b, nrm, np.zeros(c.n), np.ones(c.n)))
        return out

    def _mode(self, ru: RigidUnknown):
        """(x_ref, function x -> psi(x) (m, gdim)) of a rigid unknown."""
        gdim = self.gdim
        if ru.body in self.bodies:
            b = self.bodies[ru.body]
            c = b.couplings[ru.coupling]
            x_ref = b.to_scene(np.asarray(c.x_ref, float)[:gdim])
            axes = c.frame(gdim) @ b.rotation.T if ru.axes is None else np.asarray(ru.axes)
            j = ru.dof

            def psi(x):
                return rigid_modes(x, x_ref, axes)[:, :, j]

            return x_ref, psi
        x_ref = np.asarray(ru.x_ref if ru.x_ref is not None else np.zeros(gdim), float)[:gdim]
        if ru.direction is not None:
            d = np.asarray(ru.direction, float)[:gdim]

            def psi(x):
                return np.broadcast_to(d, (len(x), gdim)).copy()

            return x_ref, psi
        a = np.asarray(ru.axis if ru.axis is not None else (0, 0, 1), float)

        def psi(x):
            dx = np.zeros((len(x), 3))
            dx[:, :gdim] = x - x_ref
            return np.cross(a[None, :], dx)[:, :gdim]

        return x_ref, psi

    def _prepare(self) -> None:
        """Set up bodies, gap operators, no-contact gaps and the compliance C (once)."""
        if self._prepared:
            return
        comm = self.comm
        t0 = MPI.Wtime()
        for ru in self.rigid_unknowns:
            if ru.body in self.bodies:
                b = self.bodies[ru.body]
                if not b.ready:
                    b.hold(ru.coupling, ru.dof)
                elif (ru.coupling, ru.dof) not in b.held:  # a body kept from another problem
                    raise ValueError(
                        f"rigid unknown '{ru.name}': body '{ru.body}' was factorized without "
                        f"DOF {ru.dof} of '{ru.coupling}' held"
                    )
            elif ru.body not in self.obstacles:
                raise KeyError(f"rigid unknown '{ru.name}': unknown body '{ru.body}'")
        for b in self.bodies.values():
            b.setup()
        t1 = MPI.Wtime()
        self.G: dict[str, PETSc.Mat] = {}
        self.G_fe: dict[str, PETSc.Mat] = {}
        self.G_depth: dict[str, PETSc.Mat] = {}
        depth = self._depth_grids() if self.zoned else None
        h = np.zeros(self.n)
        for name, b in self.bodies.items():
            blocks = self._blocks(name)
            if blocks:
                self.G[name], hb = gap_matrix(b, blocks, self.n)
                h = np.where(hb > 0, np.where(h > 0, np.minimum(h, hb), hb), h)
                self.G_fe[name] = self.G[name]
                if self.zoned:
                    self.G_fe[name] = gap_matrix(b, self._blocks(name, fe=True), self.n_fe)[0]
                    self.G_depth[name] = gap_matrix(
                        b, self._blocks(name, fe=True, grids=depth), self.n_fe
                    )[0]
        self.h = h
        t2 = MPI.Wtime()
        # contact modulus per point and penalty
        estar = np.zeros(self.n)
        for i, p in enumerate(self.pairs):
            comp = 0.0
            for nm in (p.body_a, p.body_b):
                if nm in self.bodies:
                    comp += 1.0 / self.bodies[nm].material.e_plane
            estar[self.offsets[i] : self.offsets[i + 1]] = 1.0 / comp
        self.estar = estar
        # no-contact solution and gaps
        self.u_f = {n: b.solve(b.f_red) for n, b in self.bodies.items()}
        self.g_f = np.zeros(self.n)
        for n, G in self.G.items():
            self.g_f += self._gather(G, self.u_f[n])
        # rigid columns
        nr = len(self.rigid_unknowns)
        self.R = np.zeros((self.n, nr))
        for j, ru in enumerate(self.rigid_unknowns):
            _, psi = self._mode(ru)
            for i, p in enumerate(self.pairs):
                sl = slice(self.offsets[i], self.offsets[i + 1])
                nrm = np.asarray(p.grid.normals, float)
                if p.body_b == ru.body:
                    self.R[sl, j] += np.einsum("kc,kc->k", nrm, psi(np.asarray(p.grid.x_b)))
                if p.body_a == ru.body:
                    self.R[sl, j] -= np.einsum("kc,kc->k", nrm, psi(np.asarray(p.grid.x_a)))
        t3 = MPI.Wtime()
        # compliance columns are formed on demand (only for points that ever become active)
        self.C = np.zeros((self.n, self.n))
        self.have = np.zeros(self.n, dtype=bool)
        self.C_fe = np.zeros((self.n_fe, self.n_fe)) if self.zoned else self.C
        self.C_depth = np.zeros((self.n_fe, self.n_fe)) if self.zoned else None
        self.have_fe = np.zeros(self.n_fe, dtype=bool)
        self.near = self._near_field()
        self.body_rows = {
            n: np.unique(
                np.concatenate([np.arange(o, o + g.n) for o, g, _ in self._blocks(n, fe=True)])
            )
            for n in self.G
        }
        self.row_keys = {n: self._row_keys(n, depth) for n in self.G}
        self.timings.update(
            setup_bodies=t1 - t0, gap_operator=t2 - t1, free_solve=t3 - t2, compliance=0.0
        )
        self.timings["compliance_columns"] = 0
        self.timings["compliance_solves"] = 0  # a body's FE columns solved
        self.timings["compliance_columns_kept"] = 0  # and read from its kept columns
        self.timings["correction_clipped"] = 0.0
        if self.eager:
            self.ensure_columns(np.arange(self.n))
        self.timings["factorize"] = sum(b.timings["factorize"] for b in self.bodies.values())
        self._prepared = True
        comm.Barrier()

    def _row_keys(self, name: str, depth) -> list[bytes]:
        """The body-frame keys (:func:`solvers.body_columns.node_keys`) of body ``name``'s FE
        rows, in the order of ``body_rows[name]``: each row's spreading points, weights
        (signed by side) and normal, and its depth row's point where the problem has one."""
        b = self.bodies[name]
        keys = {}
        depth_blocks = self._blocks(name, fe=True, grids=depth) if self.zoned else None
        for i, (offset, grid, side) in enumerate(self._blocks(name, fe=True)):
            sign = 1.0 if side == "b" else -1.0
            pts, _, wq = grid.spread_points(side)
            n, gd = grid.n, grid.gdim
            spread = b.to_body(pts).reshape(-1, n, gd).transpose(1, 0, 2)
            weights = sign * wq.reshape(-1, n).T
            normal = np.asarray(grid.normals, float) @ b.rotation
            dep = None
            if depth_blocks is not None:
                dep = b.to_body(np.asarray(getattr(depth_blocks[i][1], "x_" + side), float))
            for k, key in enumerate(node_keys(spread, weights, normal, dep)):
                keys[offset + k] = key
        return [keys[int(r)] for r in self.body_rows[name]]

    def _body_entries(self, name: str, G: PETSc.Mat, cols: np.ndarray):
        """Body ``name``'s share of the FE columns ``cols``: (G K^{-1} G^T [:, cols],
        G_depth K^{-1} G^T [:, cols] or None), read from the body's kept columns
        (:mod:`solvers.body_columns`), the rest solved (:meth:`_compliance`, with the body's
        own factors) and kept.

        A kept column that lacks entries at a few rows new to it (a row another problem
        did not have: a section kept here and not there) is completed from the new rows'
        own columns, S[n, j] = S[j, n] (K symmetric), and for the depth entries from the
        depth rows' columns, D[n, j] = d_n^T K^{-1} g_j = (G K^{-1} G_depth^T)[j, n]; where
        more rows than columns are missing, the columns are solved instead."""
        body = self.bodies[name]
        base = getattr(body, "_body", body)  # a modulus view: its solves are the body's / s
        scale = float(getattr(body, "scale", 1.0))
        store = body_columns(body)
        rows = self.body_rows[name]
        nodes = store.nodes(self.row_keys[name])
        pos = np.searchsorted(rows, cols)
        cn = nodes[pos]
        G_obs = self.G_depth.get(name)
        held, missing = store.coverage(nodes, cn)
        partial = held & missing.any(axis=0)
        new = np.flatnonzero(missing[:, partial].any(axis=1))  # rows to complete them at
        solves = 0
        if partial.any() and len(new) <= 0.5 * partial.sum():
            s_n, d_n = self._compliance(base, G, rows[new], G_obs)
            a_n = None if G_obs is None else self._compliance(base, G_obs, rows[new], G)[1]
            solves += len(new) * (1 if G_obs is None else 2)
            for i in np.flatnonzero(partial):
                lack = missing[new, i]
                at = new[lack]
                store.extend(
                    cn[i],
                    nodes[at],
                    s_n[rows[pos[i]], lack],
                    None if a_n is None else a_n[rows[pos[i]], lack],
                )
            store.write(nodes, nodes[new], s_n[rows], None if d_n is None else d_n[rows])
        known = store.known_columns(nodes, cn)
        S = np.empty((len(rows), len(cols)))
        D = np.empty((len(rows), len(cols)))
        if known.any():
            S[:, known], D[:, known] = store.read(nodes, cn[known])
        if not known.all():
            miss = ~known
            s_new, d_new = self._compliance(base, G, cols[miss], G_obs)
            S[:, miss] = s_new[rows]
            D[:, miss] = 0.0 if d_new is None else d_new[rows]
            store.write(nodes, cn[miss], S[:, miss], None if d_new is None else D[:, miss])
            solves += int(miss.sum())
        store.trim(keep=len(cols))
        self.timings["compliance_solves"] += solves
        self.timings["compliance_columns_kept"] += int(known.sum())
        surf = np.zeros((self.n_fe, len(cols)))
        surf[rows] = S if scale == 1.0 else S / scale
        dep = None
        if G_obs is not None:
            dep = np.zeros((self.n_fe, len(cols)))
            dep[rows] = D if scale == 1.0 else D / scale
        return surf, dep

    def _gather(self, G: PETSc.Mat, x: PETSc.Vec) -> np.ndarray:
        """y = G x gathered on every rank."""
        y = G.createVecLeft()
        G.mult(x, y)
        return np.concatenate(self.comm.allgather(y.getArray(readonly=True).copy()))

    def ensure_columns(self, cols: np.ndarray) -> None:
        """Form the compliance columns C[:, j] = sum_b G_b K_b^{-1} G_b^T e_j not yet formed.

        Collective. Each body's share is one MUMPS multi-RHS solve per block of
        ``block_size`` columns with the body's single factorization; no refactorization.
        """
        cols = np.asarray(cols, dtype=np.int64)
        new = np.unique(cols[~self.have[cols]])
        if len(new) == 0:
            return
        fe = self.parent[new]
        touched = []
        if self.zoned:  # a tooth pair's body correction needs all of its coarse columns
            touched = [g for g in self.near if np.isin(g["fine"], new, assume_unique=True).any()]
            fe = np.concatenate([fe] + [g["coarse"] for g in touched])
        fe = np.unique(fe)
        fe = fe[~self.have_fe[fe]]
        t0 = MPI.Wtime()
        for name, G in self.G_fe.items():
            mine = np.intersect1d(fe, self.body_rows[name])
            if len(mine):
                surf, dep = self._body_entries(name, G, mine)
                self.C_fe[:, mine] += surf
                if dep is not None:
                    self.C_depth[:, mine] += dep
        self.have_fe[fe] = True
        self.timings["compliance"] += MPI.Wtime() - t0
        self.timings["compliance_columns"] += len(fe)
        if self.zoned:  # eq. (5): FE far field by parent, near field within a tooth pair
            par = self.parent
            self.C[:, new] = self.C_fe[np.ix_(par, par[new])]
            for g in touched:
                if g["correction"] is None:
                    g["correction"] = self._body_correction(g)
                f = g["fine"]
                j = np.flatnonzero(np.isin(f, new, assume_unique=True))
                li, lj = g["loc"], g["loc"][j]
                self.C[np.ix_(f, f[j])] += (
                    g["correction"][np.ix_(li, lj)]
                    - self.C_fe[np.ix_(par[f], par[f[j]])]
                    + g["h_f"][:, j]
                )
        self.have[new] = True

    def _compliance(self, body: ElasticBody, G: PETSc.Mat, cols: np.ndarray, G_obs=None):
        """(G K^{-1} G^T [:, cols], G_obs K^{-1} G^T [:, cols] or None), replicated, by
        blocks of multi-RHS solves (one solve serves both row operators)."""
        comm = self.comm
        n_rows = G.getSize()[0]
        N_red = body.K_red.getSize()[0]
        # right-hand sides per block: B and X dense N x mb, ~200 MB each at most
        mb = self.block_size or int(np.clip(2e8 / (8 * max(N_red, 1)), 32, 512))
        Gt = G.transpose(PETSc.Mat())  # out of place (G.transpose() would overwrite G)
        r0, r1 = Gt.getOwnershipRange()
        isrow = PETSc.IS().createStride(r1 - r0, first=r0, step=1, comm=comm)
        out = np.zeros((n_rows, len(cols)))
        obs = None if G_obs is None else np.zeros((G_obs.getSize()[0], len(cols)))
        for s in range(0, len(cols), mb):
            blk = cols[s : s + mb]
            mine = np.array_split(blk, comm.size)[comm.rank].astype(PETSc.IntType)
            iscol = PETSc.IS().createGeneral(mine, comm=comm)
            B = Gt.createSubMatrix(isrow, iscol).convert(PETSc.Mat.Type.DENSE)
            X = body.solve_dense(B)
            Y = G.matMult(X)  # (n x len(blk)) dense, rows distributed
            Yl = Y.getDenseArray(readonly=True).copy()
            out[:, s : s + len(blk)] = np.vstack(comm.allgather(Yl))
            if G_obs is not None:
                Yo = G_obs.matMult(X)
                obs[:, s : s + len(blk)] = np.vstack(
                    comm.allgather(Yo.getDenseArray(readonly=True).copy())
                )
                Yo.destroy()
            for m in (B, X, Y, iscol):
                m.destroy()
        Gt.destroy()
        isrow.destroy()
        return out, obs

    # ------------------------------------------------------------------ solve
    def _diag_estimate(self) -> np.ndarray:
        """Rough self-compliance per point, 1 / (E* h), to pick the stiffest point."""
        return 1.0 / (self.estar * self.h)

    def _initial_active(self, g_base: np.ndarray, rigid_free: bool) -> np.ndarray:
        """Starting active set.

        Displacement control: the points already penetrating without contact forces (empty:
        the open gaps are then the exact answer). Force control (free rigid unknowns): per
        pair, the points whose no-contact gap is within 10 % of the pair's gap range of its
        smallest gap, i.e. around where the flanks are closest; the iteration grows or
        shrinks it from there, and only those points' compliance columns get formed. A
        ``standby`` pair (coast flanks, open by the backlash) starts with only its points
        that penetrate: forcing an open pair shut in the first iterate can empty the set.
        """
        if not rigid_free:
            return g_base < 0
        A = np.zeros(self.n, dtype=bool)
        for i, pair in enumerate(self.pairs):
            if pair.standby:
                continue  # open at the start (coast flanks): only its closed points, below
            sl = slice(self.offsets[i], self.offsets[i + 1])
            g = g_base[sl]
            A[sl] = g <= g.min() + 0.1 * (g.max() - g.min())
        return A | (g_base < 0)

    def penalty(self, factor: float | None = None) -> np.ndarray:
        """eps_k = factor * E*_k / h_k (N/mm^3); inf at a zone point (exact contact)."""
        f = self.penalty_factor if factor is None else factor
        return np.where(self.exact, np.inf, f * self.estar / np.where(self.h > 0, self.h, 1.0))

    def solve(
        self,
        penalty_factor: float | None = None,
        loads: dict[str, float] | None = None,
        prescribed: dict[str, float] | None = None,
        max_iter: int = 60,
    ) -> ContactResult:
        """Solve the contact problem; C is formed once and reused for every call.

        ``loads`` / ``prescribed`` override the rigid unknowns' generalized loads or
        prescribed values by name (a load sweep at no refactorization cost).
        """
        self._prepare()
        t0 = MPI.Wtime()
        comp0 = self.timings["compliance"]
        loads = loads or {}
        prescribed = prescribed or {}
        eps = self.penalty(penalty_factor)
        kpen = np.where(self.exact, 0.0, eps * self.weights)  # N/mm per penalty point
        D = np.where(self.exact, 0.0, 1.0 / np.where(self.exact, 1.0, kpen))
        # cheap bound of cond(C_AA + D): lambda_min >= min D, lambda_max <= ||C|| + max D; the
        # column of the stiffest-penalty point with the largest compliance bounds ||C||
        k0 = int(np.argmax(kpen * self._diag_estimate()))
        cnorm = 0.0
        if kpen[k0] > 0:
            self.ensure_columns(np.array([k0]))
            cnorm = np.abs(self.C[:, k0]).sum()
        if kpen.max() * cnorm > MAX_PENALTY_CONDITION:
            raise PenaltyConditioningError(
                f"penalty factor {penalty_factor or self.penalty_factor:.3g} makes the contact "
                f"system ill-conditioned: max(eps w) * ||C|| = {kpen.max() * cnorm:.3g} > "
                f"{MAX_PENALTY_CONDITION:.0e} (the penalty layer is that many times stiffer "
                f"than the bodies); use a factor 10-1000",
                partial={"penalty": eps},
            )
        nr = len(self.rigid_unknowns)
        pres = np.array(
            [
                prescribed.get(ru.name, ru.prescribed)
                if prescribed.get(ru.name, ru.prescribed) is not None
                else np.nan
                for ru in self.rigid_unknowns
            ]
        )
        is_pres = ~np.isnan(pres)
        free = np.flatnonzero(~is_pres)
        K_r, f_d = self._rigid_stiffness()
        f_r = np.array([loads.get(ru.name, ru.load) for ru in self.rigid_unknowns]) + f_d
        g_base = self.gap0 + self.g_f + (self.R[:, is_pres] @ pres[is_pres] if nr else 0.0)
        A = self._initial_active(g_base, len(free) > 0)
        history: list[dict] = []
        seen = set()
        F = np.zeros(self.n)
        r = np.where(is_pres, pres, 0.0)
        for it in range(max_iter):
            idx = np.flatnonzero(A)
            nA, nf = len(idx), len(free)
            self.ensure_columns(idx)
            M = np.zeros((nA + nf, nA + nf))
            M[:nA, :nA] = self.C[np.ix_(idx, idx)] + np.diag(D[idx])
            Rf = self.R[np.ix_(idx, free)]
            M[:nA, nA:] = Rf
            M[nA:, :nA] = Rf.T
            M[nA:, nA:] = -K_r[np.ix_(free, free)]
            f_springs = K_r[np.ix_(free, np.flatnonzero(is_pres))] @ pres[is_pres]
            rhs = np.concatenate([-g_base[idx], -f_r[free] + f_springs])
            # the small dense system is solved on rank 0 and broadcast: every rank then holds
            # bitwise the same iterate and takes the same active-set decisions
            sol, ok = None, True
            if self.comm.rank == 0:
                try:
                    sol = np.linalg.solve(M, rhs) if len(rhs) else np.zeros(0)
                    ok = bool(np.all(np.isfinite(sol)))
                except np.linalg.LinAlgError:
                    ok = False
                if nf and nA:
                    # a rigid unknown that neither an active point nor a spring restrains is
                    # undetermined (springs scaled to the contact columns' units)
                    Kf = K_r[np.ix_(free, free)]
                    sc = max(np.abs(Rf).max(), 1e-300) / max(np.abs(Kf).max(), 1e-300)
                    sv = np.linalg.svd(np.vstack([Rf, sc * Kf]), compute_uv=False)
                    ok = ok and sv.min() > 1e-12 * max(sv.max(), 1e-300)
            sol, ok = self.comm.bcast((sol, ok), root=0)
            if not ok or (nf and nA == 0):
                undetermined = [
                    self.rigid_unknowns[j].name
                    for j in free
                    if nA == 0 or np.all(np.abs(self.R[idx, j]) < 1e-14)
                ] or [self.rigid_unknowns[j].name for j in free]
                raise RigidUnknownError(
                    f"rigid unknown(s) {undetermined} not determined at active-set iteration "
                    f"{it}: {nA} active point(s) do not restrain them (flanks not touching "
                    f"this body, or a mode that contact cannot balance)",
                    partial={"history": history, "forces": F, "rigid": r},
                )
            F = np.zeros(self.n)
            F[idx] = sol[:nA]
            r = np.where(is_pres, pres, 0.0)
            r[free] = sol[nA:]
            g = self.gap0 + self.g_f + self.C[:, idx] @ F[idx] + self.R @ r
            # penalty points: active where penetrating (F = -g / D); exact (zone) points have
            # g = 0 on the active set, so they stay while F > 0 and join where g < 0
            A_new = np.where(self.exact, np.where(A, F > 0, g < 0), g < 0)
            key = A_new.tobytes()
            history.append(
                {
                    "iteration": it,
                    "active": int(nA),
                    "added": int(np.sum(A_new & ~A)),
                    "removed": int(np.sum(A & ~A_new)),
                    "min_gap": float(g.min()),
                    "total_force": float(F.sum()),
                    "min_force": float(F[idx].min()) if nA else 0.0,
                }
            )
            if np.array_equal(A_new, A):
                break
            if key in seen:
                raise ActiveSetError(
                    f"contact active set cycles at iteration {it} "
                    f"(active counts {[h['active'] for h in history]})",
                    partial={"history": history, "forces": F, "rigid": r},
                )
            seen.add(A.tobytes())
            A = A_new
            if not np.any(A) and nf == 0:
                break
        else:
            raise ActiveSetError(
                f"contact active set did not converge in {max_iter} iterations "
                f"(active counts {[h['active'] for h in history]})",
                partial={"history": history, "forces": F, "rigid": r},
            )
        if not np.any(A):
            F = np.zeros(self.n)
            g = self.gap0 + self.g_f + self.R @ r  # the open gaps, without the last iterate
            k = int(np.argmin(g))
            pair = self.pairs[int(np.searchsorted(self.offsets, k, side="right") - 1)]
            raise NoContactError(
                f"no contact: every grid point stays open under this load (smallest gap "
                f"{g[k]:.4g} mm on pair '{pair.grid.name}'); the flanks do not touch",
                partial={"history": history, "gaps": g},
            )
        effect, spread = self._clip_effect(idx, free, M, rhs, F, r)
        t1 = MPI.Wtime()
        disp, red = {}, {}
        for name, b in self.bodies.items():
            rhs = b.f_red.copy()
            if name in self.G:
                Fv = self.G[name].createVecLeft()
                lo, hi = Fv.getOwnershipRange()
                Fv.setArray(F[lo:hi])
                self.G[name].multTransposeAdd(Fv, b.f_red, rhs)
            x = b.solve(rhs)
            red[name] = x
            rig = np.zeros(b.n_own)
            xs = b.to_scene(b.dof_x[: b.n_own])
            for j, ru in enumerate(self.rigid_unknowns):
                if ru.body == name and r[j] != 0:
                    _, psi = self._mode(ru)
                    field = psi(xs) @ b.rotation  # scene-frame rigid field in the body frame
                    rig += r[j] * field[np.arange(b.n_own), b.dof_comp[: b.n_own]]
            disp[name] = b.expand(x, rig)
        t2 = MPI.Wtime()
        names = [p.grid.name for p in self.pairs]
        sl = [slice(self.offsets[i], self.offsets[i + 1]) for i in range(len(self.pairs))]
        timings = dict(self.timings)
        # the compliance columns formed during this solve are reported under "compliance"
        timings.update(
            active_set=t1 - t0 - (self.timings["compliance"] - comp0),
            final_solve=t2 - t1,
            iterations=len(history),
            correction_clip_effect=effect,
            correction_clip_redistribution=spread,
        )
        return ContactResult(
            forces=F,
            gaps=g,
            active=A,
            rigid={ru.name: float(r[j]) for j, ru in enumerate(self.rigid_unknowns)},
            history=history,
            pairs=list(zip(names, sl, strict=True)),
            penalty=eps,
            displacements=disp,
            reduced=red,
            timings=timings,
        )

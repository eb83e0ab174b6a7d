"""Root stress from a submodel of the loaded teeth, driven by the solved gear train.

The global model resolves the moments (within 0.5 % at level 1) but not the fillet stress:
its P1 surface value rises 3-8 % from level 1 to 2 and is not in the asymptotic range
(:mod:`solvers.root_stress`). The stress concentration of a root fillet is local (it decays
within about one fillet radius), so it is read on a separate, finer model of the teeth
around it (cut-boundary displacement submodelling):

    find u in V_h (P2 on the sector mesh) with u = u_G on Gamma_cut and
    int sigma(u) : eps(v) dx = sum_k F_k n_k . v(x_k)  for all v in V_h, v = 0 on Gamma_cut,

u_G the global displacement (rigid part included, in the gear's body frame), Gamma_cut the
sector's cut faces and its inner (outer) arc (:mod:`meshing.submodel`), F_k n_k the contact
forces of the solved grid acting on this gear at the spreading points x_k of their cells,
the same consistent loads as the global model's G^T F (:mod:`solvers.gap_operator`), on the
teeth inside the sector (the loads outside it reach the cut through u_G). The cut lies a
tooth space beyond the read teeth and 2.5 modules below the root circle, where u_G is smooth
and carries the global model's converged compliance; the read teeth see exactly the
global contact loads. The submodel adds nothing to the global solution (one-way).

The root stress is then read on the submodel's fillets as on the global model
(:func:`solvers.root_stress.body_root_stress`). One canonical sector per gear and loaded
side (:func:`meshing.submodel.submodel_body`), as many read teeth as its mesh's grid names
at most over the mesh cycle (``sector``; a position with fewer loaded teeth leaves the
last ones unread), serves every position: a position's sector is
the canonical one turned by :func:`meshing.submodel.sector_turn`, so the submodel's
stiffness matrix (with its Dirichlet rows) is assembled once and its solver set up once (the
AMG hierarchy of the default CG + GAMG, or the LU factors of MUMPS; :class:`SubmodelBody`),
and each position is a right-hand side.

Collective; the same values on every rank.
"""

from __future__ import annotations

import dolfinx_solver  # noqa: F401 - orders MPI ahead of the bindings

# isort: split
import json
import time
from collections.abc import Callable
from dataclasses import dataclass, replace

import dolfinx
import dolfinx.fem.petsc
import numpy as np
import ufl
from petsc4py import PETSc

from meshing import tags as tagnames
from meshing.body_cache import body_params, load_body
from meshing.sizing import level_record
from meshing.submodel import (
    SUBMODEL_DEGREE,
    SUBMODEL_MARGIN,
    max_read_teeth,
    sector_turn,
    submodel_body,
    submodel_level,
)
from solvers.body_store import BodyStore
from solvers.elastic_body import Material, mpi_sum
from solvers.gap_operator import locate
from solvers.gear_train import contact_grids
from solvers.modulus_scaling import ScaledSubmodel, with_material
from solvers.rigid_coupling import rigid_modes
from solvers.root_stress import (
    body_root_stress,
    collect,
    grid_teeth,
    loaded_fillets,
    loaded_teeth,
    set_keys,
)

#: solvers of the submodel: "cg-gamg" (CG + smoothed-aggregation AMG, no factor in memory;
#: the default) or "mumps" (exact LU, the reference it is tested against). Not an LU
#: factorized once and reused over a study's positions: the factors of one level-1 sector
#: do not fit in memory beside the global model; other smoothers save at most about 1 s a
#: solve (measured: docs/performance.md).
SUBMODEL_SOLVERS = ("cg-gamg", "mumps")
#: CG's initial guess: "rigid", the rigid motion nearest to the cut values (the gear's
#: rigid motion dominates them; the interior takes it with no stress, so CG starts from
#: the elastic part alone), or "zero". The rigid guess saves a few iterations; the global
#: field as a guess saves more but costs more to evaluate than it saves (measured:
#: docs/performance.md)
SUBMODEL_GUESSES = ("rigid", "zero")
#: relative residual of the CG solve. CG takes nearly all of a sector's solve time, so this
#: sets what the submodels cost per position. At 1e-6 the root stresses differ from a 1e-10
#: solve by a few 1e-4: far below the smallest root-stress ± and the 1 MPa the values are
#: reported to (``python -m studies.benchmarks.submodel``; measured: docs/performance.md)
SUBMODEL_CG_RTOL = 1e-6
#: GAMG's graph threshold for the sectors' aggregation (edges weaker than it, relative, are
#: dropped before aggregating). The set-up is paid once per sector, the CG once per position:
#: 0.0 sets a sector up about twice as fast as 0.02 and solves it a little slower, which
#: halves a sector solved once (a ladder run) and changes a case run that reuses its
#: sectors over 10-20 solves by a few per cent either way. So one threshold for every
#: sector, 0.0 (``python -m studies.benchmarks.submodel --thresholds``; measured:
#: docs/performance.md).
SUBMODEL_GAMG_THRESHOLD = 0.0


class SubmodelError(RuntimeError):
    """The loaded teeth of a gear do not fit a submodel (not one run of consecutive teeth,
    or more than a sector of half the gear holds)."""


def _turn(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def field_at(body, u: dolfinx.fem.Function, points: np.ndarray) -> np.ndarray:
    """Values (m, gdim) of ``u`` (a field on ``body``'s mesh) at ``points`` (m, gdim; the same
    on every rank; collective): each point evaluated by the rank whose cell holds it
    (:func:`solvers.gap_operator.locate`, which refuses points off the mesh) and summed."""
    mine, cells, X, _ = locate(body, points)
    gd = body.gdim
    out = np.zeros((len(points), gd))
    if np.any(mine):
        elem = u.function_space.element.basix_element
        phi = elem.tabulate(0, X[mine])[0, :, :, 0]  # (p, ndofs)
        dofs = u.function_space.dofmap.list[cells[mine]]  # (p, ndofs)
        vals = u.x.array.reshape(-1, gd)[dofs]  # (p, ndofs, gd)
        out[mine] = np.einsum("pd,pdc->pc", phi, vals)
    return mpi_sum(body.comm, out)


@dataclass
class SubmodelBody:
    """The canonical sector of one gear and loaded side, assembled and its solver set up once.

    Holds what :func:`solvers.root_stress.body_root_stress` reads of a body (``name``,
    ``mesh``, ``facet_tags``, ``tags``, ``material``, ``gdim``, ``comm``, ``degree``).
    ``cut``: the tag names of the driven boundary.
    """

    name: str
    mesh: dolfinx.mesh.Mesh
    facet_tags: dolfinx.mesh.MeshTags
    tags: dict
    material: Material
    degree: int
    cut: tuple[str, ...]
    solver: str = "cg-gamg"
    guess: str = "rigid"  # CG's initial guess, SUBMODEL_GUESSES

    def __post_init__(self):
        if self.solver not in SUBMODEL_SOLVERS:
            raise ValueError(f"submodel solver {self.solver!r}: must be one of {SUBMODEL_SOLVERS}")
        if self.guess not in SUBMODEL_GUESSES:
            raise ValueError(f"submodel guess {self.guess!r}: must be one of {SUBMODEL_GUESSES}")
        self.comm = self.mesh.comm
        self.gdim = self.mesh.geometry.dim
        t0 = time.perf_counter()
        self.V = dolfinx.fem.functionspace(self.mesh, ("Lagrange", self.degree, (self.gdim,)))
        fdim = self.gdim - 1
        self.mesh.topology.create_connectivity(fdim, self.gdim)
        facets = np.concatenate([self.facet_tags.find(self.tags[s]) for s in self.cut])
        self.cut_dofs = dolfinx.fem.locate_dofs_topological(self.V, fdim, facets)
        self.g = dolfinx.fem.Function(self.V)
        self.bc = dolfinx.fem.dirichletbc(self.g, self.cut_dofs)
        mat = self.material
        u, v = ufl.TrialFunction(self.V), ufl.TestFunction(self.V)

        def eps(w):
            return ufl.sym(ufl.grad(w))

        sig = mat.lam * ufl.tr(eps(u)) * ufl.Identity(self.gdim) + 2 * mat.mu * eps(u)
        self.a = dolfinx.fem.form(ufl.inner(sig, eps(v)) * ufl.dx)
        self.A = dolfinx.fem.petsc.assemble_matrix(self.a, bcs=[self.bc])
        self.A.assemble()
        self.ksp = PETSc.KSP().create(self.comm)
        self.ksp.setOperators(self.A)
        if self.solver == "mumps":
            self.ksp.setType("preonly")
            self.ksp.getPC().setType("lu")
            self.ksp.getPC().setFactorSolverType("mumps")
        else:  # CG + smoothed aggregation with the rigid modes (solvers.elastic_body)
            self._near_null_space()
            self.ksp.setType("cg")
            self.ksp.setTolerances(rtol=SUBMODEL_CG_RTOL, atol=0.0, max_it=2000)
            pc = self.ksp.getPC()
            pc.setType("gamg")
            opts = PETSc.Options()
            pre = f"submodel_{id(self)}_"
            self.ksp.setOptionsPrefix(pre)
            sets = {
                "pc_gamg_threshold": SUBMODEL_GAMG_THRESHOLD,
                "mg_levels_ksp_type": "chebyshev",
                "mg_levels_pc_type": "jacobi",
            }
            for k, v in sets.items():
                opts[pre + k] = v
            self.ksp.setFromOptions()
            for k in sets:
                opts.delValue(pre + k)
        self.ksp.setUp()
        self.dofs = self.V.dofmap.index_map.size_global * self.V.dofmap.index_map_bs
        self.timings = {"factorize": time.perf_counter() - t0}
        self.x_dofs = self.V.tabulate_dof_coordinates()  # local, with ghosts
        self.x_cut = self.x_dofs[self.cut_dofs]

    def _near_null_space(self) -> None:
        """The six rigid modes of the sector (orthonormalised) as the near null space of A."""
        n_own = self.V.dofmap.index_map.size_local
        x = self.V.tabulate_dof_coordinates()[:n_own]
        psi = rigid_modes(x, np.zeros(3))  # (n, 3, 6)
        vecs = []
        for m in range(6):
            w = self.A.createVecRight()
            w.getArray()[:] = psi[:, :, m].ravel()
            for v in vecs:
                w.axpy(-w.dot(v), v)
            w.scale(1.0 / w.norm())
            vecs.append(w)
        self.A.setNearNullSpace(PETSc.NullSpace().create(vectors=vecs, comm=self.comm))

    def rigid_fit(self, cut_values: np.ndarray) -> np.ndarray:
        """The rigid motion (translation + rotation about the origin of the sector's frame,
        the gear axis) nearest to ``cut_values`` (this rank's cut DOFs, (m, 3)) in the least
        squares over every rank's owned cut DOFs, at every local DOF (n, 3). Collective."""
        own = self.cut_dofs < self.V.dofmap.index_map.size_local
        P = rigid_modes(self.x_cut[own], np.zeros(3)).reshape(-1, 6)  # row: node * 3 + comp
        M = mpi_sum(self.comm, P.T @ P)
        r = mpi_sum(self.comm, P.T @ np.asarray(cut_values)[own].ravel())
        c = np.linalg.solve(M, r)
        return rigid_modes(self.x_dofs, np.zeros(3)) @ c

    def solve(self, global_body, u_global, loads, angle: float) -> dolfinx.fem.Function:
        """The submodel's displacement for one position (collective).

        ``global_body``/``u_global``: the gear's body and displacement in the global model
        (body frame); ``loads``: (points (m, 3), forces (m, 3)) in the global body frame
        (:func:`sector_loads`); ``angle``: the turn from this canonical sector to the
        global body frame (:func:`meshing.submodel.sector_turn`)."""
        t0 = time.perf_counter()
        Q = _turn(angle)  # canonical -> global body frame: x_G = Q x
        # cut values: the global field at every rank's cut DOFs, in canonical components
        parts = self.comm.allgather(self.x_cut)
        counts = [len(p) for p in parts]
        every = np.vstack(parts) if sum(counts) else np.zeros((0, 3))
        vals = field_at(global_body, u_global, every @ Q.T) @ Q  # (Q^T u)^T = u^T Q
        mine = vals[sum(counts[: self.comm.rank]) : sum(counts[: self.comm.rank + 1])]
        arr = self.g.x.array.reshape(-1, self.gdim)
        arr[self.cut_dofs] = mine
        t_cut = time.perf_counter()
        # loads: consistent nodal forces of the point forces on the canonical mesh
        pts, forces = loads
        f = dolfinx.fem.Function(self.V)
        own, cells, X, _ = locate(self, pts @ Q, curved=True)
        if np.any(own):
            elem = self.V.element.basix_element
            phi = elem.tabulate(0, X[own])[0, :, :, 0]
            dofs = self.V.dofmap.list[cells[own]]
            fv = f.x.array.reshape(-1, self.gdim)
            np.add.at(
                fv,
                dofs.ravel(),
                (phi[:, :, None] * (forces[own] @ Q)[:, None, :]).reshape(-1, self.gdim),
            )
        # ghost entries reach their owners once, in the ghost update after the lifting
        b = f.x.petsc_vec
        dolfinx.fem.petsc.apply_lifting(b, [self.a], bcs=[[self.bc]])
        b.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
        dolfinx.fem.petsc.set_bc(b, [self.bc])
        u = dolfinx.fem.Function(self.V, name="displacement")
        if self.solver == "cg-gamg":  # (an initial guess means nothing to a direct solve)
            if self.guess == "rigid":
                u.x.array[:] = self.rigid_fit(mine).ravel()
                u.x.array.reshape(-1, self.gdim)[self.cut_dofs] = mine
            self.ksp.setInitialGuessNonzero(self.guess == "rigid")
        t_rhs = time.perf_counter()
        self.ksp.solve(b, u.x.petsc_vec)
        if self.ksp.getConvergedReason() < 0:
            raise SubmodelError(
                f"submodel of {self.name}: {self.solver} did not converge (PETSc reason "
                f"{self.ksp.getConvergedReason()}, {self.ksp.getIterationNumber()} iterations)"
            )
        self.iterations = int(self.ksp.getIterationNumber())
        u.x.scatter_forward()
        self.solve_timings = {
            "cut_s": t_cut - t0,
            "loads_s": t_rhs - t_cut,
            "krylov_s": time.perf_counter() - t_rhs,
        }
        return u


def sector_loads(problem, result, body: str, gear, first_tooth: int, n_teeth: int):
    """The contact forces acting on ``body`` at the spreading points of their grid cells, in
    its body frame, kept where they lie on the teeth ``first_tooth`` ... ``+ n_teeth - 1``
    (by polar angle less the helix rotation): (points (m, 3), forces (m, 3)); eq. (2) of
    :mod:`solvers.contact` (f = sigma F n, sigma = +1 on side B, -1 on side A)."""
    b = problem.bodies[body]
    pitch = 2.0 * np.pi / gear.teeth
    lo = (first_tooth - 0.5) * pitch
    pts, frc = [], []
    for i, p in enumerate(problem.pairs):
        F = result.forces[problem.offsets[i] : problem.offsets[i + 1]]
        for side, name in (("a", p.body_a), ("b", p.body_b)):
            if name != body or not np.any(F):
                continue
            x, parent, w = p.grid.spread_points(side)
            x = b.to_body(x)
            n = np.asarray(p.grid.normals, float)[parent] @ b.rotation
            sign = 1.0 if side == "b" else -1.0
            th = np.arctan2(x[:, 1], x[:, 0]) - np.asarray(gear.helix_rotation(x[:, 2]), float)
            rel = np.mod(th - lo, 2.0 * np.pi)
            keep = (rel < n_teeth * pitch) & (F[parent] != 0)
            pts.append(x[keep])
            frc.append(sign * (F[parent] * w)[keep, None] * n[keep])
    if not pts:
        return np.zeros((0, 3)), np.zeros((0, 3))
    return np.vstack(pts), np.vstack(frc)


def cut_names(body: str, internal: bool) -> tuple[str, ...]:
    """The driven boundary of a sector submodel: its cut faces and its inner (outer) arc."""
    arc = tagnames.RIM if internal else tagnames.BORE
    return tuple(tagnames.surface(body, k) for k in (tagnames.CUT_POS, tagnames.CUT_NEG, arc))


def tooth_run(key: str, teeth, z: int) -> tuple[int, int]:
    """(first tooth, number of teeth) of ``teeth``, consecutive teeth of a gear of ``z`` teeth
    (the run may wrap past tooth z - 1 to 0); :class:`SubmodelError` if they are not one run."""
    ts = sorted({int(t) for t in teeth})
    starts = [t for t in ts if (t - 1) % z not in ts]
    if not ts or len(starts) != 1:
        raise SubmodelError(
            f"root stress submodel of {key}: the loaded teeth {ts} are not one run of "
            "consecutive teeth (set numerics.root_stress = 'global' to read the global model)"
        )
    return starts[0], len(ts)


def sector_teeth(scene, inputs, spacing: float, width=None, micro=None) -> dict[str, int]:
    """Per output key how many teeth the drive grid of its mesh names in ``scene`` (the teeth
    :func:`submodel_root_stress` reads there), from the grids :func:`build_gear_train
    <solvers.gear_train.build_gear_train>` lays with the same ``inputs``
    (:class:`solvers.train_inputs.TrainInputs`), without the FE."""
    grids, _ = contact_grids(scene, inputs, spacing, width, micro, coast=False)
    return {key: len(ts) for key, ts in grid_teeth(scene, grids).items()}


def sector_body(scene, body: str, n_read: int, side: str):
    """The canonical sector (:func:`meshing.submodel.submodel_body`) of ``body`` of ``scene``
    with ``n_read`` read teeth on ``side``; a planet's is cut from its gear of the gear set
    (``pinion``, not ``pinion2``), so one sector serves every planet: the same mesh and the
    same assembled operator, turned onto each planet's teeth."""
    pg = scene.gear(body)
    gbody = pg.body
    if pg.gear_name != gbody.body:
        gbody = replace(gbody, gear=replace(gbody.gear, name=pg.gear_name), name=None)
    return submodel_body(gbody, n_read, side)


def most_loaded(set_key: dict[str, str], load_n: dict[str, float]) -> set[str]:
    """The output keys read on submodels: per gear and side of the gear set (``set_key``:
    output key -> gear-set key, :func:`solvers.root_stress.set_keys`) the one whose sector
    carries the largest contact load (``load_n``, N; the first of equal ones). With one
    planet every key is its own gear-set key and every key is read; with several, the
    planets' meshes of one gear differ only in their share of the load (the floating sun's
    K_gamma, pin-hole errors) and the mesh phase, and the most loaded one bounds the others'
    root stress at the same phase."""
    best: dict[str, str] = {}
    for k in load_n:
        s = set_key.get(k, k)
        if s not in best or load_n[k] > load_n[best[s]]:
            best[s] = k
    return set(best.values())


def read_for(key: str, set_key: dict[str, str], read: set[str]) -> str:
    """The read key that stands for ``key`` (the same gear-set key)."""
    return next(k for k in sorted(read) if set_key.get(k, k) == set_key.get(key, key))


def submodel_root_stress(
    model,
    result,
    level,
    store: BodyStore | None = None,
    degree: int = SUBMODEL_DEGREE,
    sector: dict[str, int] | None = None,
    log: Callable[[str], None] | None = None,
) -> dict:
    """The root stress of a solved gear train read on submodels of its loaded teeth
    (module docstring), in the layout of :func:`solvers.root_stress.root_stress`; every
    key's ``locations`` also hold ``submodel``: its DOFs, read-fillet size, degree, sector
    (first tooth, teeth), the resultant of the loads on it (N), its set-up time (s;
    ``set_up_here``: in this call, not reused) and solve time (s). ``level``: the global
    model's level (the submodel's sizes:
    :func:`meshing.submodel.submodel_level`); ``store``: where the factorized submodels are
    kept across positions and cases (:class:`solvers.body_store.BodyStore`); ``sector``: per
    key the read teeth of its sector (at least the loaded teeth: the most of the mesh cycle,
    :func:`sector_teeth`, so one sector serves every position; default, or where that sector
    would exceed half the gear, the loaded teeth), the extra ones beyond the last loaded
    tooth and not read. With several planets only the most loaded mesh of each gear and side
    is read (:func:`most_loaded`); every other key's value is None, its ``locations`` entry
    naming the key read instead (``read_instead``) and its load. ``log``: called on every rank
    with a line per solved sector (DOFs, set-up, solve, CG iterations; a ladder run's log).
    Collective."""
    store = BodyStore() if store is None else store
    p, scene = model.problem, model.scene
    teeth = loaded_teeth(model)
    zones = {f"{zn.driver}-{zn.driven}": zn for zn in scene.zones}
    lv = submodel_level(level)
    runs = {}  # key -> (body, side, gear, first loaded tooth, read teeth, loads on the sector)
    for key, body, grid, which in loaded_fillets(scene):
        zn = zones[grid]
        side = zn.driver_side if which == "driver_tooth" else zn.driven_side
        gear = scene.gear(body).gear
        first, n = tooth_run(key, teeth[key], gear.teeth)
        most = (sector or {}).get(key, 0)
        if n < most <= max_read_teeth(gear):  # else: the loaded teeth
            n = most
        start = first - SUBMODEL_MARGIN
        loads = sector_loads(p, result, body, gear, start, n + 2 * SUBMODEL_MARGIN)
        runs[key] = (body, side, gear, first, n, loads)
    load_n = {k: float(np.linalg.norm(r[5][1].sum(axis=0))) for k, r in runs.items()}
    to_set = set_keys(scene)
    # every rank solves the same sectors (a collective each): rank 0's choice
    read = p.comm.bcast(most_loaded(to_set, load_n), root=0)
    recs = {}
    for key, (body, side, gear, first, n, loads) in runs.items():
        if key not in read:
            recs[key] = {
                "value": None,
                "tangent": None,
                "cell_max": None,
                "face_end": None,
                "teeth": list(teeth[key]),
                "load_N": load_n[key],
                "read_instead": read_for(key, to_set, read),
            }
            continue
        z = gear.teeth
        try:
            sb = sector_body(scene, body, n, side)
        except ValueError as exc:
            raise SubmodelError(f"root stress submodel of {key}: {exc}") from exc
        gb = p.bodies[body]
        mat = gb.material
        # keyed without E: a gear set of another modulus reads on the same sector
        skey = (
            "submodel",
            json.dumps(body_params(sb, level_record(lv)), sort_keys=True),
            degree,
            mat.nu,
        )

        def make(sb=sb, mat=mat, internal=gear.internal, comm=gb.comm):
            bundle = load_body(sb, lv, comm)
            tags = {nm: tg for nm, (d, tg) in bundle.names.items() if d == 2}
            return SubmodelBody(
                sb.body,
                bundle.mesh,
                bundle.facet_tags,
                tags,
                mat,
                degree,
                cut_names(sb.body, internal),
            )

        built = store.built
        sub = with_material(store.keep(skey, make), mat, ScaledSubmodel)
        t0 = time.perf_counter()
        start = first - SUBMODEL_MARGIN
        angle = sector_turn(gear, first)
        u = sub.solve(gb, gb.function(result.displacements[body]), loads, angle)
        t_read = time.perf_counter()
        canon = [(t - start) % z for t in teeth[key]]
        forces_at = loads[0] @ _turn(angle)  # canonical frame: (Q^T x)^T = x^T Q
        rec = body_root_stress(sub, u, gear, {key: canon}, load_points=forces_at)[key]
        for r in (rec, rec["recovered"]):  # canonical sector -> the gear's teeth
            for k in ("tooth", "tangent_tooth"):
                if r[k] is not None:
                    r[k] = int((r[k] + start) % z)
        rec["teeth"] = list(teeth[key])
        rec["load_N"] = load_n[key]
        rec["submodel"] = {
            "dofs": sub.dofs,
            "fillet_mm": lv.fillet,
            "degree": degree,
            "first_tooth": int(start % z),
            "teeth": n + 2 * SUBMODEL_MARGIN,
            "load_N": load_n[key],
            "setup_s": sub.timings["factorize"],
            "set_up_here": store.built > built,
            "solve_s": time.perf_counter() - t0,
            "iterations": sub.iterations,
            **sub.solve_timings,
            "read_s": time.perf_counter() - t_read,
        }
        recs[key] = rec
        if log is not None:
            m = rec["submodel"]
            log(
                f"submodel {key}, fillet {lv.fillet:g} mm: {m['dofs']} DOFs, set-up "
                f"{m['setup_s']:.0f} s{'' if m['set_up_here'] else ' (kept)'}, solve "
                f"{m['solve_s']:.0f} s, {m['iterations']} iterations"
            )
        del sub, u  # a submodel the store does not keep is freed before the next is built
    method = (
        f"P{degree} submodel of the loaded teeth (read fillets {lv.fillet:g} mm), driven "
        "by the global displacement; cell stress at the fillet vertices, averaged over "
        "the surface cells"
    )
    return collect(scene, recs, method)


__all__ = [
    "SubmodelBody",
    "SubmodelError",
    "cut_names",
    "field_at",
    "most_loaded",
    "sector_body",
    "sector_loads",
    "sector_teeth",
    "sector_turn",
    "submodel_root_stress",
    "tooth_run",
]

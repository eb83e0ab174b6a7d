"""One elastic body: its own finite element system, assembled and factorized once.

Linear elasticity, small strain, isotropic (plane strain in 2D):

    sigma(u) = lambda tr(eps(u)) I + 2 mu eps(u),   eps(u) = (grad u + grad u^T) / 2
    K u = f,   K_ij = int_Omega sigma(phi_j) : eps(phi_i) dx,   f_i = int_Gamma_t t . phi_i ds

Bodies are independent systems (the global stiffness is block diagonal); they are coupled
only through contact, which :mod:`solvers.contact` condenses onto the contact grid.

Supports act on the *reduced* system of :mod:`solvers.rigid_coupling`: u = P u_red with
u_red = [FE DOFs | reference DOFs q of every coupling], K_red = P^T K P + diag(springs), and
the constrained reduced DOFs (homogeneous Dirichlet components, slaved surface DOFs, fixed
and held reference DOFs) zeroed in rows and columns with the mean diagonal of K put back on
the diagonal (so the scaling stays that of K and a constrained rigid mode stays visibly
constrained in the singularity check).

Placement. A body is assembled in its own frame; ``place(Q, t)`` says where it sits in the
scene (x_scene = Q x + t, a rigid map). K does not depend on the placement, so one
factorization serves every mesh position; the contact grid is mapped into the body frame
(:mod:`solvers.gap_operator`) and the results back (:mod:`solvers.results`).

Linear solver (:class:`LinearSolver`, ``[numerics] linear_solver``). Every body is solved
with its own solver of K_red, set up once and reused for every right-hand side:

* ``mumps`` (default): exact sparse LU (MUMPS), the reference;
* ``mumps-blr``: MUMPS block low-rank LU (ICNTL(35) = 2, dropping threshold CNTL(7) =
  ``tolerance``, default 1e-6): off-diagonal blocks of the factors compressed to that relative
  accuracy: a faster factorization in less memory, results moved by about 1e-4 at most
  (measured: docs/performance.md);
* ``cg-gamg``: conjugate gradients preconditioned by smoothed-aggregation AMG (PETSc GAMG,
  the body's rigid modes as near null space), relative residual ``tolerance`` (default 1e-8):
  no factor in memory (1-GB level 0: 0.6 GB against 1.25 GB), but every right-hand side is
  an iterative solve (16-17 iterations there, the compliance columns ~60x slower than the
  LU's substitutions). For bodies whose factor does not fit in memory.

``make bench-linear`` measures all three (results/bench/linear_solver.md).

Out of core (``LinearSolver(out_of_core=True)``, ``[numerics] out_of_core``; the LU kinds):
MUMPS writes the factors to disk (ICNTL(22) = 1, a fresh folder per body under
``$PLANETARY_OOC_DIR`` or the system's temporary folder, removed with the body) and reads
them back for every block of substitutions. The same factorization, so the same answer to
round-off; memory about the largest frontal matrix instead of the whole factor, for bodies
whose factors do not fit beside each other.

Parallel layout of u_red: every rank owns its FE DOFs in DOLFINx order; the reference DOFs
are appended to rank 0's block, so a full global index g becomes g + n_ref on ranks > 0.
"""

from __future__ import annotations

import itertools
import os
import shutil
import tempfile
import weakref
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

import dolfinx_solver  # noqa: F401 - orders MPI ahead of the bindings

# isort: split
import dolfinx
import dolfinx.fem.petsc
import numpy as np
import ufl
from mpi4py import MPI
from petsc4py import PETSc

from solvers.errors import FactorizationError, SingularBodyError
from solvers.rigid_coupling import (
    RigidCoupling,
    global_mode_names,
    n_rigid,
    reference_motion,
    rigid_modes,
)

_ids = itertools.count()


LINEAR_SOLVERS = ("mumps", "mumps-blr", "cg-gamg")
#: default ``tolerance`` per solver kind (None: exact)
DEFAULT_TOLERANCE = {"mumps": None, "mumps-blr": 1e-6, "cg-gamg": 1e-8}


@dataclass(frozen=True)
class LinearSolver:
    """How a body's K_red is solved (module docstring): ``kind`` one of LINEAR_SOLVERS,
    ``tolerance`` the BLR dropping threshold or the CG relative residual (None: the kind's
    default), ``out_of_core`` the LU factors on disk (module docstring)."""

    kind: str = "mumps"
    tolerance: float | None = None
    out_of_core: bool = False

    def __post_init__(self):
        if self.kind not in LINEAR_SOLVERS:
            raise ValueError(f"linear solver {self.kind!r}: must be one of {LINEAR_SOLVERS}")
        if self.tolerance is None:
            object.__setattr__(self, "tolerance", DEFAULT_TOLERANCE[self.kind])
        elif self.kind == "mumps":
            raise ValueError("linear solver 'mumps' is exact: it takes no tolerance")
        if self.out_of_core and not self.factorized:
            raise ValueError(f"linear solver {self.kind!r} has no factors to keep out of core")

    @property
    def factorized(self) -> bool:
        """True for the LU kinds (a factor matrix, substitutions per right-hand side)."""
        return self.kind != "cg-gamg"


@dataclass(frozen=True)
class Material:
    """Isotropic linear elastic material (MPa)."""

    E: float
    nu: float

    def __post_init__(self):
        if not (self.E > 0 and -1.0 < self.nu < 0.5):
            raise ValueError(f"material needs E > 0 and -1 < nu < 0.5, got {self}")

    @property
    def lam(self) -> float:
        return self.E * self.nu / ((1 + self.nu) * (1 - 2 * self.nu))

    @property
    def mu(self) -> float:
        return self.E / (2 * (1 + self.nu))

    @property
    def e_plane(self) -> float:
        """Plane-strain modulus E / (1 - nu^2) (Hertz contact modulus of one body)."""
        return self.E / (1 - self.nu**2)


@dataclass(frozen=True)
class Dirichlet:
    """Homogeneous Dirichlet condition u_c = 0 on a tagged surface (components None = all)."""

    surface: str
    components: tuple[int, ...] | None = None


@dataclass(frozen=True)
class Traction:
    """Surface traction t(x) (MPa) on a tagged surface; ``value(x)`` returns a UFL vector."""

    surface: str
    value: Callable[[ufl.SpatialCoordinate], ufl.core.expr.Expr]


#: where out-of-core factor files go (a folder, made if needed); unset: the temporary folder
OOC_DIR_ENV = "PLANETARY_OOC_DIR"


def ooc_folder(prefix: str) -> str:
    """A fresh folder for out-of-core factor files under ``$PLANETARY_OOC_DIR`` (made if
    needed), else the system's temporary folder; the caller removes it."""
    root = os.environ.get(OOC_DIR_ENV) or None
    if root is not None:
        os.makedirs(root, exist_ok=True)
    return tempfile.mkdtemp(prefix=prefix, dir=root)


def _drop_ooc(ksp: PETSc.KSP, folder: str) -> None:
    """Destroy a body's solver, then remove its out-of-core folder: MUMPS closes and deletes
    its factor files when it is destroyed, and reports an error (INFOG(1) = -90) if the
    folder went first (as it did when a body was collected or the interpreter exited).
    Collective, like the destruction of any PETSc object."""
    ksp.destroy()
    shutil.rmtree(folder, ignore_errors=True)


def mpi_sum(comm: MPI.Comm, a: np.ndarray | float) -> np.ndarray:
    """Sum an array over the ranks of ``comm`` (every rank must call it)."""
    a = np.asarray(a, dtype=float)
    buf = np.ascontiguousarray(a).reshape(-1)
    out = np.empty_like(buf)
    comm.Allreduce(buf, out, op=MPI.SUM)
    return out.reshape(a.shape)


class ElasticBody:
    """A body: DOLFINx mesh + tags + material + degree, supports, loads; K factorized once.

    Args:
        name: body name (used in every message).
        mesh: DOLFINx mesh (affine simplices).
        facet_tags: facet MeshTags.
        tags: facet tag name -> integer tag.
        material: E, nu.
        degree: Lagrange degree (1 or 2).
        dirichlet: homogeneous Dirichlet conditions.
        couplings: rigid couplings (bores) to reference points, see
            :mod:`solvers.rigid_coupling`.
        tractions: surface loads.
        centre: the point moments are reported about (default: centroid of the mesh nodes).
        petsc_options: extra options for this body's solver (dict, unprefixed keys).
        linear_solver: how K_red is solved (default exact MUMPS LU, see the module docstring).
    """

    def __init__(
        self,
        name: str,
        mesh: dolfinx.mesh.Mesh,
        facet_tags: dolfinx.mesh.MeshTags,
        tags: Mapping[str, int],
        material: Material,
        degree: int = 1,
        *,
        dirichlet: Sequence[Dirichlet] = (),
        couplings: Sequence[RigidCoupling] = (),
        tractions: Sequence[Traction] = (),
        centre: Sequence[float] | None = None,
        petsc_options: Mapping[str, object] | None = None,
        linear_solver: LinearSolver | None = None,
    ):
        self.name = name
        self.mesh = mesh
        self.comm = mesh.comm
        self.facet_tags = facet_tags
        self.tags = dict(tags)
        self.material = material
        self.degree = degree
        self.dirichlet = tuple(dirichlet)
        self.couplings = {c.name: c for c in couplings}
        if len(self.couplings) != len(couplings):
            raise ValueError(f"body '{name}': coupling names must be unique")
        self.tractions = tuple(tractions)
        self.gdim = mesh.geometry.dim
        if mesh.topology.dim != self.gdim:
            raise ValueError(f"body '{name}': needs a {self.gdim}D solid mesh (tdim == gdim)")
        for c in couplings:
            if c.nr != n_rigid(self.gdim):
                raise ValueError(
                    f"body '{name}', coupling '{c.name}': {c.nr} DOFs given, "
                    f"{n_rigid(self.gdim)} needed in {self.gdim}D"
                )
        for s in (
            [d.surface for d in dirichlet]
            + [t.surface for t in tractions]
            + [c.surface for c in couplings]
        ):
            if s not in self.tags:
                raise KeyError(
                    f"body '{name}': no facet tag named '{s}' (have {sorted(self.tags)})"
                )
        self.petsc_options = dict(petsc_options or {})
        self.linear_solver = LinearSolver() if linear_solver is None else linear_solver
        self.prefix = f"body_{''.join(ch if ch.isalnum() else '_' for ch in name)}_{next(_ids)}_"
        self.V = dolfinx.fem.functionspace(mesh, ("Lagrange", degree, (self.gdim,)))
        x = mesh.geometry.x[: mesh.geometry.index_map().size_local, : self.gdim]
        if centre is None:
            s = mpi_sum(self.comm, np.append(x.sum(axis=0), len(x)))
            centre = s[:-1] / s[-1]
        self.centre = np.asarray(centre, dtype=float)[: self.gdim]
        self.rotation = np.eye(self.gdim)  # placement in the scene: x_scene = Q x + t
        self.translation = np.zeros(self.gdim)
        self._held: set[tuple[str, int]] = set()
        self._ready = False
        self._ooc_dir: str | None = None
        self._ooc_drop: weakref.finalize | None = None
        self.timings: dict[str, float] = {}

    # ------------------------------------------------------------------ placement
    def place(self, rotation: np.ndarray, translation: Sequence[float]) -> None:
        """Place the body in the scene: x_scene = Q x_body + t (Q orthonormal). K, its
        factorization and every body-frame quantity stay as they are."""
        Q = np.asarray(rotation, dtype=float)[: self.gdim, : self.gdim]
        if not np.allclose(Q @ Q.T, np.eye(self.gdim), atol=1e-12):
            raise ValueError(f"body '{self.name}': placement rotation must be orthonormal")
        self.rotation = Q
        self.translation = np.asarray(translation, dtype=float)[: self.gdim]

    def to_scene(self, x: np.ndarray) -> np.ndarray:
        """Body-frame points (..., gdim) in the scene frame."""
        return np.asarray(x, dtype=float) @ self.rotation.T + self.translation

    def to_body(self, x: np.ndarray) -> np.ndarray:
        """Scene-frame points (..., gdim) in the body frame."""
        return (np.asarray(x, dtype=float) - self.translation) @ self.rotation

    @property
    def scene_centre(self) -> np.ndarray:
        """The centre moments are reported about, in the scene frame."""
        return self.to_scene(self.centre)

    @property
    def ready(self) -> bool:
        """True once K is assembled, reduced and factorized (:meth:`setup`)."""
        return self._ready

    def release(self) -> None:
        """Free the solver (a factorization is the largest object of a run) and the
        stiffness matrices of a body no later solve needs; the mesh, function space and
        placement stay, and :meth:`setup` builds the rest again. Collective."""
        for name in ("ksp", "K_red", "K"):
            obj = getattr(self, name, None)
            if obj is not None:
                obj.destroy()
                setattr(self, name, None)
        if self._ooc_drop is not None:
            self._ooc_drop()
            self._ooc_drop = None
        elif self._ooc_dir is not None:
            shutil.rmtree(self._ooc_dir, ignore_errors=True)
        self._ooc_dir = None
        self._ready = False

    @property
    def held(self) -> frozenset[tuple[str, int]]:
        """The (coupling, DOF) pairs held in the FE system (rigid unknowns)."""
        return frozenset(self._held)

    # ------------------------------------------------------------------ set-up
    def hold(self, coupling: str, dof: int) -> None:
        """Constrain reference DOF ``dof`` of ``coupling`` in the FE system.

        Used for a rigid unknown: the rigid motion of that DOF is superposed explicitly and
        balanced by contact (see :mod:`solvers.contact`). The DOF must be free (stiffness 0).
        """
        if self._ready:
            raise RuntimeError(f"body '{self.name}': hold() after setup()")
        c = self.couplings.get(coupling)
        if c is None:
            raise KeyError(f"body '{self.name}': no coupling '{coupling}'")
        if c.stiffness[dof] != 0:
            raise ValueError(
                f"body '{self.name}', coupling '{coupling}': DOF {dof} has stiffness "
                f"{c.stiffness[dof]}; a rigid unknown needs a free DOF (stiffness 0)"
            )
        self._held.add((coupling, dof))

    def _facets(self, surface: str) -> np.ndarray:
        return self.facet_tags.find(self.tags[surface]).astype(np.int32)

    def _component_dofs(self, surface: str, comps: Sequence[int]) -> np.ndarray:
        """Local unrolled DOF indices (block * bs + c, owned and ghost) on a surface."""
        fdim = self.gdim - 1
        self.mesh.topology.create_connectivity(fdim, self.gdim)
        facets = self._facets(surface)
        out = [dolfinx.fem.locate_dofs_topological(self.V.sub(c), fdim, facets) for c in comps]
        return np.unique(np.concatenate(out)) if out else np.zeros(0, dtype=np.int32)

    def setup(self) -> None:
        """Assemble K and f, build P and K_red, check for free rigid modes, factorize."""
        if self._ready:
            return
        t0 = MPI.Wtime()
        comm, gdim, V = self.comm, self.gdim, self.V
        imap, bs = V.dofmap.index_map, V.dofmap.index_map_bs
        n_own_b, n_ghost = imap.size_local, imap.num_ghosts
        n_own = n_own_b * bs
        self.n_own = n_own
        rank = comm.rank
        owners = np.concatenate([np.full(n_own_b, rank, dtype=np.int32), imap.owners])
        gblock = imap.local_to_global(np.arange(n_own_b + n_ghost, dtype=np.int32))
        self.full_global = (gblock[:, None] * bs + np.arange(bs)[None, :]).ravel()
        owner_scalar = np.repeat(owners, bs)
        self.n_ref = sum(c.nr for c in self.couplings.values())
        self.red_global = self.full_global + np.where(owner_scalar > 0, self.n_ref, 0)
        n0 = comm.bcast(n_own if rank == 0 else None, root=0)
        self.ref_offset = {}
        off = n0
        for cname, c in self.couplings.items():
            self.ref_offset[cname] = off
            off += c.nr
        self.n_red_local = n_own + (self.n_ref if rank == 0 else 0)
        self.dof_x = np.repeat(V.tabulate_dof_coordinates()[:, :gdim], bs, axis=0)
        self.dof_comp = np.tile(np.arange(bs), n_own_b + n_ghost)

        # --- stiffness and load, full (no constraints: the residual is read from it)
        u, v = ufl.TrialFunction(V), ufl.TestFunction(V)
        mat = self.material

        def eps(w):
            return ufl.sym(ufl.grad(w))

        def sigma(w):
            return mat.lam * ufl.tr(eps(w)) * ufl.Identity(gdim) + 2 * mat.mu * eps(w)

        a = ufl.inner(sigma(u), eps(v)) * ufl.dx
        self.K = dolfinx.fem.petsc.assemble_matrix(dolfinx.fem.form(a))
        self.K.assemble()
        ds = ufl.Measure("ds", domain=self.mesh, subdomain_data=self.facet_tags)
        xs = ufl.SpatialCoordinate(self.mesh)
        if self.tractions:
            L = sum(ufl.inner(t.value(xs), v) * ds(self.tags[t.surface]) for t in self.tractions)
        else:
            L = ufl.inner(dolfinx.fem.Constant(self.mesh, np.zeros(gdim)), v) * ufl.dx
        self.f = dolfinx.fem.petsc.assemble_vector(dolfinx.fem.form(L))
        self.f.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
        diag = self.K.getDiagonal()
        self.diag_scale = float(mpi_sum(comm, np.abs(diag.array).sum())) / diag.getSize()
        t1 = MPI.Wtime()

        # --- prolongation P (full rows x reduced columns), COO with global indices
        rows = [self.full_global[:n_own]]
        cols = [self.red_global[:n_own]]
        vals = [np.ones(n_own)]
        slaved = np.zeros(n_own, dtype=bool)
        self.support_mask = np.zeros(n_own, dtype=bool)  # owned scalar DOFs held by supports
        for cname, c in self.couplings.items():
            loc = self._component_dofs(c.surface, range(gdim))
            n_loc = int(mpi_sum(comm, float(len(loc))))
            if n_loc == 0:
                raise ValueError(f"body '{self.name}', coupling '{cname}': surface is empty")
            loc = loc[loc < n_own]
            if np.any(slaved[loc]):
                raise ValueError(f"body '{self.name}': coupling '{cname}' overlaps another one")
            slaved[loc] = True
            psi = rigid_modes(self.dof_x[loc], np.asarray(c.x_ref), c.frame(gdim))
            psi_c = psi[np.arange(len(loc)), self.dof_comp[loc], :]  # (n, nr)
            for j in range(c.nr):
                rows.append(self.full_global[loc])
                cols.append(np.full(len(loc), self.ref_offset[cname] + j))
                vals.append(psi_c[:, j])
        self.slaved = slaved
        N_full = self.K.getSize()[0]
        N_red = N_full + self.n_ref
        P = PETSc.Mat().create(comm=comm)
        P.setSizes(((n_own, N_full), (self.n_red_local, N_red)))
        P.setType(PETSc.Mat.Type.AIJ)
        ri = np.concatenate(rows).astype(PETSc.IntType)
        ci = np.concatenate(cols).astype(PETSc.IntType)
        P.setPreallocationCOO(ri, ci)
        P.setValuesCOO(np.concatenate(vals))
        P.assemble()
        self.P = P

        # --- reduced stiffness, springs, constraints
        Kr = self.K.ptap(P)
        constrained = [self.red_global[:n_own][slaved]]
        self.support_mask |= slaved
        for d in self.dirichlet:
            comps = range(gdim) if d.components is None else d.components
            loc = self._component_dofs(d.surface, comps)
            loc = loc[loc < n_own]
            constrained.append(self.red_global[loc])
            self.support_mask[loc] = True
        Kr.setOption(PETSc.Mat.Option.NEW_NONZERO_ALLOCATION_ERR, False)
        if rank == 0:
            for cname, c in self.couplings.items():
                o = self.ref_offset[cname]
                for j, k in enumerate(c.springs()):
                    if k > 0:
                        Kr.setValue(o + j, o + j, k, addv=PETSc.InsertMode.ADD_VALUES)
                fixed = c.fixed() | np.array([(cname, j) in self._held for j in range(c.nr)])
                constrained.append(o + np.flatnonzero(fixed))
        Kr.assemble()
        self.constrained = np.unique(np.concatenate(constrained)).astype(PETSc.IntType)
        Kr.zeroRowsColumns(self.constrained, diag=self.diag_scale)
        self.K_red = Kr

        f_red = P.createVecRight()
        P.multTranspose(self.f, f_red)
        if rank == 0:
            for cname, c in self.couplings.items():
                o = self.ref_offset[cname]
                f_red.setValues(np.arange(o, o + c.nr, dtype=PETSc.IntType), c.loads(), True)
        f_red.assemble()
        f_red.setValues(self.constrained, np.zeros(len(self.constrained)))
        f_red.assemble()
        self.f_red = f_red
        t2 = MPI.Wtime()

        self._check_rigid_modes()
        self._factorize()
        t3 = MPI.Wtime()
        self.timings.update(assemble=t1 - t0, reduce=t2 - t1, factorize=t3 - t2)
        self._ready = True

    # ------------------------------------------------------------------ checks
    def reduced_rigid_modes(self) -> list[PETSc.Vec]:
        """The body's global rigid modes as reduced vectors, max displacement normalised to 1.

        Translations along x, y(, z), then rotations about the axes through ``centre``.
        """
        gdim, n_own = self.gdim, self.n_own
        x = self.dof_x[:n_own]
        psi = rigid_modes(x, self.centre)[np.arange(n_own), self.dof_comp[:n_own], :]
        local_r = np.max(np.linalg.norm(x - self.centre, axis=1), initial=0.0)
        r_max = self.comm.allreduce(local_r, op=MPI.MAX)
        scale = np.ones(n_rigid(gdim))
        scale[gdim:] = 1.0 / max(r_max, 1e-300)
        vecs = []
        for m in range(n_rigid(gdim)):
            w = self.K_red.createVecRight()
            arr = w.getArray()
            # slaved DOFs move through P from the reference DOFs: their own entries are 0
            arr[:n_own] = np.where(self.slaved, 0.0, psi[:, m] * scale[m])
            if self.comm.rank == 0:
                for cname, c in self.couplings.items():
                    q = reference_motion(np.asarray(c.x_ref), self.centre, c.frame(gdim))
                    o = self.ref_offset[cname] - self.K_red.getOwnershipRange()[0]
                    arr[o : o + c.nr] = q[:, m] * scale[m]
            w.setArray(arr)
            vecs.append(w)
        return vecs

    def _check_rigid_modes(self) -> None:
        """Raise SingularBodyError if a combination of rigid modes costs no energy.

        M = R^T K_red R (nr x nr, R = rigid modes with unit max displacement); a free mode
        has eigenvalue at round-off level (~1e-16 * ||K|| * n), a restrained one at least of
        the order of a support stiffness (>= the mean diagonal of K for a constrained DOF).
        The threshold 1e-8 * mean diag(K) separates the two by many decades.
        """
        vecs = self.reduced_rigid_modes()
        kv = [self.K_red.createVecLeft() for _ in vecs]
        for w, y in zip(vecs, kv, strict=True):
            self.K_red.mult(w, y)
        nr = len(vecs)
        M = np.array([[vecs[i].dot(kv[j]) for j in range(nr)] for i in range(nr)])
        M = 0.5 * (M + M.T)
        lam, vec = np.linalg.eigh(M)
        free = lam < 1e-8 * self.diag_scale
        if np.any(free):
            names = global_mode_names(self.gdim)
            modes = []
            for k in np.flatnonzero(free):
                v = vec[:, k] / np.max(np.abs(vec[:, k]))
                v = v * np.sign(v[np.argmax(np.abs(v))])
                parts = [(v[i], names[i]) for i in range(nr) if abs(v[i]) > 0.05]
                if len(parts) == 1:
                    modes.append(parts[0][1])
                else:
                    modes.append(" ".join(f"{c:+.2f} {n}" for c, n in parts))
            raise SingularBodyError(
                self.name, modes, f"energy {lam[free]} vs mean diag(K) {self.diag_scale:.3g}"
            )

    def _solver_options(self) -> dict:
        """PETSc options (unprefixed) of this body's :class:`LinearSolver`."""
        ls = self.linear_solver
        if ls.kind == "cg-gamg":
            return {
                "ksp_type": "cg",
                "ksp_rtol": ls.tolerance,
                "ksp_atol": 0.0,
                "ksp_max_it": 1000,
                "pc_type": "gamg",
                "pc_gamg_threshold": 0.02,
                "mg_levels_ksp_type": "chebyshev",
                "mg_levels_pc_type": "jacobi",
            }
        opts = {
            "ksp_type": "preonly",
            "pc_type": "lu",
            "pc_factor_mat_solver_type": "mumps",
            "mat_mumps_icntl_24": 1,  # detect null pivots: reported as an error below
            # multi-RHS blocking for the compliance columns: measured 1.5x faster than the
            # default -32 on a 32k-DOF P2 body (3D roller, 512 columns)
            "mat_mumps_icntl_27": -128,
        }
        if ls.kind == "mumps-blr":
            opts.update({"mat_mumps_icntl_35": 2, "mat_mumps_cntl_7": ls.tolerance})
        if ls.out_of_core:
            opts.update({"mat_mumps_icntl_22": 1, "mat_mumps_ooc_tmpdir": self._ooc_folder()})
        return opts

    def _ooc_folder(self) -> str:
        """This rank's folder for the body's out-of-core factors (removed by :meth:`release`,
        or when the body is collected or the interpreter exits: :func:`_drop_ooc`).
        Collective: a folder one rank cannot make fails every rank (the others would
        otherwise wait in the factorization)."""
        if self._ooc_dir is None:
            folder, error = None, None
            try:
                folder = ooc_folder(f"ooc-{self.prefix}")
            except OSError as exc:
                error = str(exc)
            bad = [(r, e) for r, e in enumerate(self.comm.allgather(error)) if e is not None]
            if bad:
                if folder is not None:
                    shutil.rmtree(folder, ignore_errors=True)
                rank, why = bad[0]
                raise FactorizationError(
                    f"body '{self.name}': no folder for its out-of-core factors (rank {rank}: "
                    f"{why}); set {OOC_DIR_ENV} to a writable folder"
                )
            self._ooc_dir = folder
        return self._ooc_dir

    def _near_null_space(self) -> None:
        """The body's rigid modes (orthonormalised) as K_red's near null space (GAMG)."""
        vs = self.reduced_rigid_modes()
        for i, v in enumerate(vs):
            for w in vs[:i]:
                v.axpy(-v.dot(w), w)
            v.scale(1.0 / v.norm())
        self.K_red.setNearNullSpace(PETSc.NullSpace().create(vectors=vs, comm=self.comm))

    def _check_converged(self, what: str) -> None:
        """An iterative solve that did not reach its tolerance is an error, not a result."""
        if self.linear_solver.factorized:
            return
        reason = self.ksp.getConvergedReason()
        if reason < 0:
            raise FactorizationError(
                f"body '{self.name}': CG/GAMG {what} did not converge (PETSc reason {reason}, "
                f"{self.ksp.getIterationNumber()} iterations, relative residual "
                f"{self.linear_solver.tolerance:g}): use linear_solver = 'mumps'"
            )

    def _factorize(self) -> None:
        ksp = PETSc.KSP().create(self.comm)
        ksp.setOptionsPrefix(self.prefix)
        ksp.setOperators(self.K_red)
        if not self.linear_solver.factorized:
            self._near_null_space()
        opts = PETSc.Options()
        defaults = self._solver_options()
        if self._ooc_dir is not None and self._ooc_drop is None:
            # the factors go before their folder, however the body ends (a failed factorization
            # too)
            self._ooc_drop = weakref.finalize(self, _drop_ooc, ksp, self._ooc_dir)
        defaults.update(self.petsc_options)
        for k, v in defaults.items():
            opts[self.prefix + k] = v
        ksp.setFromOptions()
        try:
            ksp.setUp()
        except PETSc.Error as e:
            raise FactorizationError(f"body '{self.name}': factorization failed ({e})") from e
        finally:
            for k in defaults:
                opts.delValue(self.prefix + k)
        pc = ksp.getPC()
        if self.linear_solver.factorized and pc.getFactorSolverType() == "mumps":
            F = pc.getFactorMatrix()
            info, nnull = F.getMumpsInfog(1), F.getMumpsInfog(28)
            if info < 0 or nnull > 0:
                raise FactorizationError(
                    f"body '{self.name}': MUMPS INFOG(1)={info}, {nnull} null pivot(s): the "
                    "stiffness is singular (an unrestrained body or a mechanism)"
                )
        self.ksp = ksp

    # ------------------------------------------------------------------ solves
    def solve(self, b: PETSc.Vec) -> PETSc.Vec:
        """x = K_red^{-1} b (one forward/backward substitution)."""
        x = self.K_red.createVecRight()
        self.ksp.solve(b, x)
        self._check_converged("solve")
        return x

    def solve_dense(self, B: PETSc.Mat) -> PETSc.Mat:
        """X = K_red^{-1} B for a dense block of right-hand sides (one MUMPS multi-RHS solve;
        CG/GAMG: one iterative solve per column, every one checked)."""
        X = B.duplicate()
        if self.linear_solver.factorized:
            self.ksp.getPC().getFactorMatrix().matSolve(B, X)
            return X
        b, x = self.K_red.createVecRight(), self.K_red.createVecRight()
        r0, r1 = X.getOwnershipRange()
        rows = np.arange(r0, r1, dtype=PETSc.IntType)
        for j in range(B.getSize()[1]):
            B.getColumnVector(j, b)
            self.ksp.solve(b, x)
            self._check_converged(f"column {j}")
            X.setValues(rows, [j], x.getArray(readonly=True), addv=PETSc.InsertMode.INSERT_VALUES)
        X.assemble()
        return X

    def reference_dofs(self, x_red: PETSc.Vec) -> dict[str, np.ndarray]:
        """Values of every coupling's reference DOFs q (replicated on all ranks)."""
        out = {}
        arr = x_red.getArray(readonly=True)
        start = x_red.getOwnershipRange()[0]
        for cname, c in self.couplings.items():
            o = self.ref_offset[cname]
            val = arr[o - start : o - start + c.nr].copy() if self.comm.rank == 0 else None
            out[cname] = self.comm.bcast(val, root=0)
        return out

    def expand(self, x_red: PETSc.Vec, rigid: np.ndarray | None = None) -> PETSc.Vec:
        """Full displacement u = P x_red (+ a superposed rigid field, per owned scalar DOF)."""
        u = self.K.createVecRight()
        self.P.mult(x_red, u)
        if rigid is not None:
            u.array[:] += rigid
        return u

    def function(self, u: PETSc.Vec, name: str = "u") -> dolfinx.fem.Function:
        """A DOLFINx Function holding the full displacement vector u (ghosts updated)."""
        fn = dolfinx.fem.Function(self.V, name=name)
        fn.x.array[: self.n_own] = u.getArray(readonly=True)
        fn.x.scatter_forward()
        return fn

"""An elastic body condensed onto the reference points of its couplings (a superelement).

A body that carries no contact, only loads at rigid couplings (the carrier: a pin at each
pinion, held at its hub), enters the contact problem through its stiffness at the couplings'
reference DOFs q alone. With the couplings' reference DOFs free in the FE system (stiffness
0) and the body held elsewhere (Dirichlet), K_red is regular and

    F = E^T K_red^{-1} E,   S = F^{-1},                                          (1)

E the unit columns of the reference DOFs: F (n_q x n_q) is the compliance at the reference
points and S the condensed (Schur complement) stiffness, exact for the linear FE model. S is
added to the rigid unknowns' stiffness K_r (:class:`solvers.contact.StiffnessBlock`), and the
body's displacement for given reference loads lambda = S q is u = X lambda, X = K_red^{-1} E.
One factorization and n_q solves, kept with the body across positions and cases.
"""

from __future__ import annotations

import dolfinx_solver  # noqa: F401 - orders MPI ahead of the bindings

# isort: split
import numpy as np
from petsc4py import PETSc

from solvers.elastic_body import ElasticBody


class Superelement:
    """The condensed stiffness of a set-up body at the reference DOFs of its couplings.

    Attributes:
        body: the :class:`solvers.elastic_body.ElasticBody` (couplings' DOFs free).
        dofs: (coupling name, DOF index) per row/column of S, couplings in body order.
        S: (n_q, n_q) condensed stiffness (N/mm, N mm/rad; body-frame coupling axes).
    """

    def __init__(self, body: ElasticBody):
        self.body = body
        body.setup()
        self.dofs = [(c, j) for c, cp in body.couplings.items() for j in range(cp.nr)]
        n_q = len(self.dofs)
        rows = [body.ref_offset[c] + j for c, j in self.dofs]
        N = body.K_red.getSize()[0]
        m_loc = body.K_red.getLocalSize()[0]
        E = PETSc.Mat().createDense(((m_loc, N), (PETSc.DECIDE, n_q)), comm=body.comm)
        E.setUp()
        r0, r1 = E.getOwnershipRange()
        for k, g in enumerate(rows):
            if r0 <= g < r1:
                E.setValue(g, k, 1.0)
        E.assemble()
        self.X = body.solve_dense(E)  # K_red^{-1} E, N x n_q (distributed rows)
        Xl = self.X.getDenseArray(readonly=True)
        mine = np.array([(g - r0, k) for k, g in enumerate(rows) if r0 <= g < r1], dtype=int)
        F = np.zeros((n_q, n_q))
        if len(mine):
            F[mine[:, 1], :] = Xl[mine[:, 0], :]
        F = body.comm.allreduce(F)
        F = 0.5 * (F + F.T)
        self.F = F
        self.S = np.linalg.inv(F)
        E.destroy()

    def displacement(self, loads: np.ndarray) -> PETSc.Vec:
        """Full displacement u = P X lambda of the body for reference loads ``loads``
        (n_q, along the coupling axes; N, N mm)."""
        x_red = self.body.K_red.createVecRight()
        x_red.setArray(self.X.getDenseArray(readonly=True) @ np.asarray(loads, dtype=float))
        return self.body.expand(x_red)

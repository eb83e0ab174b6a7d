"""Solver layer: elastic bodies, rigid couplings (bearings), condensed penalty contact.

``dolfinx_solver`` is imported here so that every ``solvers`` module orders MPI ahead of the
DOLFINx bindings, whatever the importer did first.
"""

import dolfinx_solver  # noqa: F401 - orders MPI ahead of the bindings

"""The contact grid's size against the machine, checked before anything is meshed.

The contact solve holds the grid's compliance as a dense matrix on every rank
(:class:`solvers.contact.ContactProblem`: ``C``, n x n doubles for n grid cells) and each
active-set step forms and factorizes a dense system of the active cells (up to n x n again,
and the LU's copy of it). The cells scale as 1 / grid_spacing^2 (along the line by the
spacing, across it by cells of at most half the spacing), so a grid spacing the validator
allows (down to 0.01 mm) can ask for terabytes: 1-GA's zone grid has 4216 cells at its
0.45 mm and 57977 at 0.1 mm (27 GB for C alone). Such a case is refused up front with the
spacing that fits, instead of meshing for minutes and then running out of memory.

The estimate, per rank: C plus the active-set system and its LU copy at their largest
(every cell active), CONTACT_COPIES x 8 n^2 bytes, an upper bound; the budget is
MEMORY_SHARE of the machine's physical memory shared by the ranks of the job (counted as if
on one machine). It is a guard
against the certainly impossible, not a tight bound: the bodies' own memory comes on top,
and a case it passes may still not fit (the case sizes' system scenes: 19144 cells, 8.8 GB
by this bound per rank, peak 19-21 GB on two ranks).
"""

from __future__ import annotations

import os

from cases.gearset import CaseError
from solvers.gear_train import contact_grids
from studies.position import train_inputs

__all__ = [
    "CONTACT_COPIES",
    "MEMORY_SHARE",
    "check_contact_size",
    "contact_bytes",
    "machine_memory",
]

#: dense n x n arrays the contact solve holds at its largest (C, the active system, its LU)
CONTACT_COPIES = 3
#: below this spacing (mm) the cells are counted at it and scaled by 1 / spacing^2
PROBE_SPACING = 0.2
#: share of the physical memory the contact matrices may take by the bound
MEMORY_SHARE = 0.8


_PASSED: set = set()  # (study, spacing, ranks, memory) found to fit


def contact_bytes(n_cells: int) -> int:
    """Bytes of the dense contact matrices of a grid of ``n_cells`` cells on one rank."""
    return CONTACT_COPIES * 8 * n_cells * n_cells


def machine_memory() -> int:
    """Physical memory of this machine, bytes."""
    return os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")


def check_contact_size(study, spacing: float, scene, comm=None, memory: int | None = None):
    """:class:`cases.gearset.CaseError` where the contact grid of ``scene`` at ``spacing``
    (mm) needs more than MEMORY_SHARE of ``memory`` on the ranks of ``comm`` (module
    docstring); the message names the spacing that fits. ``memory`` defaults to this
    machine's. Not collective: a rank that refuses while others pass (machines of different
    sizes) is shared by the command's input check (studies.run.inputs_valid, which every
    rank joins) before anything is solved. Pure geometry: the
    grids of one position, about a second; below PROBE_SPACING the cells are counted at it
    and scaled (1-GA: 15205 cells at 0.2 mm give 60820 at 0.1, 57977 counted)."""
    ranks = 1 if comm is None else comm.size
    memory = machine_memory() if memory is None else memory
    key = (repr(study), float(spacing), ranks, memory)
    if key in _PASSED:  # the run checks each case twice (all cases first, then each run)
        return
    probe = max(spacing, PROBE_SPACING)  # a fine grid would take minutes just to lay out
    _, pairs = contact_grids(scene, train_inputs(study), probe)
    n = round(sum(p.grid.n for p in pairs) * (probe / spacing) ** 2)
    need = ranks * contact_bytes(n)
    budget = MEMORY_SHARE * memory
    if need <= budget:
        _PASSED.add(key)
        return
    fits = spacing * (need / budget) ** 0.25  # n ~ 1 / spacing^2, bytes ~ n^2
    given = study.numerics.grid_spacing
    field = (
        f"numerics.grid_spacing = {given:g} mm"
        if given is not None
        else f"the grid spacing {spacing:g} mm (the flank element size of the mesh level)"
    )
    raise CaseError(
        f"{study.name}: {field} gives a contact grid of about {n} cells, whose dense compliance "
        f"needs about {need / 1e9:.0f} GB ({CONTACT_COPIES} x 8 n^2 bytes per rank, {ranks} "
        f"rank{'s' * (ranks > 1)}), more than {MEMORY_SHARE:.0%} of this machine's "
        f"{memory / 1e9:.0f} GB: set numerics.grid_spacing >= {1.05 * fits:.2g} mm (the cells "
        "grow as 1 / spacing^2)"
    )

"""The serial reference of a parallel-consistency test, solved once on rank 0 only.

Solving the serial reference on every rank (``COMM_SELF`` on each) holds one full serial
model per rank next to the parallel one: twice the memory for nothing. Rank 0 solves it and
broadcasts the result; a failure there is broadcast too, so no rank waits for ever.
"""

from mpi4py import MPI


def serial_on_rank0(solve):
    """``solve(MPI.COMM_SELF)`` on rank 0 of COMM_WORLD, its result on every rank."""
    comm = MPI.COMM_WORLD
    result = error = None
    if comm.rank == 0:
        try:
            result = solve(MPI.COMM_SELF)
        except Exception as exc:  # handed to every rank, raised there
            error = f"{type(exc).__name__}: {exc}"
    result, error = comm.bcast((result, error), root=0)
    if error is not None:
        raise RuntimeError(f"serial reference on rank 0 failed: {error}")
    return result

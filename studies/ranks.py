"""MPI-safe failure: every rank learns of an error on any rank, and no rank is left waiting.

Under ``mpiexec -n N`` every rank runs the same steps; an exception on one rank only (a
PETSc or DOLFINx error in a solve, a full disk on rank 0) must not let the other ranks go on
to a collective call alone, or the job hangs until it is killed. After each step that can
fail on one rank, every rank calls :meth:`Ranks.agree` with its own failure (None if the
step went well) and gets back the failures of all ranks, the same list everywhere, so they
take the same branch (record the failure and go on, or stop).

A rank that failed while the others are blocked inside a collective call of the step it
left (a MUMPS factorization, a mesh broadcast) cannot be reached by any message. It waits
for them at most :data:`DEFAULT_TIMEOUT_S` seconds (``PLANETARY_RANK_TIMEOUT`` overrides),
then prints its error (and appends it to ``log``, if given: mpiexec may drop the last
output of a job it aborts) and aborts the whole job with exit code
:data:`EXIT_RANKS_OUT_OF_STEP`: finished results stay on disk, nothing hangs.

The agreement runs on a duplicate of the communicator, so it never matches a collective
call of the solver on the original one.
"""

from __future__ import annotations

import os
import sys
import time
from pathlib import Path

#: exit code of a job aborted because its ranks could not agree (documented in README.md)
EXIT_RANKS_OUT_OF_STEP = 4

# How long a failed rank waits for the others before it aborts the job. After one rank has
# failed, the others either reach the agreement soon (they failed too, or finished the step)
# or never (they wait in a collective call the failed rank left). The longest legitimate
# lag is serial work on rank 0 inside a step, e.g. gmsh building a cold mesh cache (21 s for
# the level-3 one-branch scene, meshing.sizing; more for larger scenes), hence 120 s.
DEFAULT_TIMEOUT_S = 120.0
_POLL_S = 0.01
# Pause between printing the error and MPI_Abort: the rank's stderr goes through a pipe to
# mpiexec's proxy, which is killed by the abort; without the pause a loaded machine lost the
# message (CI, 2 cores). One second is ample for the proxy to forward one line.
_FLUSH_S = 1.0


def rank_timeout() -> float:
    """The wait of a failed rank in seconds (``PLANETARY_RANK_TIMEOUT`` or the default)."""
    raw = os.environ.get("PLANETARY_RANK_TIMEOUT", "")
    try:
        value = float(raw) if raw else DEFAULT_TIMEOUT_S
    except ValueError:
        value = DEFAULT_TIMEOUT_S
    return value if value > 0 else DEFAULT_TIMEOUT_S


class Ranks:
    """Failure agreement over ``comm`` (collective to create: every rank must construct it
    at the same point)."""

    def __init__(self, comm, timeout: float | None = None, log: Path | None = None):
        self.comm = comm
        self.log = log
        self.timeout = rank_timeout() if timeout is None else float(timeout)
        self._side = comm.Dup() if comm.size > 1 else None

    def agree(self, failure, what: str) -> list[tuple[int, object]]:
        """Every rank calls this after the step ``what`` with its failure (any picklable
        object, e.g. a message; None if the step went well). Returns ``[(rank, failure)]``
        of every rank that failed, in rank order, the same on every rank."""
        if self._side is None:
            return [] if failure is None else [(0, failure)]
        req = self._side.Ibarrier()
        if failure is None:
            req.Wait()  # the failed rank arrives, or aborts the job after its timeout
        else:
            deadline = time.monotonic() + self.timeout
            while not req.Test():
                if time.monotonic() > deadline:
                    self._abort(failure, what)
                time.sleep(_POLL_S)
        return [(r, f) for r, f in enumerate(self._side.allgather(failure)) if f is not None]

    def _abort(self, failure, what: str) -> None:
        message = failure[0] if isinstance(failure, tuple) else failure
        line = (
            f"error: rank {self.comm.rank}: {what}: {message}; the other ranks did not reach "
            f"the same point within {self.timeout:g} s (they wait in a collective call this "
            f"rank left), so the job is aborted (exit code {EXIT_RANKS_OUT_OF_STEP}); "
            "finished results are kept\n"
        )
        if self.log is not None:
            try:
                self.log.parent.mkdir(parents=True, exist_ok=True)
                with open(self.log, "a", encoding="utf-8") as f:
                    f.write(line)
            except OSError:
                pass  # the message still goes to stderr
        sys.stderr.write(line)
        sys.stderr.flush()
        time.sleep(_FLUSH_S)
        self.comm.Abort(EXIT_RANKS_OUT_OF_STEP)

    def free(self) -> None:
        if self._side is not None:
            self._side.Free()
            self._side = None

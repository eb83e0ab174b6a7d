"""Exit codes and one-line messages of the entry points (documented in README.md, "Exit codes
and messages").

Every failure a user can cause or meet ends in one line ``error: ...`` that names the file,
field or option and what is allowed, and in an exit code by kind. A Python traceback is
printed only with ``--traceback`` (for a bug report); position failures keep theirs in
``summary.json`` (``failed_positions``).
"""

from __future__ import annotations

import contextlib
import signal
import sys
import threading
from pathlib import Path

from cases.gearset import CaseError
from gears.spec import GeometryError
from meshing.cache import CacheDirError
from meshing.sizing import MeshingError
from studies.files import ResultFileError
from studies.ranks import EXIT_RANKS_OUT_OF_STEP

EXIT_OK = 0
#: a mesh position failed while solving; finished positions are kept (summary.json lists the
#: failed ones; it is not written when no position finished)
EXIT_POSITION_FAILED = 1
#: invalid input: a case file, a gear set, a command-line option; nothing was solved
EXIT_INVALID_INPUT = 2
#: a result or cache file or folder could not be written or read (full disk, permissions,
#: a file where a folder should be)
EXIT_FILES = 3
#: MPI ranks out of step: one rank failed while the others waited in a collective call; the
#: job was aborted (:mod:`studies.ranks`); finished positions are kept
EXIT_RANKS = EXIT_RANKS_OUT_OF_STEP
#: an unexpected error (a bug): rerun with --traceback and report it
EXIT_INTERNAL = 5
#: interrupted (Ctrl-C; SIGTERM in a serial process, :func:`interrupt_on_sigterm`)
EXIT_INTERRUPTED = 130


class InputError(ValueError):
    """A command-line option or a combination of inputs is invalid (the message names the
    option and what is allowed)."""


class StudyFailed(RuntimeError):
    """Mesh positions failed while solving; finished positions are kept on disk."""


INPUT_ERRORS = (CaseError, GeometryError, MeshingError, InputError)
FILE_ERRORS = (ResultFileError, CacheDirError, OSError)


def exit_code(exc: BaseException) -> int:
    """The exit code of a failure (see the module constants)."""
    if isinstance(exc, KeyboardInterrupt):
        return EXIT_INTERRUPTED
    if isinstance(exc, StudyFailed):
        return EXIT_POSITION_FAILED
    if isinstance(exc, INPUT_ERRORS):
        return EXIT_INVALID_INPUT
    if isinstance(exc, FILE_ERRORS):
        return EXIT_FILES
    return EXIT_INTERNAL


def one_line(exc: BaseException) -> str:
    """The message of ``exc`` on one line; errors the pipeline raises for the user are their
    message alone, anything else is prefixed by its type (``ZeroDivisionError: ...``)."""
    text = " ".join(str(exc).split()) or "(no message)"
    if isinstance(exc, (*INPUT_ERRORS, ResultFileError, CacheDirError, StudyFailed)):
        return text
    return f"{type(exc).__name__}: {text}"


def with_path(text: str, name: str) -> str:
    """The case loader names a file by its name (``my_case.toml: ...``); the path the user
    gave is clearer when the case is not in cases/."""
    base = Path(name).name
    if name.endswith(".toml") and name != base and text.startswith(f"{base}: "):
        return f"{name}: {text[len(base) + 2 :]}"
    return text


def _interrupt(signum, frame) -> None:
    raise KeyboardInterrupt(f"stopped by {signal.Signals(signum).name}")


@contextlib.contextmanager
def interrupt_on_sigterm():
    """Within the block, SIGTERM (``kill``, a batch system's time limit) unwinds a serial
    process as Ctrl-C does, so its ``finally`` blocks run: the out-of-core factor folders of
    a convergence ladder (tens of GB at level 2) are removed instead of left in the temporary
    folder. Under MPI (``mpi4py`` imported, more than one rank) SIGTERM keeps its default: a
    rank unwinding alone could wait forever in a collective call for the others. After the
    block the caller's handler is back (a test process, a notebook)."""
    mpi = sys.modules.get("mpi4py.MPI")
    serial = mpi is None or mpi.COMM_WORLD.Get_size() == 1
    if not serial or threading.current_thread() is not threading.main_thread():
        yield
        return
    before = signal.signal(signal.SIGTERM, _interrupt)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, before)


def guarded(body, *, traceback: bool = False) -> int:
    """Run an entry point's ``body()`` and turn a failure into one line ``error: ...`` on
    stderr and the pipeline's exit code (with ``traceback``, re-raise for a bug report).
    A serial process stops on SIGTERM as on Ctrl-C (:func:`interrupt_on_sigterm`)."""
    try:
        with interrupt_on_sigterm():
            body()
    except KeyboardInterrupt as exc:
        if traceback:
            raise
        print(f"error: interrupted ({str(exc) or 'Ctrl-C'})", file=sys.stderr)
        return EXIT_INTERRUPTED
    except Exception as exc:
        if traceback:
            raise
        print(f"error: {one_line(exc)}", file=sys.stderr)
        return exit_code(exc)
    return EXIT_OK

"""Result files written safely: atomically (a reader never sees half a file, a kill or a full
disk never leaves a truncated one) and under MPI from rank 0 with the outcome shared, so an
I/O error on rank 0 ends every rank with the message instead of leaving the others waiting."""

from __future__ import annotations

import json
import os
import tempfile
from collections.abc import Callable
from pathlib import Path

# The process umask, read once (os.umask can only be read by setting it): result files get
# the permissions any new file gets (mkstemp alone would make them private, 0600).
_UMASK = os.umask(0o022)
os.umask(_UMASK)


class ResultFileError(OSError):
    """A result file or folder could not be written or read; the message names it."""


def atomic_write_text(path: Path, text: str) -> None:
    """Write ``text`` to ``path`` through a temporary file in the same folder + rename."""
    path = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        os.fchmod(fd, 0o666 & ~_UMASK)
        with os.fdopen(fd, "w") as f:
            f.write(text)
            f.flush()
            os.fsync(f.fileno())  # on disk before the rename: no empty file after a crash
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def write_json(path: Path, data) -> None:
    atomic_write_text(path, json.dumps(data, indent=1) + "\n")


def read_json(path: Path):
    """The JSON in ``path``; a file that does not parse raises :class:`ResultFileError`
    naming it."""
    try:
        return json.loads(Path(path).read_text())
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise ResultFileError(f"{path}: cannot read ({exc})") from exc


def describe(exc: BaseException) -> str:
    """One line for an error met while reading or writing: the OS reason and the file for an
    :class:`OSError` (``No space left on device (results/1-GA/positions/0.json)``), the
    message of a :class:`ResultFileError`, type and message of anything else."""
    if isinstance(exc, ResultFileError):
        text = str(exc)
    elif isinstance(exc, OSError) and exc.strerror:
        text = f"{exc.strerror} ({exc.filename})" if exc.filename else exc.strerror
    else:
        text = f"{type(exc).__name__}: {exc}"
    return " ".join(text.split())


def on_root(comm, action: Callable[[], object], what: str):
    """Run ``action`` on rank 0 only and return its result on every rank; an exception there
    is re-raised on every rank as :class:`ResultFileError` (``what`` names the step)."""
    value, err = None, None
    if comm.rank == 0:
        try:
            value = action()
        except Exception as exc:  # shared with the other ranks below
            err = f"{what}: {describe(exc)}"
    if comm.size > 1:
        err, value = comm.bcast((err, value), root=0)
    if err is not None:
        raise ResultFileError(err)
    return value

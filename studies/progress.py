"""What a person reads while a study runs: rank 0 only, plain text.

* a line per mesh position that grows stage by stage (``scene``, ``meshes``, ``model``,
  ``solve``, ``post``), each stage's elapsed time written when the next one starts, so a
  long stage shows which one it is;
* a result line per position with a compact progress bar, the elapsed time and an estimate
  of the time left; reused positions are said to be reused;
* ``warning: ...`` and ``error: ...`` lines on stderr, also in quiet mode.

No colour codes and no carriage returns: the output reads the same on a terminal and in a
log file. Quiet mode (``--quiet``, ``make ... QUIET=1``) keeps only warnings and errors.
"""

from __future__ import annotations

import sys
import time


def clock(seconds: float) -> str:
    """``m:ss`` (or ``h:mm:ss``) for a duration in seconds."""
    s = round(max(seconds, 0.0))
    h, rest = divmod(s, 3600)
    m, s = divmod(rest, 60)
    return f"{h}:{m:02d}:{s:02d}" if h else f"{m}:{s:02d}"


def bar(done: int, total: int, width: int = 20) -> str:
    """``[####......]``: ``done`` of ``total`` in at most ``width`` characters."""
    width = max(1, min(width, total))
    filled = round(width * done / total) if total else width
    return "[" + "#" * filled + "." * (width - filled) + "]"


class Progress:
    """Progress and messages of one run (``comm``: only rank 0 writes; None: this process).
    ``out``/``err`` default to the current ``sys.stdout``/``sys.stderr``."""

    def __init__(self, comm=None, quiet: bool = False, out=None, err=None):
        self.rank0 = comm is None or comm.rank == 0
        self.quiet = quiet
        self._out, self._err = out, err
        self._open = False  # a stage line is being written (no newline yet)

    @property
    def out(self):
        return self._out or sys.stdout

    @property
    def err(self):
        return self._err or sys.stderr

    def _write(self, stream, text: str) -> None:
        stream.write(text)
        stream.flush()

    def _end_line(self) -> None:
        if self._open:
            self._write(self.out, "\n")
            self._open = False

    def info(self, text: str) -> None:
        """A line of progress (not in quiet mode)."""
        if self.rank0 and not self.quiet:
            self._end_line()
            self._write(self.out, text + "\n")

    def warn(self, text: str) -> None:
        """``warning: text`` on stderr (also in quiet mode)."""
        if self.rank0:
            self._end_line()
            self._write(self.err, f"warning: {text}\n")

    def error(self, text: str) -> None:
        """``error: text`` on stderr (also in quiet mode)."""
        if self.rank0:
            self._end_line()
            self._write(self.err, f"error: {text}\n")

    def position(self, label: str) -> StageLine:
        """The stage line of one position, headed ``label``."""
        return StageLine(self, label)


class StageLine:
    """``label: scene 0.0 s | meshes 2.1 s | model 4.0 s | solve 12.2 s | post 0.4 s``,
    written as the stages go. Call it with the name of each stage as the stage starts (the
    hook :func:`studies.position.solve_position` takes), then :meth:`close`."""

    def __init__(self, progress: Progress, label: str):
        self.p = progress
        self.label = label
        self.stage: str | None = None
        self.times: dict[str, float] = {}
        self.t0 = self._t = time.perf_counter()

    def _show(self) -> bool:
        return self.p.rank0 and not self.p.quiet

    def __call__(self, stage: str) -> None:
        now = time.perf_counter()
        text = ""
        if self.stage is None:
            if self._show():
                self.p._end_line()
            text = f"{self.label}: {stage}"
        else:
            self.times[self.stage] = now - self._t
            text = f" {now - self._t:.1f} s | {stage}"
        self.stage, self._t = stage, now
        if self._show():
            self.p._write(self.p.out, text)
            self.p._open = True

    def close(self, failed: bool = False) -> float:
        """End the line (``failed``: the current stage did not finish); returns the wall
        time since the line was started."""
        now = time.perf_counter()
        if self.stage is not None:
            self.times[self.stage] = now - self._t
            if self._show() and self.p._open:
                self.p._write(self.p.out, " failed\n" if failed else f" {now - self._t:.1f} s\n")
                self.p._open = False
        return now - self.t0


class LoopClock:
    """Elapsed time and an estimate of the time left over a loop of ``total`` items, of which
    ``to_work`` take work (the others are reused). The first item worked pays the set-up
    (bodies factorized, sectors built) that the others reuse, so it is left out of the
    estimate: the time left is the mean of the items worked after it times the number still
    to work, and none is given before one is known (the first's cost would overstate the
    rest several times over)."""

    def __init__(self, total: int, to_work: int):
        self.total, self.to_work = total, to_work
        self.done = 0
        self.t0 = time.perf_counter()
        self._times: list[float] = []

    def step(self, seconds: float | None = None) -> None:
        """One item finished after ``seconds`` of work (None: reused)."""
        self.done += 1
        if seconds is not None:
            self._times.append(seconds)

    def status(self) -> str:
        """``[###..] 3/5, 0:45 elapsed, about 0:30 left``."""
        elapsed = time.perf_counter() - self.t0
        text = f"{bar(self.done, self.total)} {self.done}/{self.total}, {clock(elapsed)} elapsed"
        left = self.to_work - len(self._times)
        if left <= 0 or not self._times:
            return text
        reused_cost = self._times[1:]
        if reused_cost:
            text += f", about {clock(left * sum(reused_cost) / len(reused_cost))} left"
        else:
            text += (
                f" (the first took {clock(self._times[0])} with the set-up; the time left "
                "follows from the next)"
            )
        return text

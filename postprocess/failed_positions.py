"""The line a report prints for a case whose study lost mesh positions: the summary's means
and cycle maxima are then over the positions that finished (``summary.json``
``failed_positions``, :func:`postprocess.summary.summarize`), which a table of values alone
does not show."""

from __future__ import annotations

from collections.abc import Mapping


def failed_positions_lines(runs: Mapping[str, Mapping]) -> list[str]:
    """One warning line per case with failed positions (none: an empty list), each naming
    the positions, the first error and how many positions the values are over."""
    lines = []
    for name, s in runs.items():
        failed = s.get("failed_positions") or []
        if not failed:
            continue
        # stored from 0 (studies.run), named from 1 as the run's log and error name them
        which = ", ".join(
            str(k + 1) if isinstance(k := f.get("position"), int) else "?" for f in failed
        )
        first = str(failed[0].get("error", "no error recorded")).splitlines()[0]
        lines.append(
            f"**Warning: {name} lost position(s) {which} of "
            f"{len(failed) + len(s.get('positions') or [])}** (first error: {first}); its "
            f"means and cycle maxima are over the {len(s.get('positions') or [])} that finished."
        )
    return ["", *lines, ""] if lines else []

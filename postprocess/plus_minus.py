"""The ± a report prints beside a value of a case summary, from the summary's
``uncertainty`` (:func:`postprocess.convergence_record.uncertainty_for`: the relative uncertainty of
each scalar in the convergence study of its gear set, scene and numerics).

A moment or a stress takes the study's relative uncertainty times its own value: every case
of a gear set shares the study of one of them (1-GB's for case 1, 2B-GA's for case 2), and
it is the relative error that carries between cases whose bearings differ.

An offset (``Z*``, ``*_mm``, ``*_um``: load-centroid offsets, misalignments) can sit near
zero, where its relative uncertainty says nothing. In the study's own case it takes the
study's absolute uncertainty (there the same number as the relative one times the value).
In another case the absolute one alone would be wrong: 2B-GA (rigid bearing) has ZS =
-0.012 mm with U = 0.017 mm, 2B-GB has ZS = -3.69 mm. So another case takes the relative one
only where the study's offset is clear of zero (U at most :data:`OFFSET_REL_MAX` of it:
1-GB's ZS 3.1 %, 2B-GA's f_ma_SPRP_um 1.1 %), and never less than the study's absolute U
(the same grids put the centroid no closer in another case: 1-GA's ZS of -0.19 mm took
3.1 % of itself, 0.006 mm, against 1-GB's 0.096 mm); otherwise :data:`NOT_CARRIED` is
printed, not a number. A difference of two larger moments
(:data:`postprocess.paper_moments.DIFFERENTIALS`) errs like an offset, by its moments' U,
not its own size: in another case it takes the larger of the two too.
"""

from __future__ import annotations

from collections.abc import Mapping

from postprocess.paper_moments import DIFFERENTIALS
from postprocess.run_scalars import lookup, scalar_kind

#: an offset whose relative uncertainty in the study is above this is within four U of zero
#: there: its error is the study's absolute floor, which does not scale to another case's
#: offset, so none is carried (2B-GA at level 1: ZS 137 %, ZR 54 %, Z_SPRP 2.8 %)
OFFSET_REL_MAX = 0.25
#: printed in place of an offset's ± that the study cannot give this case
NOT_CARRIED = " ± n/a"
#: the rule in one sentence, for the reports that print offsets
OFFSET_NOTE = (
    "The ± of an offset: the study's absolute U in the study's own case; in another case the "
    "study's relative U times the offset, at least the study's absolute U, where the study's "
    f"offset is clear of zero (U at most {OFFSET_REL_MAX:.0%} of it), else n/a "
    "(postprocess/plus_minus.py)."
)


def _number(v) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def plus_minus(summary: Mapping, key: str, fmt: str = ".1f", value: float | None = None) -> str:
    """`` ± x`` (in the value's unit) for ``key`` of a summary with an ``uncertainty``
    ('' without one, or where the study gives none for the key); ``value`` the printed
    value when it is not the summary's own at ``key`` (a maximum, a derived form)."""
    rel = (summary.get("uncertainty") or {}).get(key)
    absolute = (summary.get("uncertainty_abs") or {}).get(key)
    value = lookup(summary, key) if value is None else value
    study_case = (summary.get("uncertainty_source") or {}).get("case")
    own = study_case is not None and study_case == summary.get("case")
    floor = absolute if _number(absolute) and not own else 0.0  # another case: the study's U
    if scalar_kind(key) != "offset":
        u = rel * abs(value) if _number(rel) and _number(value) else None
        if u is not None and key in DIFFERENTIALS:
            u = max(u, floor)
        return "" if u is None else f" ± {format(u, fmt)}"
    if own:
        return "" if not _number(absolute) else f" ± {format(absolute, fmt)}"
    if absolute is None and rel is None:
        return ""  # the study has no uncertainty for this key at all
    if _number(rel) and rel <= OFFSET_REL_MAX and _number(value):
        return f" ± {format(max(rel * abs(value), floor), fmt)}"
    return NOT_CARRIED

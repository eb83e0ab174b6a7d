"""Discretisation error of a scalar from a mesh ladder: Richardson extrapolation with the
observed order and Roache's grid convergence index (GCI), for three grids of any ratios.

Three solutions f1, f2, f3 on grids of size h1 < h2 < h3 (fine, medium, coarse), assumed in
the asymptotic range f(h) = f_ext + C h^p (Celik et al. 2008, J. Fluids Eng. 130 078001,
the generalised form for ratios r21 = h2/h1, r32 = h3/h2 that differ):

    e21 = f2 - f1,  e32 = f3 - f2,  R = e32 / e21
    R = r21^p (r32^p - 1) / (r21^p - 1)           (solved for p; r^p for a constant ratio r)
    f_ext = f1 - e21 / (r21^p - 1) = (r21^p f1 - f2) / (r21^p - 1)
    GCI_k = Fs |f_k - f_ext| / |f_k|,  Fs = 1.25  (the uncertainty of level k; for the fine
            grid this is Roache's GCI_fine = Fs |e21 / f1| / (r21^p - 1))

The observed order p is what the data say; the GCI uses min(p, p_cap) when a cap is given
(Roache: an observed order above the formal one is not trusted, the smaller order is the
conservative one). When the three grids do not converge monotonically there is no
extrapolation, and the uncertainty of every level falls back to the spread of the levels,
(max f - min f) / |f_k|, with the status saying why (:func:`richardson`):

* ``zero``: every value is below ``zero_scale`` (a quantity that vanishes, read as
  round-off); no extrapolation and no relative number;
* ``mesh-independent``: the three values agree to round-off (an input, not an FE result), or
  within the solver's noise (``noise``: a change below an iterative solve's tolerance has no
  sign, so neither an order nor an oscillation can be read from it; a finer pair within it
  counts as ``stagnant``, a coarser pair as ``divergent``);
* ``oscillatory``: e21 and e32 differ in sign;
* ``divergent``: the changes grow as the grid is refined (p <= 0);
* ``stagnant``: they barely shrink (0 < p < P_MIN): r^p - 1 < 0.2 for these ratios, so an
  extrapolation would multiply the last change by more than five, more than three grids
  support.

Where only two grids are run (a third that does not fit in memory or time, ``--levels 0 1``),
:func:`two_grid` gives Roache's two-grid GCI with the formal order assumed (the caller's,
:func:`studies.convergence.reduction._p_cap`) and the factor of safety 3: an uncertainty, no
extrapolated value.

A run off the ladder (another degree, e.g. P2 at the coarsest level) is compared with the
extrapolated value in the same way (:func:`off_ladder`).

:mod:`postprocess.convergence_record` reads a reduced study into a summary's ``uncertainty``
entry (:mod:`postprocess.plus_minus` prints it beside a value); the factors of safety are
defined there, with the record format. The scalars a run records are read by
:mod:`postprocess.run_scalars`. This module and :mod:`studies.convergence.reduction` are
reductions of stored runs, outside the source hash: a study is reduced when it is written
(:func:`studies.convergence.reduction.reduce_study`), and ``python -m studies.convergence
--reduce-records`` reduces the records again after a change to them.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import asdict, dataclass

from postprocess.convergence_record import SAFETY, SAFETY_TWO_GRID

P_MIN = 0.5  # below: stagnant (see the module docstring)
P_BOUNDS = (-10.0, 20.0)  # the observed order is searched in here
SAME_RTOL = 1e-9  # three values within this (relative) are mesh-independent

MOMENT_RTOL = 0.01  # issue 13: moments within 1 % of the extrapolated value
STRESS_RTOL = 0.05  # and stresses within 5 %
# A relative error is given only where the value is above this fraction of the largest
# value of its kind (Mz_pin of a pinion free to spin is round-off, not a moment to quote).
NEAR_ZERO = 1e-3


@dataclass(frozen=True)
class Richardson:
    """The convergence of one scalar over three grids (values per grid as given: same
    order as the ``h`` and ``f`` passed to :func:`richardson`)."""

    status: str  # monotone, oscillatory, divergent, stagnant, zero, mesh-independent, two-grid
    order: float | None  # observed order p (None unless solved)
    extrapolated: float | None  # f_ext (None unless monotone)
    rel_error: tuple[float | None, ...]  # (f_k - f_ext) / |f_ext| per grid
    uncertainty: tuple[float | None, ...]  # relative, per grid (GCI or spread)
    uncertainty_abs: tuple[float, ...]  # the same in the scalar's unit
    gci_order: float | None  # the order the GCI used: min(p, p_cap)
    note: str  # one line: what was done and why

    def as_dict(self) -> dict:
        return asdict(self)


def _ratio_function(p: float, r21: float, r32: float) -> float:
    """ln F(p), F(p) = r21^p (r32^p - 1) / (r21^p - 1); F(0) = ln r32 / ln r21 (the limit)."""
    a, b = math.log(r21), math.log(r32)
    if abs(p) < 1e-12:
        return math.log(b / a)
    return p * a + math.log(math.expm1(p * b) / math.expm1(p * a))


def observed_order(r21: float, r32: float, ratio: float) -> float:
    """The p with r21^p (r32^p - 1) / (r21^p - 1) = ``ratio`` (= e32 / e21 > 0), by
    bisection on its logarithm (monotone in p); clipped to :data:`P_BOUNDS`. For a constant
    ratio r this is ln(ratio) / ln r."""
    if not (r21 > 1.0 and r32 > 1.0 and ratio > 0.0):
        raise ValueError(
            f"observed_order needs r21, r32 > 1 and ratio > 0, got {r21}, {r32}, {ratio}"
        )
    target = math.log(ratio)
    lo, hi = P_BOUNDS
    if _ratio_function(lo, r21, r32) >= target:
        return lo
    if _ratio_function(hi, r21, r32) <= target:
        return hi
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if _ratio_function(mid, r21, r32) < target:
            lo = mid
        else:
            hi = mid
        if hi - lo < 1e-12:
            break
    return 0.5 * (lo + hi)


def _rel(num: float, den: float) -> float | None:
    return abs(num) / abs(den) if den != 0.0 else None


def richardson(
    h: Sequence[float],
    f: Sequence[float],
    *,
    safety: float = SAFETY,
    p_cap: float | None = None,
    zero_scale: float = 0.0,
    noise: float = 0.0,
) -> Richardson:
    """Richardson extrapolation and GCI of three values ``f`` on grids of size ``h`` (any
    order, all different; see the module docstring for the equations and the statuses).
    ``p_cap``: the GCI uses min(p, p_cap); ``zero_scale``: relative numbers are None where
    the value they are relative to is below it (a quantity that is zero by physics);
    ``noise``: the solver's noise relative to the largest value (an iterative solve's
    tolerance): a change between two grids within it has no sign, so an order cannot be
    observed from it (without it, [110, 100 + 1e-6, 100] was monotone with U ~ 0 and
    [110, 100 - 1e-6, 100] oscillatory with U 10 %; both now take the spread)."""
    if len(h) != 3 or len(f) != 3:
        raise ValueError(f"richardson needs three grids, got {len(h)} sizes and {len(f)} values")
    if not all(math.isfinite(v) for v in (*h, *f)) or min(h) <= 0.0:
        raise ValueError(f"richardson needs finite values and sizes h > 0, got h={h}, f={f}")
    order = sorted(range(3), key=lambda i: h[i])
    if len({h[i] for i in order}) != 3:
        raise ValueError(f"richardson needs three different grid sizes, got h={list(h)}")
    (h1, h2, h3), (f1, f2, f3) = ([h[i] for i in order], [f[i] for i in order])
    r21, r32 = h2 / h1, h3 / h2
    e21, e32 = f2 - f1, f3 - f2
    spread = max(f) - min(f)
    big = max(abs(v) for v in f)

    def rel_or_none(num, den):
        return None if abs(den) <= zero_scale else _rel(num, den)

    def fallback(status: str, note: str, p: float | None) -> Richardson:
        return Richardson(
            status=status,
            order=p,
            extrapolated=None,
            rel_error=(None, None, None),
            uncertainty=tuple(rel_or_none(spread, v) for v in f),
            uncertainty_abs=(spread,) * 3,
            gci_order=None,
            note=note + "; uncertainty = spread of the levels (max - min)",
        )

    if big <= zero_scale:  # e.g. Mz of a pinion free to spin: round-off, nothing converges
        return fallback(
            "zero",
            "below the zero scale on every grid: the round-off of a quantity that vanishes",
            None,
        )
    if spread <= SAME_RTOL * big:
        return fallback("mesh-independent", "the same value on every grid", None)
    floor = noise * big
    if spread <= floor:
        return fallback("mesh-independent", "every grid within the solver's noise", None)
    if abs(e21) <= floor:
        return fallback(
            "stagnant", "the two finer grids agree within the solver's noise: no order", None
        )
    if abs(e32) <= floor:
        return fallback(
            "divergent",
            "the coarser pair agrees within the solver's noise but the finer does not",
            None,
        )
    if e21 * e32 < 0.0:
        return fallback("oscillatory", "changes alternate in sign: no extrapolation", None)
    if e21 == 0.0:  # the two finer grids agree exactly, the coarse one does not
        return fallback("stagnant", "the two finer grids agree exactly: no order", None)
    if e32 == 0.0:
        return fallback("divergent", "the coarser pair agrees but the finer does not", None)
    p = observed_order(r21, r32, e32 / e21)
    if p <= 0.0:
        return fallback("divergent", f"changes grow as the grid is refined (p = {p:.2f})", p)
    if p < P_MIN:
        return fallback("stagnant", f"changes barely shrink (p = {p:.2f} < {P_MIN})", p)
    f_ext = f1 - e21 / (r21**p - 1.0)
    p_gci = p if p_cap is None else min(p, p_cap)
    f_gci = f1 - e21 / (r21**p_gci - 1.0)
    note = f"monotone, observed order {p:.2f}"
    if p_gci < p:
        note += f" (above the cap {p_cap:g}: the GCI uses {p_gci:g})"
    if p >= P_BOUNDS[1]:
        note += "; the finer grids agree to within the order search: f_ext ~ the finest"
    return Richardson(
        status="monotone",
        order=p,
        extrapolated=f_ext,
        rel_error=tuple(None if abs(f_ext) <= zero_scale else (v - f_ext) / abs(f_ext) for v in f),
        uncertainty=tuple(
            None if abs(v) <= zero_scale else safety * abs(v - f_gci) / abs(v) for v in f
        ),
        uncertainty_abs=tuple(safety * abs(v - f_gci) for v in f),
        gci_order=p_gci,
        note=note,
    )


def two_grid(
    h: Sequence[float],
    f: Sequence[float],
    order: float,
    *,
    safety: float = SAFETY_TWO_GRID,
    zero_scale: float = 0.0,
) -> Richardson:
    """Roache's two-grid GCI with an assumed (formal) ``order`` p, for a ladder where the
    third grid does not fit in memory: with r = h2 / h1 (h1 < h2) and e21 = f2 - f1,

        GCI_fine = Fs |e21| / (r^p - 1) / |f1|,   GCI_coarse = Fs |e21| r^p / (r^p - 1) / |f2|,

    Fs = 3 (the order is not verified by a third grid). No extrapolated value and no error:
    two grids cannot tell whether they are in the asymptotic range; status ``two-grid``
    (``mesh-independent`` if the two agree to round-off, ``zero`` if both are below
    ``zero_scale``)."""
    if len(h) != 2 or len(f) != 2:
        raise ValueError(f"two_grid needs two grids, got {len(h)} sizes and {len(f)} values")
    if not all(math.isfinite(v) for v in (*h, *f)) or min(h) <= 0.0 or h[0] == h[1]:
        raise ValueError(f"two_grid needs finite values and two sizes h > 0, got h={h}, f={f}")
    if not order > 0.0:
        raise ValueError(f"two_grid needs an order > 0, got {order}")
    fine, coarse = sorted(range(2), key=lambda i: h[i])
    r = h[coarse] / h[fine]
    e21 = f[coarse] - f[fine]
    big = max(abs(v) for v in f)
    if big <= zero_scale:
        return Richardson(
            "zero",
            None,
            None,
            (None, None),
            (None, None),
            (abs(e21),) * 2,
            None,
            "below the zero scale on both grids: round-off",
        )
    if abs(e21) <= SAME_RTOL * big:
        return Richardson(
            "mesh-independent",
            None,
            None,
            (None, None),
            (0.0, 0.0),
            (0.0, 0.0),
            None,
            "the same value on both grids",
        )
    rp = r**order
    unc_abs = [0.0, 0.0]
    unc_abs[fine] = safety * abs(e21) / (rp - 1.0)
    unc_abs[coarse] = safety * abs(e21) * rp / (rp - 1.0)
    unc = tuple(
        None if abs(v) <= zero_scale else u / abs(v) for u, v in zip(unc_abs, f, strict=True)
    )
    return Richardson(
        status="two-grid",
        order=None,
        extrapolated=None,
        rel_error=(None, None),
        uncertainty=unc,
        uncertainty_abs=tuple(unc_abs),
        gci_order=order,
        note=f"two grids: GCI with the assumed order {order:g} and Fs {safety:g}, no "
        "extrapolation (a third grid did not fit)",
    )


def off_ladder(
    res: Richardson,
    f: float,
    f_ladder: Sequence[float],
    *,
    safety: float = SAFETY,
    zero_scale: float = 0.0,
) -> dict:
    """A run off the ladder (another element degree) against the ladder's result ``res``:
    its error relative to f_ext and its uncertainty Fs |f - f_ext| / |f|; without an
    extrapolation, the spread of the ladder and this value."""
    if res.extrapolated is not None:
        err = f - res.extrapolated
        rel = None if abs(res.extrapolated) <= zero_scale else err / abs(res.extrapolated)
        unc = safety * abs(err)
    else:
        rel = None
        unc = max(*f_ladder, f) - min(*f_ladder, f)
    return {
        "value": f,
        "rel_error": rel,
        "uncertainty_abs": unc,
        "uncertainty": None if abs(f) <= zero_scale else unc / abs(f),
    }

"""Planet phasing: which mesh-frequency harmonics reach the sun (parker2000).

Planet i sits at carrier angle psi_i (RADIANS throughout this module; convert degrees at the
call site with ``numpy.radians``). Its sun mesh lags the first by phi_i = Zs psi_i: one
carrier revolution relative to the sun passes Zs mesh cycles, so phi_i is in radians of mesh
phase and need not be a whole number of teeth (2 pi) for the rules below to hold.

Each mesh force is a Fourier series in the planet's local radial/tangential basis. Summing
the l-th harmonic over the planets in the carrier frame, the radial/tangential basis turns
with the planet (e^(+-i psi_i)), so the net sun force has the two rotating components and
the net sun torque the plain sum::

    force:  S-(l) = |sum_i exp(i (l phi_i - psi_i))|,   S+(l) = |sum_i exp(i (l phi_i + psi_i))|
    torque: T(l)  = |sum_i exp(i l phi_i)|

(a value of N means all planets add in phase; the net force of harmonic l is zero for any
mesh force waveform if and only if both S- and S+ vanish). The closed-form rules:

* equally spaced planets, psi_i = 2 pi (i - 1) / N, k = mod(l Zs, N): k = 0 -> force zero,
  torque non-zero; k = 1 or N - 1 -> force non-zero, torque zero; otherwise both zero.
* diametrically opposed pairs (psi_(M+i) = psi_i + pi, N = 2M): l Zs even -> force zero,
  torque non-zero; l Zs odd -> force non-zero, torque zero.

Assembly: N equally spaced planets fit a single pinion set if (Zs + Zr) / N is an integer,
a double pinion set if (Zr - Zs) / N is; otherwise planet i can sit only at multiples of
2 pi / (Zs +- Zr). The default layout then (:func:`assemblable_angles`) keeps diametrically
opposed pairs where the tooth numbers allow them (N and Zs +- Zr even), as parker2000's
four-planet OH-58 set does.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

ZERO_TOL = 1e-9  # a phasor sum below ZERO_TOL * N is zero (round-off of N unit phasors)


def mesh_phases(zs: int, psi: Sequence[float]) -> np.ndarray:
    """phi_i = Zs psi_i (rad) for planet angles psi_i (rad)."""
    return zs * np.asarray(psi, dtype=float)


def net_force_components(l: int, zs: int, psi: Sequence[float]) -> tuple[float, float]:
    """(S-, S+) = |sum_i exp(i (l phi_i -+ psi_i))|: the two rotating components of the
    l-th harmonic of the net sun force (unit mesh force amplitude per planet)."""
    psi = np.asarray(psi, dtype=float)
    lphi = l * mesh_phases(zs, psi)
    return (
        float(abs(np.exp(1j * (lphi - psi)).sum())),
        float(abs(np.exp(1j * (lphi + psi)).sum())),
    )


def net_force_amplitude(l: int, zs: int, psi: Sequence[float]) -> float:
    """max(S-, S+): zero if and only if the net sun force has no l-th harmonic."""
    return max(net_force_components(l, zs, psi))


def net_torque_amplitude(l: int, zs: int, psi: Sequence[float]) -> float:
    """T(l) = |sum_i exp(i l phi_i)|: the l-th harmonic of the net sun torque."""
    return float(abs(np.exp(1j * l * mesh_phases(zs, psi)).sum()))


def is_zero(amplitude: float, n: int) -> bool:
    """A phasor sum of ``n`` unit phasors is zero up to round-off."""
    return amplitude < ZERO_TOL * max(n, 1)


def phase_index(l: int, zs: int, n: int) -> int:
    """k = mod(l Zs, N) of parker2000."""
    return (l * zs) % n


def equally_spaced_rule(l: int, zs: int, n: int) -> dict[str, bool]:
    """parker2000 rule for N >= 2 equally spaced planets: is the l-th harmonic of the net
    force / torque non-zero?"""
    if n < 2:
        raise ValueError(f"n = {n}: the phasing rules need at least two planets")
    k = phase_index(l, zs, n)
    return {"force": k in (1, n - 1), "torque": k == 0}


def opposed_pairs_rule(l: int, zs: int) -> dict[str, bool]:
    """parker2000 rule for diametrically opposed pairs: odd l Zs -> force, even -> torque."""
    odd = (l * zs) % 2 == 1
    return {"force": odd, "torque": not odd}


def equally_spaced_angles(n: int) -> np.ndarray:
    """psi_i = 2 pi (i - 1) / N, rad."""
    return 2.0 * math.pi * np.arange(n) / n


def is_diametrically_opposed(psi: Sequence[float], tol: float = 1e-9) -> bool:
    """True if the planets form pairs psi_j = psi_i + pi (any order, any pair spacing)."""
    angles = np.mod(np.asarray(psi, dtype=float), 2.0 * math.pi)
    if angles.size % 2:
        return False
    unused = list(angles)
    while unused:
        a = unused.pop(0)
        gaps = [abs(math.remainder(b - a - math.pi, 2.0 * math.pi)) for b in unused]
        if not gaps or min(gaps) > tol:
            return False
        unused.pop(int(np.argmin(gaps)))
    return True


def assembly_number(zs: int, zr: int, n: int, double_pinion: bool = False) -> float:
    """(Zs + Zr) / N (single pinion) or (Zr - Zs) / N (double pinion): an integer if N
    equally spaced planets can be assembled."""
    return ((zr - zs) if double_pinion else (zs + zr)) / n


def assembly_steps(zs: int, zr: int, double_pinion: bool = False) -> int:
    """S = Zs + Zr (single pinion) or Zr - Zs (double pinion): a planet can sit at the
    multiples of 2 pi / S only."""
    return (zr - zs) if double_pinion else (zs + zr)


def planet_layout(zs: int, zr: int, n: int, double_pinion: bool = False) -> str:
    """Which default layout :func:`assemblable_angles` gives: ``"equally spaced"`` (S / N an
    integer), ``"opposed pairs"`` (N even, S even: pi is S / 2 steps) or ``"nearest to
    equal spacing"`` (neither: no harmonic is suppressed exactly)."""
    steps = assembly_steps(zs, zr, double_pinion)
    if steps % n == 0:
        return "equally spaced"
    if n % 2 == 0 and steps % 2 == 0:
        return "opposed pairs"
    return "nearest to equal spacing"


def assemblable_angles(zs: int, zr: int, n: int, double_pinion: bool = False) -> np.ndarray:
    """Default planet angles (rad), multiples of 2 pi / S (:func:`assembly_steps`):

    * S / N an integer: equal spacing, psi_i = 2 pi (i - 1) / N;
    * else N = 2M even and S even (parker2000's paired-planet layout, e.g. the OH-58 four
      planets at 0/91.43/180/271.43 deg): planets 1..M nearest to equal spacing,
      round((i - 1) S / N) steps, and planet M + i diametrically opposite planet i (S / 2
      steps further), so the opposed-pairs rule holds;
    * else the nearest to equal spacing, round((i - 1) S / N) steps (no pairs possible).
    """
    steps = assembly_steps(zs, zr, double_pinion)
    if planet_layout(zs, zr, n, double_pinion) == "opposed pairs":
        half = np.round(np.arange(n // 2) * steps / n)
        k = np.concatenate([half, half + steps // 2])
    else:
        k = np.round(np.arange(n) * steps / n)
    return 2.0 * math.pi * k / steps


def snap_to_assemblable(
    psi: Sequence[float], zs: int, zr: int, double_pinion: bool = False
) -> np.ndarray:
    """Each angle (rad) moved to the nearest assemblable position, a multiple of
    2 pi / (Zs + Zr) (single pinion) or 2 pi / (Zr - Zs) (double pinion)."""
    steps = (zr - zs) if double_pinion else (zs + zr)
    return 2.0 * math.pi * np.round(np.asarray(psi, dtype=float) * steps / (2.0 * math.pi)) / steps


def harmonic_table(zs: int, psi: Sequence[float], l_max: int) -> list[dict]:
    """Direct phasor sums for l = 1..l_max, with the applicable closed-form rule (if any)."""
    psi = np.asarray(psi, dtype=float)
    n = psi.size
    equal = bool(np.allclose(np.sort(np.mod(psi - psi[0], 2 * math.pi)), equally_spaced_angles(n)))
    opposed = is_diametrically_opposed(psi)
    rows = []
    for l in range(1, l_max + 1):
        s_minus, s_plus = net_force_components(l, zs, psi)
        torque = net_torque_amplitude(l, zs, psi)
        row = {
            "l": l,
            "force_minus": s_minus,
            "force_plus": s_plus,
            "torque": torque,
            "force_nonzero": not is_zero(max(s_minus, s_plus), n),
            "torque_nonzero": not is_zero(torque, n),
        }
        rule = None
        if equal and n >= 2:
            row["k"] = phase_index(l, zs, n)
            row["rule"] = "equally spaced"
            rule = equally_spaced_rule(l, zs, n)
        elif opposed:
            row["rule"] = "opposed pairs"
            rule = opposed_pairs_rule(l, zs)
        if rule is not None:
            row["rule_force"], row["rule_torque"] = rule["force"], rule["torque"]
        rows.append(row)
    return rows

"""parker2000 phasing rules against direct phasor sums over the planets.

Planet angles in radians (degrees converted at the call), mesh phase phi_i = Zs psi_i.
A phasor sum of N unit phasors is "zero" below 1e-9 N (round-off of sums of order N);
every "non-zero" sum met here is above 1e-6 (checked in ``direct``), so the split is
unambiguous; random pair spacings can bring a sum close to (not onto) zero, e.g. 0.034.
"""

import math

import numpy as np
import pytest

from gears.analytic import phasing as ph

L_RANGE = range(1, 25)
NONZERO_FLOOR = 1e-6  # seven orders of magnitude above the round-off of the sums


def direct(l: int, zs: int, psi) -> tuple[bool, bool]:
    """(net force non-zero, net torque non-zero) of harmonic l from the phasor sums."""
    n = len(psi)
    force = ph.net_force_amplitude(l, zs, psi)
    torque = ph.net_torque_amplitude(l, zs, psi)
    for value in (force, torque):
        assert value < 1e-9 * n or value > NONZERO_FLOOR, (l, value)  # unambiguous split
    return not ph.is_zero(force, n), not ph.is_zero(torque, n)


def test_oh58_three_planets_no_net_force_in_any_harmonic():
    # Zs = 27, N = 3: k = mod(27 l, 3) = 0 for every l: force zero, torque non-zero (= N).
    psi = ph.equally_spaced_angles(3)
    for l in L_RANGE:
        assert ph.phase_index(l, 27, 3) == 0
        assert direct(l, 27, psi) == (False, True)
        assert ph.net_torque_amplitude(l, 27, psi) == pytest.approx(3.0, abs=1e-9)


@pytest.mark.parametrize("snap", [False, True], ids=["printed-91.4", "assemblable-91.43"])
def test_oh58_four_planets_force_odd_torque_even(snap):
    # Planets at 0, 91.4, 180, 271.4 deg (as printed, or snapped to the assemblable
    # 32 x 360 / 126 = 91.43 deg): 27 x 91.4 / 360 = 6.855 is no whole number of teeth, yet
    # the pairs are opposed, so sun translation has only odd and rotation only even harmonics.
    psi = np.radians([0.0, 91.4, 180.0, 271.4])
    if snap:
        psi = ph.snap_to_assemblable(psi, 27, 99)
        assert math.degrees(psi[1]) == pytest.approx(32 * 360 / 126, abs=1e-9)
        assert round(math.degrees(psi[1]), 1) == 91.4
    assert ph.is_diametrically_opposed(psi)
    assert not float(27 * 91.4 / 360).is_integer()
    for l in L_RANGE:
        odd = l % 2 == 1
        assert direct(l, 27, psi) == (odd, not odd)
        assert ph.opposed_pairs_rule(l, 27) == {"force": odd, "torque": not odd}


def test_oh58_assembly_numbers():
    # (Zs + Zr) / N: 126 / 3 = 42 (equal spacing assembles), 126 / 4 = 31.5 (it does not:
    # hence the unequal, opposed four-planet arrangement).
    assert ph.assembly_number(27, 99, 3) == 42.0
    assert ph.assembly_number(27, 99, 4) == 31.5


@pytest.mark.parametrize("n", range(2, 8))
def test_equally_spaced_rule_matches_direct_sums(n):
    # The k = mod(l Zs, N) table against the sums, for a spread of tooth counts.
    psi = ph.equally_spaced_angles(n)
    for zs in (17, 27, 35, 40, 53, 60):
        for l in L_RANGE:
            rule = ph.equally_spaced_rule(l, zs, n)
            assert direct(l, zs, psi) == (rule["force"], rule["torque"]), (zs, n, l)


@pytest.mark.parametrize("m", [1, 2, 3])
def test_opposed_pairs_rule_matches_direct_sums_for_any_spacing(m):
    # Pairs psi_i, psi_i + pi with arbitrary (seeded random) spacing of the pairs.
    rng = np.random.default_rng(20000 + m)
    base = np.sort(rng.uniform(0.0, math.pi, m))
    psi = np.concatenate([base, base + math.pi])
    assert ph.is_diametrically_opposed(psi)
    for zs in (27, 30, 35):
        for l in L_RANGE:
            rule = ph.opposed_pairs_rule(l, zs)
            assert direct(l, zs, psi) == (rule["force"], rule["torque"]), (zs, m, l)


def test_force_uses_both_basis_rotations():
    # Equal spacing, k = 1 excites only the S- component, k = N - 1 only S+ (the radial /
    # tangential basis turns with the planet): both must be checked for a zero net force.
    psi = ph.equally_spaced_angles(5)
    s_minus, s_plus = ph.net_force_components(1, 26, psi)  # k = 1
    assert (s_minus, s_plus) == pytest.approx((5.0, 0.0), abs=1e-9)
    s_minus, s_plus = ph.net_force_components(1, 24, psi)  # k = 4 = N - 1
    assert (s_minus, s_plus) == pytest.approx((0.0, 5.0), abs=1e-9)


def test_case1_planetary():
    # Zs = 35, Zr = 86, three pinions: (35 + 86) / 3 = 40.33 is not an integer, so three
    # equally spaced pinions cannot be assembled in the case-1 set. If they could: k = mod(35 l,
    # 3) = 2, 1, 0, ...: force in l = 1, 2, 4, 5, ..., torque in l = 3, 6, ...
    assert ph.assembly_number(35, 86, 3) == pytest.approx(121 / 3)
    assert not ph.assembly_number(35, 86, 3).is_integer()
    psi = ph.equally_spaced_angles(3)
    for l in L_RANGE:
        k = ph.phase_index(l, 35, 3)
        assert k == (2, 1, 0)[(l - 1) % 3]
        assert direct(l, 35, psi) == (k != 0, k == 0)
    # The nearest assemblable positions (40 and 81 of 121 steps: 119.01, 240.99 deg)
    # suppress no harmonic exactly: every sum of l = 1..24 is non-zero.
    near = ph.assemblable_angles(35, 86, 3)
    assert np.degrees(near) == pytest.approx([0.0, 40 * 360 / 121, 81 * 360 / 121], abs=1e-9)
    for l in L_RANGE:
        assert ph.net_force_amplitude(l, 35, near) > NONZERO_FLOOR
        assert ph.net_torque_amplitude(l, 35, near) > 1e-3


def test_case2_planetary_assembles():
    # Double pinion: (Zr - Zs) / N = (92 - 35) / 3 = 19, an integer: equal spacing assembles.
    assert ph.assembly_number(35, 92, 3, double_pinion=True) == 19.0


def test_rule_inputs():
    with pytest.raises(ValueError, match="two planets"):
        ph.equally_spaced_rule(1, 27, 1)
    assert not ph.is_diametrically_opposed(np.radians([0.0, 90.0, 180.0]))
    assert not ph.is_diametrically_opposed(np.radians([0.0, 90.0, 180.0, 300.0]))
    assert ph.is_diametrically_opposed(np.radians([10.0, 250.0, 190.0, 70.0]))


def test_harmonic_table_labels_the_rule():
    rows = ph.harmonic_table(27, ph.equally_spaced_angles(3), 4)
    assert [r["rule"] for r in rows] == ["equally spaced"] * 4
    assert all(r["rule_force"] == r["force_nonzero"] for r in rows)
    rows = ph.harmonic_table(27, np.radians([0.0, 91.4, 180.0, 271.4]), 4)
    assert [r["rule"] for r in rows] == ["opposed pairs"] * 4
    assert all(r["rule_torque"] == r["torque_nonzero"] for r in rows)

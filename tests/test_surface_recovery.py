"""The moving least-squares recovery of a fillet's surface stress (solvers.surface_recovery):
the fillet's (s, z) coordinates against the generated fillet curve, the fit exact for the
fields of its basis, dropping its quadratic term at a strip's edge, converging for a smooth
peak, and taking the nodal scatter off a line's maximum. Pure numpy, no solve."""

import math

import numpy as np
import pytest

from cases.study_case import load_study_case
from gears.iso6336_root import fillet_tangent_point
from gears.profile import tooth_profile
from solvers.surface_recovery import (
    fillet_coordinates,
    fillet_curve,
    recover,
    strip_spacings,
)

GEARS = load_study_case("1-GB").gearset.gears


def _strip(h_s, h_z, length=0.8, half=4.0, jitter=0.0, seed=0):
    """A structured strip like meshing.body_mesh.structure_fillets' in (s, z): nodes, and
    two triangles per quad."""
    s = np.arange(0.0, length + 1e-12, h_s)
    z = np.arange(-half, half + 1e-12, h_z)
    S, Z = np.meshgrid(s, z, indexing="ij")
    sz = np.c_[S.ravel(), Z.ravel()]
    if jitter:
        sz += np.random.default_rng(seed).uniform(-jitter, jitter, sz.shape) * [h_s, h_z]
    ns, nz = len(s), len(z)
    idx = np.arange(ns * nz).reshape(ns, nz)
    a, b, c, d = idx[:-1, :-1], idx[1:, :-1], idx[1:, 1:], idx[:-1, 1:]
    tri = np.r_[np.c_[a.ravel(), b.ravel(), c.ravel()], np.c_[a.ravel(), c.ravel(), d.ravel()]]
    return sz, tri


def _tensors(values):
    """(n, 3, 3) symmetric tensors with sigma_xx = values and small fixed other entries."""
    t = np.zeros((len(values), 3, 3))
    t[:, 0, 0] = values
    t[:, 1, 1] = 0.1 * values
    t[:, 0, 1] = t[:, 1, 0] = 5.0
    return t


@pytest.mark.parametrize(
    "name, tooth, side", [("sun", 3, "neg"), ("ring", 5, "pos"), ("pinion", 0, "pos")]
)
def test_fillet_coordinates_are_the_arc_length_on_the_generated_fillet(name, tooth, side):
    """Points of the generated fillet (sampled four times finer than the module's curve),
    turned to another tooth and side and screwed along the helix to z, map to their own arc
    length from the root circle and keep their z. Tolerance 2e-4 mm: the chord error of the
    module's 801-sample curve on a 0.3-1 mm fillet radius is below 1e-5 mm, and the finer
    sampling's own arc length differs from the coarse one's by the same order."""
    gear = GEARS[name]
    fine = tooth_profile(gear, n_fillet=3201).fillet_pos
    arc = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(fine, axis=0), axis=1))]
    pick = np.arange(40, len(fine) - 40, 97)
    p = fine[pick].copy()
    if side == "neg":
        p[:, 1] *= -1.0
    z = np.linspace(-0.45, 0.45, len(pick)) * gear.face_width
    ang = 2.0 * math.pi * tooth / gear.teeth + np.asarray(gear.helix_rotation(z), float)
    c, s = np.cos(ang), np.sin(ang)
    xyz = np.c_[c * p[:, 0] - s * p[:, 1], s * p[:, 0] + c * p[:, 1], z]
    sz = fillet_coordinates(gear, tooth, side, xyz)
    assert np.abs(sz[:, 0] - arc[pick]).max() < 2e-4
    assert np.array_equal(sz[:, 1], z)


def test_iso_point_lies_inside_the_fillet():
    """ISO's 30 / 60 deg point is a point of the fillet: its s lies strictly between the
    root circle (0) and the form circle (the curve's length)."""
    for name in ("sun", "pinion", "ring"):
        gear = GEARS[name]
        _, arc = fillet_curve(gear)
        p = fillet_tangent_point(gear)["point"]
        s = fillet_coordinates(gear, 0, "pos", np.array([[p[0], p[1], 0.0]]))[0, 0]
        assert 0.05 * arc[-1] < s < 0.95 * arc[-1], name


def test_spacings_of_a_structured_strip():
    sz, tri = _strip(0.1, 0.2)
    assert strip_spacings(sz, tri) == pytest.approx((0.1, 0.2))


def test_fields_of_the_basis_are_recovered_exactly():
    """c0 + c1 s + c2 z + c3 s^2 is reproduced to round-off wherever the window holds two
    nodes either side across the profile, on a jittered strip."""
    sz, tri = _strip(0.1, 0.2, jitter=0.2)
    h_s, h_z = strip_spacings(sz, tri)
    f = lambda s, z: 700.0 + 150.0 * s - 12.0 * z - 900.0 * s**2  # noqa: E731
    at = np.c_[np.linspace(0.3, 0.5, 7), np.linspace(-3.0, 3.0, 7)]
    got = recover(sz, _tensors(f(sz[:, 0], sz[:, 1])), at, h_s, h_z)
    assert np.allclose(got, _tensors(f(at[:, 0], at[:, 1])), rtol=0.0, atol=1e-8)


def test_the_quadratic_term_is_dropped_at_a_strip_edge():
    """At the strip's edge (one node beyond s0 on one side) the fit is linear: a linear field
    is still exact, a quadratic one no longer is; a window with no node gives NaN."""
    sz, tri = _strip(0.1, 0.2)
    h_s, h_z = strip_spacings(sz, tri)
    at = np.array([[0.02, 0.0], [5.0, 0.0]])
    lin = recover(sz, _tensors(600.0 + 100.0 * sz[:, 0]), at, h_s, h_z)
    assert lin[0, 0, 0] == pytest.approx(602.0, abs=1e-8)
    assert np.isnan(lin[1]).all()
    quad = recover(sz, _tensors(600.0 - 900.0 * sz[:, 0] ** 2), at, h_s, h_z)
    assert abs(quad[0, 0, 0] - (600.0 - 900.0 * 0.02**2)) > 1e-3


def _peak(s, z):
    """A fillet-like stress: a peak across the profile of 0.3 mm (1/e) half-width, rising
    along the face width. Twice as sharp as the sharpest measured: the nodal values across
    1-GB's ring fillet at mid-cycle (624 / 729 / 767 / 767 / 665 / 537 / 447 MPa at 0.12 mm
    steps, level-1 driver, 0.15 mm sector) fall off over about 0.6 mm."""
    return 800.0 * np.exp(-(((s - 0.37) / 0.3) ** 2)) * (1.0 + 0.02 * z)


def test_recovery_converges_on_a_smooth_peak():
    """The error at the peak falls at least 4x as the strip's spacings halve (the window
    shrinks with them; a quadratic fit across a window symmetric about the point errs by
    O(h^4) at it: measured 13x and 26x, from 0.27 % at 0.1 mm)."""
    errs = []
    for h_s in (0.1, 0.05, 0.025):
        sz, tri = _strip(h_s, 2.0 * h_s)
        at = np.array([[0.37, 1.0]])
        got = recover(sz, _tensors(_peak(sz[:, 0], sz[:, 1])), at, *strip_spacings(sz, tri))
        errs.append(abs(got[0, 0, 0] - _peak(0.37, 1.0)))
    assert errs[0] > 4.0 * errs[1] > 16.0 * errs[2] > 0.0
    assert errs[0] / _peak(0.37, 1.0) < 0.005  # 0.1 mm spacing, 0.3 mm peak: within 0.5 %


def test_a_lines_maximum_loses_the_nodal_scatter():
    """With a 3 % nodal scatter (uniform, fixed seed) on the peak, the largest value along
    the line at the peak's s is within 1.5 % of the field's maximum along it recovered, while
    the nodal values' maximum along the nodes of that s sits near the scatter's top."""
    sz, tri = _strip(0.1, 0.2, length=0.8, half=8.0)
    h_s, h_z = strip_spacings(sz, tri)
    rng = np.random.default_rng(7)
    noisy = _peak(sz[:, 0], sz[:, 1]) * (1.0 + rng.uniform(-0.03, 0.03, len(sz)))
    z = np.linspace(-7.0, 7.0, 281)
    line = recover(sz, _tensors(noisy), np.c_[np.full(len(z), 0.4), z], h_s, h_z)
    exact = _peak(0.4, 7.0)
    assert abs(line[:, 0, 0].max() / exact - 1.0) < 0.015
    on = np.isclose(sz[:, 0], 0.4) & (np.abs(sz[:, 1]) <= 7.0)
    assert noisy[on].max() / exact - 1.0 > 0.02

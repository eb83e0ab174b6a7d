"""Involute helical gear geometry in pure numpy: external and internal gears, the root
fillets their generating tools leave, gear meshes and the profile shifts centre distances need.

Conventions
-----------
* Units mm. The dataclass *input* angles are degrees (they come from case files); every
  derived angle (properties, methods, functions) is in radians.
* Gear frame: centre at the origin, z along the axis, z = 0 at mid face width. Tooth 0 is
  symmetric about +x (the tip of an internal gear's tooth points to the centre). ``"pos"`` is
  the counter-clockwise (+theta) side of a tooth, ``"neg"`` the clockwise side.
* Hands: a right-hand gear is a right-handed screw, its transverse section turns
  counter-clockwise as z grows (``helix_rotation``).
* Profile shift x: the generating tool's datum line lies x m_n farther from the gear axis
  than the reference circle. External gears (ISO 21771): positive x thickens the tooth.
  Internal gears: positive x widens the tooth *space*, thins the tooth and moves tip and root
  circles outward, so a positive x_ring - x_pinion increases the internal centre distance
  (the convention of KHK's gear handbook; DIN 3960 and ISO 21771, which give internal gears a
  negative tooth number, count x with the opposite sign).

Symbols (ISO 21771): z teeth, m_n normal module, alpha_n normal pressure angle, beta helix
angle, m_t = m_n / cos(beta), tan(alpha_t) = tan(alpha_n) / cos(beta), r = z m_t / 2,
r_b = r cos(alpha_t), inv(alpha) = tan(alpha) - alpha, sigma = +1 external / -1 internal.
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass, replace
from functools import cached_property

import numpy as np

MIN_TEETH = 5
MIN_SHAPER_TEETH = 10
PRESSURE_ANGLE_RANGE = (10.0, 35.0)  # deg, normal
HELIX_ANGLE_RANGE = (0.0, 45.0)  # deg
MIN_TIP_THICKNESS = 0.2  # transverse tip thickness / m_n below which a tooth counts as pointed
# Largest share of the involute an undercut may remove, in roll length (proportional to the
# path of contact) from the base to the tip circle: 9 % for z = 12, x = 0 at 20 deg (allowed),
# 14 % for z = 10 (refused). Meshes also check that the mate's tip stays above the form circle.
MAX_UNDERCUT = 0.1


class GeometryError(ValueError):
    """Invalid gear data; the message names the field and the allowed range or value."""


def involute(alpha):
    """inv(alpha) = tan(alpha) - alpha (vectorised, radians)."""
    a = np.asarray(alpha, dtype=float)
    return (np.tan(a) - a)[()]


def inverse_involute(value):
    """alpha with inv(alpha) = value (vectorised, odd in value, radians, to about 1e-15).

    Newton on f(alpha) = tan(alpha) - alpha - v, f' = tan(alpha)^2, started from
    min(cbrt(3 v), atan(v + pi/2)). Both bound the root from above (tan(a) - a >= a^3 / 3 and
    tan(a) = v + a < v + pi/2) and f is convex and increasing on [0, pi/2), so the iterates
    fall monotonically onto the root.
    """
    v = np.asarray(value, dtype=float)
    s = np.abs(v)
    a = np.minimum(np.cbrt(3.0 * s), np.arctan(s + 0.5 * np.pi))
    for _ in range(60):
        t = np.tan(a)
        f = t - a - s
        step = np.divide(f, t * t, out=np.zeros_like(f), where=t != 0.0)
        a = a - step
        if np.all(np.abs(step) <= 1e-16 * np.maximum(a, 1e-300)):
            break
    return np.copysign(a, v)[()]


def _roll(r, r_b):
    """Roll length sqrt(r^2 - r_b^2) of the involute point at radius r (0 below r_b)."""
    return np.sqrt(np.maximum(np.square(r) - r_b * r_b, 0.0))


def _inv_at(r, r_b):
    """inv(alpha(r)) with cos(alpha(r)) = r_b / r (the involute's polar angle from its cusp)."""
    return involute(np.arccos(np.minimum(r_b / np.asarray(r, dtype=float), 1.0)))


def _rotate(points: np.ndarray, angle) -> np.ndarray:
    """Rotate (..., 2) points by angle (broadcast) about the origin."""
    c, s = np.cos(angle), np.sin(angle)
    x, y = points[..., 0], points[..., 1]
    return np.stack([c * x - s * y, s * x + c * y], axis=-1)


def _bisect(inside, lo: float, hi: float) -> float:
    """Last point of [lo, hi] where ``inside`` holds, given inside(lo) and not inside(hi)."""
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if inside(mid) else (lo, mid)
    return lo


def _range_text(lo: float, hi: float, lo_open: bool) -> str:
    if hi == math.inf:
        return f"> {lo:g}" if lo_open else f">= {lo:g}"
    return f"in {'(' if lo_open else '['}{lo:g}, {hi:g}]"


@dataclass(frozen=True)
class _Rack:
    """Hob (rack) that generates an external gear, in the gear's transverse section.

    Rack coordinates: u along the rolling line (tangent to the reference circle), v radial,
    measured outward from it. The tip rounding (radius rho in the normal section, centre
    (u_c, v_c) there) is an ellipse with semi-axes rho / cos(beta) along u and rho along v.
    """

    r: float  # reference (rolling) radius
    u_c: float  # normal-section tangential position of the tip-rounding centre
    v_c: float
    rho: float
    cos_beta: float
    tau_end: float  # rounding parameter at the flank tangency, pi/2 - alpha_n


@dataclass(frozen=True)
class _Shaper:
    """Pinion-type shaper (x0 = 0) that generates an internal gear, transverse section.

    Its tip rounding is a circle of radius rho centred at polar (r_c, theta_c) on the +theta
    side of the cutter tooth (the cutter tooth points along +x), tangent to the cutter tip
    circle (normal angle nu = theta_c) and to its involute flank (nu = nu_end).
    """

    teeth: int
    a: float  # cutting centre distance
    alpha: float  # cutting (operating) pressure angle
    r_w: float  # cutter operating pitch radius
    r_c: float
    theta_c: float
    nu_end: float
    rho: float


@dataclass(frozen=True)
class GearSpec:
    """One involute helical gear, external or internal, generated by a hob or a shaper.

    Validated on construction (GeometryError naming the field): teeth >= 5; m_n, face width
    > 0; alpha_n in [10, 35] deg; beta in [0, 45] deg; h_a* in (0, 2]; h_f* up to a pointed
    rack tooth, rho up to the rack's full-round tip; shaper_teeth >= 10 and able to cut the
    gear. The tooth must have a transverse tip thickness of at least ``MIN_TIP_THICKNESS``
    m_n, an undercut of at most ``MAX_UNDERCUT`` (``undercut_fraction``) and an involute
    between form and tip circle.

    Root fillets are generated, not drawn: an external gear by a rack (hob) with addendum
    ``dedendum_coef`` m_n and tip rounding ``hob_tip_radius_coef`` m_n in the normal section
    (ISO 53 profile A: 1.25, 0.38); a rack cannot cut an internal gear, which is generated by
    a pinion-type shaper with ``shaper_teeth`` teeth and no shift, its tip radius chosen to
    cut the root circle r_f = r + (h_f* + x) m_n, its tip rounding of the same radius (taken
    in the transverse section) or, where its tooth is too thin for that, a full-round tip.
    """

    name: str  # used in error messages ("sun", "pinion", ...)
    teeth: int
    normal_module: float  # mm
    normal_pressure_angle: float  # deg, PRESSURE_ANGLE_RANGE
    helix_angle: float  # deg, magnitude, HELIX_ANGLE_RANGE
    hand: str  # "right" | "left" ("R"/"L" accepted, any case); either for a spur gear
    face_width: float  # mm
    internal: bool = False
    profile_shift: float = 0.0  # x, see the module docstring for internal gears
    addendum_coef: float = 1.0  # h_a* = h_a / m_n
    dedendum_coef: float = 1.25  # h_f* = h_f / m_n, also the generating tool's addendum
    hob_tip_radius_coef: float = 0.38  # rho_a0 / m_n, tool tip rounding (ISO 53 profile A)
    shaper_teeth: int = 30  # internal gears only: teeth of the pinion-type shaper cutter

    def __post_init__(self):
        if not isinstance(self.name, str) or not self.name:
            raise GeometryError(f"name = {self.name!r}: must be a non-empty string")
        self._integer("teeth", MIN_TEETH)
        self._number("normal_module", 0.0, lo_open=True)
        self._number("normal_pressure_angle", *PRESSURE_ANGLE_RANGE)
        self._number("helix_angle", *HELIX_ANGLE_RANGE)
        hand = {"r": "right", "right": "right", "l": "left", "left": "left"}.get(
            self.hand.lower() if isinstance(self.hand, str) else None
        )
        if hand is None:
            self._fail("hand", "must be 'right' or 'left' ('R' / 'L', any case)")
        object.__setattr__(self, "hand", hand)
        self._number("face_width", 0.0, lo_open=True)
        if not isinstance(self.internal, bool):
            self._fail("internal", "must be true or false")
        self._number("profile_shift", -math.inf, math.inf)
        self._number("addendum_coef", 0.0, 2.0, lo_open=True)
        an = math.radians(self.normal_pressure_angle)
        # The generating rack tooth (addendum h_f*, tip rounding rho) must not be pointed.
        self._number("dedendum_coef", 0.0, math.pi / (4.0 * math.tan(an)), lo_open=True)
        rho_max = (math.pi / 4.0 - self.dedendum_coef * math.tan(an)) * math.cos(an)
        self._number("hob_tip_radius_coef", 0.0, rho_max / (1.0 - math.sin(an)), lo_open=True)
        if self.internal:
            if self.tip_radius <= self.base_radius:
                self._fail(
                    "profile_shift",
                    f"internal tip radius {self.tip_radius:.4f} mm must exceed the base radius "
                    f"{self.base_radius:.4f} mm (raise profile_shift or lower addendum_coef)",
                )
            self._integer("shaper_teeth", MIN_SHAPER_TEETH)
            if self.shaper_teeth >= self.teeth:
                self._fail("shaper_teeth", f"must be < teeth = {self.teeth}")
            self._check_shaper()
        self._check_tooth()

    # ----------------------------------------------------------------------------------
    # validation helpers
    # ----------------------------------------------------------------------------------

    def _fail(self, field: str, rule: str):
        raise GeometryError(f"{self.name}.{field} = {getattr(self, field)!r}: {rule}")

    def _integer(self, field: str, lo: int):
        v = getattr(self, field)
        if not isinstance(v, numbers.Integral) or isinstance(v, bool) or v < lo:
            self._fail(field, f"must be an integer >= {lo}")
        object.__setattr__(self, field, int(v))

    def _number(self, field: str, lo: float, hi: float = math.inf, lo_open: bool = False):
        v = getattr(self, field)
        ok = isinstance(v, numbers.Real) and not isinstance(v, bool) and math.isfinite(v)
        if not (ok and (lo < v if lo_open else lo <= v) and v <= hi):
            self._fail(field, f"must be a number {_range_text(lo, hi, lo_open)}")
        object.__setattr__(self, field, float(v))

    def _check_shaper(self):
        s = self._tool
        if s.alpha <= 0.0:
            self._fail(
                "profile_shift",
                f"a {s.teeth}-tooth shaper cannot cut this shift (cutting pressure angle <= 0)",
            )
        if s.r_c <= self._shaper_base_radius:
            self._fail(
                "shaper_teeth",
                f"the tip of the {s.teeth}-tooth shaper that cuts this internal gear is too "
                "thin to carry a tip rounding outside its base circle",
            )
        # The shaper must not trim the tips it has cut: its tip corner must clear them
        # (trochoid interference) and it must reach the tip circle with its involute.
        r_a0, r_b0 = s.r_c + s.rho, self._shaper_base_radius
        reach = _roll(self.tip_radius, self.base_radius) - s.a * math.sin(s.alpha)
        margin = _tip_interference_margin(
            s.teeth, r_a0, r_b0, self.teeth, self.tip_radius, self.base_radius, s.a, s.alpha
        )
        if reach < 0.0:
            self._fail(
                "shaper_teeth",
                f"the tip circle reaches inside the base circle of the {s.teeth}-tooth shaper "
                "(involute interference while cutting: use more shaper teeth)",
            )
        if margin < 0.0:
            self._fail(
                "shaper_teeth",
                f"the {s.teeth}-tooth shaper would trim the tips it cuts (trochoid "
                f"interference: teeth - shaper_teeth = {self.teeth - s.teeth} is too few)",
            )

    def _check_tooth(self):
        r_a, r_form, m_n = self.tip_radius, self.form_radius, self.normal_module
        s_a = self.tip_thickness
        if s_a < MIN_TIP_THICKNESS * m_n:
            self._fail(
                "profile_shift",
                f"tip thickness {s_a:.4f} mm < {MIN_TIP_THICKNESS:g} m_n = "
                f"{MIN_TIP_THICKNESS * m_n:.4f} mm (pointed tooth)",
            )
        if self.undercut_fraction > MAX_UNDERCUT:
            an, at = math.radians(self.normal_pressure_angle), self.transverse_pressure_angle
            x_min = (
                self.dedendum_coef
                - self.hob_tip_radius_coef * (1.0 - math.sin(an))
                - self.reference_radius * math.sin(at) ** 2 / m_n
            )
            self._fail(
                "profile_shift",
                f"undercut removes {self.undercut_fraction:.0%} of the involute (roll length "
                f"from base to tip circle), at most {MAX_UNDERCUT:.0%} allowed; no undercut "
                f"needs profile_shift >= {x_min:.3f}",
            )
        if self._sigma * (r_a - r_form) <= 0.0:
            self._fail(
                "addendum_coef",
                f"tip radius {r_a:.4f} mm leaves no involute beyond the form radius "
                f"{r_form:.4f} mm",
            )

    # ----------------------------------------------------------------------------------
    # basic geometry (angles in radians)
    # ----------------------------------------------------------------------------------

    @property
    def _sigma(self) -> int:
        return -1 if self.internal else 1

    @property
    def _beta(self) -> float:
        return math.radians(self.helix_angle)

    @property
    def transverse_module(self) -> float:
        """m_t = m_n / cos(beta), mm."""
        return self.normal_module / math.cos(self._beta)

    @property
    def transverse_pressure_angle(self) -> float:
        """alpha_t = atan(tan(alpha_n) / cos(beta)), rad."""
        return math.atan(math.tan(math.radians(self.normal_pressure_angle)) / math.cos(self._beta))

    @property
    def base_helix_angle(self) -> float:
        """beta_b = atan(tan(beta) cos(alpha_t)), rad."""
        return math.atan(math.tan(self._beta) * math.cos(self.transverse_pressure_angle))

    @property
    def reference_radius(self) -> float:
        """r = z m_t / 2, mm."""
        return 0.5 * self.teeth * self.transverse_module

    @property
    def base_radius(self) -> float:
        """r_b = r cos(alpha_t), mm."""
        return self.reference_radius * math.cos(self.transverse_pressure_angle)

    @property
    def tip_radius(self) -> float:
        """External r_a = r + (h_a* + x) m_n; internal (the inner circle) r - (h_a* - x) m_n."""
        h = (self._sigma * self.addendum_coef + self.profile_shift) * self.normal_module
        return self.reference_radius + h

    @property
    def root_radius(self) -> float:
        """External r_f = r - (h_f* - x) m_n; internal r + (h_f* + x) m_n, mm."""
        h = (self.profile_shift - self._sigma * self.dedendum_coef) * self.normal_module
        return self.reference_radius + h

    def _half_angle(self, r):
        """Half angular tooth thickness psi(r) = pi/(2z) + sigma (2 x tan(alpha_n)/z
        + inv(alpha_t) - inv(alpha(r))) at radius r >= r_b (no check), rad."""
        z = self.teeth
        an = math.radians(self.normal_pressure_angle)
        const = 2.0 * self.profile_shift * math.tan(an) / z + involute(
            self.transverse_pressure_angle
        )
        return 0.5 * math.pi / z + self._sigma * (const - _inv_at(r, self.base_radius))

    def tooth_thickness(self, r):
        """Transverse arc thickness s(r) = 2 r psi(r) of the involute tooth at radius r (mm,
        vectorised); at the reference circle s = m_t (pi/2 + sigma 2 x tan(alpha_n)).
        Defined for r >= r_b (GeometryError below); beyond the tooth it extends the involutes."""
        r = np.asarray(r, dtype=float)
        if np.any(r < self.base_radius):
            raise GeometryError(
                f"{self.name}: radius r = {float(np.min(r)):.6g} mm: must be >= the base "
                f"radius {self.base_radius:.6g} mm (no involute below it)"
            )
        return (2.0 * r * self._half_angle(r))[()]

    @property
    def tip_thickness(self) -> float:
        """Transverse arc thickness at the tip circle, mm."""
        return float(self.tooth_thickness(self.tip_radius))

    def helix_rotation(self, z):
        """Angle (rad, vectorised) by which the transverse section at axial position z is
        turned relative to z = 0: +z tan(beta) / r for a right hand, -z tan(beta) / r left."""
        turn = math.tan(self._beta) / self.reference_radius
        return ((turn if self.hand == "right" else -turn) * np.asarray(z, dtype=float))[()]

    # ----------------------------------------------------------------------------------
    # generation: the generating tool, its root fillet (envelope), form circle, undercut
    # ----------------------------------------------------------------------------------

    @property
    def _shaper_base_radius(self) -> float:
        return self.shaper_teeth / self.teeth * self.base_radius

    @cached_property
    def _tool(self) -> _Rack | _Shaper:
        m_n, x = self.normal_module, self.profile_shift
        an = math.radians(self.normal_pressure_angle)
        rho = self.hob_tip_radius_coef * m_n
        if not self.internal:
            v_c = (x - self.dedendum_coef) * m_n + rho
            u_c = 0.25 * math.pi * m_n + (v_c - x * m_n) * math.tan(an) - rho / math.cos(an)
            return _Rack(
                self.reference_radius, u_c, v_c, rho, math.cos(self._beta), 0.5 * math.pi - an
            )
        # Shaper z0 (x0 = 0) cutting the gear at zero backlash: inv(alpha_c) = inv(alpha_t)
        # + 2 tan(alpha_n) x / (z - z0), a_c = (z - z0) m_t cos(alpha_t) / (2 cos(alpha_c)).
        z, z0 = self.teeth, self.shaper_teeth
        at = self.transverse_pressure_angle
        r_b0 = self._shaper_base_radius
        alpha_c = float(inverse_involute(involute(at) + 2.0 * math.tan(an) * x / (z - z0)))
        a_c = (z - z0) * self.transverse_module * math.cos(at) / (2.0 * math.cos(alpha_c))
        r_a0 = self.root_radius - a_c  # the shaper's tip circle cuts the root circle

        def theta_c(rho):
            """Rounding centre angle, on the involute parallel to the cutter flank rho inside
            it: psi0(r_a0 - rho) - rho / r_b0, psi0(r) = pi/(2 z0) + inv(alpha_t) - inv(alpha)."""
            r_c = max(r_a0 - rho, r_b0)
            return 0.5 * math.pi / z0 + involute(at) - float(_inv_at(r_c, r_b0)) - rho / r_b0

        if theta_c(rho) < 0.0:  # too big for the cutter tooth: full-round tip (decreasing in rho)
            rho = _bisect(lambda p: theta_c(p) >= 0.0, 0.0, rho)
        r_c = r_a0 - rho
        nu_end = theta_c(rho) + math.asin(min(r_b0 / max(r_c, r_b0), 1.0))  # flank normal
        return _Shaper(z0, a_c, alpha_c, r_b0 / math.cos(alpha_c), r_c, theta_c(rho), nu_end, rho)

    def _envelope(self, t) -> np.ndarray:
        """Points (N, 2) of the root fillet on the neg side of tooth 0, generated by the tool
        tip rounding at parameter t in [0, 1] (0: root circle, 1: tangency with the flank).

        Equation of meshing (Willis): a tool point cuts when its normal passes through the
        pitch point of the generating motion. Rack: gear turned by phi, rack moved by r phi;
        the point (u, v) with normal n cuts at u_I = u - v n_u / n_v = -r phi. Shaper: cutter
        turned by phi0, gear by phi0 z0 / z; the point cuts when its normal line meets the
        cutter's pitch circle r_w at polar angle -phi0 (the meeting point nearer the mesh).
        """
        t = np.asarray(t, dtype=float)
        tool = self._tool
        if isinstance(tool, _Rack):
            tau = t * tool.tau_end
            u = (tool.u_c + tool.rho * np.sin(tau)) / tool.cos_beta
            v = tool.v_c - tool.rho * np.cos(tau)
            y = -v * tool.cos_beta * np.tan(tau)  # transverse normal ~ (cos(beta) sin, -cos)
            phi = (y - u) / tool.r
            world = np.stack([tool.r + v, y], axis=-1)
            return _rotate(world, -phi - math.pi / self.teeth)
        nu = tool.theta_c + t * (tool.nu_end - tool.theta_c)
        e = np.stack([np.cos(nu), np.sin(nu)], axis=-1)
        centre = tool.r_c * np.array([math.cos(tool.theta_c), math.sin(tool.theta_c)])
        ce = tool.r_c * np.cos(nu - tool.theta_c)
        lam = -ce + np.sqrt(ce * ce - tool.r_c**2 + tool.r_w**2)
        pitch = centre + lam[..., None] * e
        phi0 = -np.arctan2(pitch[..., 1], pitch[..., 0])
        world = _rotate(centre + tool.rho * e, phi0) + np.array([tool.a, 0.0])
        return _rotate(world, -phi0 * tool.teeth / self.teeth - math.pi / self.teeth)

    @cached_property
    def _generating_roll(self) -> float:
        """Roll length (along the line of action, from the base tangency) of the involute
        point that the tool flank cuts at its tangency with the tip rounding; < 0: undercut.
        Rack: L = r sin(alpha_t) + v_F / sin(alpha_t), v_F = v_c - rho sin(alpha_n).
        Shaper: L = L0 + a_c sin(alpha_c), L0 = sqrt(r_c^2 - r_b0^2) + rho on the cutter."""
        tool = self._tool
        if isinstance(tool, _Rack):
            at = self.transverse_pressure_angle
            v_f = tool.v_c - tool.rho * math.sin(math.radians(self.normal_pressure_angle))
            return tool.r * math.sin(at) + v_f / math.sin(at)
        r_b0 = self._shaper_base_radius
        return float(_roll(tool.r_c, r_b0)) + tool.rho + tool.a * math.sin(tool.alpha)

    @cached_property
    def _fillet_end(self) -> float:
        """Tool parameter t where the fillet meets the involute: 1 without undercut; with
        undercut, where the tip trochoid, which near t = 1 runs in the tooth space, last
        crosses the involute out of the tooth (scan from t = 1, then bisection)."""
        if self._generating_roll >= 0.0:
            return 1.0
        r_b = self.base_radius

        def in_space(t):  # above the base circle and clockwise of the neg flank (-psi)
            p = self._envelope(t)
            r = np.hypot(p[..., 0], p[..., 1])
            theta = np.arctan2(p[..., 1], p[..., 0])
            return (r >= r_b) & (theta + self._half_angle(np.maximum(r, r_b)) < 0.0)

        ts = 1.0 - np.linspace(0.0, 1.0, 513) ** 2  # from t = 1 down, dense near t = 1
        k = int(np.argmin(in_space(ts)))
        return _bisect(lambda t: not in_space(t), ts[k], ts[k - 1])

    @property
    def form_radius(self) -> float:
        """Radius where the involute meets the root fillet (mm): r_F = sqrt(r_b^2 + L^2) with
        the generating roll length L, or where an undercut trochoid crosses the involute.
        External gears: r_b <= r_F < r_a; internal gears: r_a < r_F < r_f."""
        if self._generating_roll >= 0.0:
            return math.hypot(self.base_radius, self._generating_roll)
        return float(np.hypot(*self._envelope(self._fillet_end)))

    @property
    def is_undercut(self) -> bool:
        """True if the tool cut into the involute above the base circle (external gears:
        r sin(alpha_t)^2 < (h_f* - x) m_n - rho (1 - sin(alpha_n)))."""
        return self._generating_roll < 0.0

    @property
    def undercut_fraction(self) -> float:
        """Share of the involute lost to undercut, in roll length from the base to the tip
        circle: sqrt(r_F^2 - r_b^2) / sqrt(r_a^2 - r_b^2); 0 without undercut."""
        if not self.is_undercut:
            return 0.0
        r_b = self.base_radius
        return float(_roll(self.form_radius, r_b) / _roll(self.tip_radius, r_b))


def _tip_interference_margin(z1, r_a1, r_b1, z2, r_a2, r_b2, a, alpha_w) -> float:
    """Tip (trochoid) interference of an internal pair, pinion 1 in ring 2 (rad of ring turn;
    >= 0 is clear). After contact ends at the pinion tip, the pinion's tip corner must leave
    the ring's tooth space (cross the ring tip circle at Q) before the ring tooth tip gets
    there: theta1 z1 / z2 + inv(alpha_w) - inv(alpha_a2) - theta2 >= 0 with
    theta1 = acos((r_a2^2 - r_a1^2 - a^2) / (2 a r_a1)) + inv(alpha_a1) - inv(alpha_w),
    theta2 = acos((a^2 + r_a2^2 - r_a1^2) / (2 a r_a2)) (KHK gear handbook)."""
    c1 = (r_a2**2 - r_a1**2 - a**2) / (2.0 * a * r_a1)
    c2 = (a**2 + r_a2**2 - r_a1**2) / (2.0 * a * r_a2)
    if abs(c1) > 1.0 or abs(c2) > 1.0:  # the tip circles do not cross: the tips never meet
        return math.inf
    inv_w = involute(alpha_w)
    theta1 = math.acos(c1) + _inv_at(r_a1, r_b1) - inv_w
    return float(theta1 * z1 / z2 + inv_w - _inv_at(r_a2, r_b2) - math.acos(c2))


# --------------------------------------------------------------------------------------
# tooth profile (transverse section at z = 0)
# --------------------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class ToothProfile:
    """Transverse section (z = 0) of tooth 0, symmetric about +x; arrays (N, 2) in mm, each
    ordered from the root towards the tip. The fillet's last point is the flank's first
    point (same values). ``fillet_*[0]`` is where the fillet leaves the root circle; the root
    arc from there to the mid-space (at +-pi/z) and the tip arc between the flank ends are
    circles about the origin."""

    teeth: int
    internal: bool
    root_radius: float
    tip_radius: float
    flank_pos: np.ndarray  # involute, counter-clockwise (+theta) side of the tooth
    flank_neg: np.ndarray  # involute, clockwise (-theta) side
    fillet_pos: np.ndarray  # generated fillet, root circle -> form circle, C1 with the flank
    fillet_neg: np.ndarray

    @property
    def pitch_angle(self) -> float:
        """2 pi / z, rad."""
        return 2.0 * math.pi / self.teeth

    def outline(self, n_arc: int = 8) -> np.ndarray:
        """Polyline (M, 2) of one pitch, counter-clockwise from the root circle at -pi/z
        (mid-space) to the root circle at +pi/z: root arc, fillet, flank, tip arc, flank,
        fillet, root arc; circular arcs with n_arc points each."""
        half = 0.5 * self.pitch_angle

        def arc(p0, p1, radius):
            a0, a1 = math.atan2(p0[1], p0[0]), math.atan2(p1[1], p1[0])
            a = np.linspace(a0, a1, max(n_arc, 2))[1:-1]
            return np.vstack([p0, radius * np.c_[np.cos(a), np.sin(a)], p1])

        def polar(a):
            return self.root_radius * np.array([math.cos(a), math.sin(a)])

        pieces = [
            arc(polar(-half), self.fillet_neg[0], self.root_radius),
            self.fillet_neg,
            self.flank_neg,
            arc(self.flank_neg[-1], self.flank_pos[-1], self.tip_radius),
            self.flank_pos[::-1],
            self.fillet_pos[::-1],
            arc(self.fillet_pos[0], polar(half), self.root_radius),
        ]
        pts = np.vstack(pieces)
        keep = np.r_[True, np.linalg.norm(np.diff(pts, axis=0), axis=1) > 1e-12]
        return pts[keep]


def tooth_profile(gear: GearSpec, n_involute: int = 20, n_fillet: int = 12) -> ToothProfile:
    """Exact transverse profile of tooth 0: involute points evenly spaced in roll length
    (equal turns of the tangent) from the form to the tip circle, fillet points evenly spaced
    in the tool's rounding parameter."""
    if n_involute < 2 or n_fillet < 2:
        raise GeometryError(f"n_involute = {n_involute}, n_fillet = {n_fillet}: must be >= 2")
    r_b = gear.base_radius
    roll = np.linspace(_roll(gear.form_radius, r_b), _roll(gear.tip_radius, r_b), n_involute)
    r = np.hypot(r_b, roll)
    r[[0, -1]] = gear.form_radius, gear.tip_radius
    psi = gear._half_angle(r)
    mirror = np.array([1.0, -1.0])
    flank_pos = np.c_[r * np.cos(psi), r * np.sin(psi)]
    fillet_neg = gear._envelope(np.linspace(0.0, gear._fillet_end, n_fillet))
    fillet_neg[-1] = flank_pos[0] * mirror
    arrays = flank_pos, flank_pos * mirror, fillet_neg * mirror, fillet_neg
    for arr in arrays:
        arr.flags.writeable = False
    return ToothProfile(gear.teeth, gear.internal, gear.root_radius, gear.tip_radius, *arrays)


def gear_outline(profile: ToothProfile, n_arc: int = 8) -> np.ndarray:
    """Closed outline (M, 2) of the whole gear at z = 0: ``profile.outline`` turned by
    k 2 pi / z for every tooth k, counter-clockwise, the first point not repeated."""
    one = profile.outline(n_arc)[:-1]
    k = np.arange(profile.teeth)[:, None]
    return _rotate(one[None, :, :], k * profile.pitch_angle).reshape(-1, 2)


# --------------------------------------------------------------------------------------
# deviations of 3D points from the exact flank and fillet surfaces
# --------------------------------------------------------------------------------------


def _side_sign(side: str) -> int:
    if side not in ("pos", "neg"):
        raise GeometryError(f"side = {side!r}: must be 'pos' or 'neg'")
    return 1 if side == "pos" else -1


def _untwist(gear: GearSpec, xyz, s: int) -> tuple[np.ndarray, np.ndarray]:
    """Radius and polar angle of points xyz (..., 3) screwed back to z = 0 along the helix,
    the angle taken from the centre line of the tooth whose side s (+1 pos, -1 neg) is
    nearest (window of one pitch centred on that side)."""
    p = np.asarray(xyz, dtype=float)
    theta = np.arctan2(p[..., 1], p[..., 0]) - gear.helix_rotation(p[..., 2])
    pitch = 2.0 * math.pi / gear.teeth
    return np.hypot(p[..., 0], p[..., 1]), theta - pitch * np.round(theta / pitch - 0.25 * s)


def involute_deviation(gear: GearSpec, xyz, side: str) -> np.ndarray:
    """Signed normal distance (mm, + outside the material) of points xyz (..., 3), gear frame
    with z = 0 at mid face width, from the exact involute helicoid of the nearest tooth's
    ``side`` ("pos" / "neg") flank:

        d = r_b cos(beta_b) (s theta - psi(rho)),  s = +1 pos / -1 neg,

    with (rho, theta) the point's radius and polar angle turned back to z = 0 by
    ``helix_rotation`` and taken from the tooth's centre line, psi the half tooth angle.

    Derivation. The flank is invariant under the screw motion that defines
    ``helix_rotation``, so the point may be moved along it to z = 0. Involutes of one base
    circle that differ by a turn delta are parallel curves a distance r_b delta apart along
    their common normals (tangents to the base circle); the involute through the point is
    turned by s theta - psi(rho) from the flank, so its transverse distance is exact. In 3D,
    an involute helicoid is swept by the straight generators of a plane tangent to the base
    cylinder, inclined at beta_b to the axis, and its normals lie in that plane. Helicoids of
    one base cylinder turned by delta cut the plane in parallel generators a distance r_b
    delta apart across the axis, hence r_b delta cos(beta_b) apart along their common normal:
    the normal distance is exact too (for rho >= r_b).
    """
    s = _side_sign(side)
    rho, theta = _untwist(gear, xyz, s)
    if np.any(rho < gear.base_radius * (1.0 - 1e-12)):
        raise GeometryError(
            f"{gear.name}: points at radius {float(np.min(rho)):.6g} mm: must be >= the base "
            f"radius {gear.base_radius:.6g} mm (the involute helicoid ends there)"
        )
    rho = np.maximum(rho, gear.base_radius)
    return gear.base_radius * math.cos(gear.base_helix_angle) * (s * theta - gear._half_angle(rho))


def fillet_deviation(gear: GearSpec, xyz, side: str, n_samples: int = 2000) -> np.ndarray:
    """Signed normal distance (mm, + outside the material) of points xyz (..., 3) from the
    root surface on the ``side`` of the nearest tooth: its generated fillet and the half root
    land from the fillet to the mid-space.

    The points are screwed back to z = 0 (as in ``involute_deviation``) and measured against
    the exact fillet trochoid sampled at ``n_samples`` points (chord error about
    L^2 / (8 R n^2), below 1e-7 mm for real fillets). The transverse distance d_t becomes
    the normal distance d_t / sqrt(1 + (k c x n_t)^2), k = d(helix_rotation)/dz, c the foot
    point and n_t the transverse unit normal, because the surface normal of a screw surface
    is (n_t, -k c x n_t) normalised; exact to first order in d_t.
    """
    s = _side_sign(side)
    rho, theta = _untwist(gear, xyz, s)
    angle = -s * theta  # the pos side is the mirror image of the neg side
    q = np.stack([rho * np.cos(angle), rho * np.sin(angle)], axis=-1).reshape(-1, 2)
    fillet = gear._envelope(np.linspace(0.0, gear._fillet_end, n_samples))
    land = np.linspace(-math.pi / gear.teeth, math.atan2(fillet[0, 1], fillet[0, 0]), 64)[:-1]
    curve = np.vstack([gear.root_radius * np.c_[np.cos(land), np.sin(land)], fillet])
    a, seg = curve[:-1], np.diff(curve, axis=0)
    seg_len2 = np.einsum("ij,ij->i", seg, seg)
    keep = seg_len2 > 0.0
    a, seg, seg_len2 = a[keep], seg[keep], seg_len2[keep]
    k = float(gear.helix_rotation(1.0))
    out = np.empty(len(q))
    chunk = max(1, 2_000_000 // len(seg))
    for i in range(0, len(q), chunk):
        p = q[i : i + chunk]
        d = p[:, None, :] - a
        dot = np.einsum("pij,ij->pi", d, seg)
        w = np.clip(dot / seg_len2, 0.0, 1.0)
        dist2 = np.einsum("pij,pij->pi", d, d) - w * (2.0 * dot - w * seg_len2)
        j = np.argmin(dist2, axis=1)
        foot = a[j] + w[np.arange(len(j)), j][:, None] * seg[j]
        tangent = seg[j] / np.sqrt(seg_len2[j])[:, None]
        # Outward normal: the body lies left of the root -> form direction on the neg side
        # of an external gear, right of it on an internal gear.
        n_t = gear._sigma * np.c_[tangent[:, 1], -tangent[:, 0]]
        d_t = np.einsum("ij,ij->i", p - foot, n_t)
        c_cross_n = foot[:, 0] * n_t[:, 1] - foot[:, 1] * n_t[:, 0]
        out[i : i + chunk] = d_t / np.sqrt(1.0 + (k * c_cross_n) ** 2)
    return out.reshape(rho.shape)


# --------------------------------------------------------------------------------------
# gear pairs
# --------------------------------------------------------------------------------------


@dataclass(frozen=True)
class GearPair:
    """One mesh: gear1 external (sun, pinion), gear2 external or internal (ring), at the
    given centre distance. The gears' shifts may disagree with the centre distance
    (``backlash`` != 0; negative means the teeth overlap); ``with_required_shift`` gives the
    zero-backlash pair.

    Validated on construction: equal normal module, normal pressure angle and helix angle;
    opposite hands for an external mesh, equal for an internal one (spur exempt); an internal
    gear2 with more teeth; a reachable centre distance (cos(alpha_wt) < 1 and a valid gear2
    with the zero-backlash shift). The zero-backlash mesh must also have tip clearance at
    both roots, no involute or fillet interference (each mate's tip meets the flank at or
    above its form circle), a total contact ratio >= 1 and, internal, no tip (trochoid)
    interference.
    """

    gear1: GearSpec
    gear2: GearSpec
    centre_distance: float  # mm

    def __post_init__(self):
        g1, g2 = self.gear1, self.gear2
        for field, g in (("gear1", g1), ("gear2", g2)):
            if not isinstance(g, GearSpec):
                raise GeometryError(f"{field} = {g!r}: must be a GearSpec")
        a = self.centre_distance
        if not (isinstance(a, numbers.Real) and not isinstance(a, bool) and 0 < a < math.inf):
            raise GeometryError(f"centre_distance = {a!r}: must be a number > 0 (mm)")
        object.__setattr__(self, "centre_distance", float(a))
        if g1.internal:
            raise GeometryError(f"{g1.name}.internal = True: gear1 must be external")
        for field in ("normal_module", "normal_pressure_angle", "helix_angle"):
            v1, v2 = getattr(g1, field), getattr(g2, field)
            if not math.isclose(v1, v2, rel_tol=1e-12):
                raise GeometryError(
                    f"{g2.name}.{field} = {v2!r}: must equal {g1.name}.{field} = {v1!r} "
                    "(meshing gears share the basic rack and helix angle)"
                )
        if g1.helix_angle > 0.0 and (g1.hand == g2.hand) != self.internal:
            need = "the same hand as" if self.internal else "the opposite hand to"
            raise GeometryError(
                f"{g2.name}.hand = {g2.hand!r}: an {'internal' if self.internal else 'external'}"
                f" helical mesh needs {need} {g1.name}.hand = {g1.hand!r}"
            )
        if self.internal and g2.teeth <= g1.teeth:
            raise GeometryError(
                f"{g2.name}.teeth = {g2.teeth}: an internal gear needs more teeth than its "
                f"pinion {g1.name}.teeth = {g1.teeth}"
            )
        a_min = self.standard_centre_distance * math.cos(g1.transverse_pressure_angle)
        if self.centre_distance <= a_min:
            raise GeometryError(
                f"centre_distance = {a}: must be > a0 cos(alpha_t) = {a_min:.4f} mm "
                "(no operating pressure angle below it)"
            )
        x2 = self._zero_backlash_shift
        if math.isclose(x2, g2.profile_shift, rel_tol=0.0, abs_tol=1e-12):
            self._check_mesh()
            return
        try:
            g2_meshed = replace(g2, profile_shift=x2)
        except GeometryError as exc:
            raise GeometryError(
                f"centre_distance = {a}: needs {g2.name}.profile_shift = {x2:.4f} for zero "
                f"backlash, which gives an invalid gear: {exc}"
            ) from exc
        GearPair(g1, g2_meshed, a)  # the mesh as it will be built must be valid

    @property
    def internal(self) -> bool:
        return self.gear2.internal

    @property
    def _sign(self) -> int:
        """+1 external, -1 internal: z2 +- z1, a = r_w2 +- r_w1."""
        return -1 if self.internal else 1

    @property
    def standard_centre_distance(self) -> float:
        """a0 = (z2 +- z1) m_t / 2, mm."""
        z_sum = self.gear2.teeth + self._sign * self.gear1.teeth
        return 0.5 * z_sum * self.gear1.transverse_module

    @property
    def operating_pressure_angle(self) -> float:
        """Transverse operating pressure angle (rad): cos(alpha_wt) = a0 cos(alpha_t) / a."""
        a0 = self.standard_centre_distance
        return math.acos(a0 * math.cos(self.gear1.transverse_pressure_angle) / self.centre_distance)

    def _gear(self, i: int) -> GearSpec:
        if i not in (1, 2):
            raise GeometryError(f"i = {i!r}: must be 1 or 2")
        return self.gear1 if i == 1 else self.gear2

    def operating_pitch_radius(self, i: int) -> float:
        """r_wi = r_bi / cos(alpha_wt), mm (i = 1, 2)."""
        return self._gear(i).base_radius / math.cos(self.operating_pressure_angle)

    def operating_helix_angle(self, i: int) -> float:
        """beta_w (rad): tan(beta_w) = tan(beta) r_wi / r_i = tan(beta_b) / cos(alpha_wt), the
        same for both gears (r_w / r = cos(alpha_t) / cos(alpha_wt) for both)."""
        tan_beta_b = math.tan(self._gear(i).base_helix_angle)
        return math.atan(tan_beta_b / math.cos(self.operating_pressure_angle))

    @property
    def required_shift(self) -> float:
        """Zero-backlash shift sum (external x1 + x2; internal x2 - x1) for the centre
        distance: inv(alpha_wt) = inv(alpha_t) + 2 tan(alpha_n) x_sum / (z2 +- z1)."""
        g1 = self.gear1
        z = self.gear2.teeth + self._sign * g1.teeth
        d_inv = involute(self.operating_pressure_angle) - involute(g1.transverse_pressure_angle)
        return float(d_inv * z / (2.0 * math.tan(math.radians(g1.normal_pressure_angle))))

    @property
    def _zero_backlash_shift(self) -> float:
        """gear2's shift that makes the backlash zero, gear1's kept."""
        return self.required_shift - self._sign * self.gear1.profile_shift

    @property
    def backlash(self) -> float:
        """Circumferential backlash on the operating pitch circles, j_wt = 2 pi r_w1 / z1
        - s1(r_w1) - s2(r_w2), mm; the same for internal pairs, where s2 is the ring's tooth
        and 2 pi r_w1 / z1 - s2 its space. Zero when the shifts equal ``required_shift``."""
        r_w1, r_w2 = self.operating_pitch_radius(1), self.operating_pitch_radius(2)
        return float(
            2.0 * math.pi * r_w1 / self.gear1.teeth
            - self.gear1.tooth_thickness(r_w1)
            - self.gear2.tooth_thickness(r_w2)
        )

    @property
    def _path_of_contact(self) -> tuple[float, float, float]:
        """(start roll length on gear1, end roll length on gear2, length of the path of
        contact), mm. With g = a sin(alpha_wt) and L_ai = sqrt(r_ai^2 - r_bi^2): external
        gear1 from g - L_a2, gear2 from g - L_a1 (its lowest point), length L_a1 + L_a2 - g;
        internal gear1 from L_a2 - g, gear2 up to L_a1 + g (its highest point), length
        L_a1 - L_a2 + g."""
        g1, g2 = self.gear1, self.gear2
        g = self.centre_distance * math.sin(self.operating_pressure_angle)
        l_a1 = float(_roll(g1.tip_radius, g1.base_radius))
        l_a2 = float(_roll(g2.tip_radius, g2.base_radius))
        if self.internal:
            return l_a2 - g, l_a1 + g, l_a1 - l_a2 + g
        return g - l_a2, g - l_a1, l_a1 + l_a2 - g

    @property
    def transverse_contact_ratio(self) -> float:
        """eps_alpha = (length of the path of contact) / p_bt, p_bt = 2 pi r_b / z."""
        p_bt = 2.0 * math.pi * self.gear1.base_radius / self.gear1.teeth
        return self._path_of_contact[2] / p_bt

    @property
    def overlap_ratio(self) -> float:
        """eps_beta = b sin(beta) / (pi m_n), b the smaller face width."""
        g1, g2 = self.gear1, self.gear2
        b = min(g1.face_width, g2.face_width)
        return b * math.sin(math.radians(g1.helix_angle)) / (math.pi * g1.normal_module)

    @property
    def total_contact_ratio(self) -> float:
        """eps_gamma = eps_alpha + eps_beta."""
        return self.transverse_contact_ratio + self.overlap_ratio

    def _check_mesh(self):
        g1, g2, a, s = self.gear1, self.gear2, self.centre_distance, self._sign
        where = f"{g1.name}/{g2.name} mesh: centre_distance = {a}"
        clearances = (
            (g1, g2, s * a - g1.tip_radius - s * g2.root_radius),
            (g2, g1, s * (a - g2.tip_radius) - g1.root_radius),
        )
        for tip, root, c in clearances:
            if c < 0.0:
                raise GeometryError(
                    f"{where}: {tip.name} tip circle cuts {root.name} root circle by "
                    f"{-c:.4f} mm (no tip clearance)"
                )
        start1, end2, _ = self._path_of_contact
        l_f1 = float(_roll(g1.form_radius, g1.base_radius))
        l_f2 = float(_roll(g2.form_radius, g2.base_radius))
        if self.internal:
            limits = ((g2, g1, start1 >= l_f1), (g1, g2, end2 <= l_f2))
        else:
            limits = ((g2, g1, start1 >= l_f1), (g1, g2, end2 >= l_f2))
        for tip, flank, ok in limits:
            if not ok:
                raise GeometryError(
                    f"{where}: {tip.name} tip meets {flank.name} beyond its involute (form "
                    f"radius {flank.form_radius:.4f} mm): involute/fillet interference"
                )
        if self.internal:
            margin = _tip_interference_margin(
                g1.teeth,
                g1.tip_radius,
                g1.base_radius,
                g2.teeth,
                g2.tip_radius,
                g2.base_radius,
                a,
                self.operating_pressure_angle,
            )
            if margin < 0.0:
                raise GeometryError(
                    f"{where}: tip interference between {g1.name} and {g2.name} tips after "
                    f"contact; {g2.name}.teeth - {g1.name}.teeth = {g2.teeth - g1.teeth} is "
                    "too few for these tip circles"
                )
        if self.total_contact_ratio < 1.0:
            raise GeometryError(
                f"{where}: total contact ratio {self.total_contact_ratio:.3f} must be >= 1"
            )


def with_required_shift(pair: GearPair) -> GearPair:
    """The pair with gear2 carrying the shift its centre distance needs for zero backlash
    (external x2 = x_sum - x1, internal x2 = x1 + x_sum); gear1 is kept."""
    return replace(pair, gear2=replace(pair.gear2, profile_shift=pair._zero_backlash_shift))


def assign_chain_shifts(gears: list[GearSpec], centre_distances: list[float]) -> list[GearSpec]:
    """Profile shifts along a power path gears[0] -> gears[1] -> ... (sun -> ... -> ring):
    gears[0] keeps its shift and every mesh i (gears[i], gears[i + 1], centre_distances[i])
    puts the shift its centre distance needs on its downstream gear (``with_required_shift``).

    Case 1 (sun, pinion, ring): the sun-pinion mesh runs at the standard centre distance, so
    the pinion gets x = -x_sun = 0 (-1.1e-4 from the printed 51.945 mm, the standard
    51.94518 mm rounded) and the ring the ring mesh's x_ring - x_pinion.
    Case 2 (sun, SP, RP, ring): SP = 0, RP carries the SP-RP sum x_SP + x_RP, the ring
    x_RP + (x_ring - x_RP) of the RP-ring mesh. Every pair is validated on the way.
    """
    if len(centre_distances) != len(gears) - 1:
        raise GeometryError(
            f"centre_distances: {len(centre_distances)} given, must be one per mesh "
            f"({len(gears) - 1} for {len(gears)} gears)"
        )
    out = [gears[0]]
    for gear, a in zip(gears[1:], centre_distances, strict=True):
        out.append(with_required_shift(GearPair(out[-1], gear, a)).gear2)
    return out

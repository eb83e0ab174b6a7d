"""A gear mesh (:class:`GearPair`): operating geometry, backlash, contact ratios, mesh
checks (tip interference, undercut against the mate), the profile shifts that centre
distances need along a power path (:func:`assign_chain_shifts`) and the tooth thickness
allowances that give each mesh of the path its normal backlash (:func:`assign_chain_backlash`,
default :func:`default_normal_backlash`).
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass, replace

from gears.involute import involute, roll_length, tip_interference_margin
from gears.spec import GearSpec, GeometryError

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
        x2 = self.zero_backlash_shift
        if math.isclose(x2, g2.profile_shift, rel_tol=0.0, abs_tol=1e-12):
            self._check_mesh()
            return
        try:
            g2_meshed = replace(g2, profile_shift=x2)
        except GeometryError as exc:
            a0 = self.standard_centre_distance
            way = "larger" if x2 < g2.profile_shift else "smaller"
            raise GeometryError(
                f"centre_distance = {a}: needs {g2.name}.profile_shift = {x2:.4f} for zero "
                f"backlash, which gives an invalid gear: {exc}; the shifts follow from the "
                f"centre distances: a {way} centre_distance, towards the standard "
                f"{a0:.3f} mm (a0 = m_n (z1 {'-' if self.internal else '+'} z2) / "
                f"(2 cos beta), no shift sum), gives {g2.name} a shift nearer 0"
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

    def gear(self, i: int) -> GearSpec:
        """Gear i (1 or 2) of the pair."""
        if i not in (1, 2):
            raise GeometryError(f"i = {i!r}: must be 1 or 2")
        return self.gear1 if i == 1 else self.gear2

    def operating_pitch_radius(self, i: int) -> float:
        """r_wi = r_bi / cos(alpha_wt), mm (i = 1, 2)."""
        return self.gear(i).base_radius / math.cos(self.operating_pressure_angle)

    def operating_helix_angle(self, i: int) -> float:
        """beta_w (rad): tan(beta_w) = tan(beta) r_wi / r_i = tan(beta_b) / cos(alpha_wt), the
        same for both gears (r_w / r = cos(alpha_t) / cos(alpha_wt) for both)."""
        tan_beta_b = math.tan(self.gear(i).base_helix_angle)
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
    def zero_backlash_shift(self) -> float:
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
    def normal_backlash(self) -> float:
        """Normal backlash j_n = j_wt cos(alpha_wt) cos(beta_b), mm: the distance between the
        coast flanks along their common normal when the drive flanks touch (involute
        helicoids of one base cylinder turned by an angle are a uniform normal distance
        apart). With the shifts of the centre distance, j_n = -(A_sn1 + A_sn2) cos(alpha_n)."""
        cos_bb = math.cos(self.gear1.base_helix_angle)
        return self.backlash * math.cos(self.operating_pressure_angle) * cos_bb

    @property
    def path_of_contact_lengths(self) -> tuple[float, float, float]:
        """(start roll length on gear1, end roll length on gear2, length of the path of
        contact), mm. With g = a sin(alpha_wt) and L_ai = sqrt(r_ai^2 - r_bi^2): external
        gear1 from g - L_a2, gear2 from g - L_a1 (its lowest point), length L_a1 + L_a2 - g;
        internal gear1 from L_a2 - g, gear2 up to L_a1 + g (its highest point), length
        L_a1 - L_a2 + g."""
        g1, g2 = self.gear1, self.gear2
        g = self.centre_distance * math.sin(self.operating_pressure_angle)
        l_a1 = float(roll_length(g1.tip_radius, g1.base_radius))
        l_a2 = float(roll_length(g2.tip_radius, g2.base_radius))
        if self.internal:
            return l_a2 - g, l_a1 + g, l_a1 - l_a2 + g
        return g - l_a2, g - l_a1, l_a1 + l_a2 - g

    @property
    def transverse_contact_ratio(self) -> float:
        """eps_alpha = (length of the path of contact) / p_bt, p_bt = 2 pi r_b / z."""
        p_bt = 2.0 * math.pi * self.gear1.base_radius / self.gear1.teeth
        return self.path_of_contact_lengths[2] / p_bt

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
                    f"{-c:.4f} mm (no tip clearance): lower {tip.name}.addendum_coef (by "
                    f"{math.ceil(-c / tip.normal_module * 1e3) / 1e3:.3f} or more, its tip by "
                    f"{-c:.4f} mm or more) or raise {root.name}.dedendum_coef by as much"
                )
        start1, end2, _ = self.path_of_contact_lengths
        l_f1 = float(roll_length(g1.form_radius, g1.base_radius))
        l_f2 = float(roll_length(g2.form_radius, g2.base_radius))
        if self.internal:
            limits = ((g2, g1, start1 >= l_f1), (g1, g2, end2 <= l_f2))
        else:
            limits = ((g2, g1, start1 >= l_f1), (g1, g2, end2 >= l_f2))
        for tip, flank, ok in limits:
            if not ok:
                raise GeometryError(
                    f"{where}: {tip.name} tip meets {flank.name} beyond its involute (form "
                    f"radius {flank.form_radius:.4f} mm): involute/fillet interference; "
                    f"lower {tip.name}.addendum_coef (a shorter tip), or give {flank.name} "
                    "a lower hob_tip_radius_coef or a higher dedendum_coef (the tool's "
                    f"straight flank then reaches deeper: {flank.name}'s involute starts "
                    "lower), or change the centre distance (the shifts follow from it)"
                )
        if self.internal:
            margin = tip_interference_margin(
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
        # eps_alpha, not eps_gamma: a helical overlap of 2 let a path of contact of negative
        # length (teeth that never meet) pass a check of the total; ISO 6336-2/-3 (Z_eps, the
        # load at the outer point of single tooth contact) take eps_alpha >= 1
        if self.transverse_contact_ratio < 1.0:
            raise GeometryError(
                f"{where}: transverse contact ratio eps_alpha = "
                f"{self.transverse_contact_ratio:.3f} must be >= 1 (the path of contact at "
                "least one base pitch; ISO 6336's factors assume it)"
            )


def with_required_shift(pair: GearPair) -> GearPair:
    """The pair with gear2 carrying the shift its centre distance needs for zero backlash
    (external x2 = x_sum - x1, internal x2 = x1 + x_sum); gear1 is kept."""
    return replace(pair, gear2=replace(pair.gear2, profile_shift=pair.zero_backlash_shift))


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


# --------------------------------------------------------------------------------------
# backlash: tooth thickness allowances along the power path
# --------------------------------------------------------------------------------------


#: allowances below this (mm) are round-off of a zero-backlash shift and set to zero
ALLOWANCE_TOL = 1e-9


def default_normal_backlash(centre_distance: float, normal_module: float) -> float:
    """Normal backlash (mm) a mesh gets when its gear set does not give one: the minimum
    normal backlash recommended for industrial steel gears in a steel or cast-iron housing
    (ISO/TR 10064-2:1996, also AGMA 2002 / ANSI-AGMA 915-1), j_bn,min = 2/3 (0.06 + 0.0005
    a + 0.03 m_n) mm, a and m_n in mm. It allows for thermal expansion, lubricant film and
    the deviations of an ordinary quality; the allowances of a real gear add their
    tolerance on top, so this is the tightest backlash a gear engineer would specify.
    Case 1 (a = 51.945 mm, m_n = 1.59 mm): 89.1 um."""
    return 2.0 / 3.0 * (0.06 + 0.0005 * centre_distance + 0.03 * normal_module)


def assign_chain_backlash(
    gears: list[GearSpec], centre_distances: list[float], normal_backlash: list[float]
) -> list[GearSpec]:
    """Tooth thickness allowances (``thickness_allowance``) along a power path gears[0] ->
    gears[1] -> ... (sun -> ... -> ring) that give mesh i the normal backlash
    ``normal_backlash[i]`` (mm, >= 0) at its centre distance, the shifts kept.

    The first gear (sun) takes half of its mesh's allowance and every later gear the rest of
    the mesh that drives it: A_sn2 = (j_n0 - j_n) / cos(alpha_n), j_n0 the mesh's normal
    backlash with gear2 at zero allowance (j_n falls by A_sn2 cos(alpha_n), exactly). With
    equal backlash at every mesh this splits it equally: case 1 (89.1 um at both meshes)
    gives sun, pinion and ring A_sn = -47.4 um each. Like the shifts, it keeps the drive
    flanks of every mesh in contact and the centre distances exact; the backlash appears on
    the coast flanks. A gear whose allowance leaves its valid range raises GeometryError.
    """
    n_mesh = len(gears) - 1
    for what, v in (("centre_distances", centre_distances), ("normal_backlash", normal_backlash)):
        if len(v) != n_mesh:
            raise GeometryError(
                f"{what}: {len(v)} given, must be one per mesh ({n_mesh} for {len(gears)} gears)"
            )
    for j in normal_backlash:
        if not (isinstance(j, numbers.Real) and math.isfinite(j) and j >= 0.0):
            raise GeometryError(f"normal_backlash = {j!r}: must be a number >= 0 (mm)")
    cos_an = math.cos(math.radians(gears[0].normal_pressure_angle))

    def allowance(j_from: float, j_to: float, share: float = 1.0) -> float:
        # a backlash change below ALLOWANCE_TOL is round-off of the shifts' zero backlash: a
        # zero-backlash set keeps exactly the gears (and meshes) of zero allowance
        a = share * (j_from - j_to) / cos_an
        return 0.0 if abs(a) < ALLOWANCE_TOL else a

    first = replace(gears[0], thickness_allowance=0.0)
    j0 = GearPair(first, replace(gears[1], thickness_allowance=0.0), centre_distances[0])
    out = [
        replace(first, thickness_allowance=allowance(j0.normal_backlash, normal_backlash[0], 0.5))
    ]
    for gear, a, j in zip(gears[1:], centre_distances, normal_backlash, strict=True):
        bare = replace(gear, thickness_allowance=0.0)
        a_sn = allowance(GearPair(out[-1], bare, a).normal_backlash, j)
        out.append(replace(bare, thickness_allowance=a_sn))
        GearPair(out[-2], out[-1], a)  # the mesh as it will be built must be valid
    return out

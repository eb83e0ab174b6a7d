"""Tooth flank modifications (microgeometry) of one gear: what they remove from its exact
involute flanks, as a normal distance (mm) at points of the flank.

The modifications are micron-sized, so they are not built into the FE meshes (those keep the
exact unmodified flanks, :mod:`gears.profile`): they enter the contact as initial gaps. The
contact grid (:mod:`solvers.flank_grid`) adds the removal of the driver's and of the driven
gear's flank at each grid point to its initial gap.

Modifications of a gear (:class:`FlankModifications`; all optional, default none), in the
gear frame (z along the axis, z = 0 at mid face width, b the gear's own face width), each
applied to both flanks of every tooth, as removal of material along the flank normal:

* lead crown C_b (``lead_crown_um``): parabolic across the face, C_b (2 z / b)^2, C_b at both
  face ends, none at mid face;
* lead slope (helix angle modification) f_Hb (``lead_slope_um``): linear across the face,
  s f_Hb z / b on the flank of side s (+1 ``pos``, -1 ``neg``): f_Hb / 2 removed at the +z end
  of the pos flank and added at its -z end, the neg flank the other way round. Every transverse
  section is turned by -f_Hb z / (b r_b cos(beta_b)): the helix turns as a whole, which is
  what a change of the helix angle does (the base helix angle of a right-hand gear falls by
  f_Hb cos(beta_b) / b rad, a left-hand gear's rises). Added material is a negative removal
  (the flank stands proud of the exact involute);
* tip relief C_a from the start diameter d_Ca (``tip_relief_um``, ``tip_relief_diameter``):
  linear in roll length L = sqrt(r^2 - r_b^2) from d_Ca (none) to the tip circle (C_a),
  C_a (L - L_Ca) / (L_a - L_Ca) where positive (internal gears: the tip is the inner circle,
  d_Ca lies outside it, the same formula);
* end relief C_I over a length l_I from each face end (``end_relief_um``,
  ``end_relief_length``): linear, C_I (|z| - (b/2 - l_I)) / l_I where positive.

The total is the sum of the four (:func:`flank_modification`). Signs: a positive removal
opens the gap; points are taken where they are, beyond the face or tip circle the linear
laws continue.
"""

from __future__ import annotations

import math
import numbers
from dataclasses import asdict, dataclass

import numpy as np

from gears.spec import GearSpec, GeometryError

UM = 1e-3  # mm per um
#: largest modification (um): micro-geometry, not a different tooth
MAX_MODIFICATION_UM = 500.0
FIELDS = (
    "lead_crown_um",
    "lead_slope_um",
    "tip_relief_um",
    "tip_relief_diameter",
    "end_relief_um",
    "end_relief_length",
)


@dataclass(frozen=True)
class FlankModifications:
    """The flank modifications of one gear (see the module docstring); every field is
    optional. Validated on construction (numbers in range, GeometryError naming the field);
    :meth:`check` checks them against the gear (start diameter, relief length)."""

    lead_crown_um: float = 0.0  # >= 0, at both face ends
    lead_slope_um: float = 0.0  # across the face width, pos flank removal at +z minus -z
    tip_relief_um: float = 0.0  # >= 0, at the tip circle
    tip_relief_diameter: float | None = None  # mm, where the tip relief starts
    end_relief_um: float = 0.0  # >= 0, at each face end
    end_relief_length: float | None = None  # mm from each face end

    def __post_init__(self):
        for f in ("lead_crown_um", "tip_relief_um", "end_relief_um"):
            self._number(f, 0.0, MAX_MODIFICATION_UM)
        self._number("lead_slope_um", -MAX_MODIFICATION_UM, MAX_MODIFICATION_UM)
        for f, amount in (
            ("tip_relief_diameter", "tip_relief_um"),
            ("end_relief_length", "end_relief_um"),
        ):
            if getattr(self, f) is not None:
                self._number(f, 0.0, math.inf, lo_open=True)
            elif getattr(self, amount) > 0.0:
                self._fail(f, f"must be given (mm) with {amount} = {getattr(self, amount)!r}")

    def _fail(self, field: str, rule: str):
        raise GeometryError(f"modifications.{field} = {getattr(self, field)!r}: {rule}")

    def _number(self, field: str, lo: float, hi: float, lo_open: bool = False):
        v = getattr(self, field)
        ok = isinstance(v, numbers.Real) and not isinstance(v, bool) and math.isfinite(v)
        if not (ok and (lo < v if lo_open else lo <= v) and v <= hi):
            if hi == math.inf:
                rng = f"> {lo:g}" if lo_open else f">= {lo:g}"
            else:
                rng = f"in {'(' if lo_open else '['}{lo:g}, {hi:g}]"
            self._fail(field, f"must be a number {rng}")
        object.__setattr__(self, field, float(v))

    @property
    def is_zero(self) -> bool:
        """True when nothing is removed anywhere."""
        return self.lead_crown_um == self.lead_slope_um == self.tip_relief_um == 0.0 and (
            self.end_relief_um == 0.0
        )

    def as_dict(self) -> dict:
        return asdict(self)

    def check(self, gear: GearSpec) -> None:
        """GeometryError (naming ``<gear>.modifications.<field>``) unless the tip relief
        starts on the gear's involute, between its form and tip diameters, and the end relief
        is at most half the face width long."""
        if self.tip_relief_diameter is not None:
            lo, hi = sorted((2.0 * gear.form_radius, 2.0 * gear.tip_radius))
            if not lo < self.tip_relief_diameter < hi:
                raise GeometryError(
                    f"{gear.name}.modifications.tip_relief_diameter = "
                    f"{self.tip_relief_diameter!r}: must lie between the form and tip "
                    f"diameters ({lo:.4f}, {hi:.4f}) mm"
                )
        if self.end_relief_length is not None and self.end_relief_length > 0.5 * gear.face_width:
            raise GeometryError(
                f"{gear.name}.modifications.end_relief_length = {self.end_relief_length!r}: "
                f"must be <= half the face width, {0.5 * gear.face_width:g} mm"
            )


NONE = FlankModifications()


def _side_sign(side: str) -> int:
    if side not in ("pos", "neg"):
        raise GeometryError(f"side = {side!r}: must be 'pos' or 'neg'")
    return 1 if side == "pos" else -1


def flank_modification(gear: GearSpec, mods: FlankModifications | None, side: str, xyz):
    """Material removed (mm, along the flank normal; negative: added) from the ``side``
    flank ("pos" / "neg") of ``gear`` by ``mods`` at points xyz (..., 3) in the gear frame
    (z = 0 at mid face width); the sum of lead crown, lead slope, tip relief and end relief
    (module docstring). ``mods`` None: no modification (zeros)."""
    s = _side_sign(side)
    p = np.asarray(xyz, dtype=float)
    out = np.zeros(p.shape[:-1])
    if mods is None or mods.is_zero:
        return out
    b = gear.face_width
    z = p[..., 2]
    if mods.lead_crown_um:
        out += mods.lead_crown_um * UM * (2.0 * z / b) ** 2
    if mods.lead_slope_um:
        out += s * mods.lead_slope_um * UM * z / b
    if mods.tip_relief_um:
        rb = gear.base_radius
        roll = np.sqrt(np.maximum(p[..., 0] ** 2 + p[..., 1] ** 2 - rb * rb, 0.0))
        l_start = math.sqrt(max((0.5 * mods.tip_relief_diameter) ** 2 - rb * rb, 0.0))
        l_tip = math.sqrt(gear.tip_radius**2 - rb * rb)
        out += mods.tip_relief_um * UM * np.maximum((roll - l_start) / (l_tip - l_start), 0.0)
    if mods.end_relief_um:
        length = mods.end_relief_length
        out += mods.end_relief_um * UM * np.maximum((np.abs(z) - (0.5 * b - length)) / length, 0.0)
    return out

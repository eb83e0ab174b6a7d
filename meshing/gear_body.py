"""What a gear body is: a helical gear (full, or a sector of n teeth) with its bore or rim.

:class:`GearBody` describes the body and checks its fields; it is pure data (no gmsh), and
its :meth:`GearBody.params` are the body's part of the mesh cache key. The body is drawn by
:mod:`meshing.body_outline` (transverse outline, numpy), built as a gmsh OCC solid and its
faces named by :mod:`meshing.body_geometry`, meshed by :mod:`meshing.body_mesh`, and cached
and loaded by :mod:`meshing.body_cache`.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

from meshing import tags as T
from meshing.sizing import MeshingError

MIN_SECTIONS = 5  # the feasibility probe: 3 sections deviate 0.64 mm, 5+ sections < 1 um


#: the thinnest rim a body keeps between its root circle and its bore (or outer rim), in
#: normal modules
RIM_MODULES = 1.0


@dataclass(frozen=True)
class GearBody:
    """What to build: a gear (GearSpec), which teeth, and the bore or rim.

    ``first_tooth``/``n_teeth``: the sector holds the teeth ``first_tooth`` ...
    ``first_tooth + n_teeth - 1`` (mod z) and is cut in the middle of the two tooth spaces
    at its ends; ``n_teeth=None`` is the full gear. ``inner_radius`` is the bore radius of
    an external gear, ``outer_radius`` the rim (outside) radius of an internal gear.
    """

    gear: object  # gears.spec.GearSpec
    name: str | None = None  # body name in the tags (default: gear.name)
    first_tooth: int = 0
    n_teeth: int | None = None
    inner_radius: float | None = None
    outer_radius: float | None = None
    n_sections: int = 9  # 9 sections: node deviation from the helicoid ~0.01 um
    n_involute: int = 20
    n_fillet: int = 14
    # (tooth, "pos"/"neg") of the fillets meshed at the level's ``fillet`` size; None: every
    # fillet of the active teeth (the other fillets of active teeth get ``fillet_far``)
    fine_fillets: tuple[tuple[int, str], ...] | None = None
    # 1: straight 4-node tets; 2: curved 10-node tets whose edge nodes lie on the CAD faces
    # (meshing.gmsh_util.curve_elements; the root-stress sectors, meshing/submodel.py)
    geometry_order: int = 1

    @property
    def body(self) -> str:
        return self.name if self.name is not None else self.gear.name

    @property
    def full(self) -> bool:
        return self.n_teeth is None

    @property
    def teeth(self) -> list[int]:
        z = self.gear.teeth
        n = z if self.full else self.n_teeth
        return [(self.first_tooth + i) % z for i in range(n)]

    @property
    def cut_angles(self) -> tuple[float, float] | None:
        """Polar angles (z = 0, gear frame) of the neg and pos sector cuts; None if full."""
        if self.full:
            return None
        p = 2.0 * math.pi / self.gear.teeth
        return (self.first_tooth - 0.5) * p, (self.first_tooth + self.n_teeth - 0.5) * p

    def validate(self) -> None:
        """Raise :class:`MeshingError` naming the field and the allowed range."""
        g = self.gear
        T.check_body_name(self.body)
        z = g.teeth
        if self.n_teeth is not None:
            if isinstance(self.n_teeth, bool) or not isinstance(self.n_teeth, int):
                raise MeshingError(f"{self.body}: n_teeth = {self.n_teeth!r}: must be an integer")
            if not 1 <= self.n_teeth <= z // 2:
                raise MeshingError(
                    f"{self.body}: n_teeth = {self.n_teeth}: a sector holds 1 to {z // 2} teeth "
                    f"(half of z = {z}); use n_teeth=None for the full gear"
                )
        if not isinstance(self.first_tooth, int) or not 0 <= self.first_tooth < z:
            raise MeshingError(
                f"{self.body}: first_tooth = {self.first_tooth!r}: must be an integer "
                f"from 0 to {z - 1}"
            )
        if not isinstance(self.n_sections, int) or not MIN_SECTIONS <= self.n_sections <= 64:
            raise MeshingError(
                f"{self.body}: n_sections = {self.n_sections!r}: must be an integer from "
                f"{MIN_SECTIONS} to 64 (fewer sections do not follow the helicoid)"
            )
        for field, val, lo in (("n_involute", self.n_involute, 8), ("n_fillet", self.n_fillet, 6)):
            if not isinstance(val, int) or not lo <= val <= 200:
                raise MeshingError(f"{self.body}: {field} = {val!r}: must be from {lo} to 200")
        if self.fine_fillets is not None:
            for item in self.fine_fillets:
                ok = isinstance(item, tuple) and len(item) == 2 and item[1] in ("pos", "neg")
                if not ok or isinstance(item[0], bool) or item[0] not in self.teeth:
                    raise MeshingError(
                        f"{self.body}: fine_fillets entry {item!r}: must be (tooth, 'pos' or "
                        f"'neg') with a tooth of the body ({self.teeth})"
                    )
        if self.geometry_order not in (1, 2) or isinstance(self.geometry_order, bool):
            raise MeshingError(
                f"{self.body}: geometry_order = {self.geometry_order!r}: must be 1 (straight "
                "tets) or 2 (curved tets)"
            )
        m = g.normal_module
        if g.internal:
            if self.inner_radius is not None:
                raise MeshingError(f"{self.body}: inner_radius: an internal gear has no bore")
            lo = g.root_radius + RIM_MODULES * m
            if self.outer_radius is None or not self.outer_radius >= lo:
                raise MeshingError(
                    f"{self.body}: outer_radius = {self.outer_radius!r}: the rim radius of an "
                    f"internal gear must be >= root radius + {RIM_MODULES:g} module = {lo:.3f} mm"
                )
        else:
            if self.outer_radius is not None:
                raise MeshingError(f"{self.body}: outer_radius: only for internal gears")
            hi = g.root_radius - RIM_MODULES * m
            if self.inner_radius is None or not 0.0 < self.inner_radius <= hi:
                raise MeshingError(
                    f"{self.body}: inner_radius = {self.inner_radius!r}: the bore radius must "
                    f"be > 0 and <= root radius - {RIM_MODULES:g} module = {hi:.3f} mm"
                )

    def params(self) -> dict:
        """Canonical parameters (for the cache key)."""
        d = {k: v for k, v in asdict(self).items() if k != "gear"}
        if self.fine_fillets is None:  # the key of a body without it is the key it had
            del d["fine_fillets"]
        if self.geometry_order == 1:  # likewise
            del d["geometry_order"]
        d["gear"] = {k: v for k, v in asdict(self.gear).items()}
        d["body"] = self.body
        return d

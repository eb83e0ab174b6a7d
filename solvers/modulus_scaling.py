"""One factorization for every Young's modulus of a body: K(s E) = s K(E) at a fixed nu.

The stiffness of a linear elastic body is linear in E at a fixed Poisson ratio (lambda and
mu both scale with E), so a body assembled and factorized with modulus E solves the same
body of modulus s E by dividing its solutions by s:

    K(s E) u = b   <=>   u = K(E)^{-1} b / s.

The paper's 1-GB-R case (the gears 10x stiffer, singh2007 section 5) is 1-GB's gear set with
E x 10: with these views it reuses 1-GB's gear factorizations and submodel sectors instead
of building them again (the gears' factors are the largest objects of a run). The supports
must scale too: a body with a finite spring to ground (neither fixed nor free) does not,
and is refused.

A view holds its own :class:`~solvers.elastic_body.Material` (what the stresses and the
contact modulus read) and passes everything else to the body it stands on.
"""

from __future__ import annotations

import math

from solvers.elastic_body import Material


def modulus_scale(base: Material, material: Material) -> float:
    """s = E / E_base for the same Poisson ratio; ValueError otherwise."""
    if material.nu != base.nu:
        raise ValueError(f"a modulus view needs the same nu ({material.nu} != {base.nu})")
    return material.E / base.E


class _View:
    """Attributes not set on the view are the body's."""

    def __init__(self, body, material: Material):
        self._body = body
        self.material = material
        self.scale = modulus_scale(body.material, material)

    def __getattr__(self, name):
        return getattr(self._body, name)


class ScaledBody(_View):
    """:class:`~solvers.elastic_body.ElasticBody` ``body`` seen with ``material`` (the same nu):
    every solve is the body's divided by s = E / E_body. Placement, holds and release act on
    the body itself."""

    def __init__(self, body, material: Material):
        for c in body.couplings.values():
            bad = [k for k in c.stiffness if k != 0 and not math.isinf(k)]
            if bad:
                raise ValueError(
                    f"body '{body.name}', coupling '{c.name}': a spring of {bad[0]} does not "
                    "scale with the modulus; set up the body with its own material"
                )
        super().__init__(body, material)

    def solve(self, b):
        x = self._body.solve(b)
        x.scale(1.0 / self.scale)
        return x

    def solve_dense(self, B):
        X = self._body.solve_dense(B)
        X.scale(1.0 / self.scale)
        return X


class ScaledSubmodel(_View):
    """:class:`~solvers.root_submodel.SubmodelBody` ``sector`` seen with ``material``: the
    sector's operator is s A, so the displacement driven by the cut values g and forces f is
    the sector's own solution for g and f / s (the same relative residual: its right-hand
    side is the scaled one divided by s)."""

    def solve(self, global_body, u_global, loads, angle: float):
        points, forces = loads
        return self._body.solve(global_body, u_global, (points, forces / self.scale), angle)


def with_material(obj, material: Material, view):
    """``obj`` itself if it has ``material`` already, else ``view(obj, material)``."""
    return obj if obj.material == material else view(obj, material)


__all__ = ["ScaledBody", "ScaledSubmodel", "modulus_scale", "with_material"]

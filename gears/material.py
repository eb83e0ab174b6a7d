"""Elastic material constants: the one place the pipeline's default steel is defined.

singh2007 gives no material; steel is taken as E = 206 GPa, nu = 0.3 (the case files say
so and may override it)."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Isotropic:
    youngs_modulus: float  # MPa
    poisson_ratio: float


STEEL = Isotropic(youngs_modulus=206.0e3, poisson_ratio=0.3)

"""A case file's study moved to the system scene, with its material edited (test helper)."""

import dataclasses


def as_system(study, **material):
    """``study`` in the ``system`` scene with ``material`` fields replaced (e.g. a carrier
    1000x stiffer than the gears: youngs_modulus=206e6, gear_modulus_factor=1e-3)."""
    mat = dataclasses.replace(study.material, **material)
    model = dataclasses.replace(study.model, scene="system")
    return dataclasses.replace(study, material=mat, model=model)

"""Variants of a case file's study that a study derives for its own purpose."""

from __future__ import annotations

import dataclasses


def global_root_stress(study):
    """``study`` with ``numerics.root_stress = "global"``: the same meshes and the same
    solution (the root-stress submodels are driven by the global solution and feed nothing
    back), so every moment, centroid, pattern and contact stress is the case file's; only
    the root stress is read on the global fillets instead of on the P2 submodels, which are
    most of a level-1 position's time. For the studies and tests that read no root stress."""
    numerics = dataclasses.replace(study.numerics, root_stress="global")
    return dataclasses.replace(study, numerics=numerics)

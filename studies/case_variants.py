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


def no_root_stress(study):
    """``study`` with ``numerics.root_stress = "none"``: the same solution, no root stress
    read, in any scene. For the studies and tests of moments, load shares or stiffness alone
    whose scene may have coarse fillets (``global_root_stress`` needs refined ones)."""
    numerics = dataclasses.replace(study.numerics, root_stress="none")
    return dataclasses.replace(study, numerics=numerics)


def coarse_root_fillets(study):
    """``study`` with ``numerics.root_fillets = "coarse"``: the global model's fillets as in
    the system scene (finer fillets make the teeth more compliant: 0.4 % of 2B-GA's LOA
    moments at level 0; the submodels still read the root stress). For comparisons with the
    system scene."""
    numerics = dataclasses.replace(study.numerics, root_fillets="coarse")
    return dataclasses.replace(study, numerics=numerics)

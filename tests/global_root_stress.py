"""A case file's study with its root stress read on the global model (test helper)."""

import dataclasses


def global_root_stress(study):
    """``study`` with ``numerics.root_stress = "global"``: the same meshes and the same
    solution (the submodels are driven by the global solution and feed nothing back), so
    every moment, centroid, pattern and contact stress is the case file's; only the root
    stress is read on the global fillets instead of on the P2 submodels, which are most of a
    level-0 position's time. For the tests that read no root stress."""
    numerics = dataclasses.replace(study.numerics, root_stress="global")
    return dataclasses.replace(study, numerics=numerics)

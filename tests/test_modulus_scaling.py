"""A gear set of another Young's modulus solves on the factors and sectors of the first
(solvers.modulus_scaling): K(s E) = s K(E) at a fixed Poisson ratio, so 1-GB-R (the gears
10x stiffer) reuses 1-GB's bodies. Checked against bodies and sectors set up with the
modulus itself, and the views refuse what does not scale."""

import dolfinx_solver  # noqa: F401 - must precede dolfinx

# isort: split
import math
from dataclasses import replace
from types import SimpleNamespace

import numpy as np
import pytest
from mpi4py import MPI

from cases.study_case import load_study_case
from meshing import sizing
from meshing.scene_bodies import load_body_meshes
from solvers.body_store import BodyStore
from solvers.elastic_body import Material
from solvers.gear_train import build_gear_train
from solvers.modulus_scaling import ScaledBody, ScaledSubmodel, modulus_scale
from solvers.root_submodel import submodel_root_stress
from studies.position import study_scene, train_inputs


def _solve(scene, meshes, study, store):
    model = build_gear_train(
        scene,
        meshes,
        train_inputs(study),
        degree=1,
        store=store,
        spacing=sizing.check_level(0).fine,
        penalty_factor=100.0,
    )
    res = model.problem.solve()
    return model, res, submodel_root_stress(model, res, 0, store)


@pytest.mark.slow
def test_a_stiffer_gear_set_solves_on_the_first_ones_factors():
    """1-GA at level 0 (one branch, P1, the P2 sectors of the root stress): solved with steel
    gears, then with the gears 10x stiffer on the same store, nothing is set up again (the
    gears and the four sectors are views), and every result equals that of bodies and
    sectors set up with 10 E. Exact arithmetic gives the same numbers (the same factors;
    CG's iterates on s A for s b are the iterates on A for b, GAMG's aggregation and
    Chebyshev bounds are relative), so the tolerances are round-off with a margin (measured
    2026-11-28: contact forces 1.1e-8 of the largest, rigid unknowns 1e-10, displacements
    5e-11, root stresses 2.3e-10): forces and rigid unknowns 1e-6 (the penalty contact
    solve amplifies round-off), displacements 1e-8, root stresses 1e-6. A view that forgot
    to divide by s (or divided twice) is off by a factor of 10."""
    study = load_study_case("1-GA")
    stiff = replace(study, material=replace(study.material, gear_modulus_factor=10.0))
    scene = study_scene(study, 0.0)
    meshes = load_body_meshes(scene, 0, MPI.COMM_WORLD)
    store = BodyStore()
    _solve(scene, meshes, study, store)
    built = store.built
    model, res, rs = _solve(scene, meshes, stiff, store)
    assert store.built == built  # every gear and sector reused
    # and the FE compliance columns, read from the gears' kept columns divided by s: the
    # stiffer set's narrower Hertz band keeps one section more on the pinion-ring mesh, whose
    # rows are completed by a few solves (measured: 8 solves against 248 columns read)
    t = model.problem.timings
    assert (
        0 < t["compliance_columns_kept"]
        and t["compliance_solves"] <= 0.05 * t["compliance_columns_kept"]
    )
    assert all(isinstance(b, ScaledBody) for b in model.problem.bodies.values())
    assert all(b.scale == pytest.approx(10.0) for b in model.problem.bodies.values())
    _, ref, ref_rs = _solve(scene, meshes, stiff, BodyStore())
    f, f0 = np.asarray(res.forces), np.asarray(ref.forces)
    assert np.abs(f - f0).max() <= 1e-6 * np.abs(f0).max()
    for k, q0 in ref.rigid.items():
        assert res.rigid[k] == pytest.approx(q0, rel=1e-6, abs=1e-12), k
    for nm, u0 in ref.displacements.items():
        a0 = u0.getArray(readonly=True)
        a = res.displacements[nm].getArray(readonly=True)
        assert np.abs(a - a0).max() <= 1e-8 * np.abs(a0).max(), nm
    keys = list(ref_rs["locations"])
    assert len(keys) == 4  # sun, pinion sun side, pinion ring side, ring
    for key in keys:
        assert rs[key] == pytest.approx(ref_rs[key], rel=1e-6), key
        for q in ("tangent", "cell_max"):
            assert rs[q][key] == pytest.approx(ref_rs[q][key], rel=1e-6), (key, q)


def test_the_views_refuse_what_does_not_scale():
    """A finite spring to ground does not scale with E (the body must be set up with its
    own modulus), nor does a body of another Poisson ratio."""
    steel = Material(206000.0, 0.3)
    assert modulus_scale(steel, Material(2060000.0, 0.3)) == pytest.approx(10.0)
    with pytest.raises(ValueError, match="same nu"):
        modulus_scale(steel, Material(206000.0, 0.29))
    spring = SimpleNamespace(name="bore", stiffness=(0.0, math.inf, 5.0e4))
    body = SimpleNamespace(name="pin", material=steel, couplings={"bore": spring})
    with pytest.raises(ValueError, match=r"pin.*bore.*does not scale"):
        ScaledBody(body, Material(412000.0, 0.3))
    free = SimpleNamespace(name="bore", stiffness=(0.0, math.inf))
    body = SimpleNamespace(name="sun", material=steel, couplings={"bore": free})
    assert ScaledBody(body, Material(412000.0, 0.3)).scale == pytest.approx(2.0)


def test_a_sector_view_divides_the_forces_not_the_cut():
    """The sector's operator is s A: its solution for cut values g and forces f is the
    stored sector's for g and f / s (the cut values are displacements, not scaled)."""
    seen = {}

    class Sector:
        material = Material(1.0, 0.3)

        def solve(self, global_body, u_global, loads, angle):
            seen.update(u=u_global, forces=loads[1], angle=angle)
            return "u"

    view = ScaledSubmodel(Sector(), Material(4.0, 0.3))
    f = np.array([[4.0, 8.0, -2.0]])
    assert view.solve(None, "g", (np.zeros((1, 3)), f), 0.5) == "u"
    assert seen["u"] == "g" and seen["angle"] == 0.5
    assert np.allclose(seen["forces"], f / 4.0)
    assert view.material.E == 4.0

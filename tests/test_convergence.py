"""Richardson extrapolation and GCI (studies.convergence.richardson): synthetic sequences with a
known order and limit, every non-monotone status, the summary scalars and uncertainty entries, and
an FE case with a closed form (Lame's thick cylinder) where the study recovers the order of
P1 elements and the exact limit."""

from __future__ import annotations

import math

import dolfinx_solver  # noqa: F401 - orders MPI ahead of the bindings

# isort: split
import dolfinx
import numpy as np
import pytest
import ufl
from mpi4py import MPI

from postprocess import run_scalars
from postprocess.convergence_record import uncertainty_for
from postprocess.plus_minus import NOT_CARRIED, OFFSET_REL_MAX, plus_minus
from solvers.elastic_body import Dirichlet, ElasticBody, Material, Traction
from studies.convergence import richardson as cv

LADDER = (1.0, 0.7, 0.45)  # the flank element sizes of levels 0, 1, 2 (meshing.sizing)


def _sequence(h, limit, c, p):
    return [limit + c * hi**p for hi in h]


@pytest.mark.parametrize("h", [(1.0, 0.5, 0.25), LADDER, (0.45, 1.0, 0.7)])
@pytest.mark.parametrize("p", [0.8, 1.0, 2.0, 3.5])
def test_known_order_and_limit(h, p):
    f = _sequence(h, 7.3, -0.9, p)
    res = cv.richardson(h, f)
    assert res.status == "monotone"
    assert res.order == pytest.approx(p, abs=1e-8)  # exact data: bisection resolution only
    assert res.extrapolated == pytest.approx(7.3, rel=1e-9)
    for hi, fi, e in zip(h, f, res.rel_error, strict=True):  # in the order given
        assert e == pytest.approx((fi - 7.3) / 7.3, rel=1e-6)
        assert hi > 0


def test_constant_ratio_order_is_the_textbook_formula():
    f = [2.0, 2.3, 2.38]  # coarse, medium, fine at r = 2
    res = cv.richardson([4.0, 2.0, 1.0], f)
    assert res.order == pytest.approx(math.log(0.3 / 0.08) / math.log(2.0), rel=1e-10)


def test_gci_of_the_finest_grid_is_roache():
    h, f = LADDER, _sequence(LADDER, 10.0, 2.0, 1.5)
    res = cv.richardson(h, f)
    r21, e21 = h[1] / h[2], f[1] - f[2]
    gci_fine = cv.SAFETY * abs(e21 / f[2]) / (r21**res.order - 1.0)
    assert res.uncertainty[2] == pytest.approx(gci_fine, rel=1e-9)
    assert res.uncertainty_abs[0] == pytest.approx(cv.SAFETY * abs(f[0] - 10.0), rel=1e-9)


def test_order_cap_makes_the_gci_larger_not_the_extrapolation():
    h, f = LADDER, _sequence(LADDER, 1.0, 0.5, 4.0)
    free, capped = cv.richardson(h, f), cv.richardson(h, f, p_cap=2.0)
    assert capped.extrapolated == free.extrapolated and capped.gci_order == 2.0
    assert all(c > u for c, u in zip(capped.uncertainty, free.uncertainty, strict=True))
    assert "cap" in capped.note


@pytest.mark.parametrize(
    ("f", "status"),
    [
        ([1.0, 1.1, 1.05], "oscillatory"),  # coarse, medium, fine
        ([1.0, 1.01, 1.03], "divergent"),  # changes grow as h falls
        (_sequence(LADDER, 1.0, 1.0, 0.3), "stagnant"),  # they barely shrink: p = 0.3
        ([2.5, 2.5, 2.5], "mesh-independent"),
    ],
)
def test_non_monotone_falls_back_to_the_spread(f, status):
    res = cv.richardson(LADDER, f)
    assert res.status == status
    assert res.extrapolated is None and res.rel_error == (None, None, None)
    spread = max(f) - min(f)
    assert res.uncertainty_abs == (spread,) * 3
    assert res.uncertainty == tuple(spread / abs(v) for v in f)
    assert "spread" in res.note


def test_zero_quantity_has_no_relative_numbers():
    res = cv.richardson(LADDER, [1e-9, 2e-10, 1e-10], zero_scale=1e-6)
    assert all(v is None for v in res.uncertainty)
    assert all(v is not None for v in res.uncertainty_abs)


def test_bad_input_is_refused():
    with pytest.raises(ValueError, match="three grids"):
        cv.richardson([1.0, 0.5], [1.0, 2.0])
    with pytest.raises(ValueError, match="different grid sizes"):
        cv.richardson([1.0, 1.0, 0.5], [1.0, 2.0, 3.0])
    with pytest.raises(ValueError, match="finite"):
        cv.richardson([1.0, 0.5, 0.25], [1.0, float("nan"), 3.0])


def test_off_ladder_run_against_the_extrapolation():
    h, f = LADDER, _sequence(LADDER, 4.0, 1.0, 2.0)
    res = cv.richardson(h, f)
    p2 = cv.off_ladder(res, 4.02, f)
    assert p2["rel_error"] == pytest.approx(0.005, rel=1e-6)
    assert p2["uncertainty_abs"] == pytest.approx(cv.SAFETY * 0.02, rel=1e-6)


SUMMARY = {
    "My_pin": 40.0,
    "Mx_pin": -12.0,
    "ZS": -0.5,
    "ZR": 0.25,
    "Mz_pin": 1e-12,
    "bending_stress": {"sun": 700.0, "ring": None, "locations": {"sun": [1.0, 2.0]}},
    "contact_stress_cycle": {
        "sun_pinion": {
            "positions": 5,
            "p_max_MPa": 2000.0,
            "K_Hbeta": 1.8,
            "interior_at": {"roll": 0.1},
            "iso_factors": {"Z_H": 2.4},
        }
    },
    "bending_stress_iso6336_nominal": {"sun": 650.0},
    "bending_stress_at": {"sun": {"position": 2, "roll": 0.1, "z_mm": 3.0}},
    "bending_stress_tangent": {"sun": 600.0},
    "inputs": {"material": {"youngs_modulus": 206000.0}},
}


def test_summary_scalars_by_key():
    got = run_scalars.summary_scalars(SUMMARY, "single_pinion")
    assert set(got) == {
        "My_pin",
        "Mx_pin",
        "ZS",
        "ZR",
        "Mz_pin",
        "bending_stress.sun",
        "contact_stress_cycle.sun_pinion.p_max_MPa",
        "contact_stress_cycle.sun_pinion.K_Hbeta",
        "bending_stress_tangent.sun",
    }
    kinds = {k: run_scalars.scalar_kind(k) for k in got}
    assert kinds["My_pin"] == "moment" and kinds["ZS"] == "offset"
    assert kinds["bending_stress.sun"] == "stress"
    assert kinds["contact_stress_cycle.sun_pinion.p_max_MPa"] == "stress"
    assert kinds["contact_stress_cycle.sun_pinion.K_Hbeta"] == "other"
    assert run_scalars.lookup(SUMMARY, "contact_stress_cycle.sun_pinion.p_max_MPa") == 2000.0
    assert run_scalars.lookup(SUMMARY, "bending_stress.pinion") is None


def test_uncertainty_entry_and_plus_minus():
    study = {
        "case": "1-GB",
        "labels": ["L0P1", "L1P1", "L2P1"],
        "positions": 1,
        "code_hash": "x",
        "scalars": {
            "My_pin": {
                "status": "monotone",
                "uncertainty": {"L1P1": 0.02},
                "uncertainty_abs": {"L1P1": 0.8},
            },
            "ZS": {
                "status": "oscillatory",
                "uncertainty": {"L1P1": 0.5},
                "uncertainty_abs": {"L1P1": 0.1},
            },
            "bending_stress_iso6336_nominal.sun": {
                "status": "mesh-independent",
                "uncertainty": {"L1P1": 0.0},
                "uncertainty_abs": {"L1P1": 0.0},
            },
        },
    }
    got = uncertainty_for(study, "L1P1", "results/convergence/1-GB/convergence.json")
    assert got["uncertainty"] == {"My_pin": 0.02, "ZS": 0.5}
    assert got["uncertainty_source"]["case"] == "1-GB"
    summary = {**SUMMARY, **got, "case": "1-GB"}
    assert plus_minus(summary, "My_pin") == " ± 0.8"  # 2 % of 40 N m
    assert plus_minus(summary, "ZS", ".2f") == " ± 0.10"  # the study's own case: absolute mm
    assert plus_minus(summary, "Mx_pin") == ""
    none = uncertainty_for(study, "L3P1", "x.json")
    assert none["uncertainty"] is None and "no run L3P1" in none["uncertainty_source"]["note"]
    assert plus_minus({**SUMMARY, **none}, "My_pin") == ""


def test_an_offset_carries_its_relative_uncertainty_to_another_case_or_none():
    """Another case of the gear set (its summary takes the study of 1-GB or 2B-GA): a
    moment's ± is the relative U times its own value; an offset's is too where the study's
    offset is clear of zero, and none where it is not: 2B-GA's ZS (-0.012 mm, U 0.017 mm)
    printed as 2B-GB's ± on -3.69 mm said ± 0.02 (the 2B-GA record; before the fix), and
    f_ma_SPRP_um (2B-GA 0.081 um, U 1.1 %) said ± 0.00 on 2B-GB's 7.6 um."""
    src = {"case": "2B-GA"}
    study_u = {"ZS": 1.37, "f_ma_SPRP_um": 0.0106, "M_LOA_SPRP_diff": 0.0106}
    study_abs = {"ZS": 0.017, "f_ma_SPRP_um": 0.00086, "M_LOA_SPRP_diff": 0.26}
    gb = {
        "case": "2B-GB",
        "ZS": -3.69,
        "f_ma_SPRP_um": 7.6,
        "M_LOA_SPRP_diff": 30.0,
        "uncertainty": study_u,
        "uncertainty_abs": study_abs,
        "uncertainty_source": src,
    }
    assert plus_minus(gb, "M_LOA_SPRP_diff") == " ± 0.3"  # 1.06 % of 30 N m
    assert plus_minus(gb, "f_ma_SPRP_um", ".2f") == " ± 0.08"  # 1.06 % of 7.6 um
    assert plus_minus(gb, "ZS", ".2f") == NOT_CARRIED  # the study's ZS is within its U of 0
    ga = {**gb, "case": "2B-GA", "ZS": -0.012, "f_ma_SPRP_um": 0.081}
    assert plus_minus(ga, "ZS", ".3f") == " ± 0.017"  # its own case: the absolute U
    assert plus_minus(ga, "f_ma_SPRP_um", ".4f") == " ± 0.0009"
    # the threshold: just below it the relative U carries, just above it none
    assert plus_minus({**gb, "uncertainty": {"ZS": OFFSET_REL_MAX}}, "ZS", ".2f") == " ± 0.92"
    above = {**gb, "uncertainty": {"ZS": OFFSET_REL_MAX * 1.01}}
    assert plus_minus(above, "ZS", ".2f") == NOT_CARRIED
    # no uncertainty for the key at all: nothing printed, as for a moment
    assert plus_minus({**gb, "uncertainty": {}, "uncertainty_abs": {}}, "ZS") == ""


def test_another_case_takes_at_least_the_studys_absolute_uncertainty():
    """1-GA takes 1-GB's study: ZS U 3.1 % of 1-GB's -3.1 mm, 0.096 mm. On 1-GA's -0.19 mm
    the relative U alone said ± 0.006 mm, 16x below what the same grids gave 1-GB; the ±
    is at least the study's absolute U. The same for a difference of two moments (its
    error is its moments', not its own size); a plain moment keeps its relative U."""
    src = {"case": "1-GB"}
    ga = {
        "case": "1-GA",
        "ZS": -0.19,
        "My_pin": 40.0,
        "M_LOA_SPRP_diff": 5.0,
        "uncertainty": {"ZS": 0.031, "My_pin": 0.02, "M_LOA_SPRP_diff": 0.0106},
        "uncertainty_abs": {"ZS": 0.096, "My_pin": 4.3, "M_LOA_SPRP_diff": 0.26},
        "uncertainty_source": src,
    }
    assert plus_minus(ga, "ZS", ".3f") == " ± 0.096"  # not 0.031 x 0.19 = 0.006
    assert plus_minus({**ga, "ZS": -9.0}, "ZS", ".2f") == " ± 0.28"  # 3.1 % of 9 mm
    assert plus_minus(ga, "M_LOA_SPRP_diff", ".2f") == " ± 0.26"  # not 1.06 % of 5 N m
    assert plus_minus(ga, "My_pin") == " ± 0.8"  # 2 % of 40 N m, not the study's 4.3


# ------------------------------------------------------------------ an FE case with a limit
A, B, PRESSURE = 1.0, 2.0, 100.0  # mm, mm, MPa
STEEL = Material(206000.0, 0.3)


def _lame_exact(r: float) -> float:
    """Radial displacement of a thick cylinder under internal pressure p, plane strain
    (Timoshenko & Goodier): u_r = (1 + nu) p a^2 / (E (b^2 - a^2)) ((1 - 2 nu) r + b^2 / r)."""
    nu, e = STEEL.nu, STEEL.E
    return (1 + nu) * PRESSURE * A**2 / (e * (B**2 - A**2)) * ((1 - 2 * nu) * r + B**2 / r)


def _lame_fe(n: int) -> float:
    """Mean radial displacement of the bore of a quarter cylinder (symmetry supports), P1 on
    an n x 2n mapped (r, theta) grid: h = 1 / n."""
    m = dolfinx.mesh.create_rectangle(
        MPI.COMM_WORLD, [[A, 0.0], [B, np.pi / 2]], [n, 2 * n], dolfinx.mesh.CellType.triangle
    )
    x = m.geometry.x
    r, t = x[:, 0].copy(), x[:, 1].copy()
    x[:, 0], x[:, 1] = r * np.cos(t), r * np.sin(t)
    m.topology.create_connectivity(1, 2)
    where = {
        1: lambda X: np.isclose(np.hypot(X[0], X[1]), A),
        2: lambda X: np.isclose(X[1], 0.0),
        3: lambda X: np.isclose(X[0], 0.0),
    }
    found = [(dolfinx.mesh.locate_entities_boundary(m, 1, fn), tag) for tag, fn in where.items()]
    facets = np.concatenate([f for f, _ in found])
    values = np.concatenate([np.full(len(f), tag, np.int32) for f, tag in found])
    order = np.argsort(facets)
    tags = dolfinx.mesh.meshtags(m, 1, facets[order], values[order])
    body = ElasticBody(
        "cylinder",
        m,
        tags,
        {"bore": 1, "y0": 2, "x0": 3},
        STEEL,
        dirichlet=[Dirichlet("y0", (1,)), Dirichlet("x0", (0,))],
        tractions=[Traction("bore", lambda X: PRESSURE * X / ufl.sqrt(ufl.dot(X, X)))],
    )
    body.setup()
    u = body.function(body.expand(body.solve(body.f_red)))
    ds = ufl.Measure("ds", domain=m, subdomain_data=tags)
    X = ufl.SpatialCoordinate(m)
    ur = dolfinx.fem.form(ufl.dot(u, X / ufl.sqrt(ufl.dot(X, X))) * ds(1))
    length = dolfinx.fem.form(dolfinx.fem.Constant(m, 1.0) * ds(1))
    return m.comm.allreduce(dolfinx.fem.assemble_scalar(ur)) / m.comm.allreduce(
        dolfinx.fem.assemble_scalar(length)
    )


@pytest.mark.parametrize("cells", [(4, 8, 16), (6, 9, 14)])  # ratio 2, and 1.5 then 1.56
def test_fe_thick_cylinder_recovers_p1_order_and_the_exact_limit(cells):
    f = [_lame_fe(n) for n in cells]
    res = cv.richardson([1.0 / n for n in cells], f)
    exact = _lame_exact(A)
    assert res.status == "monotone"
    # P1 displacement converges as h^2; these coarse grids are slightly pre-asymptotic
    assert res.order == pytest.approx(2.0, abs=0.25)
    finest = abs(f[-1] - exact) / exact
    extrapolated = abs(res.extrapolated - exact) / exact
    assert extrapolated < finest / 4  # the extrapolation removes most of the error
    assert extrapolated < 1e-3  # and lands on the closed form
    assert res.uncertainty[-1] >= finest  # the GCI bounds the true error of the finest grid


def test_two_grid_gci_is_roache_with_the_assumed_order():
    """Two grids of f = 10 + 2 h^2 (the assumed order exact): the fine grid's GCI is Fs = 3
    times its true error, the coarse grid's likewise; no extrapolation is claimed."""
    h = [0.7, 1.0]  # fine, coarse (the case levels 1 and 0)
    f = [10.0 + 2.0 * x**2 for x in h]
    res = cv.two_grid(h, f, 2.0)
    assert res.status == "two-grid" and res.extrapolated is None
    assert res.uncertainty_abs[0] == pytest.approx(3.0 * abs(f[0] - 10.0), rel=1e-12)
    assert res.uncertainty_abs[1] == pytest.approx(3.0 * abs(f[1] - 10.0), rel=1e-12)
    assert res.uncertainty[0] == pytest.approx(res.uncertainty_abs[0] / f[0], rel=1e-12)
    # a real order above the assumed one: the GCI still bounds the true error
    g = [10.0 + 2.0 * x**4 for x in h]
    assert cv.two_grid(h, g, 2.0).uncertainty_abs[0] > abs(g[0] - 10.0)
    assert cv.two_grid(h, [5.0, 5.0], 1.0).status == "mesh-independent"
    with pytest.raises(ValueError, match="two sizes"):
        cv.two_grid([1.0, 1.0], [1.0, 2.0], 1.0)


def test_round_off_of_a_vanishing_quantity_is_zero_not_converged():
    # 1-GB's record had Mz_pin -2.9e-13 / -5.8e-14 / 0 N m (a pinion free to spin) as
    # "monotone, order 4.12, extrapolated 1.1e-14": round-off read as convergence
    f = [-2.9103830456733704e-13, -5.820766091346741e-14, 0.0]
    res = cv.richardson([1.0, 0.7, 0.45], f, zero_scale=0.216)  # 1e-3 of My_pin's 216 N m
    assert res.status == "zero"
    assert res.extrapolated is None and res.order is None
    assert res.uncertainty == (None, None, None)
    assert cv.richardson([1.0, 0.7, 0.45], f).status == "monotone"  # without a zero scale
    two = cv.two_grid([1.0, 0.7], f[:2], order=2.0, zero_scale=0.216)
    assert two.status == "zero" and two.uncertainty == (None, None)
    # one value above the scale: a real (small) quantity, converged as any other
    assert cv.richardson([1.0, 0.7, 0.45], [0.5, 0.3, 0.25], zero_scale=0.216).status != "zero"

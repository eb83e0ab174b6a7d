"""Verification scenes with closed-form answers (used by the tests and the benchmark).

* :func:`hertz_scene`: NAFEMS-like plane-strain Hertz line contact. A half cylinder
  (R = 50 mm, E = 210 GPa, nu = 0.3) is pressed onto a block (E = 70 GPa, nu = 0.3) by
  P = 35 kN/mm through its flat top face (rigidly coupled, a rigid approach unknown balanced
  by the contact force, eq. (3) of :mod:`solvers.contact`). Hertz: a = 6.21 mm,
  p0 = 3585 MPa. The contact grid lies on the exact circle and the exact plane.
* :func:`pinion_bearing_scene`: a stiff hollow pinion on a needle bearing (3D).
* :func:`planetary_scene`: a 2D sun - planet - ring chain with involute-osculating flanks:
  sun driven by a torque (rotation unknown), planet on a radial bearing with free spin (spin
  unknown), ring a fixed rigid obstacle.
"""

from __future__ import annotations

import math

import dolfinx_solver  # noqa: F401 - orders MPI ahead of the bindings

# isort: split
import numpy as np
import ufl
from mpi4py import MPI

from cases.study_case import DEFAULTS
from gears.contact_stress import hertz_line_contact
from gears.material import STEEL as STEEL_PROPERTIES
from solvers import simple_meshes as sm
from solvers.contact import ContactPair, ContactProblem, RigidUnknown
from solvers.contact_grid import ContactGrid, line_grid_2d
from solvers.elastic_body import Dirichlet, ElasticBody, Material, Traction, mpi_sum
from solvers.rigid_coupling import RigidCoupling, bearing

STEEL = Material(STEEL_PROPERTIES.youngs_modulus, STEEL_PROPERTIES.poisson_ratio)
ALUMINIUM = Material(70e3, 0.3)


# ---------------------------------------------------------------------------- Hertz
def hertz_scene(
    comm: MPI.Comm = MPI.COMM_WORLD,
    h_min: float = 0.5,
    spacing: float | None = None,
    degree: int = 2,
    penalty_factor: float = DEFAULTS.penalty_factor,
    R: float = 50.0,
    P: float = 35e3,
    prescribed_approach: float | None = None,
    cylinder: Material = STEEL,
):
    """Half cylinder on a block; returns (problem, info).

    The grid spans |x| <= 14 mm (covers the contact at 2P, a = 8.8 mm) with spacing equal to
    the element size near the contact (default h_min): finer grids than the FE surface nodes
    make the point forces non-unique as eps grows (their patch averages stay right).
    """
    s = h_min if spacing is None else spacing
    cyl = sm.half_disc(comm, R, h_min=h_min, h_max=8.0, grade=0.2, plateau=12.0)
    blk = sm.block(comm, 100.0, 100.0, h_min=h_min, h_max=15.0, grade=0.2, plateau=12.0)
    b_cyl = ElasticBody(
        "cylinder",
        cyl.mesh,
        cyl.facet_tags,
        cyl.tags,
        cylinder,
        degree,
        couplings=[RigidCoupling("top", "top", (0.0, R), (math.inf, 0.0, math.inf))],
        centre=(0.0, R),
    )
    b_blk = ElasticBody(
        "block",
        blk.mesh,
        blk.facet_tags,
        blk.tags,
        ALUMINIUM,
        degree,
        dirichlet=[Dirichlet("bottom")],
        centre=(0.0, 0.0),
    )
    n_half = round(14.0 / s)
    x = s * np.arange(-n_half, n_half + 1)
    y_cyl = R - np.sqrt(R**2 - x**2)
    grid = line_grid_2d(
        "cylinder-block",
        np.c_[x, np.zeros_like(x)],
        np.c_[x, y_cyl],
        np.tile([0.0, 1.0], (len(x), 1)),
        y_cyl,
        s,
    )
    ru = RigidUnknown(
        "approach", "cylinder", coupling="top", dof=1, load=-P, prescribed=prescribed_approach
    )
    problem = ContactProblem(
        [b_cyl, b_blk],
        [ContactPair(grid, "block", "cylinder")],
        [ru],
        penalty_factor=penalty_factor,
    )
    e_star = 1.0 / (1.0 / cylinder.e_plane + 1.0 / ALUMINIUM.e_plane)
    return problem, {"x": x, "spacing": s, "R": R, "P": P, "e_star": e_star}


def hertz_measures(problem: ContactProblem, result, info) -> dict[str, float]:
    """Total force, half-width (second moment), peak pressure, approach of a Hertz solve.

    Half-width from the second moment of the pressure: for p = p0 sqrt(1 - x^2/a^2),
    int p x^2 dx / int p dx = a^2 / 4, so a = 2 sqrt(sum F x^2 / sum F); unlike the last
    active point it is not quantized by the grid spacing.
    """
    F = result.forces
    x = info["x"]
    total = float(F.sum())
    return {
        "force": total,
        "a": 2.0 * math.sqrt(float((F * x**2).sum()) / total),
        "p_max": float((F / problem.weights).max()),
        "approach": -result.rigid["approach"],
    }


def hertz_reference(info, P: float | None = None) -> dict[str, float]:
    """Hertz a, p0 and the datum-free approach nonlinearity delta(2P) - 2 delta(P).

    In 2D the approach delta(P) = P k - P / (pi E*) ln P holds for any datum: every far-field
    term is linear in P and only the contact adds -2 P/(pi E*) ln a with a ~ sqrt(P), so
    delta(2P) - 2 delta(P) = -2 P ln 2 / (pi E*) exactly (up to O((a/R)^2) of Hertz theory).
    """
    P = info["P"] if P is None else P
    a, p0 = hertz_line_contact(P, info["R"], info["e_star"])
    h = {"a": float(a), "p0": float(p0)}
    h["nonlinearity"] = -2.0 * P * math.log(2.0) / (math.pi * info["e_star"])
    return h


# ---------------------------------------------------------------------------- bearing
def pinion_bearing_scene(
    comm: MPI.Comm = MPI.COMM_WORLD,
    moment: float = 0.0,
    radial_force: float = 0.0,
    k_radial: float = 5e5,
    k_tilt: float = 5e8,
    k_axial: float = 1e7,
    E: float = 210e3 * 1e3,
    h: float = 4.0,
    degree: int = 2,
    hold_spin: bool = True,
):
    """A stiff hollow pinion (R 20, bore 8, length 20 mm) on a needle bearing at the origin.

    Loads: a pure moment about x as the traction t_z = kappa y on both end faces
    (M_x = 2 kappa I, no net force), a radial force F_x as a uniform traction on the outer
    surface (no moment about the centre). The applied resultants are read back from the
    assembled load vector (exact for the discrete load).
    """
    mb = sm.hollow_cylinder(comm, 20.0, 8.0, 20.0, h)
    i_x = math.pi * (20.0**4 - 8.0**4) / 4.0
    kappa = moment / (2.0 * i_x)
    t_r = radial_force / (2 * math.pi * 20.0 * 20.0)
    tractions = []
    if moment:
        for end in ("end_top", "end_bottom"):
            tractions.append(Traction(end, lambda x: ufl.as_vector((0, 0, kappa * x[1]))))
    if radial_force:
        tractions.append(Traction("outer", lambda x: ufl.as_vector((t_r, 0, 0))))
    brg = bearing("bearing", "bore", (0.0, 0.0, 0.0), (0.0, 0.0, 1.0), k_radial, k_tilt, k_axial)
    body = ElasticBody(
        "pinion",
        mb.mesh,
        mb.facet_tags,
        mb.tags,
        Material(E, 0.3),
        degree,
        couplings=[brg],
        tractions=tractions,
        centre=(0.0, 0.0, 0.0),
    )
    if hold_spin:
        body.hold("bearing", 5)
    return body


def applied_resultant(body: ElasticBody) -> tuple[np.ndarray, np.ndarray]:
    """(force, moment about the body centre) of the assembled external load vector."""
    n = body.n_own
    f = np.zeros((n, body.gdim))
    f[np.arange(n), body.dof_comp[:n]] = body.f.getArray(readonly=True)[:n]
    d = body.dof_x[:n] - body.centre
    m = (
        np.cross(d, f).sum(axis=0)
        if body.gdim == 3
        else np.sum(d[:, 0] * f[:, 1] - d[:, 1] * f[:, 0])
    )
    return mpi_sum(body.comm, f.sum(axis=0)), mpi_sum(body.comm, m)


# ---------------------------------------------------------------------------- planetary toy
def _flank_grid(name, P, n, rho_a, rho_b, half_width, spacing, concave_b=False) -> ContactGrid:
    """Grid on two osculating flank circles touching at P with normal n (A -> B).

    A convex with centre P - rho_a n; B convex with centre P + rho_b n, or (concave_b, an
    internal gear) concave with centre P - rho_b n. Point k at tangent coordinate s_k:
    x_a = c_a + rho_a (n cos phi + t sin phi), sin phi = s / rho_a (and likewise for B), so
    g0 = rho_a (1 - cos phi) +/- rho_b (1 - cos psi), exact for the circles.
    """
    n = np.asarray(n, float)
    t = np.array([-n[1], n[0]])
    m = round(half_width / spacing)
    s = spacing * np.arange(-m, m + 1)
    phi = np.arcsin(s / rho_a)
    psi = np.arcsin(s / rho_b)
    c_a = P - rho_a * n
    x_a = c_a + rho_a * (np.cos(phi)[:, None] * n + np.sin(phi)[:, None] * t)
    if concave_b:
        c_b = P - rho_b * n
        x_b = c_b + rho_b * (np.cos(psi)[:, None] * n + np.sin(psi)[:, None] * t)
    else:
        c_b = P + rho_b * n
        x_b = c_b + rho_b * (-np.cos(psi)[:, None] * n + np.sin(psi)[:, None] * t)
    # per-point normal: bisector of the two flank normals (each through its centre of
    # curvature on the base circle, so the lever arm about each gear centre is its base radius
    # to second order in s / rho, like the involute's normal)
    n_a = (x_a - c_a) / rho_a
    n_b = (x_b - c_b) / rho_b if concave_b else (c_b - x_b) / rho_b
    nk = n_a + n_b
    nk /= np.linalg.norm(nk, axis=1)[:, None]
    g0 = np.einsum("kc,kc->k", x_b - x_a, nk)
    return line_grid_2d(name, x_a, x_b, nk, g0, spacing)


def planetary_scene(
    comm: MPI.Comm = MPI.COMM_WORLD,
    torque: float = 9.0e4,
    r_sun: float = 20.0,
    r_planet: float = 30.0,
    alpha_deg: float = 20.0,
    k_radial: float = 1e5,
    h_min: float = 0.1,
    degree: int = 2,
    penalty_factor: float = DEFAULTS.penalty_factor,
    spacing: float | None = None,
    body_options: dict | None = None,
):
    """Sun (torque, rotation unknown) - planet (radial bearing, spin unknown) - fixed ring.

    Pitch radii r_s, r_p, r_r = r_s + 2 r_p (the tooth numbers are proportional); pressure
    angle alpha; contact at the pitch points P0 = (r_s, 0) and P1 = (r_r, 0); normals along
    the lines of action n1 = (sin a, cos a) (sun -> planet), n2 = (sin a, -cos a)
    (planet -> ring). The flanks are the involutes' osculating circles, radii
    rho = r sin(alpha), centred on the base circles. Statics alone give
    T_ring / T_sun = r_r / r_s and equal sun and ring mesh forces F = T / (r_s cos a).
    ``body_options``: further ElasticBody keywords of both bodies (``linear_solver``, ...).
    """
    a = math.radians(alpha_deg)
    s = h_min if spacing is None else spacing
    r_ring = r_sun + 2 * r_planet
    O1 = np.array([0.0, 0.0])
    O2 = np.array([r_sun + r_planet, 0.0])
    P0 = np.array([r_sun, 0.0])
    P1 = np.array([r_ring, 0.0])
    n1 = np.array([math.sin(a), math.cos(a)])
    n2 = np.array([math.sin(a), -math.cos(a)])
    rho_s, rho_p, rho_r = r_sun * math.sin(a), r_planet * math.sin(a), r_ring * math.sin(a)
    sun_mesh = sm.toothed_disc(
        comm, O1, r_sun - 3.0, 5.0, [(P0 - rho_s * n1, rho_s, P0)], r_sun + 2.0, h_min=h_min
    )
    planet_mesh = sm.toothed_disc(
        comm,
        O2,
        r_planet - 3.0,
        8.0,
        [(P0 + rho_p * n1, rho_p, P0), (P1 - rho_p * n2, rho_p, P1)],
        r_planet + 2.0,
        h_min=h_min,
    )
    sun = ElasticBody(
        "sun",
        sun_mesh.mesh,
        sun_mesh.facet_tags,
        sun_mesh.tags,
        STEEL,
        degree,
        couplings=[RigidCoupling("axis", "bore", O1, (math.inf, math.inf, 0.0))],
        centre=O1,
        **(body_options or {}),
    )
    planet = ElasticBody(
        "planet",
        planet_mesh.mesh,
        planet_mesh.facet_tags,
        planet_mesh.tags,
        STEEL,
        degree,
        couplings=[RigidCoupling("bearing", "bore", O2, (k_radial, k_radial, 0.0))],
        centre=O2,
        **(body_options or {}),
    )
    # half-width: Hertz a for the expected load, times 2.5, at least 3 grid spacings
    F = torque / (r_sun * math.cos(a))
    e_star = STEEL.e_plane / 2
    a_sp = math.sqrt(4 * F / (math.pi * e_star) / (1 / rho_s + 1 / rho_p))
    a_pr = math.sqrt(4 * F * STEEL.e_plane**-1 / math.pi / (1 / rho_p - 1 / rho_r))
    g1 = _flank_grid("sun-planet", P0, n1, rho_s, rho_p, max(2.5 * a_sp, 3 * s), s)
    g2 = _flank_grid("planet-ring", P1, n2, rho_p, rho_r, max(2.5 * a_pr, 3 * s), s, concave_b=True)
    problem = ContactProblem(
        [sun, planet],
        [ContactPair(g1, "sun", "planet"), ContactPair(g2, "planet", "ring")],
        [
            RigidUnknown("sun_rotation", "sun", coupling="axis", dof=2, load=torque),
            RigidUnknown("planet_spin", "planet", coupling="bearing", dof=2, load=0.0),
        ],
        obstacles=["ring"],
        penalty_factor=penalty_factor,
    )
    info = {
        "r_sun": r_sun,
        "r_planet": r_planet,
        "r_ring": r_ring,
        "alpha": a,
        "torque": torque,
        "mesh_force": F,
        "O1": O1,
        "O2": O2,
    }
    return problem, info


# ---------------------------------------------------------------------------- 3D roller
def roller_scene(
    comm: MPI.Comm = MPI.COMM_WORLD,
    h_min: float = 0.6,
    degree: int = 2,
    R: float = 20.0,
    L: float = 10.0,
    q: float = 1.0e4,
    penalty_factor: float = DEFAULTS.penalty_factor,
    spacing: float | None = None,
):
    """3D steel roller (R, length L, bore R/3) on a steel block under a line load q (N/mm).

    Force control by the roller's rigid approach (bore coupled to its centre); block bottom
    clamped. The grid covers |x| <= 2.5 a_Hertz across and the whole length along z, with
    spread patches of spacing x spacing. Used by the benchmark (time against error); the
    free ends make it a finite line contact, so Hertz (plane strain) holds at mid-length only.
    """
    s = h_min if spacing is None else spacing
    rol = sm.roller(comm, R, L, R / 3, h_min=h_min, h_max=4.0, grade=0.3, plateau=2.0)
    blk = sm.block3d(comm, 2 * R, 2 * R, L, h_min=h_min, h_max=8.0, grade=0.3, plateau=2.0)
    b_rol = ElasticBody(
        "roller",
        rol.mesh,
        rol.facet_tags,
        rol.tags,
        STEEL,
        degree,
        couplings=[
            RigidCoupling(
                "bore",
                "bore",
                (0.0, R, 0.0),
                (math.inf, 0.0, math.inf, math.inf, math.inf, math.inf),
            )
        ],
        centre=(0.0, R, 0.0),
    )
    b_blk = ElasticBody(
        "block",
        blk.mesh,
        blk.facet_tags,
        blk.tags,
        STEEL,
        degree,
        dirichlet=[Dirichlet("bottom")],
        centre=(0.0, 0.0, 0.0),
    )
    e_star = STEEL.e_plane / 2
    a = float(hertz_line_contact(q, R, e_star)[0])
    nx = max(3, round(2.5 * a / s))
    nz = round(L / s)
    xs = s * np.arange(-nx, nx + 1)
    zs = -L / 2 + s * (np.arange(nz) + 0.5)
    X, Z = np.meshgrid(xs, zs, indexing="ij")
    X, Z = X.ravel(), Z.ravel()
    y_r = R - np.sqrt(R**2 - X**2)
    n = len(X)
    t = np.zeros((n, 2, 3))
    t[:, 0, 0] = 1.0
    t[:, 1, 2] = 1.0
    stations = np.tile(np.arange(nz), len(xs))
    grid = ContactGrid(
        "roller-block",
        np.c_[X, np.zeros(n), Z],
        np.c_[X, y_r, Z],
        np.tile([0.0, 1.0, 0.0], (n, 1)),
        y_r,
        np.full(n, s * s),
        tangents=t,
        half_sizes=np.full((n, 2), s / 2),
        stations=stations,
        station_length=np.full(nz, s),
    )
    problem = ContactProblem(
        [b_rol, b_blk],
        [ContactPair(grid, "block", "roller")],
        [RigidUnknown("approach", "roller", coupling="bore", dof=1, load=-q * L)],
        penalty_factor=penalty_factor,
    )
    return problem, {"x": X, "z": Z, "spacing": s, "R": R, "L": L, "q": q, "e_star": e_star}

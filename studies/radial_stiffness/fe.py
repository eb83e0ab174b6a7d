"""Radial mesh stiffness from the FE contact solve (pust2016), and the floating-sun stability
it implies.

Sign convention (one for both meshes, the one of :mod:`gears.analytic.radial_stiffness`):
``F_rad`` is the radial component of a mesh's force on the pinion, along e_X of the pinion
frame (outward, from the sun centre through the pinion centre), and ``d`` the pinion's
radial offset, which changes the centre distance a of both meshes by +d. The radial mesh
stiffness is the spring the mesh adds to the pinion's radial motion::

    k_r = -dF_rad / dd,   central differences  k_r(h) = -(F_rad(+h) - F_rad(-h)) / (2 h)

External (sun) mesh: F_rad = +F_bt sin(alpha_wt(a)) pushes the pinion out and grows with a,
so k_r < 0 (pust2016's negative stiffness); internal (ring) mesh: F_rad = -F_bt sin(alpha_wt)
pulls the pinion in and grows in size with a, so k_r > 0. F_bt is the transverse normal force
(the normal force F_n times cos(beta_b)) and cos(alpha_wt) = (r_b1 +- r_b2) / a. The closed
form (pitch-radius form of pust2016 in the transverse plane, = -+Ft / (a tan(alpha_wt)))::

    k_r,ext = -F_bt cos^2(alpha_wt) / (a sin(alpha_wt))
    k_r,int = +F_bt cos^2(alpha_wt) / (a sin(alpha_wt))

The central difference of the exact F_bt sin(alpha_wt(a)) has the truncation error
h^2 F'''(a) / 6; two step sizes that agree to that order show the steps are in the linear
range. The stiffness the study reports is the slope of the least-squares line
through F_rad over all offsets (:func:`fit_stiffness`, d up to 30 um)::

    k_r = -sum (d_i - dm)(F_i - Fm) / sum (d_i - dm)^2

On a zone grid (cells with their own contact normals) F_rad scatters by about 1 N (of a
6 kN force) as the loaded cell set changes with d, which moves a 5 um central difference by
up to 200 N/mm and the fit over +-30 um by a few; the closed form's own curve fitted over the
same offsets gives the truncation the fit is held to.

Mesh stiffness (for the N-branch model): the transverse approach of the two gears at the
mesh's load centroid x_c from the rigid motions of their bores (sun: rotation about z;
pinion: translation u, tilts and spin omega; ring: held at its rim)::

    delta_t = d . (v_driver(x_c) - v_driven(x_c)),   v(x) = u + omega x (x - c)
    k_t = F_bt / delta_t

with d the transverse line-of-action direction (the driver's push): the bore-to-bore
stiffness of the mesh, both gear bodies and the contact included.

Floating sun. pust2016's 2-DOF radial model (sun y3 on the support k3, planet y2 on the pin
stiffness k_c, coupled by k_r = |k_r,ext|; :func:`gears.analytic.radial_stiffness.
floating_sun_eigenvalues`) is unstable below k3* = k_r (k_c + k_r) / k_c. The planar
N-branch model (:func:`branch_model`) keeps what the 2-DOF model leaves out: the sun's
rotation (free, torque-loaded) and translation in x and y, each planet's translation (pin
stiffness k_c, isotropic) and spin (free), the mesh stiffnesses along the lines of action
and the radial mesh stiffnesses of both meshes. Branch i at carrier angle psi_i, radial e_i,
tangential t_i (the sun turns counter-clockwise)::

    d_s,i = sin(a_s) e_i + cos(a_s) t_i       (sun -> planet push)
    d_r,i = sin(a_r) e_i - cos(a_r) t_i       (planet -> ring push)
    delta_s,i = (u_s - u_i) . d_s,i + s - p_i,   delta_r,i = u_i . d_r,i + p_i
    V = sum_i [k_ms delta_s,i^2 + k_mr delta_r,i^2 + k_c |u_i|^2
               + k_rs ((u_i - u_s) . e_i)^2 + k_rr (u_i . e_i)^2] / 2 + k3 |u_s|^2 / 2

(s = r_b,sun theta_sun, p_i = r_b,planet times the planet's spin, in mm). Condensing every
DOF but the sun's translation gives its 2x2 stiffness S(k3) = S(0) + k3 I; the sun is
statically stable if S(k3) is positive definite, i.e. above k3* = max(0, -lambda_min(S(0))).
Left out, as in pust2016: the tangential geometric stiffness (the mesh force turning with the
line of centres), friction, the carrier's compliance and the masses (a static threshold).
"""

from __future__ import annotations

import math
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from gears.analytic import radial_stiffness as rs
from gears.units import n_mm
from meshing.scenes import SUN_BORE_RADIUS, pinion_bore_radius

STEEL_DENSITY = 7.85e-6  # kg/mm^3; only the 2-DOF frequencies use it (not the threshold)
KINDS = ("external", "internal")
LABEL = {"external": "sun-pinion (external)", "internal": "pinion-ring (internal)"}


# --- reading one solved position ------------------------------------------------------------


def mesh_of(position: dict, gearset, kind: str) -> str:
    """The name of the sun mesh (``external``) or ring mesh (``internal``) of the first
    branch of a one-branch position."""
    path = gearset.power_path
    for name, m in position["meshes"].items():
        if "/" in name:  # not a drive-flank grid
            continue
        if kind == "external" and m["gears"][0] == path[0]:
            return name
        if kind == "internal" and m["gears"][1] == path[-1]:
            return name
    raise KeyError(f"no {kind} mesh in {sorted(position['meshes'])}")


def radial_record(position: dict, gearset) -> dict:
    """The pinion's mesh forces of a one-branch position, per mesh kind: F_n, F_bt, the
    radial (outward, on the pinion) and tangential components, and the operating transverse
    pressure angle read back from the contact normal."""
    pinion = gearset.power_path[1]
    p = position["pinions"][pinion]
    Q = np.asarray(p["frame"], float)
    e_r = Q[0]
    out = {"pinion_centre_mm": p["centre_mm"], "rigid": dict(position["rigid"])}
    for kind in KINDS:
        name = mesh_of(position, gearset, kind)
        m = position["meshes"][name]
        n = np.asarray(m["normal"])
        t = n[:2] / np.linalg.norm(n[:2])
        f_on = np.asarray(m["on"][pinion]["force_N"])  # pinion frame: X radial
        # the same normal force along the plane of action's n: F_rad's on-plane part
        plane = (1.0 if m["driven"] == pinion else -1.0) * m["normal_force_N"] * float((Q @ n)[0])
        out[kind] = {
            "mesh": name,
            "normal_force_N": m["normal_force_N"],
            "transverse_force_N": m["normal_force_N"] * float(np.linalg.norm(n[:2])),
            "radial_force_N": float(f_on[0]),
            "tangential_force_N": float(f_on[1]),
            "alpha_wt_deg": math.degrees(math.asin(min(1.0, abs(float(t @ e_r[:2]))))),
            "active_points": m["active_points"],
            "grid_points": m["grid_points"],
            "approach_mm": mesh_approach(position, name),
            "grid_model": m.get("grid_model", "line"),
            "plane_radial_force_N": plane,
            "off_plane_radial_force_N": float(f_on[0]) - plane,
            "off_line_N": m.get("off_line_N", {}).get(pinion),
            "transmitted_force_N": m.get("transmitted_force_N", {}).get(pinion),
            "torque_Nm": dict(m.get("torque_Nm", {})),
            "corner_cells": m.get("corner_cells"),
        }
    out["sun_contact_torque_Nm"] = position["sun_contact_torque_Nm"]
    coast = position.get("coast") or {}
    out["coast_force_N"] = float(sum(c["normal_force_N"] for c in coast.values()))
    out["coast_min_gap_mm"] = min((c["min_gap_mm"] for c in coast.values()), default=None)
    return out


def _velocity(position: dict, body: str, x: np.ndarray) -> np.ndarray:
    """Rigid displacement at ``x`` of a body's bore: the sun turns about z (and may float),
    a pinion moves by its six bore unknowns, the ring is held (zero)."""
    rigid = position["rigid"]
    if f"{body}_rotation" in rigid:
        th = rigid[f"{body}_rotation"]
        v = th * np.array([-x[1], x[0], 0.0])
        if f"{body}_x" in rigid:
            v[:2] += [rigid[f"{body}_x"], rigid[f"{body}_y"]]
        return v
    if f"{body}_spin" in rigid:
        c = np.asarray(position["pinions"][body]["centre_mm"], float)
        u = np.array([rigid[f"{body}_{d}"] for d in ("x", "y", "z")])
        w = np.array([rigid[f"{body}_{d}"] for d in ("rx", "ry", "spin")])
        return u + np.cross(w, x - c)
    return np.zeros(3)


def mesh_approach(position: dict, mesh: str) -> float:
    """delta_t = d . (v_driver - v_driven) at the load centroid (mm, see the module)."""
    m = position["meshes"][mesh]
    x = np.asarray(m["points"]["x_mm"], float)
    f = np.asarray(m["points"]["force_N"], float)
    if f.sum() <= 0:
        return float("nan")
    xc = f @ x / f.sum()
    n = np.asarray(m["normal"], float)
    d = np.r_[n[:2] / np.linalg.norm(n[:2]), 0.0]
    return float(d @ (_velocity(position, m["driver"], xc) - _velocity(position, m["driven"], xc)))


# --- stiffness from the records -------------------------------------------------------------


def central_difference(records: dict[float, dict], kind: str, h: float) -> float:
    """k_r(h) = -(F_rad(+h) - F_rad(-h)) / (2 h), N/mm; ``records`` keyed by the offset."""
    return -(records[h][kind]["radial_force_N"] - records[-h][kind]["radial_force_N"]) / (2 * h)


def radial_force(record: dict, kind: str) -> float:
    return record[kind]["radial_force_N"]


def on_plane_force(record: dict, kind: str) -> float:
    return plane_radial_force(record[kind], kind)


def fit_stiffness(records: dict[float, dict], kind: str, value=radial_force) -> float:
    """k_r = -(slope of the least-squares line through ``value(record, kind)`` over the
    offsets), N/mm; ``records`` keyed by the offset (mm), ``value`` by default F_rad."""
    d = np.array(sorted(records), dtype=float)
    return -float(np.polyfit(d, [value(records[x], kind) for x in d], 1)[0])


def analytic_stiffness(gearset, sun_torque_nmm: float) -> dict:
    """The closed forms at the nominal centre distance for a sun torque (N mm on one branch):
    transverse normal force F_bt = T / r_b,sun on both meshes (the pinion's spin balance),
    k_r from the pitch-radius form (:func:`k_r_external`, :func:`k_r_internal`), the same
    from -+Ft / (a tan(alpha_wt)) (:func:`k_r_helical`), F'''(a) for the truncation error,
    and pust2016's formula applied naively with the normal force and the normal pressure
    angle at the reference radii (what a spur-gear reading of the paper would give)."""
    path = gearset.power_path
    sun, pin, ring = (gearset.gears[g] for g in path)
    f_bt = sun_torque_nmm / sun.base_radius
    out = {"transverse_force_N": f_bt}
    for kind, pair in (
        ("external", gearset.pair(path[0], path[1])),
        ("internal", gearset.pair(path[1], path[2])),
    ):
        a, al = pair.centre_distance, pair.operating_pressure_angle
        r1, r2 = pair.operating_pitch_radius(1), pair.operating_pitch_radius(2)
        if kind == "external":
            k_pitch = rs.k_r_external(f_bt, al, r1, r2)
        else:
            k_pitch = rs.k_r_internal(f_bt, al, r2, r1)
        ft = f_bt * math.cos(al)
        k_hel = rs.k_r_helical(ft, al, a, internal=kind == "internal")
        rb_sum = (
            sun.base_radius + pin.base_radius
            if kind == "external"
            else (ring.base_radius - pin.base_radius)
        )
        # F(a) = F_bt sin(alpha(a)); third derivative by a fine difference of the exact form
        hh = 1e-2
        fa = [rs.separating_force(f_bt, rb_sum, a + j * hh) for j in (-2, -1, 1, 2)]
        f3 = (fa[3] - 2 * fa[2] + 2 * fa[1] - fa[0]) / (2 * hh**3)
        bn = pin.base_helix_angle
        f_n = f_bt / math.cos(bn)
        an = math.radians(pin.normal_pressure_angle)
        r_ref = pin.reference_radius + (
            sun.reference_radius if kind == "external" else (-ring.reference_radius)
        )
        naive = -f_n * math.cos(an) ** 2 / (abs(r_ref) * math.sin(an))
        out[kind] = {
            "centre_distance_mm": a,
            "alpha_wt_deg": math.degrees(al),
            "operating_pitch_radii_mm": [r1, r2],
            "k_r_pitch_form_N_per_mm": k_pitch,
            "k_r_helical_form_N_per_mm": k_hel,
            "radial_force_N": (1 if kind == "external" else -1) * f_bt * math.sin(al),
            "third_derivative_N_per_mm3": (1 if kind == "external" else -1) * f3,
            "k_r_naive_normal_plane_N_per_mm": naive if kind == "external" else -naive,
        }
    return out


# --- what the records show -------------------------------------------------------------------

#: the agreement tolerances: AGREE_FACTOR times the truncation term the closed form's own
#: curve gives the measure, at least AGREE_FLOOR (round-off: the line model holds F_bt to
#: 1e-9 and k_r to the truncation term, 3e-7 at h = 5 um for case 1)
AGREE_FACTOR = 10.0
AGREE_FLOOR = 1e-6


def plane_radial_force(rec: dict, kind: str) -> float:
    """The on-plane part of a mesh's F_rad (N): its normal force along the plane of action,
    +-F_bt sin(alpha_wt) (records written before ``plane_radial_force_N`` was kept: from
    their F_bt and alpha_wt, the same number)."""
    if "plane_radial_force_N" in rec:
        return rec["plane_radial_force_N"]
    sgn = 1.0 if kind == "external" else -1.0
    return sgn * rec["transverse_force_N"] * math.sin(math.radians(rec["alpha_wt_deg"]))


def _range(values) -> list | None:
    v = [x for x in values if x is not None]
    return [min(v), max(v)] if v else None


def _closed_curve(an: dict, kind: str, d: np.ndarray) -> np.ndarray:
    """The closed form's F_rad(d) = +-F_bt sin(alpha_wt(a + d)) at the offsets ``d`` (mm)."""
    a = an[kind]
    sgn = 1.0 if kind == "external" else -1.0
    a0 = a["centre_distance_mm"]
    rb = a0 * math.cos(math.radians(a["alpha_wt_deg"]))
    return np.array([sgn * rs.separating_force(an["transverse_force_N"], rb, a0 + x) for x in d])


def checks(data: dict) -> dict:
    """Every agreement the report states, from the records, with its tolerance (``tol``):
    ``exact`` k_r (the fit over the sweep) / closed form - 1, ``position`` second / first
    mesh position - 1, ``load`` FE / closed form - 1 over the torques, each held to the
    closed form's own curve fitted over the same offsets (``fit_truncation_rel``);
    ``steps`` the central differences k_r(h_max) / k_r(h_min) - 1 less the truncation terms'
    ratio; ``linearity`` the sweep's largest departure from its fitted line (of F_rad's
    change) less the closed-form curve's from its own. Per mesh also the central difference
    k_r(h_min) against the closed form, the split of F_rad into its on-plane part (the
    normal force along the plane of action) and the off-plane rest (cells whose contact
    normal is turned off the plane, zone grids) with their slopes, the rest's scatter about
    its own line (N; over h_min it bounds the error it puts into k_r(h_min)), and the ranges
    over the sweep of the loaded cells, the tip-corner cells and off_line_N."""
    inp, nom = data["inputs"], data["nominal"]
    an = nom["analytic"]
    steps = sorted(inp["steps_mm"])
    h0, h1 = steps[0], steps[-1]
    recs = {float(d): r for d, r in nom["records"].items()}
    d = np.array(sorted(recs))
    out = {"factor": AGREE_FACTOR, "floor": AGREE_FLOOR, "kinds": {}}
    for kind in KINDS:
        a = an[kind]
        kc = a["k_r_pitch_form_N_per_mm"]

        def trunc(h, a=a, kc=kc):
            return -(h**2) * a["third_derivative_N_per_mm3"] / 6 / kc

        def tol(x):
            return max(AGREE_FACTOR * abs(x), AGREE_FLOOR)

        k = nom["k_r"][kind]
        k0 = nom["k_r_steps"][kind][str(h0)]
        k1 = nom["k_r_steps"][kind][str(h1)]
        step_expect = (1 + trunc(h1)) / (1 + trunc(h0)) - 1
        f = np.array([radial_force(recs[x], kind) for x in d])
        fa = _closed_curve(an, kind, d)
        fit_trunc = -float(np.polyfit(d, fa, 1)[0]) / kc - 1

        def departure(y):
            return float(np.max(np.abs(y - np.polyval(np.polyfit(d, y, 1), d))))

        lin = departure(f) / max(abs(float(f[-1] - f[0])), 1e-30)
        lin_expect = departure(fa) / max(abs(float(fa[-1] - fa[0])), 1e-30)
        load = [
            r["k_r"][kind] / r["analytic"][kind]["k_r_pitch_form_N_per_mm"] - 1
            for r in data["torque_runs"]
        ]
        fp = np.array([plane_radial_force(recs[x][kind], kind) for x in d])
        fo = f - fp
        k_plane = -float(np.polyfit(d, fp, 1)[0])
        fbt = [recs[x][kind]["transverse_force_N"] for x in d]
        rows = [recs[x][kind] for x in d]
        corner = [r.get("corner_cells") for r in rows]
        f0 = recs[0.0][kind]["radial_force_N"]
        c = {
            "closed_form_N_per_mm": kc,
            "k_r_N_per_mm": k,
            "fit_truncation_rel": fit_trunc,
            "k_cd_N_per_mm": k0,
            "cd_rel": k0 / kc - 1,
            "truncation_rel": trunc(h0),
            "exact": {"rel": k / kc - 1, "tol": tol(fit_trunc)},
            "steps": {"rel": k1 / k0 - 1, "expected": step_expect, "tol": tol(step_expect)},
            "position": {"rel": data["second_roll"][kind] / k - 1, "tol": tol(fit_trunc)},
            "load": {"rel": [min(load), max(load)], "tol": tol(fit_trunc)},
            "linearity": {"rel": lin, "expected": lin_expect, "tol": tol(fit_trunc)},
            "k_plane_N_per_mm": k_plane,
            "k_off_N_per_mm": k - k_plane,
            "off_plane_force_N": float(fo[list(d).index(0.0)]),
            "off_plane_share": abs(float(fo[list(d).index(0.0)] / f0)),
            "off_plane_scatter_N": departure(fo),
            # the most a scatter of that size about the line can tilt the fit
            "fit_scatter_bound_N_per_mm": departure(fo)
            * float(np.sum(np.abs(d - d.mean())) / np.sum((d - d.mean()) ** 2)),
            "transverse_force_spread_rel": (max(fbt) - min(fbt)) / float(np.mean(fbt)),
            "active_points": _range(r["active_points"] for r in rows),
            "off_line_N": _range(r.get("off_line_N") for r in rows),
            "corner_active_points": _range(c and c["active_points"] for c in corner),
            "corner_force_N": _range(c and c["force_N"] for c in corner),
        }
        for key in ("exact", "position"):
            c[key]["ok"] = abs(c[key]["rel"]) <= c[key]["tol"]
        for key in ("steps", "linearity"):  # against the closed-form curve's own
            c[key]["ok"] = abs(c[key]["rel"] - c[key]["expected"]) <= c[key]["tol"]
        c["load"]["ok"] = max(abs(x) for x in c["load"]["rel"]) <= c["load"]["tol"]
        r2 = {float(x): r for x, r in (data.get("second_roll_records") or {}).items()}
        if len(r2) >= 2:
            kp2 = fit_stiffness(r2, kind, on_plane_force)
            c["position"]["k_plane_N_per_mm"] = kp2
            c["position"]["k_off_N_per_mm"] = data["second_roll"][kind] - kp2
        out["kinds"][kind] = c
    for key in ("exact", "steps", "position", "load", "linearity"):
        out[key] = all(out["kinds"][k][key]["ok"] for k in KINDS)
    return out


# --- floating-sun stability -----------------------------------------------------------------


def body_masses(gearset) -> dict[str, float]:
    """Sun and pinion masses (kg): steel annuli from the bore to the pitch circle over the
    face width (the 2-DOF frequencies only; the threshold does not depend on them)."""
    sun, pin = (gearset.gears[g] for g in gearset.power_path[:2])

    def annulus(g, bore):
        return STEEL_DENSITY * math.pi * (g.reference_radius**2 - bore**2) * g.face_width

    return {"sun": annulus(sun, SUN_BORE_RADIUS), "pinion": annulus(pin, pinion_bore_radius())}


def branch_model(
    n: int,
    k_ms: float,
    k_mr: float,
    k_rs: float,
    k_rr: float,
    k_c: float,
    alpha_s: float,
    alpha_r: float,
    psi=None,
) -> dict:
    """The planar N-branch model of the module docstring (N/mm, rad): the sun translation's
    condensed stiffness S(0) (2x2), its eigenvalues and the threshold k3* (N/mm)."""
    psi = 2 * math.pi * np.arange(n) / n if psi is None else np.asarray(psi, float)
    ndof = 3 + 3 * n
    K = np.zeros((ndof, ndof))

    def add(k, b):
        K[:, :] += k * np.outer(b, b)

    for i, a in enumerate(psi):
        e = np.array([math.cos(a), math.sin(a)])
        t = np.array([-math.sin(a), math.cos(a)])
        ds = math.sin(alpha_s) * e + math.cos(alpha_s) * t
        dr = math.sin(alpha_r) * e - math.cos(alpha_r) * t
        j = 3 + 3 * i
        b = np.zeros(ndof)
        b[0:2], b[2], b[j : j + 2], b[j + 2] = ds, 1.0, -ds, -1.0
        add(k_ms, b)
        b = np.zeros(ndof)
        b[j : j + 2], b[j + 2] = dr, 1.0
        add(k_mr, b)
        for c in range(2):
            b = np.zeros(ndof)
            b[j + c] = 1.0
            add(k_c, b)
        b = np.zeros(ndof)
        b[j : j + 2], b[0:2] = e, -e
        add(k_rs, b)
        b = np.zeros(ndof)
        b[j : j + 2] = e
        add(k_rr, b)
    u, o = slice(0, 2), slice(2, ndof)
    S = K[u, u] - K[u, o] @ np.linalg.solve(K[o, o], K[o, u])
    S = 0.5 * (S + S.T)
    lam = np.linalg.eigvalsh(S)
    return {
        "branches": n,
        "psi_deg": np.degrees(psi).tolist(),
        "S_N_per_mm": S.tolist(),
        "eigenvalues_N_per_mm": lam.tolist(),
        "threshold_k3_N_per_mm": float(max(0.0, -lam[0])),
    }


def stability(
    k_r_ext: float,
    k_r_int: float,
    k_ms: float,
    k_mr: float,
    k_c: float,
    alpha_s: float,
    alpha_r: float,
    masses: dict,
    branches=(1, 2, 3, 4),
) -> dict:
    """pust2016's 2-DOF threshold and eigenvalues (SI: N/m, kg) with the FE k_r, and the
    N-branch model for each number of equally spaced branches, with and without the radial
    mesh stiffnesses (N/mm)."""
    kr = abs(k_r_ext) * 1e3  # N/m
    kc = k_c * 1e3
    m2, m3 = masses["pinion"], masses["sun"]
    w0 = rs.floating_sun_eigenvalues(m2, m3, kc, 0.0, kr)
    two = {
        "k_r_N_per_m": kr,
        "k_c_N_per_m": kc,
        "m2_kg": m2,
        "m3_kg": m3,
        "threshold_k3_N_per_m": rs.stability_threshold(kc, kr),
        "omega_sq_at_k3_0": list(w0),
        "growth_rate_at_k3_0_per_s": math.sqrt(-w0[0]) if w0[0] < 0 else 0.0,
    }
    nb = {}
    for n in branches:
        with_kr = branch_model(n, k_ms, k_mr, k_r_ext, k_r_int, k_c, alpha_s, alpha_r)
        without = branch_model(n, k_ms, k_mr, 0.0, 0.0, k_c, alpha_s, alpha_r)
        nb[str(n)] = {"with_radial": with_kr, "without_radial": without}
    return {"two_dof": two, "branches": nb}


# --- figures and report ---------------------------------------------------------------------


def _offsets(records: dict) -> np.ndarray:
    return np.array(sorted(records))


def figure_radial_force(data: dict, path: Path) -> Path:
    """F_rad - F_rad(0) against the centre-distance change at each torque, FE points and the
    closed form's F_bt sin(alpha_wt(a)) curve."""
    fig, axes = plt.subplots(1, 2, figsize=(10.5, 4.2))
    for ax, kind in zip(axes, KINDS, strict=True):
        for j, run in enumerate(data["torque_runs"]):
            recs = {float(k): v for k, v in run["records"].items()}
            d = _offsets(recs)
            f = np.array([radial_force(recs[x], kind) for x in d])
            f0 = radial_force(recs[0.0], kind)
            dd = np.linspace(d.min(), d.max(), 101)
            fa = _closed_curve(run["analytic"], kind, dd)
            fa0 = _closed_curve(run["analytic"], kind, np.zeros(1))[0]
            c = f"C{j}"
            ax.plot(dd * 1e3, fa - fa0, color=c, lw=0.9)
            ax.plot(
                d * 1e3,
                f - f0,
                "o",
                color=c,
                ms=4,
                label=f"{run['sun_torque_Nm']:.0f} N m: fit k = {run['k_r'][kind]:+.0f} N/mm",
            )
        ax.axhline(0, color="0.6", lw=0.6)
        ax.axvline(0, color="0.6", lw=0.6)
        ax.set_xlabel("pinion radial offset d = change of centre distance (um)")
        ax.set_ylabel("F_rad(d) - F_rad(0) on the pinion, outward (N)")
        ax.set_title(LABEL[kind], fontsize=10)
        ax.legend(fontsize=7, title="FE (points), closed form (lines)", title_fontsize=7)
    fig.suptitle("Radial mesh force against centre distance at constant sun torque", fontsize=11)
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return path


def figure_load(data: dict, path: Path) -> Path:
    """FE and closed-form k_r against the sun torque of one branch."""
    fig, ax = plt.subplots(figsize=(6.5, 4.2))
    t = np.array([r["sun_torque_Nm"] for r in data["torque_runs"]])
    tt = np.linspace(0, t.max() * 1.05, 50)
    for kind, c in zip(KINDS, ("C3", "C0"), strict=True):
        k = np.array([r["k_r"][kind] for r in data["torque_runs"]])
        ka = np.array([r["analytic"][kind]["k_r_pitch_form_N_per_mm"] for r in data["torque_runs"]])
        ax.plot(tt, tt * (ka / t).mean(), color=c, lw=1.0, label=f"{LABEL[kind]}, closed form")
        ax.plot(t, k, "o", color=c, mfc="none", ms=7, label=f"{LABEL[kind]}, FE")
    ax.axhline(0, color="0.5", lw=0.6)
    ax.set_xlabel("sun torque on the branch (N m)")
    ax.set_ylabel("radial mesh stiffness k_r = -dF_rad/da, fit (N/mm)")
    ax.set_title("Load dependence of the radial mesh stiffness", fontsize=10)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return path


def figure_stability(data: dict, path: Path) -> Path:
    """Left: pust2016 2-DOF W1^2 against k3 with the FE k_r. Right: the lowest eigenvalue of
    the sun's condensed translation stiffness against k3, N = 1..4 branches."""
    st = data["stability"]
    two = st["two_dof"]
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    ax = axes[0]
    thr = two["threshold_k3_N_per_m"]
    k3 = np.linspace(0, 2.5 * thr, 200)
    w1 = [
        rs.floating_sun_eigenvalues(
            two["m2_kg"], two["m3_kg"], two["k_c_N_per_m"], k, two["k_r_N_per_m"]
        )[0]
        for k in k3
    ]
    ax.plot(k3 * 1e-3, w1, color="C3")
    ax.axhline(0, color="0.5", lw=0.6)
    ax.axvline(thr * 1e-3, color="C3", ls="--", lw=0.8)
    ax.annotate(
        f"k3* = {thr * 1e-3:.0f} N/mm",
        (thr * 1e-3, 0),
        textcoords="offset points",
        xytext=(6, 10),
        fontsize=8,
    )
    ax.set_xlabel("sun support stiffness k3 (N/mm)")
    ax.set_ylabel("W1² ((rad/s)²)")
    ax.set_title("pust2016 2-DOF model, FE k_r: W1² < 0 is unstable", fontsize=10)
    ax = axes[1]
    kmax = 2.5 * max(thr * 1e-3, 1.0)
    k3 = np.linspace(0, kmax, 200)
    for n, c in zip(st["branches"], ("C3", "C1", "C0", "C2"), strict=False):
        lam = st["branches"][n]["with_radial"]["eigenvalues_N_per_mm"][0]
        ax.plot(k3, lam + k3, color=c, label=f"N = {n}: lambda_min(S(0)) = {lam:+.3g} N/mm")
    ax.axhline(0, color="0.5", lw=0.6)
    ax.set_yscale("symlog", linthresh=kmax)  # linear near zero, N >= 3 far above
    ax.set_xlabel("sun support stiffness k3 (N/mm)")
    ax.set_ylabel("lowest sun translation stiffness (N/mm)")
    ax.set_title("Planar N-branch model, FE mesh and radial stiffnesses", fontsize=10)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return path


def _f(x: float, nd: int = 1) -> str:
    return f"{x:+.{nd}f}"


def report(data: dict) -> str:
    """The markdown report of the radial-stiffness study (``data``: radial_stiffness.json)."""
    inp = data["inputs"]
    nom = data["nominal"]
    an = nom["analytic"]
    model = inp.get("contact_model", "line")
    ck = checks(data)
    lines = [
        "# Radial mesh stiffness from the FE contact solve (pust2016)",
        "",
        f"Case {inp['case']} (gear set {inp['gearset']}), scene one_branch, level "
        f"{inp['level']}, P{inp['degree']}, {inp['dofs']} DOFs. The pinion is moved radially by "
        "d (scene option `pinion_radial_offset`), which changes the centre distance of both "
        "meshes by +d: the sun mesh opens, the pinion goes deeper into the ring. The sun "
        "torque is a load (the sun's rotation is a free unknown with its moment balance), so "
        "the transmitted torque is held at every offset; the pinion stays on its bearing "
        f"(radial {inp['bearing_radial_N_per_mm']:.3g} N/mm). "
        + MODEL_TEXT.get(model, f"Contact model {model}."),
        "",
        *_backlash_text(inp, data),
        "",
        "k_r = -dF_rad/dd, F_rad the radial (outward) component of the mesh's force on the "
        "pinion, read per mesh from `meshes[...]['on'][pinion]`: **the slope of the "
        "least-squares line through F_rad over all offsets** (d up to "
        f"{max(inp['sweep_mm']) * 1e3:g} um), with the central differences k_r(h) beside it. "
        "Negative: a destabilising spring (external mesh); positive: restoring (internal).",
        "",
        "## At the nominal torque",
        "",
        f"Sun torque on the branch {nom['sun_torque_Nm']:.1f} N m, transverse normal force "
        f"F_bt = {an['transverse_force_N']:.0f} N on both meshes, sun mesh position "
        f"{inp['rolls_pitch'][0]:g} pitch.",
        "",
        "| mesh | alpha_wt geometry / FE normal (deg) | F_rad at d = 0 (N) FE / closed form | "
        + " | ".join(f"k_r, h = {h * 1e3:g} um" for h in inp["steps_mm"])
        + " | **k_r, fit** | closed form k_r | FE fit / closed form - 1 | the closed form's "
        "own fit / closed form - 1 (truncation) |",
        "|---|---|---|" + "---|" * len(inp["steps_mm"]) + "---|---|---|---|",
    ]
    for kind in KINDS:
        a = an[kind]
        r0 = nom["records"]["0.0"][kind]
        ks = [nom["k_r_steps"][kind][str(h)] for h in inp["steps_mm"]]
        c = ck["kinds"][kind]
        lines.append(
            f"| {LABEL[kind]} | {a['alpha_wt_deg']:.4f} / {r0['alpha_wt_deg']:.4f} | "
            f"{r0['radial_force_N']:.2f} / {a['radial_force_N']:.2f} | "
            + " | ".join(f"{k:.3f}" for k in ks)
            + f" | **{c['k_r_N_per_mm']:.3f}** | {c['closed_form_N_per_mm']:.3f} | "
            f"{c['exact']['rel']:+.1e} | {c['fit_truncation_rel']:+.1e} |"
        )
    lines += ["", *_agreement_text(ck, data), ""]
    lines += [
        "Other readings of the formula (external mesh): pust2016's spur form with the 3D "
        f"normal force and the normal pressure angle at the reference radii gives "
        f"{an['external']['k_r_naive_normal_plane_N_per_mm']:.0f} N/mm, "
        f"{an['external']['k_r_naive_normal_plane_N_per_mm'] / an['external']['k_r_pitch_form_N_per_mm'] - 1:+.0%}"  # noqa: E501
        " off: for a helical mesh the formula holds in the transverse plane (F_bt, alpha_wt, "
        "operating pitch radii). The base-radius and -+Ft / (a tan alpha_wt) forms are the same"
        f" number ({an['external']['k_r_helical_form_N_per_mm']:.3f} N/mm).",
        "",
        "## Load dependence",
        "",
        "| sun torque on the branch (N m) | F_bt (N) | k_r external FE / closed form (N/mm) | "
        "k_r internal FE / closed form (N/mm) | k_r external / torque (N/mm per N m) |",
        "|---|---|---|---|---|",
    ]
    for r in data["torque_runs"]:
        a = r["analytic"]
        lines.append(
            f"| {r['sun_torque_Nm']:.1f} | {a['transverse_force_N']:.0f} | "
            f"{r['k_r']['external']:.2f} / {a['external']['k_r_pitch_form_N_per_mm']:.2f} | "
            f"{r['k_r']['internal']:.2f} / {a['internal']['k_r_pitch_form_N_per_mm']:.2f} | "
            f"{r['k_r']['external'] / r['sun_torque_Nm']:.5f} |"
        )
    lines += [
        "",
        _load_text(ck, data),
        "",
        "![radial force](radial_force.png)",
        "",
        "![load dependence](load_dependence.png)",
        "",
        *(_why_exact(ck, data) if ck["exact"] else _why_not(ck, data)),
        "",
        "## Floating sun",
        "",
    ]
    st = data["stability"]
    two = st["two_dof"]
    ms = data["mesh_stiffness"]
    lines += [
        f"FE values at the nominal torque: k_r,ext = {ms['k_r_external']:.1f} N/mm, k_r,int = "
        f"{ms['k_r_internal']:+.1f} N/mm; bore-to-bore transverse mesh stiffness from the "
        f"rigid motions at the load centroid: sun mesh {ms['k_ms'] / 1e3:.0f} N/um, ring mesh "
        f"{ms['k_mr'] / 1e3:.0f} N/um (both gear bodies, the rim-held ring and the contact; "
        f"level {inp['level']}); pin bearing k_c = {ms['k_c']:.3g} N/mm."
        + (
            ""
            if ck["exact"]
            else " These k_r are the fits over the sweep, which depart from the closed form "
            "by " + _pair(ck, "exact", "+.1%") + " (above): the thresholds below move with them."
        ),
        "",
        f"pust2016 2-DOF radial model (sun on k3, one planet on k_c, m3 = {two['m3_kg']:.2f} kg,"
        f" m2 = {two['m2_kg']:.2f} kg, steel annuli): W1² changes sign at **k3* = k_r (k_c + "
        f"k_r) / k_c = {two['threshold_k3_N_per_m'] / 1e3:.1f} N/mm** "
        f"({two['threshold_k3_N_per_m']:.4g} N/m); below it a sun held by one branch diverges "
        f"(at k3 = 0: W1² = {two['omega_sq_at_k3_0'][0]:.3g} (rad/s)², growth rate "
        f"{two['growth_rate_at_k3_0_per_s']:.0f} 1/s). k_c >> k_r: the threshold is |k_r| to "
        f"{abs(two['threshold_k3_N_per_m'] / two['k_r_N_per_m'] - 1):.0e}.",
        "",
        "Planar N-branch model (module docstring: sun rotation and planet spins free, mesh "
        "stiffness along the lines of action, both radial mesh stiffnesses), equally spaced "
        "branches; S(0) the sun translation's condensed stiffness without support:",
        "",
        "| branches N | eigenvalues of S(0) with k_r (N/mm) | without k_r (N/mm) | support "
        "needed k3* (N/mm) |",
        "|---|---|---|---|",
    ]
    for n, b in st["branches"].items():
        w, wo = b["with_radial"], b["without_radial"]
        lines.append(
            f"| {n} | {', '.join(f'{x:.4g}' for x in w['eigenvalues_N_per_mm'])} | "
            f"{', '.join(f'{x:.4g}' for x in wo['eigenvalues_N_per_mm'])} | "
            f"{w['threshold_k3_N_per_mm']:.1f} |"
        )
    lines += [
        "",
        *_branch_text(st, ms, an),
        "",
        "![stability](stability.png)",
        "",
    ]
    return "\n".join(lines)


MODEL_TEXT = {
    "line": "Contact model line: one row of points on the theoretical contact lines, every "
    "point's force along the plane of action (the closed form's premise).",
    "zone": "Contact model zone: a grid over the whole potential contact zone, each cell's "
    "force along its own contact normal (the bisector of the two flank normals off the "
    "contact line, the other flank's normal at a tip corner), so part of the force acts off "
    "the plane of action.",
}


def _um(h: float) -> str:
    return f"{h * 1e3:g} um"


def _pair(c: dict, key: str, fmt: str) -> str:
    """``key`` of both meshes, external / internal."""
    return " / ".join(format(c["kinds"][k][key]["rel"], fmt) for k in KINDS)


def _tol_text(c: dict) -> str:
    return f"tolerance max({c['factor']:g} x the truncation term, {c['floor']:g})"


def _agreement_text(c: dict, data: dict) -> list[str]:
    """The agreement paragraph under the nominal table: what each check measured and whether
    it passed its tolerance (:func:`checks`)."""
    inp = data["inputs"]
    steps = sorted(inp["steps_mm"])
    h0, h1 = _um(steps[0]), _um(steps[-1])
    kk = c["kinds"]
    ex, it = kk["external"], kk["internal"]
    out = []
    if c["exact"]:
        out.append(
            f"The fit's FE / closed form - 1 is {_pair(c, 'exact', '+.1e')} (external / "
            f"internal), the closed form's own curve fitted over the same offsets "
            f"{ex['fit_truncation_rel']:+.1e} / {it['fit_truncation_rel']:+.1e}: within the "
            f"{_tol_text(c)} ({ex['exact']['tol']:.1e} / {it['exact']['tol']:.1e}), the FE "
            "gives the closed form."
        )
    else:
        out.append(
            f"The fit's FE / closed form - 1 is {_pair(c, 'exact', '+.1%')} (external / "
            f"internal), against a truncation of {ex['fit_truncation_rel']:.1e} / "
            f"{it['fit_truncation_rel']:.1e}: **the FE does not give the closed form** "
            f"({_tol_text(c)}). The central difference k_r(h = {h0}) is "
            + " / ".join(f"{kk[k]['cd_rel']:+.1%}" for k in KINDS)
            + " on the closed form."
        )
    steps_txt = (
        f"k_r(h = {h1}) / k_r(h = {h0}) - 1 is {_pair(c, 'steps', '+.1e')}, the closed "
        f"form's curve gives {ex['steps']['expected']:+.1e} / {it['steps']['expected']:+.1e}"
    )
    if c["steps"]:
        out.append(steps_txt + ": the steps are in the linear range.")
    else:
        out.append(steps_txt + ": **the central differences depend on the step.**")
    lin = (
        f"Over the whole sweep (d up to {max(inp['sweep_mm']) * 1e3:g} um) F_rad departs "
        f"from its fitted line by at most {_pair(c, 'linearity', '.1e')} of its change, the "
        f"closed-form curve from its own by {ex['linearity']['expected']:.1e} / "
        f"{it['linearity']['expected']:.1e}"
    )
    if c["linearity"]:
        out.append(lin + ": the FE follows the closed form's curve (radial_force.png).")
    else:
        out.append(lin + ": F_rad(d) is not the closed form's smooth curve (radial_force.png).")
    sm = data["nominal"]["k_r"]
    pos = (
        f"At a second mesh position ({inp['rolls_pitch'][-1]:g} pitch, other tooth pairs in "
        f"contact) the fit is {_f(sm['external'], 1)} / "
        f"{_f(data['second_roll']['external'], 1)} N/mm (external, first / second) and "
        f"{_f(sm['internal'], 1)} / {_f(data['second_roll']['internal'], 1)} N/mm (internal)"
    )
    if c["position"]:
        out.append(
            pos + f", the same to {max(abs(k['position']['rel']) for k in kk.values()):.1e}:"
            " independent of the mesh position."
        )
    else:
        out.append(pos + f": {_pair(c, 'position', '+.1%')}, **k_r depends on the mesh position**.")
    return [" ".join(out)]


def _load_text(c: dict, data: dict) -> str:
    kk = c["kinds"]
    per_t = [r["k_r"]["external"] / r["sun_torque_Nm"] for r in data["torque_runs"]]
    if c["load"]:
        return (
            "k_r is proportional to the transmitted load (a geometric stiffness: it vanishes "
            "unloaded); FE / closed form - 1 stays within "
            f"{max(abs(x) for k in kk.values() for x in k['load']['rel']):.1e} over the torques."
        )
    rng = " and ".join(
        f"{kk[k]['load']['rel'][0]:+.1%} to {kk[k]['load']['rel'][1]:+.1%} ({k})" for k in KINDS
    )
    text = (
        f"The closed form is proportional to the load; FE / closed form - 1 runs from {rng} "
        f"over the torques, so the FE is not the closed form at every torque to the "
        f"{_tol_text(c)}. "
    )
    if len(per_t) < 2:  # a departure from the closed form says nothing about proportionality
        return text + "One torque solved: whether the FE k_r is proportional to it is not tested."
    spread = (max(per_t) - min(per_t)) / abs(float(np.mean(per_t)))
    return text + (
        f"Its proportionality on its own: k_r external per N m runs from {min(per_t):.3f} to "
        f"{max(per_t):.3f} N/mm per N m, a spread of {spread:.1%} over the torques."
    )


def _why_exact(c: dict, data: dict) -> list[str]:
    """Why the FE gives the closed form (only when :func:`checks` says it does)."""
    inp = data["inputs"]
    spread = max(k["transverse_force_spread_rel"] for k in c["kinds"].values())
    pos = (
        ", and the result does not depend on the mesh position"
        if c["position"]
        else "; the mesh position does change k_r (above)"
    )
    coast = data.get("coast_force_max_N", 0.0)
    text = (
        "The match is exact to the truncation error, and it has to be: in this contact model "
        "each mesh force acts along the exact plane of action of the unloaded gears at the "
        "current centre distance (the contact normal of the grid), and the sun's moment "
        "balance fixes its size, F_bt = T / r_b,sun at any centre distance (the FE transverse "
        f"normal force is the same to {spread:.0e} over all offsets); the pinion's spin "
        "balance gives the ring mesh the same F_bt. F_rad = F_bt sin(alpha_wt(a)) is then "
        "pust2016's premise, and its derivative is the formula. What the 3D solve adds is the "
        "evidence that nothing else enters at this load: "
        + ("no load moves to the coast flanks, " if coast == 0 else "")
        + "the helix does not add a radial term, the load sharing between tooth pairs (which "
        f"changes with the contact ratio) does not change the resultant{pos}. What the model "
        "does not hold: the loaded position of the gears (the pinion's bearing deflects "
        f"{data['pinion_radial_deflection_um']:.2f} um radially and "
        f"{data['pinion_tangential_deflection_um']:.1f} um tangentially; a small-displacement "
        "contact keeps the unloaded plane of action; the radial part is "
        f"{data['pinion_radial_deflection_um'] / (min(inp['steps_mm']) * 1e3):.0%} of the "
        "smallest step), friction (pust2016: negligible), and contact off the plane of "
        "action, which a line grid does not hold (the zone model does: "
        "`--contact-model zone`). So this is a check of the contact model's consistency with "
        "the closed form, not an independent test of pust2016."
    )
    return ["## Why the FE gives the closed form", "", text]


def _why_not(c: dict, data: dict) -> list[str]:
    """What the records show when the FE does not give the closed form: F_rad split into its
    on-plane part (the normal force along the plane of action) and the off-plane rest."""
    inp = data["inputs"]
    steps = sorted(inp["steps_mm"])
    h0 = steps[0]
    kk = c["kinds"]
    ex, it = kk["external"], kk["internal"]

    def both(key, fmt, scale=1.0):
        return " / ".join(format(kk[k][key] * scale, fmt) for k in KINDS)

    plane_rel = " / ".join(
        f"{kk[k]['k_plane_N_per_mm'] / kk[k]['closed_form_N_per_mm'] - 1:+.2%}" for k in KINDS
    )
    text = [
        "Values external / internal. F_rad splits into its on-plane part, the mesh's normal "
        "force along the plane of action's normal (F_bt sin(alpha_wt), the closed form's "
        "premise), and the rest, the radial force the cells carry because their contact "
        "normals are turned off the plane. At d = 0 the rest is "
        f"{both('off_plane_force_N', '+.1f')} N, "
        f"{both('off_plane_share', '.1%')} of F_rad. Its share of k_r (the slopes of the "
        f"fitted lines) is {both('k_off_N_per_mm', '+.1f')} N/mm; the on-plane part gives "
        f"{both('k_plane_N_per_mm', '+.1f')} N/mm, {plane_rel} on the closed form (the FE "
        f"F_bt, from the sum of the cell forces, varies by "
        f"{both('transverse_force_spread_rel', '.0e')} over the sweep: with arms off r_b the "
        "held torque no longer fixes it exactly)."
    ]
    p2 = [kk[k]["position"].get("k_off_N_per_mm") for k in KINDS]
    if None not in p2:
        text.append(
            f"At the second mesh position the rest's share is {p2[0]:+.1f} / {p2[1]:+.1f} N/mm "
            f"and the on-plane part {kk['external']['position']['k_plane_N_per_mm']:+.1f} / "
            f"{kk['internal']['position']['k_plane_N_per_mm']:+.1f} N/mm."
        )
    text.append(
        "The rest is not smooth in d: about its own straight line over the sweep it scatters "
        f"by up to {both('off_plane_scatter_N', '.2f')} N, which alone can move "
        f"k_r(h = {_um(h0)}) by {ex['off_plane_scatter_N'] / h0:.0f} / "
        f"{it['off_plane_scatter_N'] / h0:.0f} N/mm, while the loaded cells number "
        + " / ".join("{}-{}".format(*kk[k]["active_points"]) for k in KINDS)
        + " over the offsets"
    )
    if ex["corner_active_points"] is not None:
        text[-1] += (
            " (tip-corner cells: "
            + " / ".join("{}-{}".format(*kk[k]["corner_active_points"]) for k in KINDS)
            + " loaded, carrying "
            + " / ".join("{:.0f}-{:.0f}".format(*kk[k]["corner_force_N"]) for k in KINDS)
            + " N)"
        )
    if ex["off_line_N"] is not None:
        text[-1] += (
            "; the force-weighted departure of the arms from the plane of action (off_line_N, "
            "pinion) is "
            + " / ".join("{:.0f}-{:.0f}".format(*kk[k]["off_line_N"]) for k in KINDS)
            + " N"
        )
    text[-1] += (
        ". So central differences over a few um see the grid's discrete cell set as well as "
        "the geometric stiffness, which is why k_r is the fit over the whole sweep: a scatter "
        "s tilts it by at most s sum|d_i - dm| / sum (d_i - dm)^2, here "
        f"{both('fit_scatter_bound_N_per_mm', '.0f')} N/mm ("
        + " / ".join(
            f"{kk[k]['fit_scatter_bound_N_per_mm'] / abs(kk[k]['closed_form_N_per_mm']):.1%}"
            for k in KINDS
        )
        + " of the closed form)."
    )
    text.append(
        "The closed form's premise, every mesh force on the plane of action, is the line "
        "contact model's (`--contact-model line`; `make radial-stiffness` runs both); the "
        "off-plane forces of the zone grid are what it leaves out, and they change k_r by the "
        "rest's share above."
        if inp.get("contact_model") == "zone"
        else "The closed form's premise is every mesh force on the plane of action; the "
        "records show forces off it."
    )
    return ["## Why the FE differs from the closed form", "", " ".join(text)]


def _backlash_text(inp: dict, data: dict) -> list[str]:
    """How the meshes make room for the offsets, and whether the coast flanks stayed open."""
    d_max = max(inp["sweep_mm"]) * 1e3
    if inp["backlash_shift"]:
        text = (
            f"The pinion teeth are thinned by a profile shift of -{inp['backlash_shift']:g} "
            f"(addendum +{inp['backlash_shift']:g}, dedendum -{inp['backlash_shift']:g}: tip "
            f"and root circles kept), which gives the meshes a normal backlash of at least "
            f"{inp['backlash_normal_um']:.0f} um"
        )
    else:
        jn = inp["backlash_normal_um"]
        text = f"The meshes have the case's normal backlash, at least {jn:.0f} um"
    text += (
        f"; an offset d closes the coast flanks of one mesh by about 0.87 d, so offsets up to "
        f"{d_max:.0f} um leave them open. The operating pressure angle, hence k_r, depends on "
        "the base radii and the centre distance only, not on tooth thickness."
    )
    gap = data.get("coast_min_gap_um")
    if gap is not None:
        text += (
            f" Coast-flank grids: smallest gap {gap:.1f} um, largest coast force "
            f"{data['coast_force_max_N']:.2g} N over all solves."
        )
    return [text]


def _branch_text(st: dict, ms: dict, an: dict) -> list[str]:
    """What the N-branch table says, from its numbers."""
    b = st["branches"]
    out = []
    if "1" in b:
        k1 = b["1"]["with_radial"]["threshold_k3_N_per_mm"]
        out.append(
            "One branch: the sun's translation along the line of action is a mechanism (the sun "
            "rolls on the planet: a zero eigenvalue without k_r), and the radial mesh stiffness"
            f" makes the sun unstable below k3* = {k1:.1f} N/mm, the 2-DOF value."
        )
    if "2" in b:
        a = math.radians(an["external"]["alpha_wt_deg"])
        out.append(
            "Two opposed branches hold the sun along the line of action by the mesh stiffness "
            "but not across it, where only the two radial stiffnesses act: k3* = "
            f"{b['2']['with_radial']['threshold_k3_N_per_mm']:.1f} N/mm, about 2 |k_r| "
            f"cos²(alpha_wt) = {2 * abs(ms['k_r_external']) * math.cos(a) ** 2:.1f} N/mm "
            "(the rest: the finite mesh and pin stiffnesses)."
        )
    big = [n for n in b if int(n) >= 3]
    if big:
        n = big[0]
        w = b[n]["with_radial"]["eigenvalues_N_per_mm"][0]
        wo = b[n]["without_radial"]["eigenvalues_N_per_mm"][0]
        out.append(
            f"From three equally spaced branches on, the mesh stiffness of the other branches "
            f"holds the sun in every direction (S(0) isotropic, {w:.4g} N/mm for N = {n}, "
            f"{w / abs(ms['k_r_external']):.0f} |k_r|): the floating sun is stable with no "
            f"support at all, as pust2016 states; the radial mesh stiffness lowers its "
            f"centring stiffness by {1 - w / wo:.2%} ((N/2) |k_r| cos²(alpha_wt))."
        )
    return [" ".join(out)]


def sun_torque_nmm(gearset, branches: int = 1) -> float:
    """Sun torque (N mm) on ``branches`` of the set (equal sharing)."""
    return n_mm(gearset.input_torque / gearset.planets * branches)

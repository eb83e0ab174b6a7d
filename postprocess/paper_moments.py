"""The paper's quantities of each branch of a solved gear train, and the closed form beside them.

A branch is one pinion (single-pinion set, singh2007 sections 2-3 and 7) or one pinion pair
SP-RP (double-pinion set, section 5). From :func:`postprocess.train_results.train_results`:

Single pinion (pinion frame of section 3): ``Mx_pin``, ``My_pin``, ``Mz_pin`` (N m), ``ZS``,
``ZR`` (load-centroid offsets of the sun and ring meshes, mm), the LOA moments
``M_LOA_sun = Mx cos(a1) + My sin(a1)``, ``M_LOA_ring = Mx cos(a2) - My sin(a2)`` (Table 3)
from the FE moments, and ``analytic``: Table 7 (the Table 3 forces moved to the FE's own ZS,
ZR).

Double pinion (the SP and RP frames of section 5): ``Mx_SP``, ``My_SP``, ``Mx_RP``, ``My_RP``
(N m), the centroid offsets of every mesh in the frame of each pinion in it (``Z_<mesh>_<p>``,
with ``ZS``, ``Z_SPRP``, ``ZR`` for the sun-SP, SP-RP and RP-ring meshes), the FE axial
forces, the four LOA moments of section 5 from the FE moments, and ``analytic``: Table 5
(concentrated load at the pitch points) and the same closed form with each mesh force moved
to the FE's own load centroid (``at_fe_centroids``). The four LOA moments also under the
names of issue 12, ``M_LOA_sun_SP``, ``M_LOA_SP_RP``, ``M_LOA_RP_SP``, ``M_LOA_RP_ring`` (the
same numbers as ``M_LOA_SP_SUN`` ... ``M_LOA_RP_RING``), and the SP-RP differential
``M_LOA_SPRP_diff = M_LOA_SP_RP + M_LOA_RP_SP`` with its exact split over the mesh load
centroids (``sp_rp_differential``, :func:`_sp_rp_differential`).

With several branches in a scene (``all_planets``) the top-level keys are the means over the
branches and ``branches`` lists each.
"""

from __future__ import annotations

import math

import numpy as np

from gears.analytic import double_pinion as dp
from gears.analytic import single_pinion as sp
from gears.analytic.planetary import (
    double_pinion_axial_forces,
    double_pinion_geometry,
    single_pinion_geometry,
)
from gears.units import n_m
from solvers.flank_grid import flank_grid

#: top-level scalars of a branch, per gear-set kind (means over positions in a summary)
MEAN_KEYS = {
    "single_pinion": ("Mx_pin", "My_pin", "Mz_pin", "ZS", "ZR", "M_LOA_sun", "M_LOA_ring"),
    "double_pinion": (
        "Mx_SP",
        "My_SP",
        "Mz_SP",
        "Mx_RP",
        "My_RP",
        "Mz_RP",
        "ZS",
        "Z_SPRP",
        "ZR",
        "M_LOA_SP_SUN",
        "M_LOA_SP_RP",
        "M_LOA_RP_SP",
        "M_LOA_RP_RING",
        "M_LOA_sun_SP",
        "M_LOA_RP_ring",
        "M_LOA_SPRP_diff",
        "f_ma_SPRP_um",
    ),
}

#: the issue-12 names of the double-pinion LOA moments -> the names of section 5's formulas
#: (:func:`gears.analytic.double_pinion.loa_moments`); M_LOA_SP_RP, M_LOA_RP_SP are the same
LOA_ALIASES = {"M_LOA_sun_SP": "M_LOA_SP_SUN", "M_LOA_RP_ring": "M_LOA_RP_RING"}
_PINION_MOMENTS = ("Mx_SP", "My_SP", "Mx_RP", "My_RP")
#: a differential -> the two moments of opposite sign it is the sum of (one place for it: the
#: convergence verdict judges it relative to the larger of them)
DIFFERENTIALS = {"M_LOA_SPRP_diff": ("M_LOA_SP_RP", "M_LOA_RP_SP")}


def with_loa_aliases(moments: dict) -> dict:
    """``moments`` with the :data:`LOA_ALIASES` keys added (same numbers) and the SP-RP
    differential ``M_LOA_SPRP_diff`` (when both SP-RP moments are there)."""
    out = dict(moments)
    out.update({new: moments[old] for new, old in LOA_ALIASES.items() if old in moments})
    for diff, terms in DIFFERENTIALS.items():
        if all(k in moments for k in terms):
            out[diff] = sum(moments[k] for k in terms)
    return out


def _single_branch(train: dict, gearset, names: list[str], lines=None) -> dict:
    """Section 3 quantities of one sun-pinion-ring branch (see the module docstring)."""
    sun, ring = gearset.power_path[0], gearset.power_path[-1]
    (pinion,) = names
    P = train["pinions"][pinion]
    out: dict = {
        "pinion": pinion,
        "pinion_centre_mm": P["centre_mm"],
        "frame": P["frame"],
        "pinion_force_N": P["force_N"],
        "Mx_pin": P["Mx"],
        "My_pin": P["My"],
        "Mz_pin": P["Mz"],
        "pinion_moment_residual_Nm": P["moment_residual_Nm"],
        "pinion_support_moment_Nm": P["support_moment_Nm"],
        "bearing_spring_force_N": P["bearing_spring_force_N"],
        "bearing_spring_moment_Nm": P["bearing_spring_moment_Nm"],
        "pinion_tilt_rad": P["tilt_rad"],
        "pinion_spin_moment_Nm": P["spin_moment_Nm"],
    }
    for key, mesh in (("S", f"{sun}-{pinion}"), ("R", f"{pinion}-{ring}")):
        M = train["meshes"][mesh]
        on = M["on"][pinion]
        out[f"mesh_{key}"] = mesh
        out[f"Z{key}"] = on["Z_mm"]
        out[f"mesh_normal_force_{key}_N"] = M["normal_force_N"]
        out[f"F{key}_pinion_N"] = on["force_N"]
        out[f"active_points_{key}"] = M["active_points"]
        out[f"grid_points_{key}"] = M["grid_points"]
        out[f"centroid_{key}_mm"] = on["centroid_mm"]
    inp = gearset.planetary_input()
    geo = single_pinion_geometry(inp)
    f = sp.mesh_forces(inp.torque_per_branch, geo)
    out["M_LOA_sun"], out["M_LOA_ring"] = sp.loa_moments(
        out["Mx_pin"], out["My_pin"], geo.alpha1, geo.alpha2
    )
    mx_a, my_a, mz_a = sp.pinion_moments(f, geo, out["ZS"], out["ZR"])
    la_s, la_r = sp.loa_moments(mx_a, my_a, geo.alpha1, geo.alpha2)
    out["analytic"] = {
        "Mx_pin": mx_a,
        "My_pin": my_a,
        "Mz_pin": mz_a,
        "M_LOA_sun": la_s,
        "M_LOA_ring": la_r,
        "FzS": f.FzS,
        "FzR": f.FzR,
        "Fpin": list(f.resultant),
    }
    return out


def _double_branch(train: dict, gearset, names: list[str], lines=None) -> dict:
    """Section 5 quantities of one sun-SP-RP-ring branch (see the module docstring)."""
    sun, set_sp, set_rp, ring = gearset.power_path
    b_sp, b_rp = names  # body names of this branch's SP and RP
    roles = {b_sp: set_sp, b_rp: set_rp}
    meshes = {
        "sun-SP": f"{sun}-{b_sp}",
        "SP-RP": f"{b_sp}-{b_rp}",
        "RP-ring": f"{b_rp}-{ring}",
    }
    frames = {roles[b]: np.asarray(train["pinions"][b]["frame"]) for b in names}
    centres = {roles[b]: np.asarray(train["pinions"][b]["centre_mm"]) for b in names}
    # "pinion_bodies", not "pinions": a position also holds train_results' "pinions" (per
    # body), which this key would overwrite
    out: dict = {
        "pinion_bodies": list(names),
        "centres_mm": {k: v.tolist() for k, v in centres.items()},
        "frames": {k: v.tolist() for k, v in frames.items()},
    }
    for b in names:
        pn, P = roles[b], train["pinions"][b]
        out[f"Mx_{pn}"], out[f"My_{pn}"], out[f"Mz_{pn}"] = P["Mx"], P["My"], P["Mz"]
        out[f"{pn}_force_N"] = P["force_N"]
        out[f"{pn}_spin_moment_Nm"] = P["spin_moment_Nm"]
        out[f"{pn}_support_moment_Nm"] = P["support_moment_Nm"]
        out[f"{pn}_bearing_spring_force_N"] = P["bearing_spring_force_N"]
        out[f"{pn}_bearing_spring_moment_Nm"] = P["bearing_spring_moment_Nm"]
        out[f"{pn}_tilt_rad"] = P["tilt_rad"]
    fe_fz, cent = {}, {}
    for label, mesh in meshes.items():
        M = train["meshes"][mesh]
        out[f"normal_force_{label}_N"] = M["normal_force_N"]
        out[f"active_points_{label}"] = M["active_points"]
        out[f"grid_points_{label}"] = M["grid_points"]
        for b, on in M["on"].items():
            pn = roles[b]
            fe_fz[(label, pn)] = float(on["force_N"][2])
            cent[(label, pn)] = np.asarray(on["centroid_mm"] or [np.nan] * 3)
            out[f"Z_{label}_{pn}"] = on["Z_mm"]
            out[f"F_{label}_on_{pn}_N"] = on["force_N"]
    out["FzSUN_fe"] = fe_fz[("sun-SP", "SP")]
    out["FzRP_fe"] = fe_fz[("SP-RP", "SP")]
    out["FzSP_fe"] = fe_fz[("SP-RP", "RP")]
    out["FzRING_fe"] = fe_fz[("RP-ring", "RP")]
    out["ZS"] = out["Z_sun-SP_SP"]
    out["Z_SPRP"] = out["Z_SP-RP_SP"]
    out["ZR"] = out["Z_RP-ring_RP"]
    inp = gearset.planetary_input()
    geo, fz = double_pinion_geometry(inp), double_pinion_axial_forces(inp)
    out.update(
        with_loa_aliases(
            dp.loa_moments(out["Mx_SP"], out["My_SP"], out["Mx_RP"], out["My_RP"], geo)
        )
    )
    table5 = with_loa_aliases(dp.double_pinion_moments(fz, geo))
    # Closed form moved to the FE centroid offsets: the analytic mesh forces (axial part from
    # the closed form, direction = the exact plane-of-action normal of the grid) at the pitch
    # point + Z e_Z; the transverse parts then add Z x F_transverse to Mx, My.
    fz_an = {
        ("sun-SP", "SP"): fz.FzSUN,
        ("SP-RP", "SP"): fz.FzRP,
        ("SP-RP", "RP"): fz.FzSP,
        ("RP-ring", "RP"): fz.FzRING,
    }
    # pitch point: operating pitch radius from the pinion centre towards the mating centre
    pitch = {
        ("sun-SP", "SP"): (geo.r_sp_sun, "sun"),
        ("SP-RP", "SP"): (geo.r_sp_rp, "RP"),
        ("SP-RP", "RP"): (geo.r_rp_sp, "SP"),
        ("RP-ring", "RP"): (geo.r_rp_ring, "out"),
    }
    on_sign = {
        ("sun-SP", "SP"): +1.0,
        ("SP-RP", "SP"): -1.0,
        ("SP-RP", "RP"): +1.0,
        ("RP-ring", "RP"): -1.0,
    }
    shifted, pitch_points = {}, {}
    for pn in ("SP", "RP"):
        Q = frames[pn]
        m = np.zeros(3)
        for (label, who), fza in fz_an.items():
            if who != pn:
                continue
            normal = np.asarray(train["meshes"][meshes[label]]["normal"])
            n = on_sign[(label, pn)] * (Q @ normal)
            f_vec = fza / n[2] * n
            r_w, towards = pitch[(label, pn)]
            if towards == "sun":
                d = -centres[pn]
            elif towards == "out":
                d = centres[pn].copy()
            else:
                d = centres[towards] - centres[pn]
            d = Q @ (d / np.linalg.norm(d))
            pitch_points[(label, pn)] = (r_w, d)
            r = r_w * d + np.array([0.0, 0.0, out[f"Z_{label}_{pn}"]])
            m += n_m(np.cross(r, f_vec))
            # where the FE centroid sits along the transverse line of action from the pitch
            # point (mm): the closed form has 0; the axial force there adds s x Fz to Mx, My
            t = np.array([n[0], n[1], 0.0]) / math.hypot(n[0], n[1])
            out[f"loa_offset_{label}_{pn}_mm"] = float((cent[(label, pn)] @ Q.T - r_w * d) @ t)
        shifted[f"Mx_{pn}"], shifted[f"My_{pn}"] = float(m[0]), float(m[1])
    shifted.update(with_loa_aliases(dp.loa_moments(*(shifted[k] for k in _PINION_MOMENTS), geo)))
    out["analytic"] = {
        "table5": table5,
        "at_fe_centroids": shifted,
        "FzSUN": fz.FzSUN,
        "FzRP": fz.FzRP,
        "FzSP": fz.FzSP,
        "FzRING": fz.FzRING,
        "theta_deg": math.degrees(geo.theta),
        "phi_deg": math.degrees(geo.phi),
    }
    face = min(gearset.gears[set_sp].face_width, gearset.gears[set_rp].face_width)
    out["sp_rp_differential"] = _sp_rp_differential(
        train, meshes, frames, centres, pitch_points, geo, face, out, table5, lines
    )
    out["f_ma_SPRP_um"] = out["sp_rp_differential"]["misalignment_um"]
    return out


def _sp_rp_differential(
    train, meshes, frames, centres, pitch_points, geo, face, out, table5, lines=None
):
    """The SP-RP LOA differential D = M_LOA_SP_RP + M_LOA_RP_SP split exactly over the mesh
    load centroids (singh2007 Table 5 gives 11 N m with every mesh force at its pitch point).

    In the scene frame D = (M_RP - M_SP) . u, u the normal of the SP-RP plane of action
    (M_LOA_SP_RP = w_SP . M_SP, M_LOA_RP_SP = w_RP . M_RP in the pinion frames, section 5):
    the relative tilt of the two pinions in that plane, the SP-RP misalignment, is D over the
    tilting stiffness. The force F of a mesh on a pinion acts at its load centroid (all the
    grid forces of a helical involute mesh share one direction), which lies in the plane of
    action: pitch point + s t + Z e_Z, t the transverse direction of F. The pinion's share
    of D is therefore exactly

        D_side = (r_pitch x F) . w + Z (e_Z x F) . w + s (t x F) . w     (N mm; N m below)

    the first term Table 5's (the axial force at the pitch point: r_pitch x F_transverse
    is along e_Z), the others the centroid terms, ``dD_dZ`` and ``dD_ds`` their
    sensitivities (N m per mm). ``other`` closes the sum (the centroid off the plane of
    action, round-off). The SP-RP mesh force acts on both pinions: its Z term counts twice
    (an axial offset puts opposite moments on SP and RP), its s term cancels (the centroid
    moves along the line of action by +s from one pinion and -s from the other).

    ``from_cells`` = D_fe - sum of the sides' D: the moment of the point forces about their
    centroid, sum_k (x_k - x_bar) x F_k n_k, which the one-force reading leaves out. 0
    (round-off) on a line grid, whose forces share one direction; a zone grid's cells off
    the line carry their own normals (:func:`solvers.flank_grid.contact_normals`), so there
    it is the cells' share, and D_fe = D_pitch + from_Z + from_s + other + from_cells.

    ``misalignment_um``: the relative tilt of RP against SP about u (the bearing tilts)
    times the smaller face width; ``Z_lines_<side>``: the centroid of the theoretical contact
    lines themselves (what a uniform line load would give at this mesh position): the mean Z
    of ``lines[mesh]`` (:func:`contact_line_points`), without them of the grid points."""
    c1, s1 = math.cos(geo.theta - geo.a2), math.sin(geo.theta - geo.a2)
    c2, s2 = math.cos(geo.phi + geo.a2), math.sin(geo.phi + geo.a2)
    w = {"SP": np.array([-c1, -s1, 0.0]), "RP": np.array([-c2, s2, 0.0])}
    u = -frames["SP"].T @ w["SP"]  # scene frame; equal to frames["RP"].T @ w["RP"]
    sides = {}
    body = dict(zip(("SP", "RP"), out["pinion_bodies"], strict=True))  # role -> body name
    for (label, pn), (r_w, d) in pitch_points.items():
        M = train["meshes"][meshes[label]]
        Q = frames[pn]
        F = np.asarray(out[f"F_{label}_on_{pn}_N"], float)  # pinion frame
        r = np.asarray(M["on"][body[pn]]["centroid_mm"], float) @ Q.T  # from the centre
        t = np.array([F[0], F[1], 0.0]) / math.hypot(F[0], F[1])
        Z, s = float(r[2]), float(r @ t)
        r_pitch = r_w * d
        s -= float(r_pitch @ t)
        total = float(n_m(np.cross(r, F) @ w[pn]))
        pitch = float(n_m(np.cross(r_pitch, F) @ w[pn]))
        dz = float(n_m(np.cross([0.0, 0.0, 1.0], F) @ w[pn]))
        ds = float(n_m(np.cross(t, F) @ w[pn]))
        x_lines = (lines or {}).get(meshes[label], M["points"]["x_mm"])
        z_lines = (np.asarray(x_lines, float).reshape(-1, 3) - centres[pn]) @ Q[2]
        sides[f"{label}_{pn}"] = {
            "D": total,
            "pitch": pitch,
            "Z_mm": Z,
            "s_mm": s,
            "dD_dZ": dz,
            "dD_ds": ds,
            "from_Z": Z * dz,
            "from_s": s * ds,
            "other": total - pitch - Z * dz - s * ds,
            "Z_lines_mm": float(z_lines.mean()) if z_lines.size else float("nan"),
        }
    tilt = {pn: frames[pn].T @ np.asarray(out[f"{pn}_tilt_rad"], float) for pn in frames}
    rel = float((tilt["RP"] - tilt["SP"]) @ u)
    d_fe = out["M_LOA_SPRP_diff"]
    return {
        "D_fe": d_fe,
        "D_table5": table5["M_LOA_SPRP_diff"],
        "D_pitch": sum(v["pitch"] for v in sides.values()),
        "from_Z": sum(v["from_Z"] for v in sides.values()),
        "from_s": sum(v["from_s"] for v in sides.values()),
        "other": sum(v["other"] for v in sides.values()),
        "from_cells": d_fe - sum(v["D"] for v in sides.values()),
        "sides": sides,
        "u": u.tolist(),
        "relative_tilt_rad": rel,
        "misalignment_um": rel * face * 1e3,
        "face_width_mm": face,
    }


_BRANCH = {"single_pinion": _single_branch, "double_pinion": _double_branch}


def contact_line_points(train: dict, scene, spacing: float | None = None) -> dict[str, np.ndarray]:
    """Per mesh, points (n, 3) equally spaced along the theoretical contact lines, for a
    uniform line load's centroid: a line grid's own points (equal segments along each line);
    for a zone grid, whose cells and sections also cover the flanks off the lines, the points
    a line grid of point ``spacing`` (mm) would have there
    (:func:`solvers.flank_grid.flank_grid`), without a spacing the scene's theoretical lines
    (:attr:`meshing.mesh_zones.MeshZone.contact_lines`, equal steps in z: equal lengths
    along lines of one helix angle; their centroid differs from a line grid's by the
    discretisation, up to 0.1 mm at level 0)."""
    zones = {f"{z.driver}-{z.driven}": z for z in scene.zones}
    out = {}
    for name, mesh in train["meshes"].items():
        if mesh.get("grid_model", "line") == "zone":
            zn = zones[name]
            if spacing:
                grid, _ = flank_grid(zn, scene.gear(zn.driver), scene.gear(zn.driven), spacing)
                out[name] = np.asarray(grid.x_a, float)
                continue
            pts = [np.asarray(p, float) for *_, p in zn.contact_lines]
            out[name] = np.vstack(pts) if pts else np.zeros((0, 3))
        else:
            out[name] = np.asarray(mesh["points"]["x_mm"], float).reshape(-1, 3)
    return out


def branch_pinions(scene, gearset) -> list[list[str]]:
    """The pinion body names of each branch of the scene, branch by branch."""
    per = len(gearset.power_path) - 2
    names = list(scene.pinion_names)
    return [names[i : i + per] for i in range(0, len(names), per)]


def paper_moments(train: dict, scene, gearset, spacing: float | None = None) -> dict:
    """The paper's quantities of every branch (one branch: its dict; several: the means of
    :data:`MEAN_KEYS` at the top level and ``branches``, each with its carrier angle and its
    load share: the normal force of its sun mesh over the mean of all branches (the tangential
    force in the same ratio, the meshes being alike), and ``K_gamma``, the largest share).
    ``spacing``: the contact grid's point spacing (mm), for the centroid of the contact
    lines of a zone grid (:func:`contact_line_points`)."""
    branch = _BRANCH[gearset.kind]
    groups = branch_pinions(scene, gearset)
    lines = contact_line_points(train, scene, spacing)
    rows = [branch(train, gearset, names, lines) for names in groups]
    if len(rows) == 1:
        return rows[0]
    sun = scene.sun_name
    loads = np.array([train["meshes"][f"{sun}-{names[0]}"]["normal_force_N"] for names in groups])
    for row, names, load in zip(rows, groups, loads, strict=True):
        c = train["pinions"][names[0]]["centre_mm"]
        row["angle_deg"] = float(np.degrees(np.arctan2(c[1], c[0])) % 360.0)
        row["load_share"] = float(load / loads.mean())
    out = {k: float(np.mean([r[k] for r in rows])) for k in MEAN_KEYS[gearset.kind]}
    out["K_gamma"] = float(max(r["load_share"] for r in rows))
    out["branches"] = rows
    return out

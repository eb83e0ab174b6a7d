"""Contact stress at the contact-grid points of a solved position and over a mesh cycle, and
the ISO 6336-3 nominal root stress of a gear set: the stress numbers beside the FE ones.

Contact stress (:func:`contact_stress_at_points`): Hertz line contact at every grid point of
every mesh, from the FE line load w there and the exact normal-plane curvatures at the
point's roll position s (distance from the pitch point along the line of action, from the
point's radius on the mesh's driver, :func:`gears.contact_stress.position_from_radius`).

Over the mesh cycle (:func:`contact_stress_cycle`): the maximum over every grid point of
every position, split into interior and edge points (:func:`edge_points`). Edge points are
the line ends (first and last point of each contact line, where the grid is cut at a face
end or at the path of contact and a Hertz line load has no physical meaning without relief)
and points within one grid spacing, along their contact line, of a tip or form circle of
either gear. The interior maximum is the contact stress to quote; the edge maximum is an
edge-load indicator (tip or face-end contact a relief would remove). With the interior line
loads w of all positions, K_Hbeta = w_max / w_mean, and the ISO 6336-2 nominal stress at the
pitch point sigma_H0 (:func:`gears.contact_stress.iso6336_pitch_contact_stress`) times
sqrt(K_Hbeta) is ISO's contact stress with that face load factor (the other factors 1), to
set beside the FE interior maximum.

Root stress (:func:`iso_nominal_root_stress`, :func:`iso_root_stress_factors`): ISO 6336-3
method B nominal stress (all K factors 1, Y_beta of the 2006 edition, the 2019 form beside
it) of every gear at every mesh it takes part in, internal gears by ISO's substitute rack,
keyed as the FE root stress (:func:`gears.train.mesh_side_keys`).
"""

from __future__ import annotations

import math

import numpy as np

from gears import contact_stress
from gears.involute import roll_length
from gears.iso6336_root import fillet_tangent_point, nominal_root_stress
from gears.train import mesh_side_keys
from gears.units import n_m, n_mm


def contact_stress_at_points(gearset, material, pos: dict) -> dict:
    """Per mesh of the position ``pos``: ``s_mm`` and Hertz ``p_max`` (MPa) at every grid
    point. ``material``: the study's (E of the gears = E gear_modulus_factor, nu)."""
    steel = (material.gear_youngs_modulus, material.poisson_ratio)
    out = {}
    for name, mesh in pos["meshes"].items():
        pair = gearset.pair(*mesh["gears"])
        driver = pos["pinions"].get(mesh["driver"])
        centre = np.asarray(driver["centre_mm"][:2]) if driver else np.zeros(2)
        pts = mesh["points"]
        x = np.asarray(pts["x_mm"])
        w = np.clip(np.asarray(pts["line_load_N_per_mm"]), 0.0, None)
        r1 = np.linalg.norm(x[:, :2] - centre, axis=1)
        s = contact_stress.position_from_radius(pair, r1)
        hz = contact_stress.mesh_contact(pair, s, w, steel, steel)
        out[name] = {"s_mm": np.atleast_1d(s), "p_max": np.atleast_1d(hz.p_max)}
    return out


def driver_torques(gearset) -> dict[tuple[str, str], float]:
    """Torque (N mm) on the driver of each mesh (driver, driven) for the sun torque of one
    branch, carrier held: T_sun = input torque / planets on the first mesh, then each mesh
    passes the tangential force on, T_driven = T_driver z_driven / z_driver."""
    torque = n_mm(gearset.torque_per_branch)  # N mm on the sun
    out = {}
    for m in gearset.meshes:
        out[(m.gear1, m.gear2)] = torque
        torque = torque * gearset.gears[m.gear2].teeth / gearset.gears[m.gear1].teeth
    return out


ISO_ROOT_KEYS = ("Y_F", "Y_S", "Y_beta", "s_Fn", "rho_F", "h_Fe", "x_E", "q_s", "F_t", "b")


def iso_root_stress_factors(gearset) -> dict:
    """Per gear and mesh (keys of :func:`gears.train.mesh_side_keys`) the ISO 6336-3 method B
    nominal root stress for the sun torque of one branch (the torque on each mesh's driver
    follows the tooth ratios along the path, :func:`driver_torques`), external and internal
    gears: ``sigma_F0`` (MPa, Y_beta of the 2006 edition), ``sigma_F0_Ybeta2019`` (the same
    with the 2019 edition's Y_beta), ``edition`` (2006), ``internal``, the factors
    ``ISO_ROOT_KEYS`` (:func:`gears.iso6336_root.nominal_root_stress`) and the chord and
    radius of curvature at ISO's critical point of the generated transverse fillet
    (``s_Fn_generated``, ``rho_F_generated``, :func:`gears.iso6336_root.fillet_tangent_point`)."""
    meshes = [(m.gear1, m.gear2) for m in gearset.meshes]
    driver_torque = driver_torques(gearset)
    out = {}
    for key, gear, mate, i in mesh_side_keys(meshes):
        a, b = (gear, mate) if i == 1 else (mate, gear)
        pair = gearset.pair(a, b)
        r = nominal_root_stress(pair, i, driver_torque[(a, b)])
        r19 = nominal_root_stress(pair, i, driver_torque[(a, b)], edition=2019)
        ex = fillet_tangent_point(pair.gear(i))
        out[key] = {"sigma_F0": r["sigma_F0"], "sigma_F0_Ybeta2019": r19["sigma_F0"],
                    "edition": r["edition"], "internal": pair.gear(i).internal,
                    **{k: r[k] for k in ISO_ROOT_KEYS},
                    "rho_F_generated": ex["rho_F"], "s_Fn_generated": ex["s_Fn"]}  # fmt: skip
    return out


def iso_nominal_root_stress(gearset) -> dict:
    """ISO 6336-3 method B nominal root stress sigma_F0 (MPa, Y_beta 2006) per gear and
    mesh, internal gears included (:func:`iso_root_stress_factors`)."""
    return {k: v["sigma_F0"] for k, v in iso_root_stress_factors(gearset).items()}


def _centre(pos: dict, body: str) -> np.ndarray:
    """(x, y) of a body's axis: a pinion's centre, else the scene axis (sun, ring)."""
    p = pos["pinions"].get(body)
    return np.asarray(p["centre_mm"][:2], float) if p else np.zeros(2)


def edge_points(gearset, pos: dict) -> dict:
    """Per mesh of the position ``pos``: ``line_end`` and ``tip_form`` (bool per grid point)
    and their union ``edge`` (see the module docstring).

    Line ends come from ``pos["grid_lines"][mesh]`` (``rows`` [first, last + 1) of each
    contact line); without them (older results) no point counts as a line end. Tip / form:
    along a contact line, which is inclined at the base helix angle beta_b to the axis in the
    plane of action, the roll length u = sqrt(r^2 - r_b^2) of a gear changes by sin(beta_b)
    per unit length, so a point lies a distance |u - u_e| / sin(beta_b) from where its line
    crosses the circle of roll length u_e (|u - u_e| for a spur gear); it is an edge point if
    that is below its line's spacing for the tip or form circle of either gear."""
    out = {}
    for name, mesh in pos["meshes"].items():
        x = np.asarray(mesh["points"]["x_mm"], float).reshape(-1, 3)
        n = len(x)
        line_end = np.zeros(n, bool)
        spacing = np.full(n, float(pos.get("grid_spacing_mm") or 0.0))
        for line in (pos.get("grid_lines") or {}).get(name, []):
            a, b = line["rows"]
            if b > a:
                line_end[[a, b - 1]] = True
                spacing[a:b] = line.get("spacing", spacing[a])
        tip_form = np.zeros(n, bool)
        for body, gear_name in zip((mesh["driver"], mesh["driven"]), mesh["gears"], strict=True):
            g = gearset.gears[gear_name]
            u = roll_length(np.linalg.norm(x[:, :2] - _centre(pos, body), axis=1), g.base_radius)
            sin_b = math.sin(g.base_helix_angle)
            for r_e in (g.tip_radius, g.form_radius):
                du = np.abs(u - roll_length(r_e, g.base_radius))
                tip_form |= (du / sin_b if sin_b > 1e-9 else du) < spacing
        out[name] = {"line_end": line_end, "tip_form": tip_form, "edge": line_end | tip_form}
    return out


def _where(pos: dict, name: str, i: int, s_mm) -> dict:
    """Where grid point i of mesh ``name`` lies: roll, Z in the mesh's first pinion's frame
    (mm from mid face width), s on the line of action (mm from the pitch point)."""
    mesh = pos["meshes"][name]
    x = np.asarray(mesh["points"]["x_mm"][i], float)
    out = {"roll": pos["roll"], "s_mm": float(s_mm[i])}
    pinion = next(iter(mesh.get("on", {})), None)
    if pinion is not None:
        p = pos["pinions"][pinion]
        out["Z_mm"] = float((x - np.asarray(p["centre_mm"], float)) @ np.asarray(p["frame"])[2])
    return out


def contact_stress_cycle(gearset, material, positions: list[dict]) -> dict:
    """Per mesh (grid name), the contact stress over the mesh cycle ``positions``:

    * ``p_max_MPa``: Hertz p_max over every grid point of every position;
    * ``interior_p_max_MPa`` (and ``interior_at``: roll, Z, s): over the interior points,
      the contact stress to quote; ``edge_p_max_MPa`` (``edge_at``, ``edge_kind``): over the
      edge points (:func:`edge_points`), an edge-load indicator; ``edge_to_interior``;
    * ``w_max_N_per_mm``, ``w_mean_N_per_mm``: the largest and the mean line load over the
      interior points of all positions (unloaded points count as 0: the mean is the load
      spread over the whole contact line length, as ISO's mean load per face width);
      ``K_Hbeta`` = w_max / w_mean (it holds the load sharing between the contact lines
      too, not only the distribution over the face width);
    * ISO 6336-2 (:func:`gears.contact_stress.iso6336_pitch_contact_stress`), method B at the
      pitch point: ``sigma_H0_MPa`` = Z_H Z_E Z_eps Z_beta sqrt(F_t / (d1 b) (u +- 1) / u)
      with Z_H the zone factor, Z_E = sqrt(E* / pi) from the study's gear material, Z_eps =
      sqrt(1 / eps_alpha) (eps_beta >= 1; the eps_beta < 1 form otherwise), Z_beta =
      sqrt(1 / cos(beta)), F_t = 2 T1 / d1 from the torque T1 on the mesh's driver for the
      sun torque of one branch (:func:`driver_torques`, ``iso_driver_torque_Nm``), b the
      smaller face width; K_A = K_v = K_Halpha = 1 and Z_B = Z_D = 1 (single pair contact
      factors not applied); ``sigma_H_MPa`` = sigma_H0 sqrt(K_Hbeta), ISO's stress with the FE
      face load factor, beside ``interior_p_max_MPa``; ``iso_factors``: Z_H, Z_E, Z_eps, Z_beta;
    * Hertz at the pitch point (s = 0) under a uniform line load, the cross-check between
      the two: ``hertz_pitch_w_mean_MPa`` and ``hertz_pitch_w_max_MPa`` under the FE mean and
      largest interior line load, ``hertz_pitch_w_nominal_mean_MPa`` under ISO's mean load
      per contact length ``w_nominal_mean_N_per_mm`` = F_t / (b cos(alpha_wt) eps_alpha)
      (:func:`gears.contact_stress.nominal_line_load`, "mean"), which equals sigma_H0 /
      Z_beta for eps_beta >= 1 (the normal-plane curvature at C holds the cos(beta_b)
      ISO's Z_H carries).
    """
    steel = (material.gear_youngs_modulus, material.poisson_ratio)
    hz = [contact_stress_at_points(gearset, material, p) for p in positions]
    edges = [edge_points(gearset, p) for p in positions]
    torques = driver_torques(gearset)
    out = {}
    for name, mesh0 in positions[0]["meshes"].items():
        best = {"interior": (-1.0, None), "edge": (-1.0, None)}
        w_in = []
        for j, (pos, h, e) in enumerate(zip(positions, hz, edges, strict=True)):
            p = np.asarray(h[name]["p_max"], float)
            edge = e[name]["edge"]
            w = np.asarray(pos["meshes"][name]["points"]["line_load_N_per_mm"], float)
            w_in.append(np.clip(w[~edge], 0.0, None))
            for kind, mask in (("interior", ~edge), ("edge", edge)):
                if mask.any():
                    i = int(np.flatnonzero(mask)[np.argmax(p[mask])])
                    if p[i] > best[kind][0]:
                        best[kind] = (float(p[i]), (j, i))
        w = np.concatenate(w_in) if w_in else np.zeros(0)
        w_max = float(w.max()) if w.size else 0.0
        w_mean = float(w.mean()) if w.size else 0.0
        k_hb = w_max / w_mean if w_mean > 0.0 else float("nan")
        a, b = mesh0["gears"]
        iso = contact_stress.iso6336_pitch_contact_stress(
            gearset.pair(a, b), torques[(a, b)], steel, steel
        )
        rec = {
            "positions": len(positions),
            "interior_points": int(sum(np.count_nonzero(~e[name]["edge"]) for e in edges)),
            "edge_points": int(sum(np.count_nonzero(e[name]["edge"]) for e in edges)),
            "p_max_MPa": max(best["interior"][0], best["edge"][0], 0.0),
            "w_max_N_per_mm": w_max,
            "w_mean_N_per_mm": w_mean,
            "K_Hbeta": k_hb,
            "sigma_H0_MPa": iso["sigma_H0"],
            "sigma_H_MPa": iso["sigma_H0"] * math.sqrt(k_hb) if w_mean > 0.0 else None,
            "iso_driver_torque_Nm": float(n_m(torques[(a, b)])),
            "iso_factors": {k: iso[k] for k in ("Z_H", "Z_E", "Z_eps", "Z_beta")},
            "w_nominal_mean_N_per_mm": contact_stress.nominal_line_load(
                gearset.pair(a, b), torques[(a, b)], "mean"
            ),
        }
        for name_w, w_ in (("w_mean", w_mean), ("w_max", w_max), ("w_nominal_mean",
                           rec["w_nominal_mean_N_per_mm"])):  # fmt: skip
            hz_c = contact_stress.mesh_contact(gearset.pair(a, b), 0.0, w_, steel, steel)
            rec[f"hertz_pitch_{name_w}_MPa"] = float(hz_c.p_max)
        for kind in ("interior", "edge"):
            val, at = best[kind]
            rec[f"{kind}_p_max_MPa"] = max(val, 0.0) if at else None
            rec[f"{kind}_at"] = None
            if at:
                j, i = at
                rec[f"{kind}_at"] = _where(positions[j], name, i, hz[j][name]["s_mm"])
        if best["edge"][1]:
            j, i = best["edge"][1]
            e = edges[j][name]
            rec["edge_kind"] = " and ".join(
                k for k, m in (("line end", e["line_end"][i]), ("tip/form", e["tip_form"][i])) if m
            )
        ip, ep = rec["interior_p_max_MPa"], rec["edge_p_max_MPa"]
        rec["edge_to_interior"] = ep / ip if ip and ep is not None else None
        out[name] = rec
    return out

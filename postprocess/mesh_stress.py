"""Contact stress at the contact-grid points of a solved position, and the ISO 6336-3 nominal
root stress of a gear set: the stress numbers beside the FE ones.

Contact stress (:func:`contact_stress_at_points`): Hertz line contact at every grid point of
every mesh, from the FE line load w there and the exact normal-plane curvatures at the
point's roll position s (distance from the pitch point along the line of action, from the
point's radius on the mesh's driver, :func:`gears.contact_stress.position_from_radius`).

Root stress (:func:`iso_nominal_root_stress`): ISO 6336-3 method B nominal stress (all K
factors 1) of every external gear at every mesh it takes part in, keyed as the FE root
stress (:func:`gears.train.mesh_side_keys`); internal gears get None (not covered).
"""

from __future__ import annotations

import numpy as np

from gears import contact_stress
from gears.iso6336_root import nominal_root_stress
from gears.train import mesh_side_keys
from gears.units import n_mm


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


def iso_nominal_root_stress(gearset) -> dict:
    """ISO 6336-3 method B nominal root stress (MPa) per gear and mesh for the sun torque of
    one branch; the torque on each mesh's driver follows the tooth ratios along the path."""
    torque = n_mm(gearset.torque_per_branch)  # N mm on the sun
    meshes = [(m.gear1, m.gear2) for m in gearset.meshes]
    driver_torque = {}
    for a, b in meshes:
        driver_torque[(a, b)] = torque
        torque = torque * gearset.gears[b].teeth / gearset.gears[a].teeth
    out = {}
    for key, gear, mate, i in mesh_side_keys(meshes):
        a, b = (gear, mate) if i == 1 else (mate, gear)
        pair = gearset.pair(a, b)
        if gearset.gears[gear].internal:
            out[key] = None
            continue
        out[key] = nominal_root_stress(pair, i, driver_torque[(a, b)])["sigma_F0"]
    return out

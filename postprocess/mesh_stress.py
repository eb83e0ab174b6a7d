"""Contact stress at the contact-grid points of a solved position and over a mesh cycle, and
the ISO 6336-3 nominal root stress of a gear set: the stress numbers beside the FE ones.

Contact stress (:func:`contact_stress_at_points`). Line grid: Hertz line contact at every
grid point of every mesh, from the FE line load w there and the exact normal-plane
curvatures at the point's roll position s (distance from the pitch point along the line of
action, from the point's radius on the mesh's driver,
:func:`gears.contact_stress.position_from_radius`). Zone grid: the solved pressure of every
cell (the cell average F_k / w_k), with Hertz at its section's line load beside it.

Over the mesh cycle (:func:`contact_stress_cycle`): the maximum over every grid point of
every position, split into interior and edge points (:func:`edge_points`). Line grid: edge
points are the line ends (first and last point of each contact line, where the grid is cut
at a face end or at the path of contact and a Hertz line load has no physical meaning
without relief) and points within one grid spacing, along their contact line, of a tip or
form circle of either gear. Zone grid: the cells of the end sections at the face ends and
the cells next to a tip or form circle (corner contact of the sharp tips). Both grids: the
points in the fixed edge bands, one normal module from a face end and a quarter of one (of
profile arc) from a tip or form circle, where the ends' singular tails reach
(:data:`FACE_BAND_MODULES`). The interior
maximum is the contact stress to quote; the edge maximum is an edge-load indicator (tip or
face-end contact a relief would remove). With the line loads w of the interior stations of
all positions, K_Hbeta = w_max / w_mean, and the ISO 6336-2 nominal stress at the pitch
point sigma_H0 (:func:`gears.contact_stress.iso6336_pitch_contact_stress`) times
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
from postprocess.train_results import mesh_stations

#: zone grid: a cell is a tip / form edge cell if its centre lies within EDGE_CELLS of its own
#: widths (along the profile) plus EDGE_REACH_MM of a tip or form circle: the grid ends 0.02
#: mm (radially; ~0.025 mm of profile) inside the circles, plus up to one profile sample of
#: the grid (~0.02 mm), so this holds the last cell and, where the cells are graded fine at
#: a tip, the one before it, which carries the tail of a corner contact (1-GA level 0: the
#: last cell 4-8 GPa, the one before it 2-2.7 GPa, the third 0-0.6 GPa); see :func:`edge_points`
EDGE_CELLS = 1.0
EDGE_REACH_MM = 0.05
#: the edge bands, fixed lengths (not a number of cells or grid segments) so that the
#: interior values are read at the same place at every level: a band that shrinks with the
#: mesh moves the point read into the edge's singular tail and the value does not converge
#: (1-GB at roll 0, before the bands: the interior line-load peak of the pinion-ring mesh
#: sat one segment from a face end, 647 / 660 / 766 N/mm at levels 0 / 1 / 2, K_Hbeta and
#: sigma_H divergent; the interior pressure peaks sat one cell from a tip circle).
#: Face ends: the points within FACE_BAND_MODULES normal modules of a face end of the
#: common face width, the band of the root stress (solvers.root_stress.face_end_band): the
#: distance over which the end's disturbance decays. Tips and forms: the points within
#: TIP_BAND_MODULES normal modules of profile arc of a tip or form circle: 1-GB level 1,
#: largest cell pressure of the sun-pinion mesh by distance from the tip circle 9.9 / 3.3 /
#: 2.5 / 2.1 / 2.0 / 1.85 / 1.8 GPa at 0-0.05 / -0.1 / -0.15 / -0.2 / -0.3 / -0.4 / -0.6 mm:
#: the corner contact's tail has decayed into the Hertz field at 0.4 mm (0.25 m_n)
FACE_BAND_MODULES = 1.0
TIP_BAND_MODULES = 0.25


def _hertz(gearset, steel, pos: dict, mesh: dict, x, w) -> tuple[np.ndarray, np.ndarray]:
    """(s_mm, Hertz p_max MPa) at points x of ``mesh`` under line loads w (clipped at 0): s
    from the point's radius on the mesh's driver, the exact normal-plane curvatures there."""
    pair = gearset.pair(*mesh["gears"])
    x = np.asarray(x, float).reshape(-1, 3)
    r1 = np.linalg.norm(x[:, :2] - _centre(pos, mesh["driver"]), axis=1)
    s = np.atleast_1d(contact_stress.position_from_radius(pair, r1))
    w = np.clip(np.asarray(w, float), 0.0, None)
    return s, np.atleast_1d(contact_stress.mesh_contact(pair, s, w, steel, steel).p_max)


def contact_stress_at_points(gearset, material, pos: dict) -> dict:
    """Per mesh of the position ``pos``, the contact stress at every grid point and station.
    ``material``: the study's (E of the gears = E gear_modulus_factor, nu).

    * ``s_mm``, ``p_max`` (MPa) per grid point: a line grid, Hertz line contact under the
      line load of the point (its station); a zone grid, the solved pressure itself, the
      cell average F_k / w_k (the cells are graded down to half the Hertz semi-width a_H at
      the contact line, a_H of the grid's design stress, so the centre cell's average of
      the elliptic p0 sqrt(1 - (v/a_H)^2) over |v| <= a_H / 4 is 0.99 p0, nearer p0 where
      the stress and a_H are larger; the contact stress of a zone grid is read, not
      modelled);
    * per station (:func:`postprocess.train_results.mesh_stations`): ``station_s_mm``,
      ``station_hertz_MPa`` (Hertz at the station's line load, the cross-check of a zone
      grid's pressure) and ``station_p_max`` (the station's contact stress: Hertz for a line
      grid; for a zone grid the largest pressure of the section's interior cells, 0 where
      all its load is on edge cells (:func:`edge_points`): the corner contact of a tip is
      in ``p_max`` and the edge indicator, not in a section's peak);
    * ``grid_model``: "line" or "zone"."""
    steel = (material.gear_youngs_modulus, material.poisson_ratio)
    zoned = any(m.get("grid_model") == "zone" for m in pos["meshes"].values())
    edges = edge_points(gearset, pos) if zoned else {}
    out = {}
    for name, mesh in pos["meshes"].items():
        st = mesh_stations(mesh)
        s_st, hz_st = _hertz(gearset, steel, pos, mesh, st["x_mm"], st["line_load_N_per_mm"])
        rec = {
            "grid_model": mesh.get("grid_model", "line"),
            "station_s_mm": s_st,
            "station_hertz_MPa": hz_st,
        }
        if rec["grid_model"] == "zone":
            pts = mesh["points"]
            s, _ = _hertz(gearset, steel, pos, mesh, pts["x_mm"], np.zeros(len(pts["x_mm"])))
            p = np.clip(np.asarray(pts["pressure_MPa"], float), 0.0, None)
            inner = ~edges[name]["edge"]
            peak = np.zeros(len(hz_st))
            np.maximum.at(peak, np.asarray(pts["station"], int)[inner], p[inner])
            rec.update(s_mm=s, p_max=p, station_p_max=peak)
        else:  # one station per point
            rec.update(s_mm=s_st, p_max=hz_st, station_p_max=hz_st)
        out[name] = rec
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
        out[key] = {
            "sigma_F0": r["sigma_F0"],
            "sigma_F0_Ybeta2019": r19["sigma_F0"],
            "edition": r["edition"],
            "internal": pair.gear(i).internal,
            **{k: r[k] for k in ISO_ROOT_KEYS},
            "rho_F_generated": ex["rho_F"],
            "s_Fn_generated": ex["s_Fn"],
        }
    return out


def iso_nominal_root_stress(gearset) -> dict:
    """ISO 6336-3 method B nominal root stress sigma_F0 (MPa, Y_beta 2006) per gear and
    mesh, internal gears included (:func:`iso_root_stress_factors`)."""
    return {k: v["sigma_F0"] for k, v in iso_root_stress_factors(gearset).items()}


def _centre(pos: dict, body: str) -> np.ndarray:
    """(x, y) of a body's axis: a pinion's centre, else the scene axis (sun, ring)."""
    p = pos["pinions"].get(body)
    return np.asarray(p["centre_mm"][:2], float) if p else np.zeros(2)


def _near_circles(gearset, pos: dict, mesh: dict, x: np.ndarray, reach) -> np.ndarray:
    """Points x on a contact line within ``reach`` (mm, per point) of where the line
    crosses a tip or form circle of either gear: a contact line is inclined at the base
    helix angle beta_b to the axis in the plane of action, so the roll length
    u = sqrt(r^2 - r_b^2) of a gear changes by sin(beta_b) per unit length along it and a
    point lies |u - u_e| / sin(beta_b) from the crossing of the circle of roll length u_e
    (|u - u_e| for a spur gear)."""
    near = np.zeros(len(x), bool)
    for body, gear_name in zip((mesh["driver"], mesh["driven"]), mesh["gears"], strict=True):
        g = gearset.gears[gear_name]
        u = roll_length(np.linalg.norm(x[:, :2] - _centre(pos, body), axis=1), g.base_radius)
        sin_b = math.sin(g.base_helix_angle)
        for r_e in (g.tip_radius, g.form_radius):
            du = np.abs(u - roll_length(r_e, g.base_radius))
            near |= (du / sin_b if sin_b > 1e-9 else du) < reach
    return near


def _station_edges(gearset, pos: dict, name: str, mesh: dict) -> tuple[np.ndarray, np.ndarray]:
    """(line_end, tip_form) per station of a mesh: the first and last station of each
    contact line (tooth pair), and the stations within their length of a tip or form
    circle along the line (:func:`_near_circles`). The lines come from the stations'
    ``line``, or for a record without it (a line grid) from ``pos["grid_lines"][name]``
    (``rows`` [first, last + 1)); without either no station is a line end."""
    st = mesh_stations(mesh)
    x = np.asarray(st["x_mm"], float).reshape(-1, 3)
    n = len(x)
    line_end = np.zeros(n, bool)
    spacing = np.full(n, float(pos.get("grid_spacing_mm") or 0.0))
    if "length_mm" in st:
        spacing = np.asarray(st["length_mm"], float)
    line = np.asarray(st.get("line", [-1] * n), int)
    if (line >= 0).any():
        for j in np.unique(line[line >= 0]):
            rows = np.flatnonzero(line == j)
            line_end[[rows[0], rows[-1]]] = True
    else:
        for ln in (pos.get("grid_lines") or {}).get(name, []):
            a, b = ln["rows"]
            if b > a:
                line_end[[a, b - 1]] = True
                spacing[a:b] = ln.get("spacing", spacing[a])
    return line_end, _near_circles(gearset, pos, mesh, x, spacing)


def _bands(gearset, pos: dict, mesh: dict, x: np.ndarray, face_reach=0.0, tip_reach=0.0):
    """(face_band, tip_band) of points x of a mesh: within ``FACE_BAND_MODULES`` normal
    modules (or ``face_reach`` mm, per point, if larger) of a face end of the common face
    width (z from mid face width), within ``TIP_BAND_MODULES`` normal modules (or
    ``tip_reach``) of profile arc of a tip or form circle of either gear (see
    :data:`FACE_BAND_MODULES`)."""
    gears = [gearset.gears[g] for g in mesh["gears"]]
    m_n = max(float(g.normal_module) for g in gears)
    b = min(g.face_width for g in gears)
    face = 0.5 * b - np.abs(x[:, 2]) < np.maximum(FACE_BAND_MODULES * m_n, face_reach)
    reach = np.maximum(TIP_BAND_MODULES * m_n, tip_reach)
    tip = np.zeros(len(x), bool)
    for body, gear_name in zip((mesh["driver"], mesh["driven"]), mesh["gears"], strict=True):
        g = gearset.gears[gear_name]
        sig = _profile_arc(gearset, pos, body, gear_name, x)
        for r_e in (g.tip_radius, g.form_radius):
            sig_e = 0.5 * roll_length(r_e, g.base_radius) ** 2 / g.base_radius
            tip |= np.abs(sig - sig_e) < reach
    return face, tip


def _profile_arc(gearset, pos: dict, body: str, gear_name: str, x: np.ndarray) -> np.ndarray:
    """Arc length along the transverse involute from the base circle, sigma = u^2 / (2 r_b)
    (mm), of points x on the flank of ``body``."""
    g = gearset.gears[gear_name]
    u = roll_length(np.linalg.norm(x[:, :2] - _centre(pos, body), axis=1), g.base_radius)
    return 0.5 * u * u / g.base_radius


def _zone_cell_edges(gearset, pos: dict, mesh: dict) -> tuple[np.ndarray, np.ndarray]:
    """(face_end, tip_form) per cell of a zone grid (module docstring of :func:`edge_points`)."""
    pts, st = mesh["points"], mesh_stations(mesh)
    x = np.asarray(pts["x_mm"], float).reshape(-1, 3)
    seg = np.asarray(st["length_mm"], float)[np.asarray(pts["station"], int)]
    width = np.asarray(pts["area_mm2"], float) / seg  # across the line, along the profile
    # the fixed bands, widened to the end section and the last cell (module docstring)
    face_end, tip_form = _bands(
        gearset, pos, mesh, x, face_reach=seg, tip_reach=EDGE_CELLS * width + EDGE_REACH_MM
    )
    return face_end, tip_form


def edge_points(gearset, pos: dict) -> dict:
    """Per mesh of the position ``pos``, which grid points and stations are edges: ``edge``
    per grid point (with its parts) and ``station_edge`` per station.

    Line grid (one station per point): ``line_end`` (the first and last point of each
    contact line, from the stations' ``line`` or ``pos["grid_lines"][mesh]``; without them,
    older results, no point is a line end) and ``tip_form`` (within one grid spacing, along
    its contact line, of a tip or form circle of either gear, :func:`_near_circles`).

    Zone grid (cells over the whole potential contact zone): ``face_end``, the cells of the
    end sections (within one segment L_s of a face end of the common face width; the zone
    grid is not cut at the path of contact, so a tooth pair's last section elsewhere is no
    edge), and ``tip_form``, the cells whose profile arc sigma = u^2 / (2 r_b) lies within
    ``EDGE_CELLS`` of their own width (along the profile) plus ``EDGE_REACH_MM`` of the
    tip or form circle of either gear: the grid ends 0.02 mm inside those circles and the
    sharp tip of one gear digging into its mate's flank (corner contact, no tip relief)
    loads the cells there.

    Both grids: the fixed edge bands (:func:`_bands`, :data:`FACE_BAND_MODULES`) join
    ``face_end`` (``line_end`` on a line grid) and ``tip_form``, so the interior values are
    read at the same place at every level. ``station_edge``: the stations (sections) that
    are line ends, whose contact-line point lies within one segment of a tip or form circle
    (the line grid's criteria) or within a band; K_Hbeta reads the line loads of the other
    stations; ``station_tip_form`` the tip / form part without the band (the stations a
    flank pattern leaves out, :mod:`postprocess.flank_pattern`)."""
    out = {}
    for name, mesh in pos["meshes"].items():
        st_end, st_tf = _station_edges(gearset, pos, name, mesh)
        x_st = np.asarray(mesh_stations(mesh)["x_mm"], float).reshape(-1, 3)
        st_face, st_tip = _bands(gearset, pos, mesh, x_st)
        if mesh.get("grid_model", "line") == "zone":
            face_end, tip_form = _zone_cell_edges(gearset, pos, mesh)
            out[name] = {"face_end": face_end, "tip_form": tip_form, "edge": face_end | tip_form}
        else:
            end, tf = st_end | st_face, st_tf | st_tip
            out[name] = {"line_end": end, "tip_form": tf, "edge": end | tf}
        out[name].update(station_edge=st_end | st_tf | st_face | st_tip, station_tip_form=st_tf)
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


def _station_interior(mesh: dict, hz: dict, edge: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per station, the largest contact stress of its interior points (0: none) and whether
    its edge points carry load (a line grid's station is one point: never both)."""
    if hz["grid_model"] != "zone":
        return np.where(edge, 0.0, hz["station_p_max"]), np.zeros(len(edge), bool)
    n = len(hz["station_p_max"])
    peak, edge_load = np.zeros(n), np.zeros(n, bool)
    sec = np.asarray(mesh["points"]["station"], int)
    p = np.asarray(hz["p_max"], float)
    np.maximum.at(peak, sec[~edge], p[~edge])
    edge_load[sec[edge & (p > 0)]] = True
    return peak, edge_load


def contact_stress_cycle(gearset, material, positions: list[dict]) -> dict:
    """Per mesh (grid name), the contact stress over the mesh cycle ``positions``:

    * ``grid_model``: "line" or "zone" (:func:`contact_stress_at_points` says what p_max is
      for each: Hertz from the line load on a line grid, the solved cell pressure on a zone
      grid);
    * ``p_max_MPa``: p_max over every grid point of every position;
    * ``interior_p_max_MPa`` (and ``interior_at``: roll, Z, s): over the interior points,
      the contact stress to quote; ``edge_p_max_MPa`` (``edge_at``, ``edge_kind``): over the
      edge points (:func:`edge_points`; on a zone grid the cells at the face ends and at
      the tip and form circles, where the sharp tips give corner contact), an edge-load
      indicator; ``edge_to_interior``;
    * zone grids, the check of the solved pressure against Hertz (None on a line grid,
      whose contact stress is Hertz at the line load): ``interior_hertz_MPa``, Hertz at the
      line load of the section of the interior maximum, and ``interior_to_hertz`` =
      interior_p_max / interior_hertz; ``station_to_hertz_min`` / ``_median`` / ``_max``
      over the ``station_to_hertz_stations`` loaded interior sections (line load above half
      the largest, no load on edge cells: a whole Hertz band) of every position, of their
      largest cell pressure over Hertz at their line load;
    * ``w_max_N_per_mm``, ``w_mean_N_per_mm``: the largest and the mean line load over the
      interior stations of all positions (:func:`edge_points` ``station_edge``; on a line
      grid its points; unloaded stations count as 0: the mean is the load spread over the
      whole contact line length, as ISO's mean load per face width); ``K_Hbeta`` =
      w_max / w_mean (it holds the load sharing between the contact lines too, not only
      the distribution over the face width);
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
        w_in, ratios = [], []
        for j, (pos, h, e) in enumerate(zip(positions, hz, edges, strict=True)):
            p = np.asarray(h[name]["p_max"], float)
            edge = e[name]["edge"]
            w = np.asarray(mesh_stations(pos["meshes"][name])["line_load_N_per_mm"], float)
            inner = ~e[name]["station_edge"]
            w_in.append(np.clip(w[inner], 0.0, None))
            peak, edge_load = _station_interior(pos["meshes"][name], h[name], edge)
            # loaded sections whose load is all on interior points: a Hertz band
            loaded = inner & (w > 0.5 * w.max()) & (peak > 0) & ~edge_load
            ratios.append(peak[loaded] / h[name]["station_hertz_MPa"][loaded])
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
        ratios = np.concatenate(ratios)
        rec = {
            "grid_model": hz[0][name]["grid_model"],
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
        for name_w, w_ in (
            ("w_mean", w_mean),
            ("w_max", w_max),
            ("w_nominal_mean", rec["w_nominal_mean_N_per_mm"]),
        ):
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
            kinds = (("line end", "line_end"), ("face end", "face_end"), ("tip/form", "tip_form"))
            rec["edge_kind"] = " and ".join(k for k, key in kinds if key in e and e[key][i])
        zone = rec["grid_model"] == "zone"  # a line grid's stress is Hertz: no cross-check
        rec["interior_hertz_MPa"], rec["interior_to_hertz"] = None, None
        if zone and best["interior"][1]:
            j, i = best["interior"][1]
            k = int(positions[j]["meshes"][name]["points"].get("station", range(i + 1))[i])
            h_k = float(hz[j][name]["station_hertz_MPa"][k])
            rec["interior_hertz_MPa"] = h_k
            rec["interior_to_hertz"] = rec["interior_p_max_MPa"] / h_k if h_k > 0 else None
        ok = zone and ratios.size > 0
        for stat, f in (("min", np.min), ("median", np.median), ("max", np.max)):
            rec[f"station_to_hertz_{stat}"] = float(f(ratios)) if ok else None
        rec["station_to_hertz_stations"] = int(ratios.size) if zone else None
        ip, ep = rec["interior_p_max_MPa"], rec["edge_p_max_MPa"]
        rec["edge_to_interior"] = ep / ip if ip and ep is not None else None
        out[name] = rec
    return out

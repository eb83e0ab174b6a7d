"""Statics checks of a solved position for any contact normals (line and zone grids), from
the mesh records of postprocess.train_results (``torque_Nm``, ``transmitted_force_N``,
``off_line_N`` per gear of every drive and coast mesh)."""

from itertools import pairwise


def mesh_records(r: dict) -> list[dict]:
    """Every mesh record of a position, drive and coast."""
    return [*r["meshes"].values(), *r.get("coast", {}).values()]


def gear_torque(r: dict, name: str) -> float:
    """The moment of every contact force on gear ``name`` about its axis (N m)."""
    return sum(m["torque_Nm"].get(name, 0.0) for m in mesh_records(r))


def sun_force(r: dict, sun: str = "sun") -> float:
    """F_0 = |T_sun| / (r_b,sun cos(beta_b)): the force the sun's torque transmits (N)."""
    m = next(m for m in r["meshes"].values() if sun in m["torque_Nm"])
    arm = abs(m["torque_Nm"][sun]) / m["transmitted_force_N"][sun]  # r_b cos(beta_b), m
    return abs(gear_torque(r, sun)) / arm


def off_line_share(r: dict, sun: str = "sun") -> float:
    """The statics share of the contact off the line of action: over every mesh m (drive and
    coast), |F_tr,A - F_tr,B| / F_0 (:func:`sun_force`), F_tr = the mesh's torque about that
    gear's axis / (r_b cos(beta_b)) (``transmitted_force_N``, A its driver, B its driven
    gear). 0 (round-off) on a line grid, whose forces all act along the plane of action. It
    bounds the departure from the tooth ratio: with phi the signed torque / (r_b cos(beta_b))
    of a mesh on a gear, each mesh turns its two gears in opposite senses (phi_A + phi_B =
    +-(F_tr,A - F_tr,B)) and each pinion's add up to 0 (spin), so T_ring / r_ring + T_sun /
    r_sun = sum_m (phi_A + phi_B) and |T_ring r_b,sun / (T_sun r_b,ring) + 1| <= this share
    (triangle inequality; attained when every mesh shifts the same way)."""
    f0 = sun_force(r, sun)
    return (
        sum(
            abs(m["transmitted_force_N"][m["driver"]] - m["transmitted_force_N"][m["driven"]])
            for m in mesh_records(r)
        )
        / f0
    )


def chain_bound(r: dict, gears: list[str], k: int) -> float:
    """How far (N) the sum F_k of mesh k (``gears[k]-gears[k+1]``, the gears in power-path
    order from the sun) may lie from F_0 (:func:`sun_force`), the coast flanks open: the sun's
    F_tr is F_0 (its moment equation), each pinion's F_tr is the same at its two meshes (its
    spin equation), within a mesh the two gears' F_tr differ by at most the sum of their
    ``off_line_N`` (the force-weighted departures of the point arms from r_b cos(beta_b)),
    and sum F_k departs from a gear's F_tr by at most that gear's ``off_line_N``:

        |sum F_k - F_0| <= sum_{j<k} (off_j[g_j] + off_j[g_j+1]) + off_k[g_k].

    0 (round-off) on a line grid."""
    assert r.get("coast_force_N", 0.0) == 0.0, "the chain holds with the coast flanks open"
    off = [r["meshes"][f"{a}-{b}"]["off_line_N"] for a, b in pairwise(gears)]
    return sum(off[j][gears[j]] + off[j][gears[j + 1]] for j in range(k)) + off[k][gears[k]]

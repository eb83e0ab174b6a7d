"""A gear scene as a CalculiX (ccx 2.20) input deck, and ccx's results read back.

The peer cross-check (``make bench-peer``, :mod:`studies.peer.driver`) solves the same
tetrahedral meshes with CalculiX. This module knows nothing of gears beyond what it is handed:

* :func:`read_body`: a gmsh ``.msh`` body mesh (its own frame) placed in the scene frame by a
  rigid map; tetrahedra (C3D4) and the named facet groups (``meshing.tags`` names);
* :func:`write_deck`: the ``.inp`` deck: nodes and C3D4 elements of every body, one linear
  elastic material, rigid bores on reference + rotation nodes (``*RIGID BODY``), SPRING1
  elements to ground on the reference / rotation node DOFs (the bearing), ``*BOUNDARY`` and
  ``*CLOAD``, element-face ``*SURFACE`` pairs with linear penalty contact
  (``*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR``), one ``*STATIC`` step;
* :func:`read_dat_displacements`, :func:`read_dat_contact_statistics`,
  :func:`read_frd_block`: the ``.dat`` node print (7 digits), ccx's own totals per contact
  pair (``*CONTACT PRINT`` CF: force, moment, contact area) and the last ``.frd`` result
  block of a given name (``DISP``, ``CONTACT``);
* :func:`nodal_forces`, :func:`flank_resultant`: ccx's contact force distribution, as the
  internal nodal forces K u of the slave body at its flank nodes (the only loaded nodes there),
  reduced to force, moment and centroid; :func:`tet_stress`: the C3D4 stresses.

Why not the ``CPRESS`` of the ``.frd``: for surface-to-surface contact ccx integrates the
penalty pressure at points of the slave-master face overlaps, and its nodal ``CPRESS`` is the
pressure at the penetrated slave nodes. On faceted curved flanks the penetration peaks at the
nodes and vanishes over most of each facet, so ``CPRESS`` times the lumped nodal area is not
the force (it came out 33 times too large at level 0).

A C3D4 face k is the ccx / Abaqus numbering: S1 = (1, 2, 3), S2 = (1, 4, 2), S3 = (2, 4, 3),
S4 = (3, 4, 1). Node and element numbers are 1-based and global over the bodies.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

#: local node triples of the faces S1..S4 of a C3D4 (0-based)
TET_FACES = ((0, 1, 2), (0, 3, 1), (1, 3, 2), (2, 3, 0))


@dataclass
class Body:
    """A tetrahedral body in the scene frame (0-based local numbering)."""

    name: str
    points: np.ndarray  # (n, 3) mm
    tets: np.ndarray  # (m, 4)
    facets: dict[str, np.ndarray]  # tag name -> (k, 3) local node ids
    node0: int = 0  # global number of local node 0 is node0 + 1
    elem0: int = 0
    local: np.ndarray | None = None  # (n, 3) mm, the points in the body's own frame


@dataclass
class Coupling:
    """A surface rigidly slaved to a reference node at ``ref`` (and its rotation node).

    ``fixed``: DOFs (1-6: x, y, z, rx, ry, rz) held at zero; ``springs``: DOF -> stiffness
    (N/mm, N mm/rad) of a spring to ground; ``load``: DOF -> force / moment."""

    name: str
    body: str
    surface: str
    ref: tuple[float, float, float]
    fixed: tuple[int, ...] = ()
    springs: dict[int, float] = field(default_factory=dict)
    load: dict[int, float] = field(default_factory=dict)


@dataclass
class ContactPair:
    """Slave and master facet groups (``(body, [tag names])``) of one contact pair."""

    name: str
    slave: tuple[str, list[str]]
    master: tuple[str, list[str]]


@dataclass
class Deck:
    bodies: list[Body]
    E: float
    nu: float
    couplings: list[Coupling]
    clamps: list[tuple[str, str]]  # (body, surface) held in all three directions
    pairs: list[ContactPair]
    penalty: float  # MPa/mm, slope of pressure against overclosure
    c0: float | None = None  # mm, ccx's clearance at which the s2s pressure vanishes
    contact_type: str = "SURFACE TO SURFACE"
    adjust: float | None = None  # mm, ADJUST of *CONTACT PAIR (node-to-surface only)
    increment: tuple[float, float] = (1.0, 1.0)  # initial, total step time
    #: (coupling, DOF, value): a first step that prescribes this motion with no load, so
    #: that the contact is closed when the load step starts (see :func:`write_deck`)
    preload: tuple[str, int, float] | None = None


def read_body(name: str, msh_path, placement=None) -> Body:
    """The tetrahedra and named facet groups of a gmsh ``.msh``, placed by ``placement``
    (an object with ``apply((n, 3)) -> (n, 3)``, or None: as read). Nodes that no
    tetrahedron uses are dropped."""
    import meshio

    m = meshio.read(str(msh_path))
    phys = m.cell_data.get("gmsh:physical")
    names = {int(v[0]): nm for nm, v in m.field_data.items() if int(v[1]) == 2}
    tets, tris = [], {}
    for i, block in enumerate(m.cells):
        if block.type == "tetra":
            tets.append(block.data)
        elif block.type == "triangle" and phys is not None:
            for tag in np.unique(phys[i]):
                nm = names.get(int(tag))
                if nm is not None:
                    sel = block.data[phys[i] == tag]
                    tris[nm] = np.vstack([tris[nm], sel]) if nm in tris else sel
    if not tets:
        raise ValueError(f"{msh_path}: no tetrahedra (C3D4) in the mesh")
    tet = np.vstack(tets).astype(np.int64)
    used = np.unique(tet)
    new = -np.ones(len(m.points), np.int64)
    new[used] = np.arange(len(used))
    local = np.asarray(m.points[used], float)
    pts = local if placement is None else placement.apply(local)
    facets = {nm: new[t] for nm, t in tris.items()}
    return Body(name, pts, new[tet], facets, local=local)


def number(bodies: list[Body]) -> int:
    """Set the global node / element offsets; returns the number of FE nodes."""
    n = e = 0
    for b in bodies:
        b.node0, b.elem0 = n, e
        n += len(b.points)
        e += len(b.tets)
    return n


def element_faces(body: Body, facets: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(global element numbers, face numbers 1-4) of the tetrahedron faces that are the
    triangles ``facets`` (local ids); raises if a triangle is not a tetrahedron face."""
    n = len(body.points)
    faces = np.sort(body.tets[:, TET_FACES], axis=2)  # (m, 4, 3)
    keys = (faces[..., 0] * n + faces[..., 1]) * n + faces[..., 2]
    flat = keys.ravel()
    order = np.argsort(flat)
    f = np.sort(facets, axis=1)
    want = (f[:, 0] * n + f[:, 1]) * n + f[:, 2]
    pos = np.searchsorted(flat, want, sorter=order)
    pos = np.minimum(pos, len(flat) - 1)
    hit = order[pos]
    if not np.all(flat[hit] == want):
        raise ValueError(
            f"{body.name}: {np.count_nonzero(flat[hit] != want)} facets are no tet face"
        )
    return body.elem0 + hit // 4 + 1, hit % 4 + 1


def _lines(values, per_line: int = 8) -> list[str]:
    v = [str(int(x)) for x in values]
    return [", ".join(v[i : i + per_line]) for i in range(0, len(v), per_line)]


def write_deck(path, deck: Deck) -> dict:
    """Write the ``.inp`` file; returns the numbering (``ref_nodes``: coupling name ->
    (reference node, rotation node); ``surfaces``: pair -> (slave, master) surface names)."""
    bodies = {b.name: b for b in deck.bodies}
    nfe = number(deck.bodies)
    out: list[str] = ["*HEADING", "planetary-fe peer cross-check (studies.peer.ccx)", "*NODE"]
    for b in deck.bodies:
        ids = np.arange(len(b.points)) + b.node0 + 1
        out += [
            f"{i}, {x:.9g}, {y:.9g}, {z:.9g}" for i, (x, y, z) in zip(ids, b.points, strict=True)
        ]
    refs: dict[str, tuple[int, int]] = {}
    extra = nfe
    for c in deck.couplings:
        r, rr = extra + 1, extra + 2
        extra += 2
        refs[c.name] = (r, rr)
        out.append(f"{r}, {c.ref[0]:.9g}, {c.ref[1]:.9g}, {c.ref[2]:.9g}")
        out.append(f"{rr}, {c.ref[0]:.9g}, {c.ref[1]:.9g}, {c.ref[2]:.9g}")
    for b in deck.bodies:
        out.append(f"*ELEMENT, TYPE=C3D4, ELSET=E_{b.name.upper()}")
        ids = np.arange(len(b.tets)) + b.elem0 + 1
        conn = b.tets + b.node0 + 1
        out += [f"{i}, {a}, {bb}, {c}, {d}" for i, (a, bb, c, d) in zip(ids, conn, strict=True)]
    eid = sum(len(b.tets) for b in deck.bodies)
    spring_sets: list[tuple[str, int, float]] = []
    for c in deck.couplings:
        r, rr = refs[c.name]
        for dof, k in sorted(c.springs.items()):
            eid += 1
            es = f"SPR_{c.name.upper()}_{dof}"
            node = r if dof <= 3 else rr
            out += [f"*ELEMENT, TYPE=SPRING1, ELSET={es}", f"{eid}, {node}"]
            spring_sets.append((es, (dof - 1) % 3 + 1, k))
    for c in deck.couplings:
        b = bodies[c.body]
        nodes = np.unique(b.facets[c.surface]) + b.node0 + 1
        out.append(f"*NSET, NSET=N_{c.name.upper()}")
        out += _lines(nodes)
    for body, surf in deck.clamps:
        b = bodies[body]
        out.append(f"*NSET, NSET=CLAMP_{body.upper()}")
        out += _lines(np.unique(b.facets[surf]) + b.node0 + 1)
    for b in deck.bodies:
        out.append(f"*NSET, NSET=ALL_{b.name.upper()}, GENERATE")
        out.append(f"{b.node0 + 1}, {b.node0 + len(b.points)}, 1")
    out.append("*NSET, NSET=REFS")
    out += _lines([n for pair in refs.values() for n in pair])
    surfaces = {}
    for p in deck.pairs:
        names = []
        for role, (body, tags) in (("S", p.slave), ("M", p.master)):
            b = bodies[body]
            tri = np.vstack([b.facets[t] for t in tags])
            el, fc = element_faces(b, tri)
            sn = f"{p.name.upper()}_{role}"
            out.append(f"*SURFACE, NAME={sn}, TYPE=ELEMENT")
            out += [f"{e}, S{f}" for e, f in zip(el, fc, strict=True)]
            names.append(sn)
        surfaces[p.name] = tuple(names)
    out += ["*MATERIAL, NAME=STEEL", "*ELASTIC", f"{deck.E:.9g}, {deck.nu:.9g}"]
    for b in deck.bodies:
        out.append(f"*SOLID SECTION, ELSET=E_{b.name.upper()}, MATERIAL=STEEL")
    for es, dof, k in spring_sets:
        # a real with a decimal point: ccx tells the DOF line from the stiffness line by it
        out += [f"*SPRING, ELSET={es}", f"{dof}", f"{float(k):.10e}"]
    for c in deck.couplings:
        r, rr = refs[c.name]
        out.append(f"*RIGID BODY, NSET=N_{c.name.upper()}, REF NODE={r}, ROT NODE={rr}")
    out.append("*SURFACE INTERACTION, NAME=FLANKS")
    out.append("*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR")
    out.append(f"{deck.penalty:.9g}" + ("" if deck.c0 is None else f", , {deck.c0:.9g}"))
    for p in deck.pairs:
        s, m = surfaces[p.name]
        opt = "" if deck.adjust is None else f", ADJUST={deck.adjust:.9g}"
        if deck.contact_type == "NODE TO SURFACE":  # ccx 2.20: small sliding only there
            opt += ", SMALL SLIDING"
        out.append(f"*CONTACT PAIR, INTERACTION=FLANKS, TYPE={deck.contact_type}{opt}")
        out.append(f"{s}, {m}")

    def fixed(op: str = "") -> list[str]:
        lines = [f"*BOUNDARY{op}"] + [f"CLAMP_{body.upper()}, 1, 3" for body, _ in deck.clamps]
        for c in deck.couplings:
            r, rr = refs[c.name]
            for dof in c.fixed:
                d = (dof - 1) % 3 + 1
                lines.append(f"{r if dof <= 3 else rr}, {d}, {d}")
        return lines

    inc, total = deck.increment
    static = ["*STATIC", f"{inc:.9g}, {total:.9g}, {1e-5 * total:.9g}, {total:.9g}"]
    if deck.preload is not None:
        # Step 1 closes the contact by a prescribed motion (no load): with a load alone, the
        # first Newton iterate of a torque-driven body held only by open contact is a
        # rotation of torque / (stabilising spring), far outside small displacements.
        name, dof, value = deck.preload
        r, rr = refs[name]
        d = (dof - 1) % 3 + 1
        out += [*fixed(), "*STEP, INC=1000", *static, "*BOUNDARY"]
        out.append(f"{r if dof <= 3 else rr}, {d}, {d}, {value:.9e}")
        out += ["*END STEP", "*STEP, INC=1000", *static, *fixed(", OP=NEW")]
    else:
        out += [*fixed(), "*STEP, INC=1000", *static]
    loads = [(c, dof, v) for c in deck.couplings for dof, v in sorted(c.load.items())]
    if loads:
        out.append("*CLOAD")
        for c, dof, v in loads:
            r, rr = refs[c.name]
            out.append(f"{r if dof <= 3 else rr}, {(dof - 1) % 3 + 1}, {v:.9e}")
    # the nodes' displacements at 7 digits (the .frd has 5: too few for K u at the flanks)
    out += ["*NODE PRINT, NSET=REFS", "U"]
    out += [line for b in deck.bodies for line in (f"*NODE PRINT, NSET=ALL_{b.name.upper()}", "U")]
    out += ["*NODE FILE", "U", "*CONTACT FILE", "CSTR, CDIS"]
    for p in deck.pairs:  # ccx finds the pair by its surfaces: without them "no existing pair"
        s, m = surfaces[p.name]
        out += [f"*CONTACT PRINT, SLAVE={s}, MASTER={m}", "CF"]
    out += ["*END STEP"]
    Path(path).write_text("\n".join(out) + "\n")
    return {"ref_nodes": refs, "surfaces": surfaces, "fe_nodes": nfe}


_DISP = re.compile(r"^\s*displacements \(vx,vy,vz\) for set (\S+) and time\s+(\S+)")
_STATS = re.compile(r"^\s*statistics for slave set (\S+), master set (\S+) and time\s+(\S+)")


def read_dat_displacements(path) -> dict[int, np.ndarray]:
    """Node -> (3,) displacement at the last time of a ``.dat`` file (``*NODE PRINT`` U; the
    blocks of every node set printed at that time, merged)."""
    by_time: dict[float, dict[int, np.ndarray]] = {}
    cur: dict[int, np.ndarray] | None = None
    for line in Path(path).read_text().splitlines():
        m = _DISP.match(line)
        if m:
            cur = by_time.setdefault(float(m.group(2)), {})
            continue
        parts = line.split()
        if cur is None or not parts:
            continue
        if len(parts) == 4 and parts[0].isdigit():
            cur[int(parts[0])] = np.array([float(v) for v in parts[1:]])
        else:
            cur = None
    return by_time[max(by_time)] if by_time else {}


#: the rows of a ``*CONTACT PRINT`` CF block of ccx 2.20 (printed after its header)
_STATS_ROWS = (
    ("force_N", 0, 3),
    ("moment_origin_Nmm", 3, 6),  # total surface force, moment about 0
    ("centre_mm", 6, 9),
    ("mean_normal", 9, 12),  # centre of the contact area, mean normal
    ("moment_centre_Nmm", 12, 15),  # moment about that centre
    ("area_mm2", 15, 16),
    ("normal_force_N", 16, 17),
    ("shear_force_N", 17, 18),
)


def read_dat_contact_statistics(path) -> dict[tuple[str, str], dict]:
    """(slave, master) surface -> ccx's pair totals (``*CONTACT PRINT`` CF) at the last time:
    force and moment about the origin (on the slave), the centre and area of the contact
    area, its mean normal, and the normal (+ = tension) and shear force sizes; keys
    :data:`_STATS_ROWS`."""
    lines = Path(path).read_text().splitlines()
    found: dict[tuple[str, str], tuple[float, dict]] = {}
    for i, line in enumerate(lines):
        m = _STATS.match(line)
        if not m:
            continue
        nums: list[float] = []
        for nxt in lines[i + 1 :]:
            if _STATS.match(nxt) or _DISP.match(nxt) or len(nums) >= 18:
                break
            if re.search(r"[a-df-z]", nxt.lower().replace("nan", "")):
                continue  # a row title
            nums += [float(v) for v in nxt.split()]
        if len(nums) < 18:
            raise ValueError(f"{path}: contact statistics of {m.group(1)} cut short")
        rec = {k: (nums[a] if b == a + 1 else nums[a:b]) for k, a, b in _STATS_ROWS}
        t = float(m.group(3))
        key = (m.group(1), m.group(2))
        if key not in found or t >= found[key][0]:
            found[key] = (t, rec)
    return {k: v[1] for k, v in found.items()}


def read_frd_block(path, name: str) -> tuple[list[str], dict[int, np.ndarray]]:
    """(component names, node -> values) of the last result block ``name`` (e.g. ``DISP``,
    ``CONTACT``) of a ``.frd`` file (ASCII; fixed columns: `` -1`` + I10 node + E12.5)."""
    comps: list[str] = []
    data: dict[int, np.ndarray] = {}
    found = False
    cur_comps: list[str] = []
    cur: dict[int, np.ndarray] | None = None
    with open(path) as fh:
        for line in fh:
            if line.startswith(" -4"):
                cur = {} if line.split()[1] == name else None
                cur_comps = []
                continue
            if cur is None:
                continue
            if line.startswith(" -5"):
                cur_comps.append(line.split()[1])
            elif line.startswith(" -1"):
                body = line[13:].rstrip("\n")
                vals = [float(body[i : i + 12]) for i in range(0, len(body) - 11, 12)]
                cur[int(line[3:13])] = np.array(vals)
            elif line.startswith(" -3"):
                comps, data, found = cur_comps, cur, True
                cur = None
    if not found:
        raise ValueError(f"{path}: no result block {name!r}")
    return comps, data


def nodal_areas(points: np.ndarray, tris: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(node ids, lumped areas, area-weighted unit normals (k, 3)) of a triangle set: each
    triangle gives a third of its area to each vertex."""
    a, b, c = (points[tris[:, i]] for i in range(3))
    cr = 0.5 * np.cross(b - a, c - a)
    area = np.linalg.norm(cr, axis=1)
    nodes, inv = np.unique(tris, return_inverse=True)
    inv = inv.reshape(tris.shape)
    lump = np.zeros(len(nodes))
    nrm = np.zeros((len(nodes), 3))
    for i in range(3):
        np.add.at(lump, inv[:, i], area / 3.0)
        np.add.at(nrm, inv[:, i], cr)
    nrm /= np.maximum(np.linalg.norm(nrm, axis=1, keepdims=True), 1e-300)
    return nodes, lump, nrm


def tet_gradients(points: np.ndarray, tets: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(gradients (m, 4, 3) of the four linear shape functions, volumes (m,)) of C3D4s."""
    x = points[tets]
    J = np.stack([x[:, 1] - x[:, 0], x[:, 2] - x[:, 0], x[:, 3] - x[:, 0]], axis=1)
    dN = np.array([[-1.0, -1.0, -1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    return np.einsum("mij,aj->mai", np.linalg.inv(J), dN), np.abs(np.linalg.det(J)) / 6.0


def tet_stress(points, tets, u, E: float, nu: float) -> np.ndarray:
    """Constant stress (m, 3, 3) of C3D4s: sigma = lambda tr(eps) I + 2 mu eps, eps = sym grad
    u (MPa for mm, N)."""
    G, _ = tet_gradients(points, tets)
    H = np.einsum("mai,maj->mij", np.asarray(u, float)[tets], G)
    eps = 0.5 * (H + H.transpose(0, 2, 1))
    lam, mu = E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))
    return 2 * mu * eps + lam * np.trace(eps, axis1=1, axis2=2)[:, None, None] * np.eye(3)


def nodal_forces(points, tets, u, E: float, nu: float) -> np.ndarray:
    """Internal nodal forces K u (n, 3) of a C3D4 body, f_a = sum_e V_e sigma_e grad N_a. At a
    node with no other load they are the contact force on the body there (equilibrium)."""
    G, V = tet_gradients(points, tets)
    fe = np.einsum("mij,maj->mai", tet_stress(points, tets, u, E, nu), G) * V[:, None, None]
    f = np.zeros((len(points), 3))
    np.add.at(f, tets.reshape(-1), fe.reshape(-1, 3))
    return f


def outward(body: Body, facets: np.ndarray) -> np.ndarray:
    """The triangles ``facets`` (local ids) wound so that their normals point out of the body
    (away from the fourth vertex of the tetrahedron they bound)."""
    el, fc = element_faces(body, facets)
    tet = body.tets[el - body.elem0 - 1]
    missing = 6 - np.asarray(TET_FACES).sum(axis=1)  # the vertex face S_k does not hold
    fourth = body.points[tet[np.arange(len(tet)), missing[fc - 1]]]
    a, b, c = (body.points[facets[:, i]] for i in range(3))
    inward = (np.cross(b - a, c - a) * (fourth - a)).sum(axis=1) > 0
    out = facets.copy()
    out[inward] = out[inward][:, ::-1]
    return out


def flank_resultant(body: Body, tags: list[str], f: np.ndarray, centre) -> dict:
    """Contact resultant on ``body`` over the facet groups ``tags`` from its nodal forces ``f``
    (n, 3; :func:`nodal_forces`, body-local rows): force, normal force sum_k -f_k . n_k (n_k
    the outward nodal normal), moment about ``centre`` (N mm), normal-force-weighted centroid
    (scene frame) and the number of nodes carrying more than 1e-3 of the largest force."""
    tri = outward(body, np.vstack([body.facets[t] for t in tags]))
    nodes, _, nrm = nodal_areas(body.points, tri)
    fk, x = f[nodes], body.points[nodes]
    fn = -(fk * nrm).sum(axis=1)
    tot = float(fn.sum())
    rel = x - np.asarray(centre, float)
    return {
        "force_N": fk.sum(axis=0).tolist(),
        "normal_force_N": tot,
        "moment_Nmm": np.cross(rel, fk).sum(axis=0).tolist(),
        "centroid_mm": ((fn @ x) / tot).tolist() if tot > 0 else None,
        "nodes_loaded": int(np.count_nonzero(fn > 1e-3 * max(fn.max(initial=0.0), 1e-30))),
        "nodes": len(nodes),
    }


def facet_sag(body: Body, tags: list[str]) -> np.ndarray:
    """Per triangle of the facet groups ``tags``: the largest chord sag of its edges (mm), the
    distance by which the flat facet falls short of the curved surface its vertices lie on,
    |d^T H d| / 8 for an edge d, H the Hessian of a quadratic height field h(s, t) fitted (least
    squares) in the facet's tangent plane to the group's nodes within two longest edges."""
    tri = np.vstack([body.facets[t] for t in tags])
    nodes = np.unique(tri)
    xn = body.points[nodes]
    out = np.empty(len(tri))
    for k, t in enumerate(tri):
        x = body.points[t]
        e = np.roll(x, -1, axis=0) - x  # the three edges
        n = np.cross(e[0], -e[2])
        n /= np.linalg.norm(n)
        s_ax = e[0] / np.linalg.norm(e[0])
        t_ax = np.cross(n, s_ax)
        rel = xn - x.mean(axis=0)
        near = (rel**2).sum(axis=1) <= (2.0 * np.linalg.norm(e, axis=1).max()) ** 2
        s, tt, h = rel[near] @ s_ax, rel[near] @ t_ax, rel[near] @ n
        A = np.c_[np.ones_like(s), s, tt, s * s, s * tt, tt * tt]
        if len(s) < 8:
            out[k] = np.nan
            continue
        c = np.linalg.lstsq(A, h, rcond=None)[0]
        H = np.array([[2 * c[3], c[4]], [c[4], 2 * c[5]]])
        d = np.c_[e @ s_ax, e @ t_ax]
        out[k] = float(np.abs(np.einsum("ei,ij,ej->e", d, H, d)).max() / 8.0)
    return out

"""A gear scene as a CalculiX (ccx 2.20) input deck, and ccx's results read back.

The peer cross-check (``make bench-peer``, :mod:`studies.bench_peer`) solves the same
tetrahedral meshes with CalculiX. This module knows nothing of gears beyond what it is handed:

* :func:`read_body`: a gmsh ``.msh`` body mesh (its own frame) placed in the scene frame by a
  rigid map; tetrahedra (C3D4) and the named facet groups (``meshing.tags`` names);
* :func:`write_deck`: the ``.inp`` deck: nodes and C3D4 elements of every body, one linear
  elastic material, rigid bores on reference + rotation nodes (``*RIGID BODY``), SPRING1
  elements to ground on the reference / rotation node DOFs (the bearing), ``*BOUNDARY`` and
  ``*CLOAD``, element-face ``*SURFACE`` pairs with linear penalty contact
  (``*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR``), one ``*STATIC`` step;
* :func:`read_dat_displacements`, :func:`read_frd_block`: the ``.dat`` node print and the
  last ``.frd`` result block of a given name (``DISP``, ``CONTACT``);
* :func:`contact_resultant`: force, moment and axial centroid of a slave surface from its
  nodal contact pressures (``CPRESS``) and lumped facet areas.

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
    pts = np.asarray(m.points[used], float)
    if placement is not None:
        pts = placement.apply(pts)
    facets = {nm: new[t] for nm, t in tris.items()}
    return Body(name, pts, new[tet], facets)


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
    out: list[str] = ["*HEADING", "planetary-fe peer cross-check (postprocess.peer_ccx)", "*NODE"]
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
    out += ["*NODE PRINT, NSET=REFS", "U", "*NODE FILE", "U", "*CONTACT FILE", "CSTR, CDIS"]
    out += ["*END STEP"]  # *CONTACT PRINT, CF: refused by ccx 2.20 here ("no existing pair")
    Path(path).write_text("\n".join(out) + "\n")
    return {"ref_nodes": refs, "surfaces": surfaces, "fe_nodes": nfe}


_FLOAT = r"[-+]?\d*\.?\d+(?:[eE][-+]?\d+)?"


def read_dat_displacements(path) -> dict[int, np.ndarray]:
    """Node -> (3,) displacement of the last ``displacements`` block of a ``.dat`` file."""
    last: dict[int, np.ndarray] = {}
    cur: dict[int, np.ndarray] | None = None
    for line in Path(path).read_text().splitlines():
        s = line.strip()
        if s.startswith("displacements"):
            cur = {}
            last = cur
            continue
        if cur is None or not s:
            continue
        parts = s.split()
        if len(parts) == 4 and re.fullmatch(r"\d+", parts[0]):
            cur[int(parts[0])] = np.array([float(v) for v in parts[1:]])
        elif cur:
            cur = None
    return last


def read_dat_contact_forces(path) -> list[dict]:
    """The ``*CONTACT PRINT, CF`` blocks of the last increment: per block the header and the
    numbers that follow it (force and moment about the origin, as ccx prints them)."""
    blocks: list[dict] = []
    lines = Path(path).read_text().splitlines()
    for i, line in enumerate(lines):
        if "contact force" in line.lower() or "total surface force" in line.lower():
            nums = []
            for nxt in lines[i + 1 : i + 4]:
                nums += [float(v) for v in re.findall(_FLOAT, nxt)]
            blocks.append({"header": line.strip(), "values": nums})
    return blocks


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


def contact_resultant(body: Body, tags: list[str], pressure: dict[int, float], centre) -> dict:
    """Force (N, on ``body``: pressure pushes against the outward normal), moment about
    ``centre`` (N mm), force-weighted z centroid and peak pressure of the nodal contact
    pressures ``pressure`` (global node -> MPa) over the facet groups ``tags`` of ``body``."""
    tri = np.vstack([body.facets[t] for t in tags])
    nodes, area, nrm = nodal_areas(body.points, tri)
    p = np.array([pressure.get(int(n) + body.node0 + 1, 0.0) for n in nodes])
    p = np.maximum(p, 0.0)
    f = -(p * area)[:, None] * nrm
    x = body.points[nodes]
    fn = p * area
    tot = float(fn.sum())
    rel = x - np.asarray(centre, float)
    return {
        "force_N": f.sum(axis=0).tolist(),
        "normal_force_N": tot,
        "moment_Nmm": np.cross(rel, f).sum(axis=0).tolist(),
        "z_centroid_mm": float((fn * x[:, 2]).sum() / tot) if tot > 0 else float("nan"),
        "peak_pressure_MPa": float(p.max()) if len(p) else 0.0,
        "nodes_in_contact": int(np.count_nonzero(p > 0)),
        "nodes": len(nodes),
    }

"""Peer cross-check: one mesh position of a study case solved by us and by CalculiX on the same
tetrahedral meshes, side by side (``make bench-peer``).

For each case and level: our solve (:func:`studies.position.solve_position`, serial, in a
child process so its wall time and peak memory are its own), then the same scene written as a
CalculiX deck (:mod:`postprocess.peer_ccx`: the cached body meshes placed in the scene frame,
C3D4, same material, rigid bores on reference nodes with the bearing springs, the sun torque,
the ring rim clamped, linear penalty contact on the drive and coast flank facets of the teeth
in mesh), run by ``ccx`` (one thread), read back and reduced to the paper's quantities with
our own functions (:func:`gears.analytic.single_pinion.loa_moments`). Writes
``<out>/peer.json`` and ``<out>/peer.md``.

CalculiX needs two things our model does not: a small torsional spring on the sun rotation
and on the pinion spin (``--k-stab``, N mm/rad; ccx has no rigid-unknown elimination and its
first iteration, with the contact still open, would be singular). Their moments are reported
(the share of the torque they take) so that their effect on the answer is visible.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

MOMENTS = ("Mx_pin", "My_pin", "M_LOA_sun", "M_LOA_ring")
CENTROIDS = ("ZS", "ZR")
#: sun rotation (rad) prescribed in ccx's first step to close the contact before the torque
#: step (about a third of the 1-GA rotation at level 0: any value that closes it will do)
PRELOAD_ROTATION = 5.0e-4


def run_measured(cmd: list[str], cwd=None, env=None, log=None) -> dict:
    """Run ``cmd``; its wall time (s), peak resident memory (MB, the child's own
    ``ru_maxrss`` from ``os.wait4``), user + system CPU time and exit code."""
    t0 = time.perf_counter()
    with open(log or os.devnull, "w") as fh:
        proc = subprocess.Popen(cmd, cwd=cwd, env=env, stdout=fh, stderr=subprocess.STDOUT)
        _, status, ru = os.wait4(proc.pid, 0)
    proc.returncode = os.waitstatus_to_exitcode(status)
    return {
        "wall_s": time.perf_counter() - t0,
        "peak_rss_MB": ru.ru_maxrss / 1024.0,
        "cpu_s": ru.ru_utime + ru.ru_stime,
        "returncode": proc.returncode,
    }


# --------------------------------------------------------------------------- ours (child)


def ours(case: str, level: int, roll: float, path: Path) -> None:
    """Our solve of one position, reduced to what the comparison needs (run in a child)."""
    import dolfinx_solver  # noqa: F401  (before dolfinx)
    from mpi4py import MPI

    from cases.study_case import load_study_case
    from postprocess.mesh_stress import contact_stress_at_points
    from studies.position import solve_position

    study = load_study_case(case)
    t0 = time.perf_counter()
    pos = solve_position(study, roll, MPI.COMM_SELF, level=level)
    wall = time.perf_counter() - t0
    hz = contact_stress_at_points(study.gearset, study.material, pos)
    (pname,) = list(pos["pinions"])
    out = {k: pos[k] for k in (*MOMENTS, *CENTROIDS)}
    out["Mx_pin"], out["My_pin"] = pos["Mx_pin"], pos["My_pin"]
    out.update(
        pinion=pname,
        dofs=pos["dofs"],
        solve_position_wall_s=wall,
        timings=pos["timings"],
        mesh_normal_force_N={k: m["normal_force_N"] for k, m in pos["meshes"].items()},
        coast_force_N={k: c["normal_force_N"] for k, c in (pos.get("coast") or {}).items()},
        peak_hertz_MPa=float(max(v["p_max"].max() for v in hz.values())),
        peak_line_load_N_per_mm=float(
            max(max(m["points"]["line_load_N_per_mm"]) for m in pos["meshes"].values())
        ),
        pinion_force_N=pos["pinions"][pname]["force_N"],
        tilt_rad=pos["pinions"][pname]["tilt_rad"],
    )
    path.write_text(json.dumps(out, indent=1, default=float))


# --------------------------------------------------------------------------- CalculiX


def build_deck(case: str, level: int, roll: float, penalty_factor: float, k_stab: float):
    """The CalculiX deck of the study's scene at ``roll`` and what reading it back needs."""
    from cases.study_case import load_study_case
    from meshing import sizing
    from meshing.body_cache import body_mesh_file
    from meshing.mesh_zones import coast_zone
    from meshing.scenes import build_scene
    from postprocess import peer_ccx as P
    from solvers.gear_train import bearing_stiffness, sun_torque

    study = load_study_case(case)
    scene = build_scene(study.model.scene, study.gearset, roll)
    if len(scene.pinion_names) != 1:
        raise SystemExit(f"error: {case}: the peer check handles single-pinion scenes only")
    bodies = []
    for g in scene.gears:
        path, _ = body_mesh_file(g.body, level, g.active_teeth)
        bodies.append(P.read_body(g.name, path, g.placement))
    by = {b.name: b for b in bodies}
    sun, ring = scene.sun_name, scene.ring_name
    (pin,) = scene.pinion_names
    centre = (*scene.gear(pin).placement.centre, 0.0)
    k = bearing_stiffness(study.bearing)
    torque = sun_torque(study.gearset, scene.branches)
    couplings = [
        P.Coupling("sun", sun, f"{sun}/bore", (0.0, 0.0, 0.0), fixed=(1, 2, 3, 4, 5),
                   springs={6: k_stab}, load={6: torque}),
        P.Coupling("pin", pin, f"{pin}/bore", centre,
                   springs={1: k[0], 2: k[1], 3: k[2], 4: k[3], 5: k[4], 6: k_stab}),
    ]  # fmt: skip
    pairs, flank_tags = [], {}
    for zn in scene.zones:
        drv, dvn = scene.gear(zn.driver), scene.gear(zn.driven)
        for kind, z in (("drive", zn), ("coast", coast_zone(zn, drv, dvn))):
            a = sorted({f"{zn.driver}/tooth{i:02d}/flank_{z.driver_side}"
                        for i, _, _ in z.contact_lines})  # fmt: skip
            b = sorted({f"{zn.driven}/tooth{j:02d}/flank_{z.driven_side}"
                        for _, j, _ in z.contact_lines})  # fmt: skip
            a = [t for t in a if t in by[zn.driver].facets]
            b = [t for t in b if t in by[zn.driven].facets]
            if not a or not b:
                continue
            # the pinion is the slave in both meshes: its pressures give its contact moment
            sl, ms = (
                ((zn.driven, b), (zn.driver, a))
                if zn.driven == pin
                else ((zn.driver, a), (zn.driven, b))
            )
            name = f"{zn.driver}-{zn.driven}" + ("" if kind == "drive" else "/coast")
            pairs.append(P.ContactPair(name.replace("/", "_").replace("-", "_"), sl, ms))
            flank_tags[name] = sl
    E = study.material.gear_youngs_modulus
    nu = study.material.poisson_ratio
    h = sizing.check_level(level).fine
    e_star = E / (2.0 * (1.0 - nu**2))
    penalty = penalty_factor * e_star / h
    deck = P.Deck(bodies, E, nu, couplings, [(ring, f"{ring}/rim")], pairs, penalty=penalty,
                  preload=("sun", 6, PRELOAD_ROTATION))  # fmt: skip
    return study, scene, deck, flank_tags, centre


def ccx_reduce(study, scene, deck, info, flank_tags, centre, job: Path) -> dict:
    """CalculiX's answer reduced to the paper's quantities (bearing springs, contact
    pressures)."""
    from gears.analytic import single_pinion as sp
    from gears.analytic.planetary import single_pinion_geometry
    from postprocess import peer_ccx as P
    from solvers.gear_train import bearing_stiffness, pinion_frame

    (pin,) = scene.pinion_names
    u = P.read_dat_displacements(job.with_suffix(".dat"))
    r, rr = info["ref_nodes"]["pin"]
    _, rrs = info["ref_nodes"]["sun"]
    q = np.concatenate([u[r], u[rr]])
    k = bearing_stiffness(study.bearing)
    kq = k * q  # bearing load on the pin, scene axes (spin free: 0)
    Q = pinion_frame(centre)
    m_spring = Q @ kq[3:] / 1000.0
    out = {"Mx_pin": float(m_spring[0]), "My_pin": float(m_spring[1])}
    geo = single_pinion_geometry(study.gearset.planetary_input())
    out["M_LOA_sun"], out["M_LOA_ring"] = sp.loa_moments(out["Mx_pin"], out["My_pin"],
                                                          geo.alpha1, geo.alpha2)  # fmt: skip
    out["tilt_rad"] = (Q @ np.array([q[3], q[4], 0.0])).tolist()
    out["pinion_spring_force_N"] = (Q @ kq[:3]).tolist()
    out["sun_rotation_rad"] = float(u[rrs][2])
    out["pinion_spin_rad"] = float(q[5])
    torque = deck.couplings[0].load[6]
    out["stab_share_of_torque"] = {
        "sun": float(deck.couplings[0].springs[6] * u[rrs][2] / torque),
        "pinion": float(deck.couplings[1].springs[6] * q[5] / torque),
    }
    comps, data = P.read_frd_block(job.with_suffix(".frd"), "CONTACT")
    ip = comps.index("CPRESS")
    pressure = {n: float(v[ip]) for n, v in data.items()}
    by = {b.name: b for b in deck.bodies}
    meshes = {}
    m_contact = np.zeros(3)
    for name, (body, tags) in flank_tags.items():
        res = P.contact_resultant(by[body], tags, pressure, centre)
        meshes[name] = res
        m_contact += np.asarray(res["moment_Nmm"])
    out["meshes"] = meshes
    out["contact_moment_pinion_Nm"] = (Q @ m_contact / 1000.0).tolist()
    sun, ring = scene.sun_name, scene.ring_name
    for key, mesh in (("ZS", f"{sun}-{pin}"), ("ZR", f"{pin}-{ring}")):
        out[key] = -meshes[mesh]["z_centroid_mm"]  # Z = -z (pinion frame), centre at z = 0
    out["peak_pressure_MPa"] = max(m["peak_pressure_MPa"] for m in meshes.values())
    out["cf_print"] = P.read_dat_contact_forces(job.with_suffix(".dat"))
    return out


def ensure_ccx() -> str:
    exe = shutil.which("ccx")
    if exe is None:
        raise SystemExit(
            "error: ccx (CalculiX) not found on PATH; install it (Debian/Ubuntu: "
            "apt-get install -y calculix-ccx) or run `make bench-peer` as root"
        )
    return exe


# --------------------------------------------------------------------------- report


def rel(a: float, b: float) -> float:
    return (a - b) / abs(b) if b else float("nan")


def write_report(rows: list[dict], out: Path, notes: dict) -> None:
    (out / "peer.json").write_text(json.dumps({"notes": notes, "runs": rows}, indent=1,
                                              default=float))  # fmt: skip
    md = ["# Peer cross-check: our contact solver against CalculiX on the same meshes", ""]
    md += [f"- {k}: {v}" for k, v in notes.items()]
    for r in rows:
        o, c = r["ours"], r["ccx"]
        md += ["", f"## {r['case']}, level {r['level']}, roll {r['roll']:.4f} rad", ""]
        if "error" in c:
            md += [f"CalculiX failed: {c['error']}", ""]
            continue
        md += ["| quantity | ours | CalculiX | ours / ccx - 1 |", "|---|---|---|---|"]
        for key, unit in [(m, "N m") for m in MOMENTS] + [(z, "mm") for z in CENTROIDS]:
            d = o[key] - c[key]
            rd = rel(o[key], c[key])
            dtxt = f"{rd * 100:+.2f} %" if unit == "N m" else f"{d:+.3f} mm (abs)"
            flag = " **>2 %**" if unit == "N m" and abs(rd) > 0.02 else ""
            md.append(f"| {key} ({unit}) | {o[key]:.3f} | {c[key]:.3f} | {dtxt}{flag} |")
        dmx = (o["Mx_pin"] - c["Mx_pin"]) / math.hypot(c["Mx_pin"], c["My_pin"])
        md.append(f"| Mx_pin difference / |M_pin| (ccx) | | | {dmx * 100:+.2f} % |")
        cm = c["contact_moment_pinion_Nm"]
        md.append(f"| Mx/My_pin from ccx contact pressures (N m) | | {cm[0]:.2f} / {cm[1]:.2f} | |")
        for mesh, fo in o["mesh_normal_force_N"].items():
            fc = c["meshes"].get(mesh, {}).get("normal_force_N", float("nan"))
            md.append(f"| normal force {mesh} (N) | {fo:.0f} | {fc:.0f} | "
                      f"{rel(fo, fc) * 100:+.2f} % |")  # fmt: skip
        for mesh, fo in o["coast_force_N"].items():
            fc = c["meshes"].get(f"{mesh}/coast", {}).get("normal_force_N", float("nan"))
            md.append(f"| coast force {mesh} (N) | {fo:.0f} | {fc:.0f} | |")
        md.append(f"| peak contact stress (MPa) | {o['peak_hertz_MPa']:.0f} (Hertz from grid "
                  f"line load) | {c['peak_pressure_MPa']:.0f} (CPRESS, facet penalty) | "
                  "not like for like |")  # fmt: skip
        md += ["", "| | ours | CalculiX | ratio ccx / ours |", "|---|---|---|---|"]
        ro, rc = r["ours_run"], r["ccx_run"]
        md.append(f"| process wall time (s) | {ro['wall_s']:.1f} | {rc['wall_s']:.1f} | "
                  f"{rc['wall_s'] / ro['wall_s']:.2f} |")  # fmt: skip
        md.append(
            f"| solve_position / ccx wall (s) | {o['solve_position_wall_s']:.1f} | "
            f"{rc['wall_s']:.1f} | {rc['wall_s'] / o['solve_position_wall_s']:.2f} |"
        )
        md.append(f"| peak memory (MB) | {ro['peak_rss_MB']:.0f} | {rc['peak_rss_MB']:.0f} | "
                  f"{rc['peak_rss_MB'] / ro['peak_rss_MB']:.2f} |")  # fmt: skip
        md.append(f"| DOFs | {o['dofs']} | {r['ccx_dofs']} | |")
        s = c["stab_share_of_torque"]
        md += ["", f"Stabilising springs carry {s['sun'] * 100:.2e} % (sun) and "
               f"{s['pinion'] * 100:.2e} % (pinion spin) of the sun torque."]  # fmt: skip
    (out / "peer.md").write_text("\n".join(md) + "\n")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--cases", nargs="+", default=["1-GA", "1-GC"])
    ap.add_argument("--levels", nargs="+", type=int, default=[0])
    ap.add_argument("--roll", type=float, default=0.0, help="sun roll angle (rad)")
    ap.add_argument("--out", type=Path, default=Path("results/bench"))
    ap.add_argument(
        "--penalty-factor",
        type=float,
        default=100.0,
        help="ccx penalty slope = factor E*/h (ours: the same law, default 100)",
    )
    ap.add_argument("--k-stab", type=float, default=1.0e3,
                    help="ccx stabilising torsional springs (N mm/rad)")  # fmt: skip
    ap.add_argument("--threads", type=int, default=1, help="ccx OMP threads (ours: serial)")
    ap.add_argument("--ours", nargs=4, metavar=("CASE", "LEVEL", "ROLL", "JSON"),
                    help=argparse.SUPPRESS)  # fmt: skip
    ap.add_argument("--report-only", action="store_true", help="rewrite peer.md from peer.json")
    a = ap.parse_args(argv)
    if a.report_only:
        data = json.loads((a.out / "peer.json").read_text())
        write_report(data["runs"], a.out, data["notes"])
        return 0
    if a.ours:
        ours(a.ours[0], int(a.ours[1]), float(a.ours[2]), Path(a.ours[3]))
        return 0
    exe = ensure_ccx()
    a.out.mkdir(parents=True, exist_ok=True)
    work = a.out / "peer"
    work.mkdir(exist_ok=True)
    rows = []
    for case in a.cases:
        for level in a.levels:
            tag = f"{case}-L{level}"
            jo = work / f"{tag}-ours.json"
            cmd = [sys.executable, "-m", "studies.bench_peer", "--ours", case, str(level),
                   repr(a.roll), str(jo)]  # fmt: skip
            env = {**os.environ, "OMP_NUM_THREADS": "1"}
            print(f"{tag}: ours ...", flush=True)
            ro = run_measured(cmd, env=env, log=work / f"{tag}-ours.log")
            if ro["returncode"] != 0:
                raise SystemExit(f"error: our solve of {tag} failed: see {work / tag}-ours.log")
            o = json.loads(jo.read_text())
            print(f"{tag}: ours {ro['wall_s']:.1f} s; writing the CalculiX deck ...", flush=True)
            study, scene, deck, tags, centre = build_deck(case, level, a.roll, a.penalty_factor,
                                                          a.k_stab)  # fmt: skip
            job = work / tag
            from postprocess.peer_ccx import write_deck

            info = write_deck(job.with_suffix(".inp"), deck)
            env = {**os.environ, "OMP_NUM_THREADS": str(a.threads),
                   "CCX_NPROC_EQUATION_SOLVER": str(a.threads)}  # fmt: skip
            print(f"{tag}: ccx ({info['fe_nodes']} nodes) ...", flush=True)
            rc = run_measured([exe, "-i", tag], cwd=work, env=env, log=work / f"{tag}-ccx.log")
            row = {"case": case, "level": level, "roll": a.roll, "ours": o, "ours_run": ro,
                   "ccx_run": rc, "ccx_dofs": 3 * info["fe_nodes"],
                   "penalty_MPa_per_mm": deck.penalty}  # fmt: skip
            try:
                if rc["returncode"] != 0:
                    raise RuntimeError(f"ccx exit code {rc['returncode']} (see {tag}-ccx.log)")
                c = ccx_reduce(study, scene, deck, info, tags, centre, job)
                row["ccx"] = c
                row["rel_diff"] = {m: rel(o[m], c[m]) for m in MOMENTS}
                row["abs_diff_mm"] = {z: o[z] - c[z] for z in CENTROIDS}
                print(f"{tag}: ccx {rc['wall_s']:.1f} s; " + ", ".join(
                    f"{m} {o[m]:.2f}/{c[m]:.2f}" for m in MOMENTS), flush=True)  # fmt: skip
            except Exception as e:  # report what failed, keep the other runs
                row["ccx"] = {"error": f"{type(e).__name__}: {e}"}
                print(f"{tag}: CalculiX result unusable: {e}", flush=True)
            rows.append(row)
            write_report(rows, a.out, _notes(a))
    return 0


def _notes(a) -> dict:
    return {
        "position": f"one mesh position, sun roll {a.roll} rad; one-branch scene",
        "ccx_contact": "surface-to-surface (ccx 2.20: no small sliding there), linear penalty "
        f"{a.penalty_factor:g} E*/h (MPa/mm), frictionless; slave = pinion flanks",
        "ccx_stabilisation": f"{a.k_stab:g} N mm/rad torsional springs on sun rotation and "
        "pinion spin (ours: none, rigid unknowns)",
        "threads": f"ccx {a.threads} thread(s); ours serial (1 MPI rank)",
        "moments_from": "ours: contact forces about the pinion centre; ccx: bearing springs "
        "k q at the reference / rotation nodes",
    }


if __name__ == "__main__":
    raise SystemExit(main())

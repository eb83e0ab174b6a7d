"""Build the scenes of gear sets and write a picture and a report of each.

    python -m studies.meshes --gearsets case1 case2 [--scenes one_branch] [--carrier]
        [--out results/meshes] [--level 1]

For every gear set (``cases/gearsets/<name>.toml`` or a path) and scene of the registry
(:data:`meshing.scenes.SCENES`; ``--carrier`` adds the carrier body, one pin per pinion of
every branch, as an extra variant), named ``<gearset>-<scene>[-carrier]``: the mesh (cached
in .cache/meshes or $PLANETARY_CACHE), a picture ``<out>/<scene>-L<level>.png`` and
``<out>/<scene>-L<level>.json`` (scene report: bodies, placements, teeth in mesh, drive
and coast flanks, what was left out; mesh statistics).
Runs under MPI too (the mesh is built on rank 0; files are written on rank 0 only).
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np
from mpi4py import MPI

from cases.gearset import load_gearset
from meshing import sizing
from meshing.build import scene_mesh_file
from meshing.pictures import scene_picture
from meshing.scenes import SCENES, build_scene


def zone_focus(scene) -> tuple[tuple[float, float, float], float]:
    """Middle of the first mesh zone's contact lines, and a half height showing it."""
    zn = scene.zones[0]
    pts = np.vstack([p for _, _, p in zn.contact_lines])
    mid = pts.mean(axis=0)
    return (float(mid[0]), float(mid[1]), 0.0), 8.0


def main(argv=None) -> int:
    doc = __doc__.splitlines()[0]
    ap = argparse.ArgumentParser(prog="python -m studies.meshes", description=doc)
    ap.add_argument("--out", type=Path, default=Path("results/meshes"))
    ap.add_argument("--level", type=int, default=sizing.DEFAULT_LEVEL)
    ap.add_argument("--roll", type=float, default=0.0, help="sun angle (rad), mesh position")
    ap.add_argument("--gearsets", nargs="+", required=True, help="gear-set names or paths")
    ap.add_argument("--scenes", nargs="+", default=["one_branch"], choices=list(SCENES))
    ap.add_argument("--carrier", action="store_true", help="also the scenes with the carrier")
    ap.add_argument("--rebuild", action="store_true", help="ignore the cache")
    ap.add_argument("--no-pictures", action="store_true")
    args = ap.parse_args(argv)

    comm = MPI.COMM_WORLD
    sizing.check_level(args.level)
    jobs = []
    for gs_name in args.gearsets:
        gs = load_gearset(gs_name)
        for kind in args.scenes:
            jobs.append((f"{gs.name}-{kind}", gs, kind, {}))
            if args.carrier:
                jobs.append((f"{gs.name}-{kind}-carrier", gs, kind, {"carrier": True}))
    for name, gs, kind, options in jobs:
        scene = build_scene(kind, gs, args.roll, **options)
        path, meta = scene_mesh_file(scene, args.level, comm=comm, rebuild=args.rebuild)
        if comm.rank != 0:
            continue
        args.out.mkdir(parents=True, exist_ok=True)
        stem = args.out / f"{name}-L{args.level}"
        report = {
            "scene": name,
            "level": args.level,
            "msh": str(path),
            "cached": meta["cached"],
            "elements": meta["elements"],
            "nodes": meta["nodes"],
            "min_sicn": meta["min_sicn"],
            "volume_mm3": meta["volume"],
            "wall_seconds": meta["wall_seconds"],
            "bodies": meta["bodies"],
            "report": meta["report"],
        }
        stem.with_suffix(".json").write_text(json.dumps(report, indent=1))
        if not args.no_pictures:
            scene_picture(
                path,
                stem.with_suffix(".png"),
                f"{name}, level {args.level}, roll {args.roll:g} rad",
                focus=zone_focus(scene),
            )
        print(
            f"{name}: level {args.level}, {meta['elements']} tets, {meta['nodes']} nodes, "
            f"min SICN {meta['min_sicn']:.3f}, {meta['wall_seconds']:.1f} s"
            f"{' (cached)' if meta['cached'] else ''} -> {stem}.png/.json",
            flush=True,
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())

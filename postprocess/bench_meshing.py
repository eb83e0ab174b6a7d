"""Meshing benchmark: per body and level, elements, nodes, wall time, peak memory, quality.

    python -m postprocess.bench_meshing --out results/bench/meshing.json [--levels 0 1 2]

Every measurement runs in a fresh subprocess with an empty temporary cache (a cold build:
geometry + meshing + writing the .msh), so the peak resident memory is that of one build.
The bodies are those of the case 1 one-branch scene (sun and ring sectors, full pinion with
its teeth in mesh refined) plus the carrier; the scene itself is timed cold at every
level, against the issue's target (case 1 one branch at the default level in < 60 s).
A benchmark measures; it asserts nothing.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

TARGET_SECONDS = 60.0  # issue: case 1 one-branch scene at the default level


def _one(kind: str, level: int) -> dict:
    """Build one item cold in this process; return its statistics."""
    from meshing import scenes
    from meshing.build import scene_mesh_file
    from meshing.carrier import carrier_mesh_file, default_carrier
    from meshing.gear_body import body_mesh_file

    t0 = time.perf_counter()
    if kind == "scene:case1-branch":
        _, meta = scene_mesh_file(scenes.case1_scene(0.0), level)
    elif kind == "scene:case2-branch":
        _, meta = scene_mesh_file(scenes.case2_scene(0.0), level)
    elif kind == "carrier":
        _, meta = carrier_mesh_file(default_carrier("case1"), level)
    else:
        g = scenes.case1_scene(0.0).gear(kind)
        _, meta = body_mesh_file(g.body, level, g.active_teeth)
    wall = time.perf_counter() - t0
    peak_kb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return {
        "item": kind,
        "level": level,
        "elements": meta["elements"],
        "nodes": meta["nodes"],
        "min_sicn": meta["min_sicn"],
        "p01_sicn": meta.get("p01_sicn"),
        "wall_seconds": wall,
        "geometry_seconds": meta.get("geometry_seconds"),
        "mesh_seconds": meta.get("mesh_seconds"),
        "peak_rss_mb": peak_kb / 1024.0,
    }


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m postprocess.bench_meshing")
    ap.add_argument("--out", type=Path, default=Path("results/bench/meshing.json"))
    ap.add_argument("--levels", type=int, nargs="+", default=[0, 1, 2])
    ap.add_argument("--one", nargs=2, metavar=("ITEM", "LEVEL"), help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.one:
        print(json.dumps(_one(args.one[0], int(args.one[1]))))
        return 0

    from meshing import sizing

    items = ["sun", "pinion", "ring", "carrier", "scene:case1-branch", "scene:case2-branch"]
    rows = []
    for level in args.levels:
        sizing.check_level(level)
        for item in items:
            with tempfile.TemporaryDirectory() as tmp:
                env = {**os.environ, "PLANETARY_CACHE": tmp}
                res = subprocess.run(
                    [sys.executable, "-m", "postprocess.bench_meshing", "--one", item, str(level)],
                    env=env,
                    capture_output=True,
                    text=True,
                    check=True,
                )
            row = json.loads(res.stdout.strip().splitlines()[-1])
            rows.append(row)
            print(
                f"L{level} {item:22s} {row['elements']:8d} tets {row['nodes']:7d} nodes "
                f"{row['wall_seconds']:6.1f} s {row['peak_rss_mb']:7.0f} MB "
                f"min SICN {row['min_sicn']:.3f}",
                flush=True,
            )
    default = [
        r for r in rows if r["item"] == "scene:case1-branch" and r["level"] == sizing.DEFAULT_LEVEL
    ]
    out = {
        "machine": {
            "cpus": os.cpu_count(),
            "platform": platform.platform(),
            "python": platform.python_version(),
        },
        "default_level": sizing.DEFAULT_LEVEL,
        "target": {
            "what": "case 1 one-branch scene at the default level, cold build",
            "seconds": TARGET_SECONDS,
            "measured_seconds": default[0]["wall_seconds"] if default else None,
            "met": (default[0]["wall_seconds"] < TARGET_SECONDS) if default else None,
        },
        "levels": {str(i): vars(lv) for i, lv in enumerate(sizing.LEVELS)},
        "rows": rows,
    }
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(out, indent=1))
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

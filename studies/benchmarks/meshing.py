"""Meshing benchmark: per body and level, elements, nodes, wall time, peak memory, quality.

    python -m studies.benchmarks.meshing --gearsets case1 case2 --out results/bench/meshing.json
        [--levels 0 1 2]

Every measurement runs in a fresh subprocess with an empty temporary cache (a cold build:
geometry + meshing + writing the .msh), so the peak resident memory is that of one build.
The bodies are those of the first gear set's one-branch scene (sun and ring sectors, full
pinion with its teeth in mesh refined) plus its carrier; the one-branch scene of every gear
set is timed cold at every level, the first against the target (one branch at the default
level in < 60 s).
A benchmark measures; it asserts nothing.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from cases.gearset import load_gearset
from meshing import sizing
from meshing.body_cache import body_mesh_file
from meshing.build import scene_mesh_file
from meshing.carrier import carrier_mesh_file, carrier_spec
from meshing.scenes import build_scene
from studies.memory import peak_rss_mb

TARGET_SECONDS = 60.0  # issue: case 1 one-branch scene at the default level


def _one(item: str, level: int) -> dict:
    """Build one item (``scene:<gearset>``, ``carrier:<gearset>`` or ``<gearset>:<body>``)
    cold in this process; return its statistics."""
    what, gs_name = item.split(":", 1)
    t0 = time.perf_counter()
    if what == "scene":
        _, meta = scene_mesh_file(build_scene("one_branch", load_gearset(gs_name)), level)
    elif what == "carrier":
        _, meta = carrier_mesh_file(carrier_spec(load_gearset(gs_name)), level)
    else:
        gs_name, body = what, gs_name
        g = build_scene("one_branch", load_gearset(gs_name)).gear(body)
        _, meta = body_mesh_file(g.body, level, g.active_teeth)
    wall = time.perf_counter() - t0
    return {
        "item": item,
        "level": level,
        "elements": meta["elements"],
        "nodes": meta["nodes"],
        "min_sicn": meta["min_sicn"],
        "p01_sicn": meta.get("p01_sicn"),
        "wall_seconds": wall,
        "geometry_seconds": meta.get("geometry_seconds"),
        "mesh_seconds": meta.get("mesh_seconds"),
        "peak_rss_mb": peak_rss_mb(),
    }


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m studies.benchmarks.meshing")
    ap.add_argument("--out", type=Path, default=Path("results/bench/meshing.json"))
    ap.add_argument("--levels", type=int, nargs="+", default=[0, 1, 2])
    ap.add_argument("--gearsets", nargs="+", required=True, help="gear-set names or paths")
    ap.add_argument("--one", nargs=2, metavar=("ITEM", "LEVEL"), help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.one:
        print(json.dumps(_one(args.one[0], int(args.one[1]))))
        return 0

    first = load_gearset(args.gearsets[0])
    items = [f"{first.name}:{g}" for g in first.power_path]
    if first.kind == "single_pinion":
        items.append(f"carrier:{first.name}")
    items += [f"scene:{g}" for g in args.gearsets]
    rows = []
    for level in args.levels:
        sizing.check_level(level)
        for item in items:
            with tempfile.TemporaryDirectory() as tmp:
                env = {**os.environ, "PLANETARY_CACHE": tmp}
                res = subprocess.run(
                    [sys.executable, "-m", "studies.benchmarks.meshing", "--one", item, str(level)],
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
    target = items[-len(args.gearsets)]  # the first gear set's one-branch scene
    default = [r for r in rows if r["item"] == target and r["level"] == sizing.DEFAULT_LEVEL]
    out = {
        "machine": {
            "cpus": os.cpu_count(),
            "platform": platform.platform(),
            "python": platform.python_version(),
        },
        "default_level": sizing.DEFAULT_LEVEL,
        "target": {
            "what": f"{target} (one-branch scene) at the default level, cold build",
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

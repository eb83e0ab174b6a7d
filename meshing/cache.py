"""On-disk mesh cache keyed by the parameters of the mesh.

The key is the sha256 of a canonical JSON of ``kind``, all parameters and a version
string made of the sha256 of the source files that shape a mesh (the geometry module, the
body builder, the size ladder, ...): change any of them and every key changes, so a stale
mesh can never be reused. Entries live in ``$PLANETARY_CACHE`` or ``<repo>/.cache/meshes``
(gitignored) as ``<kind>-<key16>.msh`` with a ``.json`` sidecar (parameters, statistics,
timings). Builds happen on one rank; the others wait for the file.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import math
import os
import tempfile
from collections.abc import Callable
from pathlib import Path

import numpy as np

REPO_ROOT = Path(__file__).resolve().parent.parent
_SOURCES = (
    "gear_geometry.py",
    "gear_body.py",
    "sizing.py",
    "tags.py",
    "carrier.py",
    "scenes.py",
    "assemble.py",
    "build.py",
)


def cache_dir() -> Path:
    d = Path(os.environ.get("PLANETARY_CACHE", REPO_ROOT / ".cache" / "meshes"))
    d.mkdir(parents=True, exist_ok=True)
    return d


def source_version() -> str:
    """sha256 (16 hex) of the meshing sources that determine a mesh."""
    h = hashlib.sha256()
    here = Path(__file__).resolve().parent
    for name in _SOURCES:
        p = here / name
        h.update(name.encode())
        h.update(p.read_bytes() if p.is_file() else b"<absent>")
    return h.hexdigest()[:16]


def _canon(obj):
    """JSON-able canonical form: dataclasses to dicts, floats rounded to 12 digits."""
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        return {f.name: _canon(getattr(obj, f.name)) for f in dataclasses.fields(obj)}
    if isinstance(obj, dict):
        return {str(k): _canon(v) for k, v in sorted(obj.items(), key=lambda kv: str(kv[0]))}
    if isinstance(obj, (list, tuple, set, frozenset)):
        items = [_canon(v) for v in obj]
        return sorted(items, key=json.dumps) if isinstance(obj, (set, frozenset)) else items
    if isinstance(obj, (bool, np.bool_)):
        return bool(obj)
    if isinstance(obj, (int, np.integer)):
        return int(obj)
    if isinstance(obj, (float, np.floating)):
        x = float(obj)
        if not math.isfinite(x):
            return repr(x)
        return float(f"{x:.12g}")
    if isinstance(obj, np.ndarray):
        return _canon(obj.tolist())
    if obj is None or isinstance(obj, str):
        return obj
    raise TypeError(f"cannot put {type(obj).__name__} into a cache key")


def key(kind: str, params) -> str:
    payload = {"kind": kind, "version": source_version(), "params": _canon(params)}
    text = json.dumps(payload, sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()


def paths(kind: str, params) -> tuple[Path, Path]:
    k = key(kind, params)[:16]
    d = cache_dir()
    return d / f"{kind}-{k}.msh", d / f"{kind}-{k}.json"


def get_or_build(
    kind: str,
    params,
    builder: Callable[[Path], dict],
    comm=None,
    rebuild: bool = False,
) -> tuple[Path, dict]:
    """Return ``(msh_path, meta)``; call ``builder(tmp_msh_path) -> meta`` on rank 0 if the
    entry is missing (or ``rebuild``). ``meta`` gains ``cached`` (True if reused)."""
    rank = 0 if comm is None else comm.rank
    msh, meta_path = paths(kind, params)
    err = None
    meta = None
    if rank == 0:
        try:
            if not rebuild and msh.is_file() and meta_path.is_file():
                meta = json.loads(meta_path.read_text())
                meta["cached"] = True
            else:
                fd, tmp = tempfile.mkstemp(suffix=".msh", dir=msh.parent)
                os.close(fd)
                try:
                    meta = dict(builder(Path(tmp)))
                    meta["params"] = _canon(params)
                    meta["kind"] = kind
                    meta["version"] = source_version()
                    os.replace(tmp, msh)
                finally:
                    if os.path.exists(tmp):
                        os.unlink(tmp)
                meta_path.write_text(json.dumps(meta, indent=1, sort_keys=True))
                meta["cached"] = False
        except Exception as exc:  # re-raised on every rank below
            err = exc
    if comm is not None:
        err_msg = comm.bcast(None if err is None else f"{type(err).__name__}: {err}", root=0)
        if err_msg is not None:
            if err is not None:
                raise err
            raise RuntimeError(f"mesh build failed on rank 0: {err_msg}")
        meta = comm.bcast(meta, root=0)
    elif err is not None:
        raise err
    return msh, meta

"""On-disk mesh cache keyed by the parameters of the mesh and the code that builds it.

The key is the sha256 of a canonical JSON of ``kind``, all parameters and a version string:
the sha256 of the source of every module that shapes a mesh or its sidecar (the gear
geometry, the body and carrier builders, the size ladder, the tag names, the scene layout,
the assembly, the gmsh output options). Change any of them and every key changes, so a
stale mesh is never reused. The modules are named by dotted module name in
:data:`MESH_MODULES` and located with ``importlib`` (where an import would find them), not by
file name in this folder: a module that moved without the list being updated raises a
:class:`RuntimeError` instead of silently dropping out of the key. Every top-level module of
the packages in :data:`AUTO_PACKAGES` (the pure-numpy gear geometry, ``gears``) is hashed too,
listed or not, so a new geometry module is covered on its own. :func:`hashed_sources` shows
what is hashed; the version is computed once per process.

Entries live in ``$PLANETARY_CACHE`` or ``<repo>/.cache/meshes`` (gitignored) as
``<kind>-<key16>.msh`` with a ``.json`` sidecar (parameters, statistics, timings, and the
size and sha256 of the ``.msh``). Both files are written atomically (temporary file, then
``os.replace``), the sidecar last. An entry whose sidecar does not parse or lacks the keys
written at build time, or whose ``.msh`` is missing, empty, or differs from the size (and, up
to :data:`SHA_CHECK_MAX_BYTES`, the sha256) recorded in the sidecar, is named on stderr and
rebuilt. Builds happen on rank 0; errors are broadcast so that no rank hangs, and the other
ranks read the file once rank 0 is done.
"""

from __future__ import annotations

import dataclasses
import functools
import hashlib
import importlib.util
import json
import math
import os
import sys
import tempfile
from collections.abc import Callable
from pathlib import Path

import numpy as np

REPO_ROOT = Path(__file__).resolve().parent.parent

# Modules whose source shapes a mesh file or what its sidecar records, as dotted module
# names. When a module is moved, renamed or split (e.g. meshing/gear_body.py or
# meshing/scenes.py into several modules), list the new modules here: a listed module that is
# not found stops every build, and tests/test_mesh_cache.py checks that each one is found
# and that every meshing/*.py module is either listed here or in NOT_MESH_SHAPING.
# Modules whose results reach the mesh only through the cache parameters (e.g. the planet
# angles of gears.analytic.phasing, which are in the scene and carrier parameters) need not
# be listed.
MESH_MODULES: tuple[str, ...] = (
    # gear geometry (also covered by AUTO_PACKAGES; listed so a move is noticed)
    "gears.involute",
    "gears.spec",
    "gears.profile",
    "gears.pair",
    # meshers
    "meshing.gear_body",
    "meshing.body_outline",
    "meshing.body_geometry",
    "meshing.body_mesh",
    "meshing.body_cache",
    "meshing.carrier",
    "meshing.sizing",
    "meshing.tags",
    "meshing.gmsh_util",  # MSH version, binary output
    # scenes: layout, placements, mesh zones (in the scene report of the sidecar), merge
    "meshing.scenes",
    "meshing.mesh_zones",
    "meshing.assemble",
    "meshing.build",
)

# Packages of which every top-level ``*.py`` module is hashed without being listed.
AUTO_PACKAGES: tuple[str, ...] = ("gears",)

# meshing modules that do not shape a mesh (loading, pictures, the cache itself): hashing
# them would throw away every cached mesh on each edit. Checked by tests/test_mesh_cache.py.
NOT_MESH_SHAPING: tuple[str, ...] = (
    "meshing.cache",
    "meshing.pictures",
    "meshing.to_dolfinx",
    "meshing.scene_bodies",
    "meshing.submodel",  # a submodel's sector and sizes reach its mesh as GearBody and Level
)

# The sha256 of a cached .msh is checked on reuse up to this size (~0.1 s at 1.5 GB/s);
# larger files are checked by size only.
SHA_CHECK_MAX_BYTES = 128 * 2**20

# Sidecar keys written at build time; an entry lacking one is corrupt.
_SIDECAR_KEYS = ("kind", "params", "version", "msh_bytes", "msh_sha256")


class CacheDirError(RuntimeError):
    """The cache folder cannot be created or written."""


def _cache_path() -> Path:
    return Path(os.environ.get("PLANETARY_CACHE") or REPO_ROOT / ".cache" / "meshes")


def _dir_error(d: Path, why) -> CacheDirError:
    return CacheDirError(
        f"mesh cache folder {d} is not usable ({why}); set PLANETARY_CACHE to a writable "
        "folder (e.g. PLANETARY_CACHE=/tmp/planetary-meshes)"
    )


def cache_dir() -> Path:
    """The cache folder, created if needed (:class:`CacheDirError` if that is impossible)."""
    d = _cache_path()
    if d.exists() and not d.is_dir():
        raise _dir_error(d, "it is a file, not a folder")
    try:
        d.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise _dir_error(d, exc.strerror or exc) from exc
    if not os.access(d, os.W_OK | os.X_OK):
        raise _dir_error(d, "not writable")
    return d


def _origin(name: str) -> Path:
    """Source file of the module ``name``, without importing it (its parent package is)."""
    try:
        spec = importlib.util.find_spec(name)
    except (ImportError, ValueError):
        spec = None
    if spec is None or not spec.has_location or not spec.origin:
        raise RuntimeError(
            f"mesh cache key: module {name!r} is not found (moved or renamed?); update the "
            "cache key list MESH_MODULES in meshing/cache.py so that a change to it still "
            "changes the key"
        )
    p = Path(spec.origin)
    if not p.is_file():
        raise RuntimeError(
            f"mesh cache key: module {name!r} has no source file ({spec.origin}); update the "
            "cache key list MESH_MODULES in meshing/cache.py"
        )
    return p


def _package_modules(package: str) -> dict[str, Path]:
    """Every top-level ``*.py`` module of ``package`` (all its folders), by dotted name."""
    try:
        spec = importlib.util.find_spec(package)
    except (ImportError, ValueError):
        spec = None
    if spec is None or not spec.submodule_search_locations:
        raise RuntimeError(
            f"mesh cache key: package {package!r} is not found; update AUTO_PACKAGES in "
            "meshing/cache.py"
        )
    out: dict[str, Path] = {}
    for folder in spec.submodule_search_locations:
        for p in sorted(Path(folder).glob("*.py")):
            name = package if p.stem == "__init__" else f"{package}.{p.stem}"
            out.setdefault(name, p)  # the first folder wins, as for an import
    return out


def hashed_sources() -> dict[str, Path]:
    """Dotted module name -> source file of everything that goes into :func:`source_version`
    (:data:`MESH_MODULES` and every top-level module of :data:`AUTO_PACKAGES`)."""
    out = {name: _origin(name) for name in MESH_MODULES}
    for package in AUTO_PACKAGES:
        for name, p in _package_modules(package).items():
            out.setdefault(name, p)
    return dict(sorted(out.items()))


@functools.cache
def source_version() -> str:
    """sha256 (16 hex) of the names and sources of the modules that determine a mesh,
    computed once per process (``source_version.cache_clear()`` to recompute)."""
    h = hashlib.sha256()
    for name, p in hashed_sources().items():
        data = p.read_bytes()
        h.update(f"{name}\0{len(data)}\0".encode())
        h.update(data)
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


def _entry(kind: str, params) -> tuple[Path, Path]:
    k = key(kind, params)[:16]
    d = _cache_path()
    return d / f"{kind}-{k}.msh", d / f"{kind}-{k}.json"


def paths(kind: str, params) -> tuple[Path, Path]:
    """``(msh, json)`` paths of the entry (the cache folder is created)."""
    cache_dir()
    return _entry(kind, params)


def _sha256(path: Path) -> str:
    with open(path, "rb") as f:
        return hashlib.file_digest(f, "sha256").hexdigest()


def _check_entry(msh: Path, meta_path: Path) -> tuple[dict | None, Path | None, str | None]:
    """``(meta, None, None)`` for a sound entry, ``(None, None, None)`` for none at all, and
    ``(None, bad_path, why)`` for a corrupt or partial one."""
    has_msh, has_meta = msh.is_file(), meta_path.is_file()
    if not has_msh and not has_meta:
        return None, None, None
    if not has_meta:
        return None, msh, f"no sidecar {meta_path.name}"
    if not has_msh:
        return None, meta_path, f"its mesh file {msh.name} is missing"
    try:
        meta = json.loads(meta_path.read_text())
    except (ValueError, UnicodeDecodeError) as exc:
        return None, meta_path, f"sidecar does not parse: {exc}"
    if not isinstance(meta, dict):
        return None, meta_path, "sidecar is not a JSON object"
    missing = [k for k in _SIDECAR_KEYS if k not in meta]
    if missing:
        return None, meta_path, f"sidecar lacks {', '.join(missing)}"
    recorded = meta["msh_bytes"]
    if not isinstance(recorded, int) or isinstance(recorded, bool):
        return None, meta_path, f"sidecar msh_bytes is not an integer: {recorded!r}"
    size = msh.stat().st_size
    if size == 0:
        return None, msh, "mesh file is empty"
    if size != recorded:
        return None, msh, f"mesh file has {size} bytes, the sidecar records {recorded}"
    if size <= SHA_CHECK_MAX_BYTES and _sha256(msh) != meta["msh_sha256"]:
        return None, msh, "mesh file sha256 differs from the sidecar"
    return meta, None, None


def _tmp_in(d: Path, suffix: str) -> str:
    try:
        fd, tmp = tempfile.mkstemp(suffix=suffix, dir=d)
    except OSError as exc:
        raise _dir_error(d, exc.strerror or exc) from exc
    os.close(fd)
    return tmp


def _build(kind: str, params, builder, msh: Path, meta_path: Path) -> dict:
    """Build the entry on this rank: the .msh, then the sidecar, each written atomically."""
    d = cache_dir()
    tmp = _tmp_in(d, ".msh")
    tmp_meta = None
    try:
        meta = dict(builder(Path(tmp)))
        size = os.path.getsize(tmp)
        if size == 0:
            raise RuntimeError(f"the {kind} mesh builder wrote nothing to {tmp}")
        meta.update(
            params=_canon(params),
            kind=kind,
            version=source_version(),
            msh_bytes=size,
            msh_sha256=_sha256(Path(tmp)),
        )
        text = json.dumps(meta, indent=1, sort_keys=True)  # fails before anything is replaced
        tmp_meta = _tmp_in(d, ".json")
        Path(tmp_meta).write_text(text)
        meta_path.unlink(missing_ok=True)  # a crash between the two replaces leaves no pair
        os.replace(tmp, msh)
        os.replace(tmp_meta, meta_path)
    finally:
        for t in (tmp, tmp_meta):
            if t is not None and os.path.exists(t):
                os.unlink(t)
    return meta


def get_or_build(
    kind: str,
    params,
    builder: Callable[[Path], dict],
    comm=None,
    rebuild: bool = False,
) -> tuple[Path, dict]:
    """Return ``(msh_path, meta)``; call ``builder(tmp_msh_path) -> meta`` on rank 0 if the
    entry is missing, corrupt (a warning on stderr names it) or ``rebuild``. ``meta`` gains
    ``cached`` (True if reused). Collective if ``comm``: an error on rank 0 is raised on every
    rank."""
    rank = 0 if comm is None else comm.rank
    err = None
    meta = None
    msh = None
    try:
        msh, meta_path = _entry(kind, params)  # the same on every rank, no file system access
        if rank == 0:
            if not rebuild:
                meta, bad, why = _check_entry(msh, meta_path)
                if why is not None:
                    print(f"mesh cache entry {bad} is corrupt ({why}): rebuilding", file=sys.stderr)
            if meta is not None:
                meta["cached"] = True
            else:
                meta = _build(kind, params, builder, msh, meta_path)
                meta["cached"] = False
    except Exception as exc:  # re-raised on every rank below
        err = exc
    if comm is not None:
        err_msg = comm.bcast(None if err is None else f"{type(err).__name__}: {err}", root=0)
        if err_msg is not None:
            if err is not None:
                raise err
            raise RuntimeError(f"mesh build failed on rank 0: {err_msg}")
        meta = comm.bcast(meta, root=0)  # every rank takes part before a local error is raised
    if err is not None:
        raise err
    return msh, meta

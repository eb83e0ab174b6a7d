"""Where a result came from: code revision, source hash and package versions.

Recorded in every ``summary.json`` and position file, and used to decide whether a finished
position may be reused: a position is reused only when its inputs hash (the resolved case
file and gear set, :func:`cases.study_case.inputs_hash`), the settings and the hash of the
pipeline's own source (:func:`code_hash`) are all unchanged.
"""

from __future__ import annotations

import functools
import hashlib
import importlib.metadata
import subprocess
from pathlib import Path

from meshing.cache import source_version

REPO_ROOT = Path(__file__).resolve().parent.parent
PACKAGES = ("gears", "cases", "meshing", "solvers", "postprocess", "studies")
VERSIONED = ("dolfinx-solver-real", "fenics-basix", "fenics-ffcx", "fenics-ufl", "gmsh",
             "numpy", "mpi4py", "pyvista")  # fmt: skip


@functools.cache
def code_hash() -> str:
    """sha256 (16 hex) of every Python source and case file of the pipeline packages."""
    h = hashlib.sha256()
    for pkg in PACKAGES:
        for f in sorted((REPO_ROOT / pkg).rglob("*")):
            if f.suffix in (".py", ".toml") and "__pycache__" not in f.parts:
                h.update(str(f.relative_to(REPO_ROOT)).encode())
                h.update(f.read_bytes())
    return h.hexdigest()[:16]


@functools.cache
def git_revision() -> str | None:
    """``<commit>`` (``+dirty`` with uncommitted changes), or None outside a git checkout."""
    try:
        rev = subprocess.run(["git", "rev-parse", "HEAD"], cwd=REPO_ROOT, capture_output=True,
                             text=True, timeout=10, check=True).stdout.strip()  # fmt: skip
        dirty = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no"],
                               cwd=REPO_ROOT, capture_output=True, text=True, timeout=10,
                               check=True).stdout.strip()  # fmt: skip
    except (OSError, subprocess.SubprocessError):
        return None
    return rev + ("+dirty" if dirty else "")


def package_versions() -> dict[str, str | None]:
    out = {}
    for name in VERSIONED:
        try:
            out[name] = importlib.metadata.version(name)
        except importlib.metadata.PackageNotFoundError:
            out[name] = None
    return out


def provenance() -> dict:
    """Code hash, git revision and package versions of this run."""
    return {
        "code_hash": code_hash(),
        "mesh_source_version": source_version(),
        "git_revision": git_revision(),
        "packages": package_versions(),
    }

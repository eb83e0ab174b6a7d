"""Where a result came from: code revision, source hash and package versions.

Recorded in every ``summary.json`` and position file, and used to decide whether a finished
position may be reused: a position is reused only when its inputs hash (the resolved case
file and gear set, :func:`cases.study_case.inputs_hash`), the settings and the hash of the
code that computes its numbers (:func:`code_hash`) are all unchanged. The same hash tells
whether a recorded convergence study was solved by today's code.

What :func:`code_hash` covers (:func:`numeric_sources`): every module of the pipeline that
the numbers of a position, a summary or a convergence run pass through, found as the static
import closure (every ``import`` in the module, at any depth of its body, within the pipeline
packages) of :data:`COMPUTE_ROOTS`; the drivers that choose what is solved
(:data:`DRIVERS`, their own source); and every case and gear-set file. Reports, pictures,
benchmarks and command-line shells are outside it, so a change to a report neither discards
finished positions nor marks a recorded convergence study as solved by other code. So are the
reductions of a convergence study's runs (:mod:`studies.convergence.richardson`,
:mod:`studies.convergence.reduction`): ``python -m studies.convergence --reduce-records``
applies a fix to them to the stored runs of every record without solving a run again (the
scalars a run records, :mod:`postprocess.run_scalars`, are covered).
"""

from __future__ import annotations

import ast
import datetime
import functools
import hashlib
import importlib.metadata
import subprocess
from pathlib import Path

from meshing.cache import source_version

REPO_ROOT = Path(__file__).resolve().parent.parent
PACKAGES = ("gears", "cases", "meshing", "solvers", "postprocess", "studies")
VERSIONED = (
    "dolfinx-solver-real",
    "fenics-basix",
    "fenics-ffcx",
    "fenics-ufl",
    "gmsh",
    "numpy",
    "mpi4py",
    "pyvista",
)


# the modules through which a position's, a summary's and a convergence run's numbers pass
COMPUTE_ROOTS = (
    "studies.position",
    "studies.convergence.position_runs",
    "postprocess.summary",
    "postprocess.run_scalars",
)
# the drivers that choose what is solved (their own source; their reports are outside)
DRIVERS = ("studies.run", "studies.convergence.driver")


def _module_file(name: str) -> Path | None:
    """Source file of the pipeline module ``name`` (a package's ``__init__.py``), or None."""
    path = REPO_ROOT.joinpath(*name.split("."))
    for f in (path / "__init__.py", path.with_suffix(".py")):
        if f.is_file():
            return f
    return None


def _imported(name: str) -> set[str]:
    """The pipeline modules ``name`` imports anywhere in its source (``from a.b import c``
    names ``a``, ``a.b`` and, if it is a module, ``a.b.c``)."""
    tree = ast.parse(_module_file(name).read_text())
    named = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            named.update(a.name for a in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module:
            if node.level:
                raise RuntimeError(f"code hash: {name} uses a relative import; write it absolute")
            named.add(node.module)
            named.update(f"{node.module}.{a.name}" for a in node.names)
    out = set()
    for dotted in named:
        parts = dotted.split(".")
        if parts[0] not in PACKAGES:
            continue
        for i in range(1, len(parts) + 1):
            if _module_file(".".join(parts[:i])) is not None:
                out.add(".".join(parts[:i]))
    return out


def numeric_sources() -> dict[str, Path]:
    """Dotted name -> file of every source :func:`code_hash` covers: the import closure of
    :data:`COMPUTE_ROOTS`, the :data:`DRIVERS` and every ``cases/**/*.toml``."""
    for name in (*COMPUTE_ROOTS, *DRIVERS):
        if _module_file(name) is None:
            raise RuntimeError(
                f"code hash: module {name!r} is not found; update COMPUTE_ROOTS or DRIVERS"
            )
    seen: set[str] = set()
    todo = list(COMPUTE_ROOTS)
    while todo:
        name = todo.pop()
        if name not in seen:
            seen.add(name)
            todo.extend(_imported(name) - seen)
    # importing a.b.c runs the __init__ of a and a.b too
    packages = {
        ".".join(n.split(".")[:i]) for n in seen | set(DRIVERS) for i in range(1, n.count(".") + 1)
    }
    seen |= {p for p in packages if _module_file(p) is not None}
    out = {name: _module_file(name) for name in sorted(seen | set(DRIVERS))}
    for f in sorted((REPO_ROOT / "cases").rglob("*.toml")):
        out[str(f.relative_to(REPO_ROOT))] = f
    return out


@functools.cache
def code_hash() -> str:
    """sha256 (16 hex) of the sources that compute the pipeline's numbers
    (:func:`numeric_sources`: names and contents)."""
    h = hashlib.sha256()
    for name, f in numeric_sources().items():
        h.update(name.encode())
        h.update(f.read_bytes())
    return h.hexdigest()[:16]


def utc_stamp() -> str:
    """Now, as the records date what they keep: ``YYYY-MM-DD HH:MM UTC``."""
    return datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC")


@functools.cache
def git_revision() -> str | None:
    """``<commit>`` (``+dirty`` with uncommitted changes), or None outside a git checkout."""
    try:
        rev = subprocess.run(
            ["git", "rev-parse", "HEAD"],
            cwd=REPO_ROOT,
            capture_output=True,
            text=True,
            timeout=10,
            check=True,
        ).stdout.strip()
        dirty = subprocess.run(
            ["git", "status", "--porcelain", "--untracked-files=no"],
            cwd=REPO_ROOT,
            capture_output=True,
            text=True,
            timeout=10,
            check=True,
        ).stdout.strip()
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

"""Imports follow the data flow (gears <- cases <- meshing <- solvers <- postprocess <-
studies), and the product (one run of a case and its report: ``planetary-fe``) imports no
research or verification study. Read from the source with ``ast``: nothing is imported."""

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
LAYERS = ["gears", "cases", "meshing", "solvers", "postprocess", "studies"]
PRODUCT = ["studies.console", "studies.run"]  # the entry points of one run and its report
# the research and verification studies: one folder each under studies/, holding its driver,
# its report and (convergence) the reductions; the summaries read a record's stored ± through
# postprocess.convergence_record
STUDY_FOLDERS = [
    "analytic",
    "benchmarks",
    "convergence",
    "fillet",
    "lead_correction",
    "paper",
    "peer",
    "phasing",
    "pin_errors",
    "radial_stiffness",
]
SHARED_BY_STUDIES = ["studies.case_variants"]  # variants of a case that studies derive


def _modules() -> dict[str, set[str]]:
    """Every module of the packages and the modules of the packages it imports."""
    graph = {}
    for layer in LAYERS:
        for path in sorted((ROOT / layer).rglob("*.py")):
            parts = path.relative_to(ROOT).with_suffix("").parts
            name = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
            deps = set()
            for node in ast.walk(ast.parse(path.read_text())):
                if isinstance(node, ast.Import):
                    deps |= {a.name for a in node.names}
                elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
                    deps |= {node.module, *(f"{node.module}.{a.name}" for a in node.names)}
            graph[name] = {d for d in deps if d.split(".")[0] in LAYERS}
    return graph


GRAPH = _modules()
RESEARCH = {
    m for m in GRAPH if any(f"{m}.".startswith(f"studies.{f}.") for f in STUDY_FOLDERS)
} | set(SHARED_BY_STUDIES)


def test_every_study_is_a_folder_of_its_own():
    """Each named study is a package under studies/, and no module of studies/ outside them
    is imported only by studies (it would be a study's part left at the top)."""
    for f in STUDY_FOLDERS:
        assert (ROOT / "studies" / f / "__init__.py").is_file(), f
    assert set(SHARED_BY_STUDIES) <= set(GRAPH)
    top = {m for m in GRAPH if m.count(".") == 1 and m.startswith("studies.")} - RESEARCH
    users = {m: {u for u, deps in GRAPH.items() if m in deps} for m in top}
    only_studies = sorted(m for m, u in users.items() if u and u <= RESEARCH)
    assert not only_studies, only_studies


def test_imports_point_down_the_data_flow():
    rank = {layer: i for i, layer in enumerate(LAYERS)}
    up = [
        f"{m} imports {d}"
        for m, deps in GRAPH.items()
        for d in deps
        if rank[d.split(".")[0]] > rank[m.split(".")[0]]
    ]
    assert not up


def test_the_product_imports_no_study():
    reached, todo = set(), list(PRODUCT)
    while todo:
        m = todo.pop()
        if m in reached or m not in GRAPH:
            continue
        reached.add(m)
        todo += GRAPH[m]
    assert set(PRODUCT) <= reached
    assert not reached & RESEARCH, sorted(reached & RESEARCH)

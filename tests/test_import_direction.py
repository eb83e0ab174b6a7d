"""Imports follow the data flow (gears <- cases <- meshing <- solvers <- postprocess <-
studies), and the product (one run of a case and its report: ``planetary-fe``) imports no
research or verification study. Read from the source with ``ast``: nothing is imported."""

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
LAYERS = ["gears", "cases", "meshing", "solvers", "postprocess", "studies"]
PRODUCT = ["studies.console", "studies.run"]  # the entry points of one run and its report
# the research and verification studies: drivers, their reports and the convergence
# reductions (the summaries read a record's stored ± through postprocess.convergence_record)
RESEARCH = {
    *(f"studies.{m}" for m in (
        "analytic", "bench_contact", "bench_linear", "bench_meshing", "bench_peer",
        "bench_solver", "bench_study", "bench_submodel", "case1_report", "case2_report",
        "convergence", "driver_sizes", "fillet_study", "lead_correction", "phasing",
        "pin_errors", "position_runs", "radial_stiffness", "sector_scatter", "sector_sizes",
        "system_report",
    )),
    *(f"postprocess.{m}" for m in (
        "case1_report", "case2_report", "convergence", "convergence_report",
        "convergence_study", "fillet_study", "sector_scatter",
        "lead_correction", "peer_ccx", "phasing_fe", "radial_stiffness_fe", "system_report",
    )),
}  # fmt: skip


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


def test_every_research_module_exists():
    assert RESEARCH <= set(GRAPH), sorted(RESEARCH - set(GRAPH))


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

"""The outputs reference, docs/reference/outputs.md, against the files a run writes.

The page is the one list of what a run writes: every key path of ``summary.json`` and of a
position file is a row of one of its tables (first column: the path in backticks, ``When``:
in which runs the key is there), and every file of a case's output folder is a row of its
folder table. :func:`check_run` ties the page to real outputs: every key path of the files
is a row of the page (nothing written goes undocumented) and every row whose ``When`` holds
for the run is a key path of them (nothing documented that the code no longer writes).

No finite element solve here: :func:`check_run` is called by the tests that already run a
level-0 study (``tests/test_study_run.py``, 1-GA, single pinion;
``tests/test_case2_study.py``, 2B-GA, double pinion); the tests of this module check the
page itself (its tables parse, every ``When`` and placeholder it uses is defined).

Key paths: dict keys joined by ``.``; a list of objects adds ``[]`` to its key and its
elements' keys follow (``positions[].My_pin``); anything else is a leaf (numbers, strings,
None, lists of numbers, empty lists and objects). In the page, ``<name>`` stands for one key
(or part of one) that names a gear, mesh, pinion, ...; a last segment ``*`` stands for a
whole subtree documented elsewhere on the page.
"""

from __future__ import annotations

import json
import re
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from fnmatch import fnmatchcase
from pathlib import Path

import pytest

PAGE = Path(__file__).resolve().parent.parent / "docs" / "reference" / "outputs.md"

#: first header cell of a table -> what its rows document
TABLES = {
    "Key": "summary",
    "Position file key": "position",
    "File": "folder",
    "When": "when",
    "Placeholder": "placeholder",
}


def _get(tree, *path):
    for part in path:
        if not isinstance(tree, dict):
            return None
        tree = tree.get(part)
    return tree


def _numerics(s: dict, key: str):
    return _get(s, "inputs", "study_case", "numerics", key)


def _scene(s: dict) -> str:
    return s["scene"]


#: the ``When`` of a row -> whether its keys are in the summary ``s`` of a run (None: the page
#: cannot say from the run's inputs; such rows are only checked one way: a key of the run
#: must have a row)
WHEN: dict[str, Callable[[dict], bool | None]] = {
    "every run": lambda s: True,
    "single pinion": lambda s: s["inputs"]["gearset"]["kind"] == "single_pinion",
    "double pinion": lambda s: s["inputs"]["gearset"]["kind"] == "double_pinion",
    "several planets": lambda s: _scene(s) in ("all_planets", "system"),
    "system scene": lambda s: _scene(s) == "system",
    "one branch": lambda s: _scene(s) == "one_branch",
    "zone grid": lambda s: _numerics(s, "contact_model") == "zone",
    "line grid": lambda s: _numerics(s, "contact_model") == "line",
    "root stress read": lambda s: _numerics(s, "root_stress") != "none",
    "no root stress": lambda s: _numerics(s, "root_stress") == "none",
    "submodels": lambda s: _numerics(s, "root_stress") == "submodel",
    "submodels on refined fillets": lambda s: (
        _numerics(s, "root_stress") == "submodel" and s.get("root_fillets") == "refined"
    ),
    "flank level": lambda s: "flank_level" in s["inputs"]["study_case"]["model"],
    "fillet level": lambda s: "fillet_level" in s["inputs"]["study_case"]["model"],
    "flank modifications": lambda s: bool(s["inputs"]["gearset"]["modifications"]),
    "convergence study": lambda s: "convergence_study" in (s.get("uncertainty_source") or {}),
    "study has the run": lambda s: s.get("uncertainty") is not None,
    "recorded study": lambda s: None,
    "code changed": lambda s: None,
    "scatter carried": lambda s: None,
    "study skipped": lambda s: bool((s.get("uncertainty_source") or {}).get("skipped")),
    "failed positions": lambda s: bool(s.get("failed_positions")),
}


def _mean_keys(s: dict) -> set[str]:
    from postprocess.paper_moments import MEAN_KEYS

    return set(MEAN_KEYS[s["inputs"]["gearset"]["kind"]])


#: placeholders that stand for the keys of a known set, read from the run's summary (the
#: others stand for any key): ``positions[].bending_stress.<gear key>`` must not pass off
#: an undocumented ``positions[].bending_stress.<new key>`` as a gear's
TYPED: dict[str, Callable[[dict], set[str]]] = {
    "<gear key>": lambda s: (
        set(s.get("bending_stress_iso6336") or {}) | set(s.get("bending_stress_at") or {})
    ),
    "<mean key>": _mean_keys,
}


@dataclass(frozen=True)
class Row:
    table: str  # "summary", "position" or "folder"
    pattern: str
    when: tuple[str, ...]
    line: int  # in the page, for messages

    @property
    def segments(self) -> tuple[str, ...]:
        return tuple(self.pattern.split(".")) if self.table != "folder" else (self.pattern,)


def _cells(line: str) -> list[str]:
    return [c.strip() for c in line.strip().strip("|").split("|")]


def _code(cell: str) -> list[str]:
    return re.findall(r"`([^`]+)`", cell)


def page_tables(text: str) -> dict[str, list[tuple[int, list[str]]]]:
    """Per kind of :data:`TABLES` the body rows (page line, cells) of every table whose first
    header cell names that kind."""
    out: dict[str, list[tuple[int, list[str]]]] = {k: [] for k in TABLES.values()}
    lines = text.splitlines()
    i = 0
    while i < len(lines):
        line = lines[i]
        head = _cells(line) if line.lstrip().startswith("|") else []
        is_head = i + 1 < len(lines) and re.fullmatch(r"\s*\|[\s:|-]+\|\s*", lines[i + 1])
        if head and is_head and head[0] in TABLES:
            kind = TABLES[head[0]]
            i += 2
            while i < len(lines) and lines[i].lstrip().startswith("|"):
                out[kind].append((i + 1, _cells(lines[i])))
                i += 1
            continue
        i += 1
    return out


def page_rows(text: str | None = None) -> list[Row]:
    """The key and file rows of the page: one per pattern of a first cell (a cell may name
    several, each in backticks); ``When`` is the third cell of key rows (comma-separated),
    the second of folder rows."""
    text = PAGE.read_text() if text is None else text
    rows = []
    for kind, body in page_tables(text).items():
        if kind not in ("summary", "position", "folder"):
            continue
        col = 1 if kind == "folder" else 2
        for line, cells in body:
            when = tuple(w.strip() for w in cells[col].split(",")) if len(cells) > col else ()
            for pattern in _code(cells[0]):
                rows.append(Row(kind, pattern, when, line))
    return rows


def _segment_re(segment: str) -> re.Pattern:
    parts = re.split(r"(<[^>]+>)", segment)
    return re.compile("".join(".+" if p.startswith("<") else re.escape(p) for p in parts))


def _segment_matches(pattern: str, segment: str, prefix: bool, values: dict) -> bool:
    if pattern in values:
        return segment in values[pattern]
    if _segment_re(pattern).fullmatch(segment):
        return True
    # a row naming a list (``failed_positions``) is also the row of its elements' keys
    return prefix and not pattern.endswith("[]") and segment == pattern + "[]"


def matches(
    row: Row, path: tuple[str, ...], prefix: bool = False, values: dict | None = None
) -> bool:
    """Whether ``row`` documents ``path`` (``prefix``: documents a path starting with it);
    ``values``: the keys a :data:`TYPED` placeholder stands for in this run."""
    segs = row.segments
    if segs[-1] == "*":
        segs = segs[:-1]
        if len(path) <= len(segs):
            return False
        path = path[: len(segs)]
    elif prefix:
        if len(path) < len(segs):
            return False
        path = path[: len(segs)]
    if len(path) != len(segs):
        return False
    values = values or {}
    return all(_segment_matches(p, s, prefix, values) for p, s in zip(segs, path, strict=True))


def key_paths(tree, prefix: tuple[str, ...] = ()) -> Iterator[tuple[str, ...]]:
    """Every leaf path of a JSON tree (module docstring)."""
    if isinstance(tree, dict) and tree:
        for k, v in tree.items():
            yield from key_paths(v, (*prefix, str(k)))
    elif isinstance(tree, list) and tree and prefix and all(isinstance(x, dict) for x in tree):
        head = (*prefix[:-1], prefix[-1] + "[]")
        for x in tree:
            yield from key_paths(x, head)
    else:
        yield prefix


def _applies(row: Row, summary: dict) -> bool | None:
    """Whether the keys of ``row`` must be there in the run of ``summary`` (all of its
    ``When`` hold), None where a ``When`` cannot tell."""
    got = [WHEN[w](summary) for w in row.when]
    if any(g is False for g in got):
        return False
    return None if any(g is None for g in got) else True


def _typed(summary: dict | None) -> dict[str, set[str]]:
    return {k: f(summary) for k, f in TYPED.items()} if summary else {}


def undocumented(tree, rows: list[Row], summary: dict | None = None) -> list[str]:
    """The key paths of ``tree`` that no row documents (``summary``: of the run, for the
    :data:`TYPED` placeholders; None: every placeholder stands for any key)."""
    values = _typed(summary)
    paths = dict.fromkeys(key_paths(tree))
    return [".".join(p) for p in paths if not any(matches(r, p, False, values) for r in rows)]


def not_written(tree, rows: list[Row], summary: dict) -> list[str]:
    """The rows that apply to the run of ``summary`` whose keys ``tree`` lacks."""
    values = _typed(summary)
    paths = list(dict.fromkeys(key_paths(tree)))
    return [
        f"{r.pattern} (line {r.line})"
        for r in rows
        if _applies(r, summary) and not any(matches(r, p, True, values) for p in paths)
    ]


def check_run(folder: Path) -> None:
    """The page against the outputs of one case in ``folder`` (``<out>/<case>``): its
    summary.json, its first position file and the files of the folder."""
    rows = page_rows()
    summary = json.loads((folder / "summary.json").read_text())
    position = json.loads((folder / "positions" / "0.json").read_text())
    by = {k: [r for r in rows if r.table == k] for k in ("summary", "position", "folder")}
    problems = []
    for what, tree, table in (
        ("summary.json", summary, "summary"),
        ("positions/0.json", position, "position"),
    ):
        miss = undocumented(tree, by[table], summary)
        if miss:
            problems.append(f"{what}: keys not in {PAGE.name}: {', '.join(miss)}")
        gone = not_written(tree, by[table], summary)
        if gone:
            problems.append(f"{what}: {PAGE.name} documents keys it lacks: {', '.join(gone)}")
    files = _folder_entries(folder)
    miss = [f for f in files if not any(fnmatchcase(f, _glob(r.pattern)) for r in by["folder"])]
    if miss:
        problems.append(f"{folder}: files not in {PAGE.name}: {', '.join(miss)}")
    gone = [
        f"{r.pattern} (line {r.line})"
        for r in by["folder"]
        if _applies(r, summary) and not any(fnmatchcase(f, _glob(r.pattern)) for f in files)
    ]
    if gone:
        problems.append(f"{folder}: {PAGE.name} documents files it lacks: {', '.join(gone)}")
    assert not problems, "\n".join(problems)


def _folder_entries(folder: Path) -> list[str]:
    """The files and folders of ``folder`` and of its folders (one level down), folders with
    a trailing ``/``: ``summary.json``, ``positions/``, ``positions/0.json``, ``fields/sun.bp/``."""

    def name(p: Path) -> str:
        return p.name + ("/" if p.is_dir() else "")

    out = []
    for p in sorted(folder.iterdir()):
        out.append(name(p))
        if p.is_dir():
            out += [f"{name(p)}{name(q)}" for q in sorted(p.iterdir())]
    return out


def _glob(pattern: str) -> str:
    """A folder row's pattern as a glob: ``<name>`` is any text."""
    return re.sub(r"<[^>]+>", "*", pattern)


# ---------------------------------------------------------------- the page itself (cheap)


def test_page_tables_parse():
    """Key rows, folder rows and the two legends are there; every row has its cells."""
    tables = page_tables(PAGE.read_text())
    for kind in TABLES.values():
        assert tables[kind], f"{PAGE.name}: no {kind} table"
    for kind in ("summary", "position"):
        for line, cells in tables[kind]:
            assert len(cells) == 4 and all(cells), f"{PAGE.name} line {line}: 4 cells, none empty"
            assert _code(cells[0]), f"{PAGE.name} line {line}: no key in backticks"
    for line, cells in tables["folder"]:
        assert len(cells) == 3 and all(cells), f"{PAGE.name} line {line}: 3 cells, none empty"


def test_every_key_is_listed_once():
    seen: dict[tuple[str, str], int] = {}
    for r in page_rows():
        assert (r.table, r.pattern) not in seen, (
            f"{PAGE.name}: {r.pattern} on lines {seen[(r.table, r.pattern)]} and {r.line}"
        )
        seen[(r.table, r.pattern)] = r.line


def test_every_when_and_placeholder_is_defined():
    """Every ``When`` a row uses is in the page's legend and known to this test (how it is
    told from a summary), and every placeholder a pattern uses is in the page's legend."""
    tables = page_tables(PAGE.read_text())
    legend = {c[0] for _, c in tables["when"]}
    assert legend == set(WHEN), f"{PAGE.name}: the When legend differs from tests' WHEN"
    placeholders = {p for _, c in tables["placeholder"] for p in _code(c[0])}
    for r in page_rows():
        for w in r.when:
            assert w in legend, f"{PAGE.name} line {r.line}: When {w!r} not in the legend"
        for p in re.findall(r"<[^>]+>", r.pattern):
            assert p in placeholders, f"{PAGE.name} line {r.line}: {p} not in the legend"


def test_matching_rules():
    """The path rules of the module docstring, on a small tree."""
    patterns = ("a.<mesh>", "b[].c", "d", "f.Z_<mesh>_<pinion>", "g.*", "h", "k.<gear key>", "k.m")
    rows = [Row("summary", p, ("every run",), 0) for p in patterns]
    rows.append(Row("summary", "d[].e", ("failed positions",), 0))
    tree = {
        "a": {"sun_pinion": 1.0},
        "b": [{"c": 1}, {"c": None}],
        "d": [],
        "f": {"Z_sun-SP_SP": 0.1},
        "g": {"x": {"y": [1, 2]}},
        "h": {},
        "k": {"sun": 1.0, "m": "text"},
    }
    run = {
        "bending_stress_iso6336": {"sun": {}},
        "failed_positions": [],
        "inputs": {"gearset": {"kind": "single_pinion"}},
    }
    assert undocumented(tree, rows, run) == []
    assert not_written(tree, rows, run) == []
    # a list of objects: its elements' keys, and the list's own row holds for them too
    failed = {**tree, "d": [{"e": 1}]}
    assert undocumented(failed, rows, run) == []
    assert not_written(failed, rows, {**run, "failed_positions": [{}]}) == []
    assert not_written(tree, rows, {**run, "failed_positions": [{}]}) == ["d[].e (line 0)"]
    # a key no row names; a typed placeholder stands for its set only
    wrong = {"a": {"m": {"n": 1}}, "i": 2, "k": {"ring": 1.0}}
    assert undocumented(wrong, rows, run) == ["a.m.n", "i", "k.ring"]
    assert undocumented(wrong, rows) == ["a.m.n", "i"]  # untyped without a run
    assert not [r for r in rows if matches(r, ("g",))]  # a subtree row needs keys under it
    with pytest.raises(KeyError):
        _applies(Row("summary", "x", ("sometimes",), 0), run)

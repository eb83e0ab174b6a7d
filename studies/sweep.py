"""One field of a case or of its gear set over several values, on the first variant's bodies.

``planetary-fe sweep``:

    planetary-fe sweep 1-GB --set bearing.tilting_stiffness=8.8e6,8.8e7,8.8e8
    planetary-fe sweep 1-GB --set gearset.input_torque=700,1378.7,2000 --level 0
    planetary-fe sweep my_case.toml --set gearset.gears.pinion.modifications.lead_crown_um=0,10,20

``--set FIELD=V1,V2,...`` names a field as the case file writes it: ``<table>.<key>`` of the
case (``bearing``, ``material``, ``model``, ``numerics``, ``system``), or ``gearset.<path>``
of its gear-set file (``gearset.input_torque``, ``gearset.gears.<gear>.<key>``,
``gearset.meshes.<index>.<key>``); each value is a TOML value (a number, a quoted or bare
string, true / false). Several ``--set`` sweep one field each, all around the case file.

Each variant is written as a case file (and, for a gear-set field, a gear-set file) under
``<out>/sweeps/<case>/<field>/``, checked as input before anything is solved (an invalid
value stops the command with code 2, naming the variant file and the field), and run as
``planetary-fe run`` runs a case (its own folder there, its positions reused by a later
sweep of the same inputs). All variants share one store of bodies: the factorizations, the
root-stress sectors and the bodies' compliance columns (:mod:`solvers.body_columns`). A
field that leaves the geometry alone (a bearing, the torque, the penalty) therefore solves
no body again after the first variant; a field that changes a mesh builds that body.

Beside the variants: ``sweep.json`` (every variant's value, case file, folder and the
quantities below, or why it has none), ``sweep.md`` (a table, a row per quantity) and
``sweep.png`` (a panel per quantity against the swept value): the moments and centroids of
the gear set's kind (means over the positions; a single pinion's moments with their closed
form at the variant's own load centroids, singh2007 Table 7, on the same panel), per mesh
the K_Hbeta of the summary and the largest interior contact stress, per loaded fillet the
recovered root stress. A variant that fails is named there, and the others are kept.

Exit status: that of ``planetary-fe run``, the largest over the variants.
"""

from __future__ import annotations

import argparse
import copy
import json
import math
import re
import tomllib
from dataclasses import dataclass
from pathlib import Path

import tomli_w
from mpi4py import MPI

from cases.gearset import NAME_PATTERN, CaseError
from cases.study_case import inputs_hash, load_study_case
from postprocess.paper_moments import MEAN_KEYS
from solvers.body_store import BodyStore
from studies.cli import (
    EXIT_INTERRUPTED,
    EXIT_INVALID_INPUT,
    EXIT_OK,
    InputError,
    exit_code,
    interrupt_on_sigterm,
    one_line,
)
from studies.files import ResultFileError, on_root, read_json, write_json
from studies.progress import Progress
from studies.provenance import code_hash
from studies.ranks import Ranks
from studies.run import (
    EXIT_EPILOG,
    Parser,
    add_run_options,
    case_options,
    inputs_valid,
    prepare_study,
    run_case,
)

#: the tables of a case file a field may name (``gearset.<path>`` names its gear set's)
CASE_TABLES = ("bearing", "material", "model", "numerics", "system")


@dataclass(frozen=True)
class Sweep:
    """One swept field: ``field`` as written on the command line, ``values`` parsed, and
    ``labels`` the values as given (they name the variants)."""

    field: str
    values: tuple
    labels: tuple[str, ...]

    @property
    def path(self) -> list[str]:
        return self.field.split(".")


def parse_set(text: str) -> Sweep:
    """``FIELD=V1,V2,...`` -> :class:`Sweep`; :class:`~studies.cli.InputError` names what
    is wrong."""
    field, sep, rest = text.partition("=")
    field = field.strip()
    labels = tuple(v.strip() for v in rest.split(",")) if sep else ()
    if not sep or not field or not labels or any(not v for v in labels):
        raise InputError(
            f"--set {text!r}: must be FIELD=V1,V2,... (e.g. bearing.tilting_stiffness=8.8e6,8.8e7)"
        )
    parts = field.split(".")
    if any(not p for p in parts) or len(parts) < 2:
        raise InputError(
            f"--set {field}: a field is <table>.<key> (e.g. bearing.tilting_stiffness)"
        )
    if parts[0] not in (*CASE_TABLES, "gearset"):
        raise InputError(
            f"--set {field}: {parts[0]!r} is not a table of a case file: one of "
            f"{', '.join(CASE_TABLES)}, or gearset.<field of the gear-set file>"
        )
    if len(set(labels)) != len(labels):
        raise InputError(f"--set {field}: a value is given twice ({', '.join(labels)})")
    for v in labels:
        if not NAME_PATTERN.fullmatch("v" + v):  # it follows the case name in a variant name
            raise InputError(
                f"--set {field}: value {v!r}: a value names its variant, so it is written with "
                "letters, digits and _ . + - (a number, or a bare string)"
            )
    return Sweep(field, tuple(_value(v) for v in labels), labels)


def _value(token: str):
    """A TOML value (number, boolean), else the token as a string."""
    try:
        return tomllib.loads(f"v = {token}")["v"]
    except tomllib.TOMLDecodeError:
        return token


def _set(table: dict, path: list[str], value, field: str, where: str) -> None:
    """table[path] = value; the tables on the way must exist where they name a gear or a
    mesh (a mistyped name is an error), other missing tables are made."""
    node = table
    for i, key in enumerate(path[:-1]):
        if isinstance(node, list):
            if not key.isdigit() or int(key) >= len(node):
                raise InputError(
                    f"--set {field}: {where} has {len(node)} {path[i - 1]} "
                    f"(index 0..{len(node) - 1})"
                )
            node = node[int(key)]
            continue
        if key not in node:
            if i > 0 and path[i - 1] in ("gears", "meshes"):
                have = ", ".join(node) if isinstance(node, dict) else ""
                raise InputError(
                    f"--set {field}: {where} has no {path[i - 1]}.{key} (it has: {have})"
                )
            node[key] = {}
        node = node[key]
    if not isinstance(node, dict):
        raise InputError(f"--set {field}: {'.'.join(path[:-1])} of {where} is not a table")
    node[path[-1]] = value


def variants(case: str, sweep: Sweep, folder: Path) -> list[tuple[Path, dict, dict | None]]:
    """Per value of ``sweep``: (its case file ``<folder>/<case>_<value>.toml``, the case
    file's tables with the value set and the variant named so, and for a gear-set field the
    gear set's tables with the value set, to be written beside it as ``.gearset.toml``). The
    case is loaded (and so checked) first; a gear set it names by path is named by absolute
    path. Nothing is written."""
    study = load_study_case(case)
    data = copy.deepcopy(study.source)
    base, gs_file = study.name, Path(study.gearset.path)
    if str(data.get("gearset", "")).endswith(".toml"):
        data["gearset"] = str(gs_file.resolve())
    out = []
    for value, label in zip(sweep.values, sweep.labels, strict=True):
        name = f"{base}_{label}"
        target = folder / f"{name}.toml"
        variant = copy.deepcopy(data)
        variant["name"] = name
        variant["description"] = f"{study.description}; sweep: {sweep.field} = {label}"
        gs = None
        if sweep.path[0] == "gearset":
            gs = copy.deepcopy(study.gearset.source)
            _set(gs, sweep.path[1:], value, sweep.field, gs_file.name)
            variant["gearset"] = str(target.with_suffix(".gearset.toml").resolve())
        else:
            _set(variant, sweep.path, value, sweep.field, Path(study.path).name)
        out.append((target, variant, gs))
    return out


def write_variants(planned: list[tuple[Path, dict, dict | None]]) -> list[Path]:
    """Write the case (and gear-set) files of :func:`variants`; returns the case files."""
    for target, case, gs in planned:
        target.parent.mkdir(parents=True, exist_ok=True)
        if gs is not None:
            target.with_suffix(".gearset.toml").write_text(tomli_w.dumps(gs))
        target.write_text(tomli_w.dumps(case))
    return [t for t, _, _ in planned]


#: the suffix of a moment's closed form beside the FE's (single pinion: singh2007 Table 7,
#: the mesh forces at the FE's own load centroids ZS, ZR; postprocess.summary.
#: analytic_reference), plotted on the FE moment's panel
CLOSED_FORM = " closed form"


def quantities(summary: dict) -> dict[str, float | None]:
    """What a sweep reports of one variant's summary: the kind's moments and centroids (not
    the spin moments Mz, zero by the free spin), for a single pinion each moment's closed
    form at the variant's own ZS, ZR (``<moment> closed form``: how much of the moment the
    load's axial shift explains), per mesh K_Hbeta and the largest interior contact stress
    (MPa), per loaded fillet the recovered root stress (MPa)."""
    kind = summary["inputs"]["gearset"]["kind"]
    at_z = (summary.get("analytic") or {}).get("at_fe_ZS_ZR") or {}
    out: dict[str, float | None] = {}
    for k in MEAN_KEYS[kind]:
        if not k.startswith("Mz"):
            out[k] = summary.get(k)
            if k in at_z:
                out[k + CLOSED_FORM] = at_z[k]
    for mesh, c in (summary.get("contact_stress_cycle") or {}).items():
        out[f"K_Hbeta {mesh}"] = c.get("K_Hbeta")
        out[f"contact stress {mesh} (MPa)"] = c.get("interior_p_max_MPa")
    for key, v in (summary.get("bending_stress_recovered") or {}).items():
        out[f"root stress {key} (MPa)"] = v
    return out


def sweep_record(case: str, sweep: Sweep, files: list[Path], folder: Path, made: list) -> dict:
    """``sweep.json``: per variant its value, case file, result folder and quantities, read
    from its summary where that summary was made from the variant as this sweep ran it
    (``made``: per variant its inputs hash and the code hash); a summary an earlier sweep
    left (other inputs, other code: this run wrote none) is not read."""
    rows = []
    for value, label, f, key in zip(sweep.values, sweep.labels, files, made, strict=True):
        run = folder / f.stem
        row = {"value": value, "label": label, "case_file": f.name, "folder": run.name}
        row["quantities"], row["missing"] = None, None
        if not (run / "summary.json").exists():
            row["missing"] = "no summary.json: its run failed or was stopped (see its messages)"
        else:
            try:
                summary = read_json(run / "summary.json")
                if (summary.get("inputs_hash"), summary["provenance"]["code_hash"]) != key:
                    row["missing"] = (
                        "its summary.json is from other inputs or code (this run wrote none)"
                    )
                else:
                    row["quantities"] = quantities(summary)
                    row["run"] = {
                        "sizes": summary.get("run"),
                        "positions": len(summary.get("positions") or []),
                        "root_stress": summary.get("bending_stress_method"),
                    }
                    row["warnings"] = list(summary.get("warnings") or [])
            except (ResultFileError, KeyError, TypeError) as exc:
                row["missing"] = f"its summary.json cannot be read ({one_line(exc)})"
        rows.append(row)
    return {"case": load_study_case(case).name, "field": sweep.field, "variants": rows}


def _number(v) -> str:
    return "-" if v is None else f"{v:.4g}"


def write_sweep(record: dict, folder: Path) -> list[Path]:
    """``sweep.json``, ``sweep.md`` and ``sweep.png`` of one swept field in ``folder``."""
    rows = record["variants"]
    done = [r for r in rows if r["quantities"] is not None]
    names = list(dict.fromkeys(k for r in done for k in r["quantities"]))
    field = record["field"]
    lines = [
        f"# {record['case']}: sweep of {field}",
        "",
        "Means over the mesh positions of each variant (moments N m, centroids mm); each "
        "variant's case file and results are in its folder here.",
        "",
        "![sweep](sweep.png)",
        "",
        "| quantity | " + " | ".join(r["label"] for r in done) + " |",
        "|---" * (len(done) + 1) + "|",
    ]
    for q in names:
        lines.append(f"| {q} | " + " | ".join(_number(r["quantities"].get(q)) for r in done) + " |")
    runs = {json.dumps(r["run"], sort_keys=True) for r in done}
    for run in sorted(runs):
        r = json.loads(run)
        lines += [
            "",
            f"Run: sizes {r['sizes']}, {r['positions']} position(s); root stress: "
            f"{r['root_stress'] or 'not read'}.",
        ]
    notes = [f"{field} = {r['label']}: {w}" for r in done for w in r["warnings"]]
    notes += [f"{field} = {r['label']}: no results ({r['missing']})" for r in rows if r not in done]
    if notes:
        lines += ["", "## Warnings and missing variants", ""] + [f"- {n}" for n in notes]
    paths = [folder / "sweep.json", folder / "sweep.md", folder / "sweep.png"]
    write_json(paths[0], record)
    paths[1].write_text("\n".join(lines) + "\n")
    _plot(record["case"], field, done, names, paths[2])
    return paths


def _with_unit(q: str) -> str:
    """A moment in N m, a centroid in mm (the stresses carry their unit in the name)."""
    if q.startswith("M"):
        return f"{q} (N m)"
    return f"{q} (mm)" if q.startswith("Z") else q


def _plot(title: str, field: str, done: list[dict], names: list[str], path: Path) -> None:
    """A panel per quantity against the swept value (log axis over a decade or more)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    numeric = all(
        isinstance(r["value"], int | float) and not isinstance(r["value"], bool) for r in done
    )
    x = [r["value"] for r in done] if numeric else list(range(len(done)))
    log = numeric and min(x, default=0) > 0 and max(x) >= 10 * min(x)
    cols = 3
    panels = [q for q in names if not q.endswith(CLOSED_FORM)]  # a closed form: on its FE's
    n_rows = max(1, math.ceil(len(panels) / cols))
    fig, axes = plt.subplots(n_rows, cols, figsize=(4.2 * cols, 2.8 * n_rows), squeeze=False)

    def curve(ax, q, style, label):
        y = [r["quantities"].get(q) for r in done]
        pts = [(a, b) for a, b in zip(x, y, strict=True) if b is not None]
        ax.plot([a for a, _ in pts], [b for _, b in pts], style, label=label)

    for ax, q in zip(axes.flat, panels, strict=False):
        curve(ax, q, "o-", "FE")
        if q + CLOSED_FORM in names:
            curve(ax, q + CLOSED_FORM, "k--", "closed form at the FE's ZS, ZR")
            ax.legend(fontsize=7)
        ax.set_title(_with_unit(q), fontsize=9)
        if log:
            ax.set_xscale("log")
        if not numeric:
            ax.set_xticks(x, [r["label"] for r in done])
        ax.grid(alpha=0.3)
    for ax in list(axes.flat)[len(panels) :]:
        ax.set_visible(False)
    for ax in axes[-1]:
        ax.set_xlabel(field, fontsize=8)
    fig.suptitle(f"{title}: {field}", fontsize=11)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def sweep_folder(out: Path, case: str, field: str) -> Path:
    """``<out>/sweeps/<case name>/<field>``."""
    name = load_study_case(case).name
    return Path(out) / "sweeps" / name / re.sub(r"[^A-Za-z0-9_.+-]", "_", field)


def parse_args(argv=None, prog: str = "planetary-fe sweep") -> argparse.Namespace:
    ap = Parser(prog=prog, description=__doc__.splitlines()[0], epilog=EXIT_EPILOG)
    ap.add_argument("case", help="a case name (cases/<name>.toml) or a case file path")
    ap.add_argument(
        "--set",
        dest="sets",
        action="append",
        required=True,
        metavar="FIELD=V1,V2,...",
        help="a field of the case (bearing.tilting_stiffness) or of its gear set "
        "(gearset.input_torque) and its values; repeat to sweep other fields",
    )
    add_run_options(ap)
    return ap.parse_args(argv)


def main(argv=None, comm: MPI.Comm = MPI.COMM_WORLD, prog: str = "planetary-fe sweep") -> int:
    args = parse_args(argv, prog)
    progress = Progress(comm, quiet=args.quiet)
    try:
        sweeps = [parse_set(s) for s in args.sets]
        if len({s.field for s in sweeps}) != len(sweeps):
            raise InputError("--set: a field is swept twice")
        load_study_case(args.case)
    except (InputError, CaseError) as exc:
        progress.error(one_line(exc))
        return EXIT_INVALID_INPUT
    ranks = Ranks(comm, log=Path(args.out) / "aborted.log")
    store = BodyStore(reuse=not args.no_reuse)  # every variant on the first one's bodies
    status = EXIT_OK
    try:
        with interrupt_on_sigterm():
            plans = []
            for sw in sweeps:
                folder = sweep_folder(args.out, args.case, sw.field)
                planned = variants(args.case, sw, folder)  # input errors before any file
                files = on_root(
                    comm, lambda p=planned: write_variants(p), f"writing the variants in {folder}"
                )
                plans.append((sw, folder, files))
            for _, folder, files in plans:  # every variant checked before any is solved
                checked = argparse.Namespace(
                    **{**vars(args), "cases": [str(f) for f in files], "out": folder}
                )
                if not inputs_valid(checked, comm, progress, ranks):
                    return EXIT_INVALID_INPUT
            for sw, folder, files in plans:
                variant = argparse.Namespace(**{**vars(args), "out": folder})
                for f in files:
                    status = max(status, run_case(str(f), variant, comm, progress, ranks, store))
                    if status == EXIT_INTERRUPTED:
                        break
                made = [
                    (inputs_hash(prepare_study(str(f), folder, case_options(args))[0]), code_hash())
                    for f in files
                ]
                record = sweep_record(args.case, sw, files, folder, made)
                on_root(
                    comm,
                    lambda r=record, d=folder: write_sweep(r, d),
                    f"writing {folder / 'sweep.md'}",
                )
                progress.info(f"{sw.field}: {len(files)} variants -> {folder / 'sweep.md'}")
                if status == EXIT_INTERRUPTED:
                    break
    except (InputError, CaseError, ResultFileError) as exc:
        progress.error(one_line(exc))
        status = exit_code(exc)
    except KeyboardInterrupt:
        progress.error("interrupted; finished variants and positions are kept")
        status = EXIT_INTERRUPTED
    finally:
        ranks.free()
    return status


__all__ = [
    "Sweep",
    "main",
    "parse_set",
    "quantities",
    "sweep_record",
    "variants",
    "write_sweep",
    "write_variants",
]

"""One study driver for any case file: mesh positions -> summary, contact patterns, pictures.

    python -m studies.run 1-GA [1-GB ...] [--level L] [--positions N] [--out results]
        [--scene system] [--no-reuse] [--quiet] [--traceback]
    python -m studies.run path/to/my_case.toml
    mpiexec -n 2 python -m studies.run 1-GA

A case is a study-case file (``cases/<name>.toml`` or any path): a gear set, the pinion
bearing, the material, the scene (``model.scene``) and the numerical settings (the contact
model among them, ``numerics.contact_model``: line or zone grids, recorded in the summary's
``inputs``; :mod:`postprocess.train_results` says how each is reported). It is solved
at N mesh positions over one base pitch of the sun: sun angles k (2 pi / Z_sun) / N, k = 0..
N-1, with the carrier fixed (:func:`studies.position.solve_position`). The bodies are
factorized once and reused by every position and every case of the command line that shares
their mesh, degree and material (:class:`solvers.body_store.BodyStore`; ``--no-reuse``
factorizes at every position). Each position is
written to ``<out>/<case>/positions/<k>.json`` as soon as it is solved, and reused by a later
run only if it was solved from the same inputs (hash of the resolved case and gear set), the
same settings and the same code (:mod:`studies.provenance`); the run says which positions it
reused and which it solved. A study that fails part way keeps what it finished. The
displacement of every body at the first position is written as VTX to
``<out>/<case>/fields/<body>.bp`` (ParaView), after the position file: a failed field write
is a warning, never a lost position. ``summary.json`` (:mod:`postprocess.summary`) holds the
means over the positions, the per-position values, the closed-form reference, the contact
and root stresses, plausibility ``warnings`` (:mod:`studies.plausibility`), the relative
discretisation ``uncertainty`` of each scalar from the convergence study of the case's gear
set under ``<out>/convergence`` (:mod:`studies.uncertainty`; None and a note without one),
and the inputs and provenance that produced them; it is not written when no position finished.

Under MPI every rank runs the same steps; a failure on any rank is shared with all of them
(:mod:`studies.ranks`), so a job never hangs on one rank's error.

Exit status (:mod:`studies.cli`): 0 every case finished; 1 a position failed while solving
(finished positions kept); 2 invalid input (case file, gear set, option; the message names
the file, field or option); 3 a result file or folder could not be written or read; 4 MPI
ranks out of step, job aborted; 5 an unexpected error (rerun with --traceback). With several
cases, the largest code of any case.
"""

from __future__ import annotations

import argparse
import os
import shutil
import sys
import tempfile
import time
import traceback
from pathlib import Path

from mpi4py import MPI

from cases.study_case import (
    MAX_LEVEL,
    MAX_POSITIONS,
    ROOT_FILLETS,
    SCENES,
    StudyCase,
    inputs_hash,
    load_study_case,
    study_inputs,
)
from meshing import sizing
from meshing.cache import CacheDirError, cache_dir
from postprocess.contact_pattern import draw_contact_patterns
from postprocess.flank_pictures import draw_flank_patterns
from postprocess.loaded_scene import loaded_scene_picture
from postprocess.paper_moments import MEAN_KEYS
from postprocess.run_scalars import sizes_in_words
from postprocess.summary import summarise
from solvers.body_store import BodyStore
from studies.case_options import CaseOptions
from studies.cli import (
    EXIT_INTERNAL,
    EXIT_INTERRUPTED,
    EXIT_INVALID_INPUT,
    EXIT_OK,
    INPUT_ERRORS,
    InputError,
    StudyFailed,
    exit_code,
    interrupt_on_sigterm,
    one_line,
    with_path,
)
from studies.contact_size import check_contact_size
from studies.files import ResultFileError, on_root, read_json, write_json
from studies.mesh_deflection import check_mesh_deflection
from studies.plausibility import input_warnings, plausibility_warnings
from studies.position import (
    check_coast_backlash,
    check_root_stress,
    roll_angles,
    solve_position,
    study_scene,
)
from studies.progress import LoopClock, Progress
from studies.provenance import code_hash, provenance
from studies.ranks import Ranks
from studies.settings import RunSettings
from studies.uncertainty import summary_uncertainty

# What a finished position file must hold to be reused (beyond the paper's scalars of its
# gear-set kind, postprocess.paper_moments.MEAN_KEYS): what postprocess.summary reads.
POSITION_KEYS = ("roll", "meshes", "pinions", "timings", "dofs", "reuse_key")


def reuse_key(
    study: StudyCase, level: int, degree: int, roll: float, variant: dict | None = None
) -> dict:
    """What a finished position must match to be reused; ``variant``: the sizes it takes
    from other levels (``flank_level``, ``fillet_level``)."""
    return {
        "inputs_hash": inputs_hash(study),
        "code_hash": code_hash(),
        "level": level,
        "degree": degree,
        **(variant or {}),
        "roll": roll,
    }


def _finished(path: Path, key: dict, study: StudyCase, progress: Progress) -> dict | None:
    """The position in ``path`` if it was solved with ``key``; None if absent or stale. An
    unreadable or incomplete file is reported and solved again."""
    if not path.is_file():
        return None
    try:
        old = read_json(path)
    except ResultFileError as exc:
        progress.warn(f"{exc}; solving the position again")
        return None
    if not isinstance(old, dict):
        progress.warn(f"{path}: not a position record (a JSON object); solving it again")
        return None
    if old.get("reuse_key") != key:
        return None
    missing = [k for k in (*POSITION_KEYS, *MEAN_KEYS[study.gearset.kind]) if k not in old]
    if missing:
        progress.warn(f"{path}: incomplete, lacks {', '.join(missing)}; solving it again")
        return None
    return old


def _output_folder(study: StudyCase, out_root: Path) -> Path:
    """``<out_root>/<case name>``, refused unless the name makes a folder inside ``out_root``
    (the case loader already refuses such names; this guards the driver). The path is
    normalised as written, not resolved: a results folder that is a symlink stays allowed."""
    root = Path(os.path.abspath(out_root))
    out = Path(os.path.normpath(root / study.name))
    if out == root or not out.is_relative_to(root):
        raise InputError(
            f"{study.name}: case name {study.name!r} would write outside the output folder "
            f"{out_root} (--out); a name is letters, digits and _ . + -"
        )
    return Path(out_root) / study.name


def _make_folders(out_root: Path, out: Path) -> None:
    for d in (out_root, out, out / "positions"):
        if d.exists() and not d.is_dir():
            raise ResultFileError(f"{d} is a file, not a folder (results folder --out {out_root})")
    (out / "positions").mkdir(parents=True, exist_ok=True)
    for d in (out, out / "positions"):  # a folder that exists may still refuse writing
        try:
            with tempfile.NamedTemporaryFile(dir=d, prefix=".write-check-"):
                pass
        except OSError as exc:
            raise ResultFileError(
                f"{d} cannot be written ({exc.strerror or exc}): nothing was solved; "
                f"choose another results folder (--out) or make it writable"
            ) from exc


def _check_mesh_cache() -> None:
    """The mesh cache folder is usable (made if needed), before any position is solved."""
    try:
        cache_dir()
    except CacheDirError as exc:
        raise ResultFileError(str(exc)) from exc


def run_study(
    name_or_path: str | Path,
    out_root: Path = Path("results"),
    comm: MPI.Comm = MPI.COMM_WORLD,
    *,
    options: CaseOptions | None = None,
    progress: Progress | None = None,
    ranks: Ranks | None = None,
    store: BodyStore | None = None,
) -> dict:
    """Solve every position (reusing finished ones), then write summary.json and the pictures.
    Returns the summary (on every rank). Raises :class:`~studies.cli.StudyFailed` after
    writing what finished if a position failed, the input errors of
    :data:`~studies.cli.INPUT_ERRORS` before anything is solved, and
    :class:`~studies.files.ResultFileError` when a result cannot be written (every rank
    raises the same error). ``options``: what the run asks beyond the case file
    (:class:`studies.case_options.CaseOptions`: level, positions, scene, root fillets, out of
    core; a scene, root fillets or out of core given is recorded in the summary's inputs).
    ``ranks``: the failure agreement of ``comm`` (made here if not given; it is collective
    to make, so a caller running several studies makes it once). ``store``: the bodies kept
    across positions and cases (factorized once; default: kept for this study's
    positions)."""
    progress = Progress(comm) if progress is None else progress
    study, settings, out = prepare_study(name_or_path, out_root, options, comm)
    store = BodyStore() if store is None else store
    for w in input_warnings(study):
        progress.warn(w)
    own = ranks is None
    ranks = Ranks(comm) if own else ranks
    try:
        return _run(study, Path(out_root), out, settings, comm, progress, ranks, store)
    finally:
        if own:
            ranks.free()


def prepare_study(
    name_or_path, out_root: Path, options: CaseOptions | None = None, comm=None
) -> tuple[StudyCase, RunSettings, Path]:
    """The study case with ``options`` applied, its run settings and its output folder,
    checked as input before anything is solved or written: the case file and its gear set,
    the options, the scene's geometry (milliseconds), the root-stress setting against the
    scene, the flank modifications against the backlash and the contact grid's memory on
    the ranks of ``comm`` (about a second; not collective). Raises the input errors of
    :data:`~studies.cli.INPUT_ERRORS`."""
    options = CaseOptions() if options is None else options
    study, settings = options.applied(load_study_case(name_or_path))
    out = _output_folder(study, out_root)
    try:  # the scene is pure geometry (milliseconds): a gear set it cannot place is input
        scene = study_scene(study, 0.0)
        for g in scene.gears:  # what the mesher would refuse (bores, rims, sectors)
            g.body.validate()
        if scene.carrier is not None:
            scene.carrier.validate()
    except INPUT_ERRORS as exc:
        raise InputError(f"{study.name}: model.scene = {study.model.scene!r}: {exc}") from exc
    check_root_stress(study, scene)  # before any position: a setting the scene cannot serve
    check_coast_backlash(study, scene)  # a set whose modifications eat its backlash
    check_contact_size(study, settings.spacing, scene, comm)  # a grid no machine here holds
    check_mesh_deflection(study)  # a load no zone band holds
    return study, settings, out


def _run(study, out_root: Path, out: Path, settings: RunSettings, comm, progress, ranks, store):
    level, variant, degree = settings.level, settings.variant, settings.degree
    n_pos, label = settings.positions, settings.label
    pos_dir = out / "positions"
    on_root(comm, lambda: _make_folders(out_root, out), f"creating {pos_dir}")
    on_root(comm, _check_mesh_cache, "mesh cache")
    t0 = time.perf_counter()
    rolls = roll_angles(study, n_pos)
    keys = [reuse_key(study, level, degree, roll, variant) for roll in rolls]

    def read_finished():
        return [
            _finished(pos_dir / f"{k}.json", key, study, progress) for k, key in enumerate(keys)
        ]

    old = on_root(comm, read_finished, f"reading the finished positions in {pos_dir}")
    reused = [k for k, p in enumerate(old) if p is not None]
    to_solve = [k for k in range(n_pos) if k not in reused]
    progress.info(
        f"{study.name}: {n_pos} position{'s' * (n_pos > 1)} at "
        f"{_sizes_text(label, level, variant)}, "
        f"{comm.size} rank{'s' * (comm.size > 1)} -> {out}"
    )
    if reused:
        progress.info(
            f"{study.name}: reusing position{'s' * (len(reused) > 1)} "
            f"{_numbers(reused)} (solved earlier from the same inputs, settings and code); "
            + (f"solving {_numbers(to_solve)}" if to_solve else "nothing to solve")
        )
    clock = LoopClock(n_pos, len(to_solve))
    fields = out / "fields"
    solved, failed = [], []
    for k, roll in enumerate(rolls):
        tag = f"{study.name} position {k + 1}/{n_pos}"
        pos = old[k]
        if pos is not None:
            pos["reused"] = True
            pos["position"] = k  # its index in the mesh cycle (solved may skip failed ones)
            solved.append(pos)
            clock.step()
            wall = pos["timings"].get("wall", float("nan"))
            progress.info(
                f"{tag}: reused (solved earlier in {wall:.1f} s): "
                f"{_headline(study, pos)}  {clock.status()}"
            )
            if k == 0 and not on_root(comm, fields.is_dir, f"reading {fields}"):
                progress.info(
                    f"{study.name}: no displacement fields in {fields} (not written by the "
                    "run that solved position 1); delete positions/0.json to solve it again "
                    "and write them"
                )
            continue
        if k == 0:  # the fields of other inputs must not stand beside these results
            on_root(comm, lambda: _remove(fields), f"removing the old {fields}")
        line = progress.position(tag)
        failure, write_fields = None, None
        try:
            pos = solve_position(
                study, roll, comm, settings, store=store, progress=line, keep_fields=k == 0
            )
            write_fields, pos.write_fields = pos.write_fields, None  # not held by `solved`
        except Exception as exc:  # shared with every rank below; finished positions stay
            failure = (one_line(exc), traceback.format_exc())
        errors = ranks.agree(failure, tag)
        seconds = line.close(failed=bool(errors))
        clock.step(seconds)
        if errors:
            message = _rank_messages(errors, comm.size)
            failed.append(
                {"position": k, "roll": roll, "error": message, "traceback": errors[0][1][1]}
            )
            progress.warn(f"{tag} failed: {message}")
            continue
        pos["reuse_key"] = keys[k]
        pos["position"] = k
        path = pos_dir / f"{k}.json"
        on_root(comm, lambda path=path, pos=pos: write_json(path, pos), f"writing {path}")
        solved.append(pos)
        progress.info(
            f"{tag}: {_headline(study, pos)}, solved in {pos['timings']['wall']:.1f} s"
            f"  {clock.status()}"
        )
        if write_fields is not None:
            _write_fields(write_fields, fields, study, comm, ranks, progress)
    if not solved:
        raise StudyFailed(
            f"{study.name}: {n_pos} of {n_pos} positions failed ({_distinct(failed)}); "
            f"summary.json not written (an earlier one in {out} is left as it was)"
        )
    meta = {
        "level": level,
        "degree": degree,
        **variant,
        "run": label,
        "scene": study.model.scene,
        "inputs": study_inputs(study),
        "inputs_hash": inputs_hash(study),
        "provenance": provenance(),
        "ranks": comm.size,
        "positions_reused": reused,
        "wall_time_s": time.perf_counter() - t0,
    }
    summary = summarise(study, solved, failed, meta)
    # the discretisation uncertainty per scalar, from the gear set's convergence study
    found = on_root(
        comm,
        lambda: summary_uncertainty(study, level, degree, out_root, variant=variant),
        f"reading the convergence studies under {out_root}",
    )
    summary.update(found)
    found_now = plausibility_warnings(study, summary) + widened_bands(study, solved)
    found_now += [  # a damaged or edited study is not passed over in silence
        f"{study.name}: convergence study skipped for the ±: {why}"
        for why in (summary.get("uncertainty_source") or {}).get("skipped") or []
    ]
    summary["warnings"] = input_warnings(study) + found_now  # the inputs' said before solving
    for w in found_now:
        progress.warn(w)
    on_root(
        comm, lambda: write_json(out / "summary.json", summary), f"writing {out / 'summary.json'}"
    )
    mesh_sizes = sizing.run_sizes(level, **variant)
    _pictures(study, solved, out, mesh_sizes, comm, progress)
    if failed:
        raise StudyFailed(
            f"{study.name}: {len(failed)} of {n_pos} positions failed ({_distinct(failed)}); "
            f"the {len(solved)} finished are in {out / 'summary.json'}"
        )
    progress.info(
        f"{study.name}: done, {len(solved) - len(reused)} solved, {len(reused)} reused, in "
        f"{time.perf_counter() - t0:.1f} s -> {out / 'summary.json'}"
    )
    return summary


def widened_bands(study: StudyCase, solved: list[dict]) -> list[str]:
    """A warning naming the positions solved on a zone band wider than the case's
    (:func:`studies.position.solve_position`), with the limit that would hold them."""
    wide = [p for p in solved if p.get("zone_gap_widened")]
    if not wide:
        return []
    to = max(p["zone_gap_widened"]["to_um"] for p in wide)
    reach = max(p["zone_gap_widened"]["reach_um"] for p in wide)
    return [
        f"{study.name}: position{'s' * (len(wide) > 1)} "
        f"{_numbers([p['position'] for p in wide])} reached {reach:.1f} um into the zone band "
        f"of [numerics] zone_gap_limit_um = {wide[0]['zone_gap_widened']['from_um']:g} and "
        f"{'were' if len(wide) > 1 else 'was'} solved on a band of up to {to:g} um (set it in "
        "the case file to solve every position on one band at once)"
    ]


def _numbers(ks: list[int]) -> str:
    """Position numbers as a person counts them (1-based)."""
    return ", ".join(str(k + 1) for k in ks)


def _rank_messages(errors: list, size: int) -> str:
    """The failure messages of the ranks that failed (one message when they agree)."""
    texts = [f[0] for _, f in errors]
    if size == 1 or len(set(texts)) == 1:
        return texts[0]
    return "; ".join(f"rank {r}: {f[0]}" for r, f in errors)


def _distinct(failed: list[dict]) -> str:
    """The distinct errors of the failed positions, each once, with the positions."""
    by: dict[str, list[int]] = {}
    for f in failed:
        by.setdefault(f["error"], []).append(f["position"])
    return "; ".join(f"position {_numbers(ks)}: {e}" for e, ks in by.items())


def _remove(folder: Path) -> None:
    if folder.is_dir():
        shutil.rmtree(folder)


def _write_fields(write_fields, fields: Path, study, comm, ranks: Ranks, progress: Progress):
    """The VTX fields, written into ``fields.partial`` and renamed to ``fields`` once
    complete. Called after the position file is on disk: a failure is a warning."""
    partial = fields.with_name(fields.name + ".partial")
    try:
        on_root(comm, lambda: _remove(partial), f"removing {partial}")
        failure = None
        try:
            write_fields(partial)
        except Exception as exc:
            failure = one_line(exc)
        errors = ranks.agree(failure, f"writing the displacement fields to {partial}")
        if errors:
            raise ResultFileError(_rank_messages([(r, (m,)) for r, m in errors], comm.size))
        on_root(comm, lambda: partial.rename(fields), f"renaming {partial} to {fields}")
    except ResultFileError as exc:
        progress.warn(
            f"{study.name}: displacement fields not written ({exc}); the solved position is "
            "kept; delete positions/0.json and run again to write them"
        )
        try:
            on_root(comm, lambda: shutil.rmtree(partial, ignore_errors=True), "cleaning up")
        except ResultFileError:
            pass


def _sizes_text(label: str, level: int, variant: dict) -> str:
    """``L1P1F2R2 (level 1 with level 2's flanks and contact grid and level 2's refined
    fillets)``; ``L1P1`` for a level's own sizes."""
    return f"{label} ({sizes_in_words(level, variant)})" if variant else label


def _headline(study: StudyCase, pos: dict) -> str:
    if study.gearset.kind == "single_pinion":
        return f"My_pin {pos['My_pin']:.2f} N m, ZS {pos['ZS']:+.2f}, ZR {pos['ZR']:+.2f} mm"
    return (
        f"My_SP {pos['My_SP']:.2f}, My_RP {pos['My_RP']:.2f} N m, "
        f"ZS {pos['ZS']:+.2f}, ZR {pos['ZR']:+.2f} mm"
    )


def _pictures(study: StudyCase, solved: list[dict], out: Path, level, comm, progress):
    """Contact patterns and the loaded scene (rank 0; ``level``: the sizes solved, an index
    or a :class:`meshing.sizing.Level`). A picture that cannot be drawn is a warning: the
    numbers are in summary.json already."""

    def patterns():
        draw_contact_patterns(study, solved, out)

    def flank_patterns():
        draw_flank_patterns(study, solved, out)

    def scene():
        first = solved[0]
        sc = study_scene(study, first["roll"])
        title = f"{study.name}: loaded scene, roll {first['roll']:.4f} rad"
        loaded_scene_picture(sc, first, level, out / "loaded_scene.png", title)

    drawings = (
        (patterns, "contact pattern charts"),
        (flank_patterns, "flank contact patterns"),
        (scene, "loaded scene picture"),
    )
    for draw, what in drawings:
        try:
            on_root(comm, draw, f"drawing the {what} of {study.name}")
        except ResultFileError as exc:
            progress.warn(f"{exc}; summary.json is written")


class Parser(argparse.ArgumentParser):
    """Usage errors on one line from rank 0, exit code 2 (invalid input)."""

    def error(self, message):
        if MPI.COMM_WORLD.rank == 0:
            self.print_usage(sys.stderr)
            sys.stderr.write(f"error: {message}\n")
        sys.exit(EXIT_INVALID_INPUT)


#: the exit codes as the --help epilog gives them
EXIT_EPILOG = (
    "exit status: 0 ok, 1 a position failed (finished ones kept), 2 invalid input, "
    "3 a result file could not be written or read, 4 MPI ranks out of step (aborted), "
    "5 unexpected error"
)


def parse_args(argv=None, prog: str = "python -m studies.run") -> argparse.Namespace:
    ap = Parser(prog=prog, description=__doc__.splitlines()[0], epilog=EXIT_EPILOG)
    ap.add_argument("cases", nargs="+", help="case names (cases/<name>.toml) or case file paths")
    add_run_options(ap)
    return ap.parse_args(argv)


def add_run_options(ap: argparse.ArgumentParser) -> None:
    """The options of one run of a case (level, positions, results folder, scene, root
    fillets, out of core, reuse, quiet, traceback), shared by ``run`` and ``sweep``."""
    ap.add_argument(
        "--level",
        type=int,
        default=None,
        help=f"mesh level 0-{MAX_LEVEL}, as the case file's [model] level (default: the case's)",
    )
    ap.add_argument(
        "--positions",
        type=int,
        default=None,
        help=f"positions per base pitch, 1-{MAX_POSITIONS} (default: the case's)",
    )
    ap.add_argument("--out", type=Path, default=Path("results"), help="results folder")
    ap.add_argument(
        "--scene",
        choices=SCENES,
        default=None,
        help="solve in this scene instead of the case's model.scene",
    )
    ap.add_argument(
        "--root-fillets",
        choices=ROOT_FILLETS,
        default=None,
        help="refine the root fillets (root stress read) or not, instead of the "
        "case's numerics.root_fillets",
    )
    ap.add_argument(
        "--out-of-core",
        action="store_true",
        default=None,
        help="keep the bodies' LU factors on disk (numerics.out_of_core: the same "
        "answer to round-off, a fraction of the memory)",
    )
    ap.add_argument(
        "--no-reuse", action="store_true", help="factorize every body at every position"
    )
    ap.add_argument("--quiet", action="store_true", help="only warnings and errors (for CI)")
    ap.add_argument(
        "--traceback",
        action="store_true",
        help="print Python tracebacks of errors (for a bug report)",
    )


def main(argv=None, comm: MPI.Comm = MPI.COMM_WORLD, prog: str = "python -m studies.run") -> int:
    args = parse_args(argv, prog)
    progress = Progress(comm, quiet=args.quiet)
    ranks = Ranks(comm, log=Path(args.out) / "aborted.log")
    store = BodyStore(reuse=not args.no_reuse)  # bodies factorized once for all cases
    status = EXIT_OK
    # serial: SIGTERM (kill, a batch system's limit) stops as Ctrl-C does, finished positions
    # kept and the finally blocks run; on several ranks it keeps its default (one rank
    # unwinding alone would wait in a collective for the others)
    try:
        with interrupt_on_sigterm():
            if not inputs_valid(args, comm, progress, ranks):
                return EXIT_INVALID_INPUT
            for name in args.cases:  # a failed case does not stop the others
                status = max(status, run_case(name, args, comm, progress, ranks, store))
                if status == EXIT_INTERRUPTED:
                    break
    except KeyboardInterrupt:  # between two cases
        progress.error("interrupted; finished positions are kept")
        status = EXIT_INTERRUPTED
    finally:
        ranks.free()
    return status


def case_options(args: argparse.Namespace) -> CaseOptions:
    """What the command line asks of every case beyond its file."""
    return CaseOptions(
        level=args.level,
        positions=args.positions,
        scene=args.scene,
        root_fillets=args.root_fillets,
        out_of_core=args.out_of_core,
    )


def inputs_valid(args: argparse.Namespace, comm, progress: Progress, ranks: Ranks) -> bool:
    """Every case of the command line checked as input (:func:`prepare_study`) before any
    is solved, so code 2 keeps its meaning with several cases: one invalid case file beside
    valid ones stops the command before a position is solved, each invalid one named on a
    line. Failures other than input are left to the run, which reports them."""
    valid = True
    for name in args.cases:
        failure = None
        try:
            prepare_study(name, args.out, case_options(args), comm)
        except INPUT_ERRORS as exc:
            failure = (EXIT_INVALID_INPUT, with_path(one_line(exc), name), traceback.format_exc())
        except Exception:  # not input: the run meets it again and reports it
            pass
        errors = ranks.agree(failure, f"case {name}")
        if errors:
            if args.traceback and failure is not None:
                sys.stderr.write(f"[rank {comm.rank}] {failure[2]}")
            progress.error(dict(errors).get(0, errors[0][1])[1])
            valid = False
    if not valid and len(args.cases) > 1:
        progress.error("nothing was solved: correct the case(s) above or leave them out")
    return valid


def run_case(
    name: str,
    args: argparse.Namespace,
    comm,
    progress: Progress,
    ranks: Ranks,
    store: BodyStore | None = None,
) -> int:
    """One case of the command line: its exit code, with its error printed on one line
    (every rank agrees on the outcome first, so none goes on alone)."""
    failure = None
    try:
        run_study(
            name,
            args.out,
            comm,
            options=case_options(args),
            progress=progress,
            ranks=ranks,
            store=store,
        )
    except KeyboardInterrupt:
        progress.error(f"{name}: interrupted; finished positions are kept")
        return EXIT_INTERRUPTED
    except Exception as exc:
        code = exit_code(exc)
        text = with_path(one_line(exc), name)
        if code == EXIT_INTERNAL:
            text += " (an unexpected error: rerun with --traceback and report it)"
        failure = (code, text, traceback.format_exc())
    errors = ranks.agree(failure, f"case {name}")
    if not errors:
        return EXIT_OK
    if args.traceback and failure is not None:
        sys.stderr.write(f"[rank {comm.rank}] {failure[2]}")
    _, text, _ = dict(errors).get(0, errors[0][1])  # rank 0's message if it has one
    progress.error(text)
    return max(f[0] for _, f in errors)


if __name__ == "__main__":
    sys.exit(main())

"""One mesh position of a study, end to end: scene -> placed meshes -> gear train -> solve ->
results (collective; the same dict on every rank).

The data flow of the pipeline in one function: the scene the case file names is built from
its gear set at the sun angle ``roll`` (:func:`meshing.scenes.build_scene`), the body meshes
are loaded in their own frames (:func:`meshing.scene_bodies.load_body_meshes`), the contact
model is
built and solved (:mod:`solvers.gear_train`), and the result is reduced to what the gear
train carries (:mod:`postprocess.train_results`), the paper's quantities of each branch
(:mod:`postprocess.paper_moments`) and the FE root stress (:mod:`solvers.root_submodel`,
:mod:`solvers.root_stress`).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from cases.gearset import CaseError
from meshing.scene_bodies import load_body_meshes
from meshing.scenes import build_scene, cycle_angles, refines_root_fillets
from meshing.submodel import submodel_level
from postprocess.paper_moments import paper_moments
from postprocess.train_results import train_results
from solvers.body_store import BodyStore
from solvers.elastic_body import LinearSolver
from solvers.errors import ZoneReachError
from solvers.flank_grid import flank_contact_pairs, is_coast, mesh_name
from solvers.gear_train import bearing_stiffness, build_gear_train
from solvers.results import write_vtx
from solvers.root_stress import root_stress
from solvers.root_submodel import sector_teeth, submodel_root_stress
from solvers.train_inputs import TrainInputs
from solvers.zone_reach import check_zone_reach, suggested_limit_um
from studies.memory import peak_rss_mb
from studies.settings import RunSettings

_SECTOR_MEMO: dict[str, dict[str, int]] = {}  # see cycle_sector_teeth


def roll_angles(study, positions: int) -> list[float]:
    """Sun angles (rad) of ``positions`` equally spaced mesh positions over one base pitch."""
    z_sun = study.gearset.gears[study.gearset.power_path[0]].teeth
    return [2.0 * math.pi / z_sun * k / positions for k in range(positions)]


def train_inputs(study) -> TrainInputs:
    """What the gear-train model takes of ``study`` (:class:`solvers.train_inputs.TrainInputs`):
    the one place the solvers' inputs are read from a study case."""
    num, mat, gs = study.numerics, study.material, study.gearset
    return TrainInputs(
        youngs_modulus=mat.youngs_modulus,
        poisson_ratio=mat.poisson_ratio,
        gear_youngs_modulus=mat.gear_youngs_modulus,
        bearing_stiffness=tuple(float(k) for k in bearing_stiffness(study.bearing)),
        torque_per_branch_Nm=gs.input_torque / gs.planets,
        linear_solver=LinearSolver(num.linear_solver, num.linear_tolerance, num.out_of_core),
        contact_model=num.contact_model,
        zone_gap_limit_mm=num.zone_gap_limit_um * 1e-3,
        modifications=getattr(gs, "modifications", None) or {},
        sun_radial_stiffness=study.system.sun_radial_stiffness,
        pin_position_errors_um=study.system.pin_position_errors_um,
    )


def check_root_stress(study, scene) -> None:
    """:class:`cases.gearset.CaseError` if ``numerics.root_stress = "global"`` meets a scene
    whose global fillets are coarse: there is nothing refined to read, and a run would end
    without a root stress and without an error."""
    if study.numerics.root_stress == "global" and not refines_root_fillets(scene):
        raise CaseError(
            f"{study.name}: numerics.root_stress = 'global' reads the global model's refined "
            f"root fillets, and the {study.model.scene} scene with numerics.root_fillets = "
            f"{study.numerics.root_fillets!r} refines none: choose 'submodel' (read on "
            "submodels, any fillets) or 'none', or root_fillets = 'refined'"
        )


def check_coast_backlash(study, scene) -> None:
    """:class:`cases.gearset.CaseError` where a mesh's flank modifications add more material
    to its coast flanks than the normal backlash leaves: the flanks would start inside each
    other (a lead slope f_Hb adds f_Hb / 2 at one face end of each flank,
    :mod:`gears.microgeometry`), a set that cannot be assembled. Read on the coast contact
    lines at this position (every section of the face lies on one of them; the lead
    modifications vary along the face only), before anything is meshed."""
    mods = {g: m for g, m in train_inputs(study).modifications.items() if not m.is_zero}
    if not mods:
        return
    grids, _ = flank_contact_pairs(scene, 1.0, None, None, modifications=mods)
    for name, (grid, info) in grids.items():
        if not is_coast(name):
            continue
        k = int(np.argmin(grid.gap0))
        if grid.gap0[k] > 0.0:
            continue
        j_n = float(info.dev_a[k] + info.dev_b[k])
        raise CaseError(
            f"{study.name}: the coast flanks of mesh {mesh_name(name)} start "
            f"{-grid.gap0[k] * 1e3:.0f} um inside each other at z = {grid.x_a[k, 2]:.1f} mm: "
            f"the flank modifications of {', '.join(sorted(mods))} add "
            f"{(j_n - grid.gap0[k]) * 1e3:.0f} um of material there against a normal backlash "
            f"of {j_n * 1e3:.0f} um (a lead slope adds half its value at one face end of each "
            "flank): reduce the modifications or set a larger backlash"
        )


def study_scene(study, roll: float, **options):
    """The scene of ``study`` at sun angle ``roll``: its ``model.scene`` with the root fillets
    of ``numerics.root_fillets`` ("auto": the scene's own choice) and ``options``
    (:func:`meshing.scenes.planetary_scene`)."""
    fillets = {"auto": None, "refined": True, "coarse": False}[study.numerics.root_fillets]
    return build_scene(
        study.model.scene, study.gearset, roll, **{"fine_fillets": fillets, **options}
    )


def cycle_sector_teeth(
    study, roll: float, spacing: float, width=None, scene_options: dict | None = None
) -> dict[str, int]:
    """Per root-stress key the most teeth its drive grid names at any of the
    :data:`meshing.scenes.CYCLE_SAMPLES` sun angles of the mesh cycle that holds ``roll``
    (:func:`solvers.root_submodel.sector_teeth`; memoized per gear set, scene, contact
    numerics, grid and cycle): the size of the root-stress sectors at every position of the
    cycle, so one sector per gear and side serves every position and every case of the gear
    set. Sized per position, a sector was set up again whenever its count changed (2B-GA's
    ring side names 4, 5, 4, 4, 4 teeth over its five positions) and the store, which keeps
    what the previous position used, had dropped the other size."""
    options = dict(scene_options or {})
    cycle, angles = cycle_angles(study.gearset, roll)
    num = study.numerics
    key = repr(
        (
            study.gearset,
            study.material,
            study.model.scene,
            num.contact_model,
            num.zone_gap_limit_um,
            num.root_fillets,
            spacing,
            width,
            cycle,
            sorted(options.items()),
        )
    )
    if key not in _SECTOR_MEMO:
        most: dict[str, int] = {}
        for angle in angles:
            scene = study_scene(study, angle, **options)
            for k, n in sector_teeth(scene, train_inputs(study), spacing, width).items():
                most[k] = max(most.get(k, 0), n)
        if len(_SECTOR_MEMO) >= 64:
            _SECTOR_MEMO.pop(next(iter(_SECTOR_MEMO)))
        _SECTOR_MEMO[key] = most
    return dict(_SECTOR_MEMO[key])


@dataclass(frozen=True)
class PositionExtras:
    """What a research study asks of a position beyond one run of a case.

    ``scene_options``: passed to the scene builder (e.g. ``pinion_radial_offset`` in mm,
    ``phase_offsets``; :func:`meshing.scenes.planetary_scene`); ``submodel_levels``: read
    the root stress also on the submodels of these global levels (their sectors,
    :func:`meshing.submodel.submodel_level`) at the same global solution, in
    ``bending_stress_fillets`` keyed by the read fillet size (``"%g"``): the submodel ladder
    of a convergence study; ``own_sectors``: False skips the read on the level's own sectors
    (``bending_stress`` None, for a diagnostic that reads ``submodel_levels`` only);
    ``sector_log``: called with a line per root-stress sector solved (every rank)."""

    scene_options: dict = field(default_factory=dict)
    submodel_levels: tuple = ()
    own_sectors: bool = True
    sector_log: Callable[[str], None] | None = None


class Position(dict):
    """The results of one solved position (JSON-ready: ``positions/<k>.json``), and where
    asked (``keep_fields``) ``write_fields(folder)``, which writes every body's displacement
    as VTX (``<folder>/<body>.bp``, collective) so the caller can save the result first and
    the fields after it (None otherwise: the closure holds the position's whole model)."""

    write_fields: Callable[[Path], list[Path]] | None = None


def solve_position(
    study,
    roll: float,
    comm,
    settings: RunSettings | None = None,
    *,
    store: BodyStore | None = None,
    progress: Callable[[str], None] | None = None,
    keep_fields: bool = False,
    extras: PositionExtras | None = None,
) -> Position:
    """Solve ``study`` at sun angle ``roll`` (rad) with ``settings`` (the case's where they
    leave one open, :meth:`studies.settings.RunSettings.resolved`); ``store``: bodies and
    meshes kept from earlier positions and cases (default: none kept; a store without reuse
    has its bodies' factors freed after the solve); ``progress``: called with the name of
    each stage as it starts (``scene``, ``meshes``, ``model``, ``solve``, ``post``);
    ``keep_fields``: :attr:`Position.write_fields` set; ``extras``: a research study's
    additions (:class:`PositionExtras`)."""
    store = BodyStore() if store is None else store
    store.begin_position()
    extras = PositionExtras() if extras is None else extras
    run = (settings or RunSettings()).resolved(study)
    num = study.numerics
    level, degree, spacing, penalty = run.level, run.degree, run.spacing, run.penalty_factor
    sizes, other = run.sizes, run.variant  # the result names the sizes of other levels
    scene_options = extras.scene_options
    submodel_levels, sector_log = extras.submodel_levels, extras.sector_log
    t0 = time.perf_counter()
    _stage(progress, "scene")
    scene = study_scene(study, roll, **scene_options)
    check_root_stress(study, scene)
    t_scene = time.perf_counter()
    _stage(progress, "meshes")
    meshes = load_body_meshes(scene, sizes, comm, store.mesh_memo)
    t_meshes = time.perf_counter()
    inputs = train_inputs(study)
    widened = None
    while True:
        _stage(progress, "model")
        model = build_gear_train(
            scene,
            meshes,
            inputs,
            degree=degree,
            spacing=spacing,
            penalty_factor=penalty,
            store=store,
        )
        _stage(progress, "solve")
        result = model.problem.solve()
        try:  # a load that reaches the edge of a zone grid's band: solved on a wider band
            reach = check_zone_reach([*model.grids.values(), *model.coast_grids.values()], result)
            break
        except ZoneReachError as exc:
            inputs, widened = _wider_band(inputs, exc, widened)
    t_solve = time.perf_counter()
    _stage(progress, "post")
    train = train_results(model, result)
    out = {**train, **paper_moments(train, scene, study.gearset, spacing)}
    if not store.reuse:  # no later position takes the factors: free them before the submodels
        for body in model.problem.bodies.values():
            body.release()
    # the root stress (numerics.root_stress): on submodels of the loaded teeth, driven by the
    # global solution whatever its fillets (the global model's own values kept as a check
    # where it refines them), or on the global model's fillets where it refines them
    out["bending_stress"] = None
    refined = refines_root_fillets(scene)
    out["root_fillets"] = "refined" if refined else "coarse"
    # one sector size per key over the mesh cycle
    sector = None
    if num.root_stress == "submodel":
        sector = cycle_sector_teeth(study, roll, spacing, scene_options=scene_options)
    if num.root_stress == "submodel" and extras.own_sectors:
        bs = submodel_root_stress(model, result, level, store, sector=sector, log=sector_log)
        if refined:  # the global model's own value beside it, a check
            check = root_stress(model, result)
            bs["global"] = {k: check[k] for k in bs["locations"]}
        out["bending_stress"] = bs
    elif num.root_stress == "global":  # refined: check_root_stress
        out["bending_stress"] = root_stress(model, result)
    t_post = time.perf_counter()
    # the submodel ladder: timed apart (and the memory peak before it kept), so a run's wall
    # time and memory stay those of the run alone
    rss_mb = peak_rss_mb()
    if submodel_levels:
        if num.root_stress != "submodel":
            raise ValueError("submodel_levels needs numerics.root_stress = 'submodel'")
        out["bending_stress_fillets"] = {
            f"{submodel_level(k).fillet:g}": submodel_root_stress(
                model, result, k, store, sector=sector, log=sector_log
            )
            for k in submodel_levels
        }
    t_ladder = time.perf_counter() - t_post
    out.update(
        case=study.name,
        scene=study.model.scene,
        roll=roll,
        dofs=model.dofs,
        ranks=comm.size,
        level=level,
        degree=degree,
        **other,
        grid_spacing_mm=spacing,
        penalty_factor=penalty,
        timings={
            "scene": t_scene - t0,
            "meshes": t_meshes - t_scene,
            **model.timings,
            **{k: float(v) for k, v in result.timings.items()},
            "solve_wall": t_solve - t_meshes,
            "post": t_post - t_solve,
            "wall": time.perf_counter() - t0 - t_ladder,
            **(
                {"fillet_ladder": t_ladder, "peak_rss_mb_before_ladder": rss_mb}
                if submodel_levels
                else {}
            ),
        },
    )
    # per drive grid its tooth pairs (rows [first, last + 1) of their grid points: a zone
    # grid's cells; each station's pair is in the mesh's stations["line"])
    out["grid_lines"] = {k: v[1].lines for k, v in model.grids.items()}
    out["zone_reach_um"] = reach
    out["zone_gap_limit_um"] = inputs.zone_gap_limit_mm * 1e3
    out["zone_gap_widened"] = widened
    out["g0_max_abs_mm"] = float(max(np.abs(v[0].gap0).max() for v in model.grids.values()))
    position = Position(out)
    if keep_fields:
        problem = model.problem

        def write_fields(folder: Path) -> list[Path]:
            return write_vtx(folder, problem, result)

        position.write_fields = write_fields
    return position


#: solves of one position on a band widened after a refusal of the reach check, at most
WIDENINGS = 3


def _wider_band(inputs: TrainInputs, exc: ZoneReachError, widened: dict | None):
    """The inputs with the gap limit the reach check suggests (:func:`solvers.zone_reach.
    suggested_limit_um`) and the record of the widening (``from_um``: the case's limit,
    ``to_um``, ``reach_um``: the reach that asked for it, ``solves``); ``exc`` again where
    the suggestion is no wider (the largest limit) or after :data:`WIDENINGS` widenings.

    The band is a numerical setting: cells only, the answer no longer depends on it once the
    reach check holds (``solvers.zone_reach``). A softer bearing, a higher torque or a sweep
    of them moves the load further into the band than the case's limit allows; the position
    is then solved on the band that holds it instead of refused, and says so."""
    limit = inputs.zone_gap_limit_mm * 1e3
    reach = max(exc.partial.get("zone_reach_um", {}).values(), default=0.0)
    wider = suggested_limit_um(reach)
    solves = 1 if widened is None else widened["solves"]
    if not wider > limit or solves > WIDENINGS:
        raise exc
    record = {
        "from_um": limit if widened is None else widened["from_um"],
        "to_um": wider,
        "reach_um": reach,
        "solves": solves + 1,
    }
    return replace(inputs, zone_gap_limit_mm=wider * 1e-3), record


def _stage(progress: Callable[[str], None] | None, name: str) -> None:
    if progress is not None:
        progress(name)

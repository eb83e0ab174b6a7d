"""A convergence study of a case from its runs: per reported scalar the Richardson
extrapolation over the three finest h-levels, the error and uncertainty of every run (the
other element degree against the same extrapolation), and the cheapest run that meets the
accuracy targets of issue 13.

The grid size h of a level (:data:`meshing.sizing.LEVELS`, recorded in each run as ``h_mm``)
is the element size where the scalar is read: the size of the fillets read for the root
stresses (keys under ``bending_stress``: the submodel's, :data:`meshing.submodel.SUBMODEL_FILLET`,
or the global model's for ``bending_stress_global``), the flank size for everything else
(moments, load centroids and
contact stresses come from the flank contact; the contact grid spacing follows the flank
size by default). The ratios are not constant (flank 1.0, 0.7, 0.45 mm: 1.43 then 1.56;
submodel fillet 0.3, 0.2, 0.15 mm: 1.5 then 1.33), so the generalised three-grid form is used
(:func:`studies.convergence.richardson.richardson`). As a check of that choice every scalar is also
extrapolated with h = N_dof^(-1/3) (``extrapolated_h_dof``); the two agree when the ladder is
in its asymptotic range. The GCI uses the observed order capped at the formal one
(:func:`_p_cap`): 2 (:data:`P_CAP`) for moments, offsets and line loads (integrals of the P1
displacement) and for the root stresses read on P2 submodels, 1 for a point stress of P1
elements (contact pressure, the global model's fillets). A root stress read on a CG
submodel has a noise floor (:data:`CG_NOISE`): a change between levels within it has no
sign (:func:`studies.convergence.richardson.richardson`).

Targets (:func:`recommend`): moments within 1 % and stresses within 5 %, judged on each
run's uncertainty U (the ± the reports print; it is at least the error against the
extrapolation), a difference of two moments relative to the larger of them
(:data:`REFERENCE_KEYS`); a targeted scalar a run lacks, or that has no U, fails it. A
stress that is a peak at the line ends (where a line load without a relief has no
converged value: keys with ``edge``, the top-level ``contact_stress`` peak, the cycle
``p_max_MPa`` that includes the edges) is reported but not a target. Of the root
stress's two readings the recovered one is the target where the runs hold it, the nodal
maxima then checks (:data:`RECOVERED_PREFIXES`). Where a scalar has no
extrapolation (not monotone) its error is bounded by the spread of the levels instead.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

from postprocess.paper_moments import DIFFERENTIALS
from postprocess.run_scalars import VARIANT_KEYS, row_label, scalar_kind, unit, variant
from studies.convergence.richardson import (
    MOMENT_RTOL,
    NEAR_ZERO,
    SAFETY,
    STRESS_RTOL,
    off_ladder,
    richardson,
    two_grid,
)
from studies.convergence.scatter import scatter_floors

P_CAP = 2.0
# Edge values, not targets: contact-grid edge points, cell peaks, the root stress within
# one element of a face end (a corner value that grows with refinement, solvers.root_stress)
# and the one beside a submodel's point force (the unresolved field of a point load).
EDGE_PATTERNS = (
    "edge",
    "contact_stress.",
    ".p_max_MPa",
    "bending_stress_face_end.",
    "bending_stress_near_load.",
)
# Checks, not targets: the global model's own fillet values beside a submodel's
# (solvers.root_submodel) and the largest fillet cell value (a cell's mean, below the surface).
CHECK_PATTERNS = ("bending_stress_global.", "bending_stress_cell.")
# The root stress's two readings of the fillet surface and of ISO's line: the nodal maxima
# (solvers.root_stress) and the moving least-squares recovery (solvers.surface_recovery,
# in runs since 2026-11-30). A study whose runs hold the recovered readings targets them and
# keeps the nodal ones as checks: a nodal maximum is the largest of values that scatter from
# node to node (1-GB's ring line 4.6 % between equally valid sectors, 1.6 % recovered), so
# its ladder measures that scatter more than the discretisation error. A study solved
# before has only the nodal readings, and targets them.
NODAL_PREFIXES = ("bending_stress.", "bending_stress_tangent.")
RECOVERED_PREFIXES = ("bending_stress_recovered.", "bending_stress_tangent_recovered.")


def holds_recovered(rows: list[dict]) -> bool:
    """Whether every finished run of ``rows`` holds recovered root-stress readings. Every,
    not any: a study reduced from runs of older and newer code (``--reduce-only``) whose
    ladder lacks them in some run has no ladder of them, and its nodal readings must stay
    the targets, or its root stresses would have none."""
    ok = [r for r in rows if "error" not in r]
    return bool(ok) and all(any(k.startswith(RECOVERED_PREFIXES) for k in r["scalars"]) for r in ok)


def target(key: str, recovered: bool = False) -> float | None:
    """The relative accuracy target of a scalar (None: not a target). ``recovered``: the
    study holds the recovered root-stress readings, which are then the targets and the
    nodal ones checks (:data:`RECOVERED_PREFIXES`); else the nodal ones are the targets."""
    kind = scalar_kind(key)
    if kind == "moment":
        return MOMENT_RTOL
    if kind != "stress" or any(p in key for p in EDGE_PATTERNS + CHECK_PATTERNS):
        return None
    if key.startswith(NODAL_PREFIXES if recovered else RECOVERED_PREFIXES):
        return None
    return STRESS_RTOL


def _h(row: dict, key: str) -> float:
    h = row["h_mm"]
    if key.startswith("bending_stress_global"):  # the global fillets beside a submodel's
        return h.get("global_fillet", h["fillet"])
    return h["fillet" if key.startswith("bending_stress") else "fine"]


def _zero_scales(row: dict) -> dict[str, float]:
    """Per kind and unit of scalar (``"offset/mm"``), the magnitude below which a value
    counts as zero: :data:`NEAR_ZERO` of the largest of its kind and unit (an offset in um is
    not compared with one in mm, a line load in N/mm not with a load factor)."""
    out: dict[str, float] = {}
    for k, v in row["scalars"].items():
        group = _unit_group(k)
        out[group] = max(out.get(group, 0.0), abs(v))
    return {k: NEAR_ZERO * v for k, v in out.items()}


def _unit_group(key: str) -> str:
    return f"{scalar_kind(key)}/{unit(key)}"


#: the noise of a root stress read on a CG submodel, relative (solvers.root_submodel's
#: CG + GAMG to rtol 1e-6 with the rigid first guess: recording 1-GB and 2B-GA again moved
#: every root stress by up to 0.062 %); a change between levels below it has no
#: sign. The direct solves of the global model (MUMPS) are exact to round-off.
CG_NOISE = 1e-3


def _read_on_submodel(row: dict, key: str) -> bool:
    """Whether ``key`` of ``row`` is read on a P2 root-stress submodel (every
    ``bending_stress*`` key but the global model's own ``bending_stress_global``)."""
    sub = (row.get("numerics") or {}).get("root_stress") == "submodel"
    return sub and key.startswith("bending_stress") and not key.startswith("bending_stress_global")


def _p_cap(row: dict, key: str) -> float:
    """The GCI's cap of the observed order: the formal order of the scalar. A point stress
    of P_k elements converges as h^k: the submodels' root stresses are P2
    (:data:`meshing.submodel.SUBMODEL_DEGREE`), every other stress is read on the global
    model of the run's degree (contact pressure, the global fillets); moments, offsets and
    line loads (integrals of the P1 displacement) converge as h^2, :data:`P_CAP`."""
    if scalar_kind(key) != "stress" or _read_on_submodel(row, key):
        return P_CAP
    return float(row["degree"])


def _noise(row: dict, key: str) -> float:
    return CG_NOISE if _read_on_submodel(row, key) else 0.0


#: the root-stress keys read on submodels, whose error splits into the driver's (the global
#: model's level) and the submodel's (its fillet size): :func:`root_stress_split`
SPLIT_PREFIXES = (
    "bending_stress.",
    "bending_stress_tangent.",
    "bending_stress_recovered.",
    "bending_stress_tangent_recovered.",
)
#: the formal order of the driver's part of a submodel's root stress (the two-grid GCI): the
#: submodel sees the global model only through its displacement at the cut (P1: O(h^2)) and
#: the contact forces (integrals over the flanks, like the moments, O(h^2); observed 3.7-4.2
#: for the moments of 1-GB), not through a point stress of the global model (O(h))
DRIVER_ORDER = 2.0


def _fillet_value(row: dict, key: str, fillet: float) -> float | None:
    """A run's value of ``key`` on the submodel of fillet size ``fillet`` (mm): its own
    scalar at its own size, else its ``fillet_scalars``
    (:func:`studies.convergence.position_runs.fillet_scalars`)."""
    if abs(row["h_mm"]["fillet"] - fillet) < 1e-12:
        return row["scalars"].get(key)
    return (row.get("fillet_scalars") or {}).get(f"{fillet:g}", {}).get(key)


def _ladder_record(res, labels_or_sizes, values) -> dict:
    return {
        "at": list(labels_or_sizes),
        "values": list(values),
        "status": res.status,
        "order": res.order,
        "extrapolated": res.extrapolated,
        "uncertainty": list(res.uncertainty),
        "note": res.note,
    }


def root_stress_split(
    lad: list[dict], key: str, case_level: int, zero_scale: float = 0.0, floor: float | None = None
):
    """The error of a root stress read on a submodel (:mod:`solvers.root_submodel`), split
    into its two sources, or None where the runs do not hold the two ladders
    (:func:`studies.convergence.driver.submodel_levels`):

    * driver: the global model's level, at the fixed submodel of the case's level (read
      fillet f_D): the values of every ladder run on that submodel against the flank size
      (Richardson over three levels, the two-grid GCI over two);
    * submodel: the submodel's level (the whole sector refined), at the fixed driver of the
      case's level: f_D and the two sectors read with it, the two finer ones where they
      exist (Richardson over the three against the read fillet size, the stress
      concentration's own length; a P2 submodel, order capped at 2), its U at each fillet
      at least ``floor``, the scatter between equally valid sectors where it was measured
      (:mod:`studies.convergence.scatter`; None: not measured, the ladder's U alone).

    Separable errors: the extrapolated value X = D_ext S_ext / v_D (D_ext, S_ext the two
    ladders' limits, v_D the case level's value); per run g of own fillet f_g the
    uncertainty U_g = U_driver(g) + U_submodel(f_g), where U_submodel(f_g) is the submodel
    ladder's at f_g, or, for a size coarser than the ladder's, the step |v_g(f_g) -
    v_g(f_D)| / |v_g| at the run's own driver plus U_submodel(f_D). The coupled ladder
    (both refined at once) mixes the two: 1-GB at roll 0, the ring's ISO 60 deg value on
    the level-0 driver is 584 / 642 / 642 / 631 MPa with 0.3 / 0.2 / 0.15 / 0.1 mm fillets,
    so the level-0 submodel (0.3 mm) is 9 % low while every finer one agrees within 2 %,
    and a spread over the coupled levels 0-2 (9.2 %) charges the default level with it."""
    base = next((r for r in lad if r["level"] == case_level), None)
    if base is None or not base.get("fillet_scalars"):
        return None
    f_d = base["h_mm"]["fillet"]
    # the case's sector and the two read beside it, coarse to fine
    sizes = sorted({f_d, *(float(f) for f in base["fillet_scalars"])}, reverse=True)
    if len(sizes) < 3:
        return None
    i = sizes.index(f_d)
    sizes = sizes[max(0, min(i - 1, len(sizes) - 3)) :][:3]
    drv_vals = [_fillet_value(r, key, f_d) for r in lad]
    sub_vals = [_fillet_value(base, key, f) for f in sizes]
    if any(v is None for v in drv_vals + sub_vals):
        return None
    labels = [row_label(r) for r in lad]
    h_drv = [r["h_mm"]["fine"] for r in lad]
    if len(lad) >= 3:
        drv = richardson(
            h_drv[-3:], drv_vals[-3:], p_cap=P_CAP, zero_scale=zero_scale, noise=CG_NOISE
        )
        labels, drv_vals = labels[-3:], drv_vals[-3:]
    else:
        drv = two_grid(h_drv, drv_vals, DRIVER_ORDER, zero_scale=zero_scale)
    sub = richardson(sizes, sub_vals, p_cap=P_CAP, zero_scale=zero_scale, noise=CG_NOISE)
    u_sub = dict(zip(sizes, sub.uncertainty, strict=True))
    if floor is not None:  # the scatter between equally valid sectors
        u_sub = {f: None if u is None else max(u, floor) for f, u in u_sub.items()}
    v_d = sub_vals[sizes.index(f_d)]
    ext = None
    if drv.extrapolated is not None and sub.extrapolated is not None and abs(v_d) > zero_scale:
        ext = drv.extrapolated * sub.extrapolated / v_d
    unc, err = {}, {}
    for r, lab, u_drv, v_fd in zip(
        lad[-len(labels) :], labels, drv.uncertainty, drv_vals, strict=True
    ):
        v = r["scalars"][key]
        f_g = r["h_mm"]["fillet"]
        u_s = next((u for f, u in u_sub.items() if abs(f - f_g) < 1e-12), None)
        if u_s is None and f_g > f_d and u_sub[f_d] is not None and abs(v) > zero_scale:
            u_s = abs(v - v_fd) / abs(v) + u_sub[f_d]
        unc[lab] = None if u_drv is None or u_s is None else u_drv + u_s
        err[lab] = None if ext is None else (v - ext) / abs(ext)
    return {
        "status": "split",
        "order": None,
        "extrapolated": ext,
        "gci_order": None,
        "note": f"driver {drv.status}, submodel {sub.status}, "
        + ("sector scatter not measured" if floor is None else f"sector scatter {floor:.2%}"),
        "rel_error": err,
        "uncertainty": unc,
        "uncertainty_abs": {
            lab: None if u is None else u * abs(lad_v)
            for (lab, u), lad_v in zip(
                unc.items(), [r["scalars"][key] for r in lad[-len(labels) :]], strict=True
            )
        },
        "split": {
            "driver": _ladder_record(drv, labels, drv_vals),
            "submodel": _ladder_record(sub, sizes, sub_vals),
            "sector_floor": floor,
            "fillet_mm": f_d,
        },
    }


def ladder(rows: list[dict], degree: int = 1) -> tuple[list[dict], list[dict]]:
    """The three finest finished h-levels of ``degree`` (coarse to fine) and the other
    finished runs (other degrees, and runs with sizes of other levels,
    :func:`postprocess.run_scalars.variant`)."""
    ok = [r for r in rows if "error" not in r]
    on = [r for r in ok if r["degree"] == degree and not variant(r)]
    levels = sorted(on, key=lambda r: r["level"])[-3:]
    return levels, [r for r in ok if r not in levels]


def scalar_table(
    rows: list[dict],
    degree: int = 1,
    case_level: int | None = None,
    floors: Mapping[str, float] | None = None,
) -> dict[str, dict]:
    """Per scalar key (those every ladder run has): values, status, observed order,
    extrapolated value, and per run label the relative error, relative and absolute
    uncertainty (see the module docstring); the root stresses read on submodels split into
    the driver's and the submodel's error where the runs hold both ladders
    (:func:`root_stress_split`; ``case_level``: the level of the case, whose run holds the
    submodel ladder; ``floors``: per root stress the scatter between equally valid sectors,
    under the submodel ladder's U, :func:`studies.convergence.scatter.scatter_floors`)."""
    lad, others = ladder(rows, degree)
    if not lad:
        return {}
    keys = [k for k in lad[-1]["scalars"] if all(k in r["scalars"] for r in lad)]
    recovered = holds_recovered(lad)
    zero = _zero_scales(lad[-1])
    table = {}
    for key in keys:
        kind = scalar_kind(key)
        zs = zero.get(_unit_group(key), 0.0)
        entry = {
            "kind": kind,
            "unit": unit(key),
            "target": target(key, recovered),
            "values": {
                row_label(r): r["scalars"][key] for r in (*lad, *others) if key in r["scalars"]
            },
        }
        f = [r["scalars"][key] for r in lad]
        if abs(f[-1]) <= zs:  # zero by physics (Mz of a pinion free to spin): no target
            entry.update(target=None, near_zero=True)
        split = None
        if case_level is not None and key.startswith(SPLIT_PREFIXES):
            split = root_stress_split(
                lad, key, case_level, zero_scale=zs, floor=(floors or {}).get(key)
            )
        if split is not None:
            entry.update(split)
            for r in others:
                if key in r["scalars"]:
                    _off_ladder_split(entry, r, key, f, zs)
            table[key] = entry
            continue
        if len(lad) == 2:  # the third grid did not fit: Roache's two-grid GCI
            res = two_grid([_h(r, key) for r in lad], f, _p_cap(lad[-1], key), zero_scale=zs)
            labels = [row_label(r) for r in lad]
            entry.update(
                status=res.status,
                order=None,
                extrapolated=None,
                gci_order=res.gci_order,
                note=res.note,
                rel_error=dict.fromkeys(labels),
                uncertainty=dict(zip(labels, res.uncertainty, strict=True)),
                uncertainty_abs=dict(zip(labels, res.uncertainty_abs, strict=True)),
            )
            _off_ladder_runs(entry, res, others, key, f, zs)
            table[key] = entry
            continue
        h = [_h(r, key) for r in lad]
        if len(lad) < 3 or len(set(h)) < 3:  # levels 3 and 4 read the same sector
            why = f"{len(lad)} h-level(s) finished, two or three needed"
            if len(lad) == 3:
                why = f"two ladder runs read it on the same grid (h {h} mm): no three grids"
            entry.update(status="incomplete", order=None, extrapolated=None, note=why)
            table[key] = entry
            continue
        cap, noise = _p_cap(lad[-1], key), _noise(lad[-1], key)
        res = richardson(h, f, p_cap=cap, zero_scale=zs, noise=noise)
        by_dof = richardson(
            [r["dofs"] ** (-1.0 / 3.0) for r in lad], f, p_cap=cap, zero_scale=zs, noise=noise
        )
        labels = [row_label(r) for r in lad]
        entry.update(
            status=res.status,
            order=res.order,
            extrapolated=res.extrapolated,
            gci_order=res.gci_order,
            note=res.note,
            rel_error=dict(zip(labels, res.rel_error, strict=True)),
            uncertainty=dict(zip(labels, res.uncertainty, strict=True)),
            uncertainty_abs=dict(zip(labels, res.uncertainty_abs, strict=True)),
            extrapolated_h_dof=by_dof.extrapolated,
            order_h_dof=by_dof.order,
        )
        if res.extrapolated is not None and by_dof.extrapolated is not None:
            d = by_dof.extrapolated - res.extrapolated
            entry["h_measure_difference"] = (
                None if abs(res.extrapolated) <= zs else (d / abs(res.extrapolated))
            )
        _off_ladder_runs(entry, res, others, key, f, zs)
        table[key] = entry
    return table


def _off_ladder_split(entry: dict, r: dict, key: str, f: list[float], zs: float) -> None:
    """A run off the ladder against a split root stress's ladders (:func:`root_stress_split`),
    into ``entry``. A run read on the case level's sector (a run with other levels' sizes,
    :func:`postprocess.run_scalars.variant`) is a point of the driver ladder's, which reads
    every level on that sector: its U is built as a ladder run's, U_driver + U_submodel(f_D),
    with U_driver = Fs |v - D_ext| / |v| (the spread of the driver ladder and v where it has
    no D_ext) and U_submodel(f_D) the case sector's, at least its scatter. Judged on its
    value against X alone, a run whose driver error happens to cancel its sector's would pass
    with a U below its sector's own (1-GB's L1P1F2R2, pinion ring side: 2.6 % against the
    4.9 % of a driver bound plus the sector's 1.9 %). Any other run (another degree, another
    sector): Fs |v - X|, else the spread with the ladder, at least the sector scatter."""
    lab, v = row_label(r), r["scalars"][key]
    x, sp = entry["extrapolated"], entry["split"]
    floor = sp["sector_floor"] or 0.0
    entry["rel_error"][lab] = None if x is None else (v - x) / abs(x)
    if abs(r["h_mm"]["fillet"] - sp["fillet_mm"]) < 1e-12 and abs(v) > zs:
        drv, sub = sp["driver"], sp["submodel"]
        d_ext = drv["extrapolated"]
        u_drv = (
            SAFETY * abs(v - d_ext)
            if d_ext is not None
            else max(*drv["values"], v) - min(*drv["values"], v)
        ) / abs(v)
        u_sub = sub["uncertainty"][sub["at"].index(sp["fillet_mm"])]
        u = None if u_sub is None else u_drv + max(u_sub, floor)
        entry["uncertainty"][lab] = u
        entry["uncertainty_abs"][lab] = None if u is None else u * abs(v)
        return
    u_abs = SAFETY * abs(v - x) if x is not None else max(*f, v) - min(*f, v)
    u_abs = max(u_abs, floor * abs(v))
    entry["uncertainty_abs"][lab] = u_abs
    entry["uncertainty"][lab] = u_abs / abs(v) if abs(v) > zs else None


def _off_ladder_runs(
    entry: dict, res, others: list[dict], key: str, f: list[float], zs: float
) -> None:
    """Each run off the ladder (another degree, other levels' sizes) against the ladder's
    result, into ``entry``:
    its error against the extrapolation, else the spread of the ladder and its value
    (:func:`studies.convergence.richardson.off_ladder`; a two-level ladder too, whose study lists
    the run and so must give it a ±)."""
    for r in others:
        if key in r["scalars"]:
            o = off_ladder(res, r["scalars"][key], f, zero_scale=zs)
            lab = row_label(r)
            entry["rel_error"][lab] = o["rel_error"]
            entry["uncertainty"][lab] = o["uncertainty"]
            entry["uncertainty_abs"][lab] = o["uncertainty_abs"]


#: a difference of two larger moments is judged against them, not against itself: the
#: SP-RP differential (about 25 N m of two 150-170 N m moments, 2B-GA) holds its moments'
#: 1 % only as 6-7 % of itself; its own relative U is still what the reports print
REFERENCE_KEYS = DIFFERENTIALS


def _error_bound(entry: dict, label: str) -> tuple[float | None, str]:
    """The bound a run is judged on: its uncertainty U, the ± the reports print (the GCI
    with the capped order, at least the error against the extrapolation with the observed
    one; without an extrapolation, the spread bound, the two-grid GCI or the split's sum)."""
    how = {"monotone": "U (GCI)", "two-grid": "two-grid GCI", "split": "driver + submodel bound"}
    return entry.get("uncertainty", {}).get(label), how.get(entry.get("status"), "spread bound")


def _reference_scale(row: dict, key: str) -> float | None:
    """|value| / the larger |value| of the moments ``key`` is the difference of
    (:data:`REFERENCE_KEYS`), or None (judged against itself)."""
    refs = REFERENCE_KEYS.get(key)
    if not refs or not all(k in row["scalars"] for k in (key, *refs)):
        return None
    big = max(abs(row["scalars"][k]) for k in refs)
    return abs(row["scalars"][key]) / big if big > 0.0 else None


def recommend(rows: list[dict], table: dict[str, dict]) -> dict:
    """Per finished run: does every targeted scalar meet its target (moments 1 %, stresses
    5 %) with its uncertainty U, the ± the reports print (a difference of two moments,
    :data:`REFERENCE_KEYS`, relative to the larger of them); the worst moment and stress; and
    the cheapest run (wall time) that meets them. A targeted scalar the run lacks (a failed
    read), or whose ladder gives no U, fails it (``missing``, ``no_bound``): a run is not
    passed on what it did not report."""
    verdicts = []
    ok = [r for r in rows if "error" not in r]
    have = {k for r in ok for k in r["scalars"]}
    recovered = holds_recovered(ladder(ok)[0])  # the ladder's, as scalar_table's targets
    for r in ok:
        label = row_label(r)
        worst: dict[str, dict] = {}
        failing, missing, no_bound = [], [], []
        for key in sorted(have):
            entry = table.get(key)
            tol = target(key, recovered) if entry is None else entry.get("target")
            if tol is None:
                continue
            if key not in r["scalars"]:
                missing.append(key)
                continue
            err, how = (None, "") if entry is None else _error_bound(entry, label)
            if err is None:
                no_bound.append(key)
                continue
            scale = _reference_scale(r, key)
            if scale is not None:
                refs = " and ".join(REFERENCE_KEYS[key])
                err, how = err * scale, f"{how}, relative to the larger of {refs}"
            kind = entry["kind"]
            if kind not in worst or err > worst[kind]["error"]:
                worst[kind] = {"key": key, "error": err, "how": how, "target": tol}
            if err > tol:
                failing.append(key)
        verdicts.append(
            {
                "run": label,
                "level": r["level"],
                "degree": r["degree"],
                **variant(r),
                "time_s": r["time_s"]["total"],
                "peak_rss_mb": r["peak_rss_mb"],
                "meets": not (failing or missing or no_bound) and bool(worst),
                "failing": failing + missing + no_bound,
                "missing": missing,
                "no_bound": no_bound,
                "worst": worst,
            }
        )
    meeting = sorted((v for v in verdicts if v["meets"]), key=lambda v: v["time_s"])
    best = meeting[0] if meeting else None
    return {
        "targets": {"moment": MOMENT_RTOL, "stress": STRESS_RTOL},
        "root_stress_targets": "recovered" if recovered else "nodal",
        "runs": verdicts,
        "recommended": None if best is None else {k: best[k] for k in RECOMMENDED if k in best},
        "note": _note(best, verdicts),
    }


#: what the recommendation keeps of the chosen run
RECOMMENDED = ("run", "level", "degree", *VARIANT_KEYS, "time_s", "peak_rss_mb")


def _note(best: dict | None, verdicts: list[dict]) -> str:
    if best is not None:
        return (
            f"{best['run']} is the cheapest run with every moment's U within "
            f"{MOMENT_RTOL:.0%} and every targeted stress's U within {STRESS_RTOL:.0%} "
            f"({best['time_s']:.0f} s, "
            f"{best['peak_rss_mb'] / 1024:.1f} GB per run)"
        )
    if not verdicts:
        return "no run finished"
    by_kind = []
    for kind, tol in (("moment", MOMENT_RTOL), ("stress", STRESS_RTOL)):
        ok = sorted(
            (v for v in verdicts if kind in v["worst"] and v["worst"][kind]["error"] <= tol),
            key=lambda v: v["time_s"],
        )
        if ok:
            by_kind.append(f"every {kind} within {tol:.0%} from {ok[0]['run']} on (the cheapest)")
        else:
            fam = sorted(
                {
                    k.split(".", 1)[0]
                    for v in verdicts
                    for k in v["failing"]
                    if k.split(".", 1)[0] != k
                }
            )
            by_kind.append(
                f"no run has every {kind} within {tol:.0%}"
                + (f" (failing: {', '.join(fam)})" if kind == "stress" and fam else "")
            )
    parts = []
    for v in verdicts:
        w = ", ".join(f"{k} {d['key']} {d['error']:.1%}" for k, d in sorted(v["worst"].items()))
        parts.append(f"{v['run']}: worst {w}" if w else f"{v['run']}: nothing to compare")
    return (
        "no run meets the targets (" + "; ".join(by_kind) + "), so the level stays a cost "
        "choice and the ± printed beside every value carries the error of the level used "
        "(worst U: " + "; ".join(parts) + ")"
    )


def reduce_study(conv: dict) -> dict:
    """The convergence study ``conv`` (a convergence.json) with its reductions, ``scalars``
    (:func:`scalar_table`) and ``recommendation`` (:func:`recommend`), made by today's code
    from its stored ``runs``. The reductions are outside the
    source hash (:mod:`postprocess.run_scalars`), so a fix to them takes effect on every
    stored study, recorded or not, without solving a run again. The root stresses' sector
    U is at least the scatter kept in the study's ``sector_scatter``
    (:mod:`studies.convergence.scatter`). A study without ``case_level`` (written before
    2026-11-28) is returned as stored."""
    if "case_level" not in conv or not isinstance(conv.get("runs"), list):
        return conv
    floors = scatter_floors(conv.get("sector_scatter") or [], conv["case_level"])
    table = scalar_table(
        conv["runs"], conv.get("ladder_degree", 1), conv["case_level"], floors=floors
    )
    return {**conv, "scalars": table, "recommendation": recommend(conv["runs"], table)}


def compare_runs(recorded: Mapping, again: Mapping) -> dict:
    """A run solved again against its record (``python -m studies.convergence CASE
    --reproduce L``): every scalar of the rows' ``scalars`` and ``fillet_scalars`` (keyed
    ``<fillet> mm:<key>``) compared. ``scalars``: how many both rows hold; ``identical``: how
    many are the same float (to the bit); ``max_rel_diff``: the largest |b - a| / max(|a|,
    z) over the others, z the zero scale of the scalar's kind and unit in the recorded run
    (:func:`_zero_scales`: a free pinion's spin moment of 3e-13 N m is round-off of zero, not
    a value to be reproduced to 1e-11 of itself), None when all are identical; ``worst``: its
    key; ``dofs``: the two runs' DOFs (another count: another mesh, whose differences are
    not round-off); ``targets``: per kind with an accuracy target (moment, stress:
    :func:`target`, the recovered root stresses where both rows hold them) the largest such
    difference among the targeted scalars and its key (what a reader holds against the ± of
    that kind); ``missing``: keys one row holds and
    the other does not (a changed reading, not a reproduction)."""

    def flat(row: Mapping) -> dict[str, float | None]:
        out = dict(row.get("scalars") or {})
        for fillet, vals in (row.get("fillet_scalars") or {}).items():
            out.update({f"{fillet} mm:{k}": v for k, v in vals.items()})
        return out

    a, b = flat(recorded), flat(again)
    zero = _zero_scales({"scalars": {k.split(":")[-1]: v for k, v in a.items() if v is not None}})
    both = sorted(a.keys() & b.keys())
    recovered = any(k.split(":")[-1].startswith(RECOVERED_PREFIXES) for k in both)
    same, worst, rel = 0, None, None
    targets: dict[str, dict] = {}
    for k in both:
        x, y = a[k], b[k]
        if x == y or (x is None and y is None):
            d = 0.0
            same += 1
        elif x is None or y is None:
            d = math.inf
        else:
            scale = max(abs(x), zero.get(_unit_group(k.split(":")[-1]), 0.0))
            d = abs(y - x) / scale if scale else abs(y - x)
        if d > 0 and (rel is None or d > rel):
            rel, worst = d, k
        name = k.split(":")[-1]
        if target(name, recovered) is not None:
            kind = scalar_kind(name)
            if kind not in targets or d > targets[kind]["max_rel_diff"]:
                targets[kind] = {"max_rel_diff": d, "key": k}
    return {
        "scalars": len(both),
        "identical": same,
        "max_rel_diff": rel,
        "worst": worst,
        "targets": targets,
        "missing": sorted(a.keys() ^ b.keys()),
        "dofs": [recorded.get("dofs"), again.get("dofs")],
    }

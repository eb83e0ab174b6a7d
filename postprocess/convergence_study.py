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
(:func:`postprocess.convergence.richardson`). As a check of that choice every scalar is also
extrapolated with h = N_dof^(-1/3) (``extrapolated_h_dof``); the two agree when the ladder is
in its asymptotic range. The GCI uses the observed order capped at 2 (:data:`P_CAP`: the
order of P1 displacements, the fastest any scalar of a P1 model converges formally).

Targets (:func:`recommend`): moments within 1 % and stresses within 5 % of the extrapolated
value. A stress that is a peak at the line ends (where a line load without a relief has no
converged value: keys with ``edge``, the top-level ``contact_stress`` peak, the cycle
``p_max_MPa`` that includes the edges) is reported but not a target. Where a scalar has no
extrapolation (not monotone) its error is bounded by the spread of the levels instead.
"""

from __future__ import annotations

from postprocess.convergence import (
    FORMAL_ORDER,
    MOMENT_RTOL,
    NEAR_ZERO,
    STRESS_RTOL,
    off_ladder,
    richardson,
    run_label,
    scalar_kind,
    two_grid,
    unit,
)

P_CAP = 2.0
# Edge values, not targets: contact-grid edge points, cell peaks, and the root stress within
# one element of a face end (a corner value that grows with refinement, solvers.root_stress).
EDGE_PATTERNS = ("edge", "contact_stress.", ".p_max_MPa", "bending_stress_face_end.")
# Checks, not targets: the global model's own fillet values beside a submodel's
# (solvers.root_submodel) and the largest fillet cell value (a cell's mean, below the surface).
CHECK_PATTERNS = ("bending_stress_global.", "bending_stress_cell.")


def target(key: str) -> float | None:
    """The relative accuracy target of a scalar (None: not a target)."""
    kind = scalar_kind(key)
    if kind == "moment":
        return MOMENT_RTOL
    if kind == "stress" and not any(p in key for p in EDGE_PATTERNS + CHECK_PATTERNS):
        return STRESS_RTOL
    return None


def _h(row: dict, key: str) -> float:
    h = row["h_mm"]
    if key.startswith("bending_stress_global"):  # the global fillets beside a submodel's
        return h.get("global_fillet", h["fillet"])
    return h["fillet" if key.startswith("bending_stress") else "fine"]


def _zero_scales(row: dict) -> dict[str, float]:
    """Per kind of scalar, the magnitude below which a value counts as zero."""
    out: dict[str, float] = {}
    for k, v in row["scalars"].items():
        kind = scalar_kind(k)
        out[kind] = max(out.get(kind, 0.0), abs(v))
    return {k: NEAR_ZERO * v for k, v in out.items()}


def ladder(rows: list[dict], degree: int = 1) -> tuple[list[dict], list[dict]]:
    """The three finest finished h-levels of ``degree`` (coarse to fine) and the other
    finished runs."""
    ok = [r for r in rows if "error" not in r]
    levels = sorted((r for r in ok if r["degree"] == degree), key=lambda r: r["level"])[-3:]
    return levels, [r for r in ok if r not in levels]


def scalar_table(rows: list[dict], degree: int = 1) -> dict[str, dict]:
    """Per scalar key (those every ladder run has): values, status, observed order,
    extrapolated value, and per run label the relative error, relative and absolute
    uncertainty (see the module docstring)."""
    lad, others = ladder(rows, degree)
    if not lad:
        return {}
    keys = [k for k in lad[-1]["scalars"] if all(k in r["scalars"] for r in lad)]
    zero = _zero_scales(lad[-1])
    table = {}
    for key in keys:
        kind = scalar_kind(key)
        zs = zero.get(kind, 0.0)
        entry = {
            "kind": kind,
            "unit": unit(key),
            "target": target(key),
            "values": {
                run_label(r["level"], r["degree"]): r["scalars"][key]
                for r in (*lad, *others)
                if key in r["scalars"]
            },
        }
        f = [r["scalars"][key] for r in lad]
        if abs(f[-1]) <= zs:  # zero by physics (Mz of a pinion free to spin): no target
            entry.update(target=None, near_zero=True)
        if len(lad) == 2:  # the third grid did not fit: Roache's two-grid GCI
            res = two_grid([_h(r, key) for r in lad], f, FORMAL_ORDER.get(kind, 2.0),
                           zero_scale=zs)  # fmt: skip
            labels = [run_label(r["level"], r["degree"]) for r in lad]
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
            table[key] = entry
            continue
        if len(lad) < 3:
            entry.update(
                status="incomplete",
                order=None,
                extrapolated=None,
                note=f"{len(lad)} h-level(s) finished, two or three needed",
            )
            table[key] = entry
            continue
        res = richardson([_h(r, key) for r in lad], f, p_cap=P_CAP, zero_scale=zs)
        by_dof = richardson([r["dofs"] ** (-1.0 / 3.0) for r in lad], f, p_cap=P_CAP, zero_scale=zs)
        labels = [run_label(r["level"], r["degree"]) for r in lad]
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
        for r in others:
            if key in r["scalars"]:
                o = off_ladder(res, r["scalars"][key], f, zero_scale=zs)
                lab = run_label(r["level"], r["degree"])
                entry["rel_error"][lab] = o["rel_error"]
                entry["uncertainty"][lab] = o["uncertainty"]
                entry["uncertainty_abs"][lab] = o["uncertainty_abs"]
        table[key] = entry
    return table


def _error_bound(entry: dict, label: str) -> tuple[float | None, str]:
    """The relative error of a run (or, without an extrapolation, its uncertainty: the
    spread bound, or the two-grid GCI)."""
    if entry.get("extrapolated") is not None:
        e = entry["rel_error"].get(label)
        return (None if e is None else abs(e)), "error"
    u = entry.get("uncertainty", {}).get(label)
    return u, "two-grid GCI" if entry.get("status") == "two-grid" else "spread bound"


def recommend(rows: list[dict], table: dict[str, dict]) -> dict:
    """Per finished run: does every targeted scalar meet its target (moments 1 %, stresses
    5 %), the worst moment and stress; and the cheapest run (wall time) that meets them."""
    verdicts = []
    for r in rows:
        if "error" in r:
            continue
        label = run_label(r["level"], r["degree"])
        worst: dict[str, dict] = {}
        failing = []
        for key, entry in table.items():
            tol = entry.get("target")
            if tol is None or entry.get("status") == "incomplete":
                continue
            err, how = _error_bound(entry, label)
            if err is None:
                continue
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
                "time_s": r["time_s"]["total"],
                "peak_rss_mb": r["peak_rss_mb"],
                "meets": not failing and bool(worst),
                "failing": failing,
                "worst": worst,
            }
        )
    meeting = sorted((v for v in verdicts if v["meets"]), key=lambda v: v["time_s"])
    best = meeting[0] if meeting else None
    return {
        "targets": {"moment": MOMENT_RTOL, "stress": STRESS_RTOL},
        "runs": verdicts,
        "recommended": None
        if best is None
        else {k: best[k] for k in ("run", "level", "degree", "time_s", "peak_rss_mb")},
        "note": _note(best, verdicts),
    }


def _note(best: dict | None, verdicts: list[dict]) -> str:
    if best is not None:
        return (
            f"{best['run']} is the cheapest run with every moment within "
            f"{MOMENT_RTOL:.0%} and every targeted stress within {STRESS_RTOL:.0%} of the "
            f"extrapolated value ({best['time_s']:.0f} s, "
            f"{best['peak_rss_mb'] / 1024:.1f} GB per run)"
        )
    if not verdicts:
        return "no run finished"
    by_kind = []
    for kind, tol in (("moment", MOMENT_RTOL), ("stress", STRESS_RTOL)):
        ok = sorted((v for v in verdicts if kind in v["worst"]
                     and v["worst"][kind]["error"] <= tol), key=lambda v: v["time_s"])  # fmt: skip
        if ok:
            by_kind.append(f"every {kind} within {tol:.0%} from {ok[0]['run']} on (the cheapest)")
        else:
            fam = sorted({k.split(".", 1)[0] for v in verdicts for k in v["failing"]
                          if k.split(".", 1)[0] != k})  # fmt: skip
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
        "(worst errors: " + "; ".join(parts) + ")"
    )

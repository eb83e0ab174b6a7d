"""The table of a fillet-only refinement study (:mod:`studies.fillet.driver`): per run the
fillet size, DOFs, time, peak memory and the root stresses per gear, and per gear the
Richardson extrapolation (:func:`studies.convergence.richardson.richardson`, h = fillet size) over
the three finest P1 runs with each run's error against it."""

from __future__ import annotations

from studies.convergence.richardson import richardson


def _fmt(v, spec=".1f") -> str:
    return "-" if v is None else format(v, spec)


def extrapolate(rows: list[dict], what: str = "surface") -> dict[str, dict]:
    """Per key: Richardson over the three finest successful P1 runs of ``what``."""
    p1 = sorted(
        (r for r in rows if r.get("degree") == 1 and "error" not in r and what in r),
        key=lambda r: r["fillet_mm"],
    )[:3]
    if len(p1) < 3:
        return {}
    out = {}
    for key in p1[0][what]:
        vals = [r[what][key] for r in p1]
        if any(v is None for v in vals):
            continue
        res = richardson([r["fillet_mm"] for r in p1], vals)
        out[key] = {"status": res.status, "order": res.order, "extrapolated": res.extrapolated}
    return out


def fillet_table(case: str, level: int, rows: list[dict]) -> str:
    """Markdown: the runs, then per recovery (surface, tangent, cell) the values with their
    error against the extrapolation of the three finest P1 runs."""
    ok = [r for r in rows if "error" not in r]
    lines = [f"# Fillet refinement: {case}, flanks and body of level {level}, one position", ""]
    lines += [
        "| fillet (mm) | P | DOFs | total (s) | meshes (s) | factorization (s) | "
        "peak memory (GB) |",
        "|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        if "error" in r:
            lines.append(f"| {r['fillet_mm']:g} | {r.get('degree')} | failed: {r['error']} |||||")
            continue
        t = r["time_s"]
        lines.append(
            f"| {r['fillet_mm']:g} | {r['degree']} | {r['dofs']} | {t['total']:.1f} | "
            f"{t['meshes']:.1f} | {t['factorization']:.1f} | {r['peak_rss_mb'] / 1024:.2f} |"
        )
    for what in ("surface", "tangent", "cell_max"):
        if not ok:
            break
        ext = extrapolate(rows, what)
        keys = list(ok[0][what])
        lines += [
            "",
            f"## {what} (MPa; error against the P1 extrapolation)",
            "",
            "| fillet (mm) | P | " + " | ".join(keys) + " |",
            "|---|---|" + "---|" * len(keys),
        ]
        for r in ok:
            if what not in r:
                continue
            cells = []
            for k in keys:
                v, e = r[what][k], ext.get(k, {}).get("extrapolated")
                err = f" ({100 * (v - e) / abs(e):+.1f} %)" if v is not None and e else ""
                cells.append(_fmt(v) + err)
            lines.append(f"| {r['fillet_mm']:g} | {r['degree']} | " + " | ".join(cells) + " |")
        lines.append(
            "| extrapolated | | "
            + " | ".join(
                f"{_fmt(ext[k]['extrapolated'])} ({ext[k]['status']}, p "
                f"{_fmt(ext[k]['order'], '.2f')})"
                if k in ext
                else "-"
                for k in keys
            )
            + " |"
        )
    return "\n".join(lines) + "\n"

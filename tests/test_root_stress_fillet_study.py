"""The fillet study's table (studies.fillet.report) on made-up runs with a known limit."""

from studies.fillet.report import extrapolate, fillet_table


def _row(h, f):
    return {
        "fillet_mm": h,
        "degree": 1,
        "dofs": 1000,
        "peak_rss_mb": 1024.0,
        "time_s": {"total": 1.0, "meshes": 0.1, "factorization": 0.5},
        "surface": {"sun": f},
        "tangent": {"sun": f},
        "cell_max": {"sun": f},
    }


def test_first_order_values_extrapolate_to_their_limit():
    # f = 900 - 600 h: first order, so Richardson over the three finest P1 runs returns 900
    # (to round-off, 1e-9 relative) with order 1; the coarsest run and a failed run are
    # left out, and the table gives each run's error against that limit
    rows = [_row(h, 900.0 - 600.0 * h) for h in (0.45, 0.3, 0.2, 0.15)]
    rows.append({"fillet_mm": 0.1, "degree": 1, "error": "exit code -9"})
    ext = extrapolate(rows)["sun"]
    assert ext["status"] == "monotone" and abs(ext["order"] - 1.0) < 1e-6
    assert abs(ext["extrapolated"] - 900.0) < 900.0 * 1e-9
    text = fillet_table("made-up", 1, rows)
    assert "failed: exit code -9" in text and "(-10.0 %)" in text  # 810 at 0.15 mm


def test_fewer_than_three_runs_give_no_extrapolation():
    assert extrapolate([_row(0.3, 700.0), _row(0.2, 750.0)]) == {}

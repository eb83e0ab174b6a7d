"""The submodel benchmark's threshold mode: its input checks and its break-even arithmetic
(the solves themselves are what the benchmark measures; nothing here solves)."""

import pytest

from studies.benchmarks.submodel import _threshold_report, main


@pytest.mark.parametrize(
    "argv, field",
    [
        (["--thresholds", "1.5"], "--thresholds"),
        (["--thresholds", "0", "--repeats", "0"], "--repeats"),
    ],
)
def test_bad_threshold_input_is_one_line(argv, field, capsys):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert field in err and "Traceback" not in err


def _pass(threshold, setup, cgs):
    """One pass of one sector: set-up ``setup`` s, CG ``cgs[i]`` s on solve i (0: first)."""
    solves = [
        {
            "keys": {
                "sun": {
                    "setup_s": setup,
                    "krylov_s": cg,
                    "iterations": 20,
                    "surface_MPa_change": 0.0,
                    "tangent_MPa_change": None,
                }
            }
        }
        for cg in cgs
    ]
    return {"threshold": threshold, "solves": solves}


def test_break_even_of_two_thresholds():
    """Threshold 0: set-up 40 s, CG 25 s per reuse; 0.02: 100 s and 20 s. The same total
    at 40 + 25 n = 100 + 20 n, n = 12; the means over interleaved passes enter."""
    data = {
        "case": "x",
        "level": 1,
        "roll": 0.0,
        "rtol": 1e-6,
        "pipeline_threshold": 0.0,
        "repeats": 2,
        "passes": [
            _pass(0.0, 40.0, [99, 24, 26]),
            _pass(0.02, 90.0, [99, 19, 21]),
            _pass(0.0, 40.0, [99, 25, 25]),
            _pass(0.02, 110.0, [99, 20, 20]),
        ],
    }
    text = _threshold_report(data)
    assert "set-up 40.0 / 100.0 s, CG per reuse 25.0 / 20.0 s" in text
    assert "n = 12.0." in text
    # the first solve's CG (the set-up pass) is not a reuse: 99 s enters no mean
    assert "| 1 | 0 | sun | 40.0 | 25.0 | 20/20/20 | 0.0e+00 |" in text

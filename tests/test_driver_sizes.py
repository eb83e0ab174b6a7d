"""The driver-size diagnostic (studies.convergence.driver_sizes): its variants change the sizes
they name and no other, and its report gives each change from base and its share of the whole
step."""

from dataclasses import asdict
from pathlib import Path
from types import SimpleNamespace

import pytest

from meshing.sizing import LEVELS
from studies.cli import InputError
from studies.convergence.driver_sizes import VARIANTS, report, run, variant_mesh

#: the Level fields (and "grid", the contact grid spacing) each variant takes from level L + 1
CHANGED = {
    "base": set(),
    "grid": {"grid"},
    "flank": {"fine"},
    "flank+grid": {"fine", "grid"},
    "tooth": {"tooth"},
    "fillet_far": {"fillet_far"},
    "fillet": {"fillet"},
    "body": {"coarse", "per_circle"},
}


@pytest.mark.parametrize("level", [0, 1])
@pytest.mark.parametrize("name", list(CHANGED))
def test_variant_changes_only_its_sizes(name, level):
    sizes, spacing = variant_mesh(name, level)
    got = {**asdict(sizes), "grid": spacing}
    a, b = LEVELS[level], LEVELS[level + 1]
    lo, hi = {**asdict(a), "grid": a.fine}, {**asdict(b), "grid": b.fine}
    for field, value in got.items():
        assert value == (hi[field] if field in CHANGED[name] else lo[field]), field


def test_next_is_the_next_level():
    assert variant_mesh("next", 1) == (LEVELS[2], LEVELS[2].fine)
    assert set(VARIANTS) == set(CHANGED) | {"next"}


def _row(name, m, s):
    return {
        "variant": name,
        "dofs": 10,
        "wall_s": 60.0,
        "peak_rss_mb": 2048.0,
        "moments": {"My_pin": m},
        "surface": {"ring": s},
        "tangent": {"ring": None},
    }


def test_report_gives_change_and_share_of_the_step():
    data = {
        "case": "X",
        "level": 0,
        "roll": 0.0,
        "read_fillet_mm": 0.15,
        "variants": [
            _row("base", 200.0, 700.0),
            _row("fillet", 201.0, 682.0),
            _row("next", 202.0, 680.0),
        ],
    }
    text = report(data)
    # fillet: +1 N m of the step's +2 (50 %), -18 MPa of -20 (90 %)
    assert "| fillet | 10 | 60 | 2.0 | 201 (+1, 50%) | 682 (-18, 90%) |" in text
    assert "| next | 10 | 60 | 2.0 | 202 (+2) | 680 (-20) |" in text
    assert "ring (MPa, tangent)" not in text  # a key without an ISO line has no column


def test_report_without_next_gives_no_share():
    data = {
        "case": "X",
        "level": 0,
        "roll": 0.0,
        "read_fillet_mm": 0.15,
        "variants": [_row("base", 200.0, 700.0), _row("grid", 199.0, 703.0)],
    }
    assert "| grid | 10 | 60 | 2.0 | 199 (-1) | 703 (+3) |" in report(data)


@pytest.mark.parametrize(
    "kw, field",
    [({"level": 4}, "--level"), ({"level": -1}, "--level"), ({"variants": ["x"]}, "--variants")],
)
def test_bad_input_names_the_option(kw, field, tmp_path: Path):
    args = SimpleNamespace(
        **{"case": "1-GB", "level": 0, "roll": 0.0, "variants": ["base"], "out": tmp_path, **kw}
    )
    with pytest.raises(InputError, match=field):
        run(args)


def test_a_variant_row_holds_the_paper_moments_and_the_read_stresses(monkeypatch):
    import studies.convergence.driver_sizes as ds

    seen = {}

    def fake_solve(study, roll, comm, settings, *, extras, **kw):  # solve_position, reduced
        seen.update(kw, level=settings.level, submodel_levels=extras.submodel_levels)
        seen.update(kw)
        bs = {"sun": 870.0, "tangent": {"sun": 820.0}, "locations": {"sun": {}}}
        return {
            "dofs": 5,
            "Mx_SP": 1.0,
            "M_LOA_sun_SP": 2.0,
            "M_LOA_SP_SUN": 2.0,
            "Mz_SP": 1e-13,
            "ZS": 0.1,
            "bending_stress_fillets": {"0.15": bs},
        }

    monkeypatch.setattr(ds, "solve_position", fake_solve)
    row = ds.solve_variant(None, "fillet", 0, 0.0, None)
    assert row["peak_rss_mb"] > 0.0
    assert seen["level"] == variant_mesh("fillet", 0)[0] and seen["submodel_levels"] == (1,)
    assert seen["store"].reuse is False  # nothing kept: each sector freed after its reading
    # the LOA alias and Mz (zero by physics) are left out, so is the offset ZS
    assert row["moments"] == {"Mx_SP": 1.0, "M_LOA_SP_SUN": 2.0}
    assert row["surface"] == {"sun": 870.0} and row["tangent"] == {"sun": 820.0}
    assert row["read_fillet_mm"] == 0.15 and row["sizes"]["fillet"] == LEVELS[1].fillet


def test_a_variant_missing_a_value_prints_a_dash():
    gone = _row("tooth", 200.5, 700.0)
    gone["surface"] = {}
    data = {
        "case": "X",
        "level": 0,
        "roll": 0.0,
        "read_fillet_mm": 0.15,
        "variants": [_row("base", 200.0, 700.0), gone],
    }
    assert "| tooth | 10 | 60 | 2.0 | 200.5 (+0.5) | - |" in report(data)

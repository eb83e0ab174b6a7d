"""The sector-size diagnostic (studies.convergence.sector_sizes): its variants are the sizes they
name, its defaults separate the read fillet's ladder from the other sizes, and its report gives
each change, the other sizes' spread at one fillet size and the driver check."""

from dataclasses import replace
from pathlib import Path
from types import SimpleNamespace

import pytest

import meshing.submodel as submodel
from meshing.sizing import LEVELS
from meshing.submodel import SUBMODEL_FILLET
from studies.cli import InputError
from studies.convergence.sector_sizes import (
    default_variants,
    fillet_ladders,
    report,
    run,
    variant_sizes,
)


def test_a_variant_is_level_k_with_the_read_fillet_f():
    assert variant_sizes("3:0.1") == (replace(LEVELS[3], fillet=0.1), 1)
    assert variant_sizes("0:0.45") == (LEVELS[0], 1)
    assert variant_sizes("2:0.1:c") == (replace(LEVELS[2], fillet=0.1), 2)


def test_the_defaults_of_level_1():
    # today's sector of level 1 (level 2's sizes, 0.15 mm), its read fillet alone refined by
    # 1.5 twice, level 1's and 3's other sizes at the middle fillet, and the fillet's ladder
    # on curved tets
    assert SUBMODEL_FILLET[2] == 0.15
    assert default_variants(1) == [
        "2:0.15",
        "2:0.1",
        "2:0.0667",
        "1:0.1",
        "3:0.1",
        "2:0.15:c",
        "2:0.1:c",
        "2:0.0667:c",
    ]


@pytest.mark.parametrize("level", range(len(LEVELS)))
def test_every_default_is_a_valid_variant(level):
    for spec in default_variants(level):
        variant_sizes(spec)


@pytest.mark.parametrize(
    "spec",
    ["2", "2:", "x:0.1", "9:0.1", "-1:0.1", "2:nan", "2:0.001", "2:5", "2:0.1:x", "2:0.1:c:c"],
)
def test_a_bad_variant_is_named(spec):
    with pytest.raises(InputError, match="--variants"):
        variant_sizes(spec)


@pytest.mark.parametrize(
    "kw, field", [({"level": 5}, "--level"), ({"variants": ["2:0.1", "q"]}, "--variants")]
)
def test_bad_input_names_the_option_before_anything_is_solved(kw, field, tmp_path: Path):
    args = SimpleNamespace(
        **{"case": "1-GB", "level": 1, "roll": 0.0, "variants": None, "out": tmp_path, **kw}
    )
    with pytest.raises(InputError, match=field):
        run(args)
    assert not any(tmp_path.iterdir())


def _row(spec, sun, tangent, moment=200.0):
    fillet = float(spec.split(":")[1])
    return {
        "variant": spec,
        "wall_s": 60.0,
        "peak_rss_mb": 2048.0,
        "sizes": {"fillet": fillet},
        "sector_dofs": {"sun": 1000},
        "moments": {"My_pin": moment},
        "surface": {"sun": sun},
        "tangent": {"sun": tangent},
    }


def test_report_gives_changes_spread_at_one_fillet_and_the_driver_check():
    data = {
        "case": "X",
        "level": 1,
        "roll": 0.0,
        "variants": [
            _row("2:0.15", 800.0, 700.0),
            _row("2:0.1", 808.0, 693.0),
            _row("1:0.1", 792.0, 693.0, moment=200.5),
        ],
    }
    text = report(data)
    assert "| 2:0.1 | 1000 | 60 | 2.0 |" in text  # the run, then a table per reading
    nodal = text.split("### Surface maximum, nodal (MPa)")[1].split("### ISO line, nodal")
    assert "| variant | sun |" in nodal[0] and "| 2:0.1 | 808.0 (+1.00) |" in nodal[0]
    assert "| 2:0.1 | 693.0 (-1.00) |" in nodal[1]
    assert "recovered" not in text  # rows from before the recovery: no table of it
    # 0.1 mm over two sets of other sizes: (808 - 792) / 800 = 2 %, the ISO line the same
    assert (
        "- 0.1 mm (2:0.1, 1:0.1): spread (max - min) / mean: sun (surface) 2.00 %, "
        "sun (tangent) 0.00 %" in text
    )
    assert "largest change over the variants is 0.5 N m" in text


def test_report_with_one_set_of_sizes_per_fillet_says_so():
    data = {"case": "X", "level": 1, "roll": 0.0, "variants": [_row("2:0.15", 800.0, 700.0)]}
    text = report(data)
    assert "No read fillet size was solved with more than one set of other sizes." in text
    assert "is 0 N m (0: the same global solution)" in text


def test_a_variant_row_reads_the_variant_sector_on_the_case_level(monkeypatch):
    import studies.convergence.sector_sizes as ss

    seen = {}

    def fake_solve(study, roll, comm, settings, *, extras, **kw):  # solve_position, reduced
        seen.update(kw, level=settings.level, submodel_levels=extras.submodel_levels)
        seen.update(kw, order=submodel.SUBMODEL_GEOMETRY_ORDER)
        bs = {
            "sun": 870.0,
            "ring": None,
            "tangent": {"sun": 820.0, "ring": None},
            "locations": {
                "sun": {"submodel": {"dofs": 7}, "recovered": {"value": 860.0, "tangent": 815.0}},
                "ring": {"read_instead": "x"},
            },
        }
        return {
            "dofs": 5,
            "Mx_SP": 1.0,
            "M_LOA_sun_SP": 2.0,
            "M_LOA_SP_SUN": 2.0,
            "Mz_SP": 1e-13,
            "bending_stress_fillets": {"0.1": bs},
        }

    monkeypatch.setattr(ss, "solve_position", fake_solve)
    row = ss.solve_variant(None, "3:0.1", 1, 0.0, None)
    assert seen["level"] == 1 and seen["submodel_levels"] == (variant_sizes("3:0.1")[0],)
    assert seen["store"].reuse is False  # nothing kept: each variant's sectors freed
    assert seen["order"] == 1 and row["geometry_order"] == 1
    ss.solve_variant(None, "3:0.1:c", 1, 0.0, None)  # curved while it solves, then as before
    assert seen["order"] == 2 and submodel.SUBMODEL_GEOMETRY_ORDER == 1
    # a key read on another gear's sector (None) is left out; so are the LOA alias and Mz
    assert row["surface"] == {"sun": 870.0} and row["sector_dofs"] == {"sun": 7}
    assert row["surface_recovered"] == {"sun": 860.0}  # solvers.surface_recovery's, beside
    assert row["tangent_recovered"] == {"sun": 815.0}
    assert row["moments"] == {"Mx_SP": 1.0, "M_LOA_SP_SUN": 2.0}


def test_the_fillet_ladders_recover_a_known_order_and_keep_geometries_apart():
    # f = 800 + 1000 h^2 on the straight sectors: order 2, limit 800; the curved rows (one
    # size only) and level 1's row make no ladder of their own and do not enter this one
    rows = [_row(f"2:{h:g}", 800.0 + 1000.0 * h * h, 700.0) for h in (0.2, 0.15, 0.1, 0.0667)]
    rows += [{**_row("2:0.1:c", 1.0, 1.0), "geometry_order": 2}, _row("1:0.1", 1.0, 1.0)]
    lines = fillet_ladders(rows, [("surface", "sun")])
    assert len(lines) == 1
    line = lines[0]
    assert line.startswith("- level 2's sizes, straight, 0.15 / 0.1 / 0.0667 mm, sun (surface)")
    assert "monotone, order 2.00, extrapolated 800.0" in line


def test_recovered_values_get_columns_and_spreads_beside_the_nodal_ones():
    """Rows since 2026-11-30 carry the recovered values (solvers.surface_recovery): the report
    gives them columns and spreads of their own; a row of an older file, without them, is a
    dash in those columns and leaves the spread to the rows that have them."""
    rows = [
        {
            **_row(f"{k}:0.1", 800.0 + k, 700.0),
            "surface_recovered": {"sun": v},
            "tangent_recovered": {"sun": v - 20.0},
        }
        for k, v in ((1, 780.0), (2, 790.0))
    ]
    rows.append(_row("3:0.1", 803.0, 700.0))
    text = report({"case": "X", "level": 1, "roll": 0.0, "variants": rows})
    assert "sun (surface_recovered)" in text and "sun (tangent_recovered)" in text
    assert "sun (surface_recovered) 1.27 %" in text  # (790 - 780) / 785 over the two rows
    assert "sun (surface) 0.25 %" in text  # (803 - 801) / 802 over all three
    recovered = text.split("### Surface maximum, recovered")[1]
    assert "| 3:0.1 | - |" in recovered and "| 2:0.1 | 790.0 (+1.28) |" in recovered

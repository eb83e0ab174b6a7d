"""The reach of a solved load into a zone grid's band (solvers.zone_reach, eq. (1)) and the
refusal of a solve whose load reaches the band's edge. Arrays stand in for a solve: the
reach is a maximum over loaded cells, so the values here are exact."""

from types import SimpleNamespace

import numpy as np
import pytest

from solvers.errors import ZoneReachError
from solvers.zone_reach import REACH_FRACTION, check_zone_reach, suggested_limit_um, zone_reach

UM = 1e-3


def _grid(name, gap0_um, ref_um, limit_um=40.0):
    grid = SimpleNamespace(name=name, gap0=np.asarray(gap0_um) * UM)
    info = SimpleNamespace(reference=np.asarray(ref_um) * UM, gap_limit=limit_um * UM)
    return grid, info


def _result(pairs, forces):
    return SimpleNamespace(pairs=pairs, forces=np.asarray(forces, float))


def test_reach_is_the_largest_gap_of_a_loaded_cell_above_its_section():
    # drive grid: cells 0-3, sections at references 0 / 5 um; cell 3 (35 um) is unloaded
    drive = _grid("sun-pinion", [0.0, 12.0, 19.0, 35.0], [0.0, 0.0, 5.0, 5.0])
    coast = _grid("sun-pinion/coast", [90.0, 95.0], [90.0, 90.0])  # open: no load
    line = (SimpleNamespace(name="line"), SimpleNamespace(reference=None, gap_limit=None))
    res = _result(
        [("sun-pinion", slice(0, 4)), ("sun-pinion/coast", slice(4, 6)), ("line", slice(6, 7))],
        [3.0, 2.0, 1.0, 0.0, 0.0, 0.0, 5.0],
    )
    reach = zone_reach([drive, coast, line], res)
    assert reach == {"sun-pinion": pytest.approx(14.0, abs=1e-9), "sun-pinion/coast": 0.0}
    assert check_zone_reach([drive, coast, line], res) == reach  # 14 < 0.5 x 40: accepted


def test_a_load_at_the_band_edge_is_refused_with_the_limit_that_holds_it():
    drive = _grid("pinion-ring", [0.0, 24.0, 38.0], [0.0, 0.0, 0.0])
    res = _result([("pinion-ring", slice(0, 3))], [1.0, 1.0, 0.0])
    assert REACH_FRACTION * 40.0 < 24.0
    with pytest.raises(ZoneReachError) as err:
        check_zone_reach([drive], res)
    msg = str(err.value)
    assert "contact grid 'pinion-ring'" in msg and "24.0 um" in msg
    assert "zone_gap_limit_um = 40 um" in msg and "set [numerics] zone_gap_limit_um = 100" in msg
    assert err.value.partial["zone_reach_um"]["pinion-ring"] == pytest.approx(24.0)
    # the suggested limit holds that reach: 24 <= REACH_FRACTION x 100
    assert 24.0 <= REACH_FRACTION * suggested_limit_um(24.0)


def test_the_suggestion_stops_at_the_largest_allowed_limit():
    from cases.study_case import ZONE_GAP_RANGE

    assert suggested_limit_um(400.0) == ZONE_GAP_RANGE[1]
    drive = _grid("sun-pinion", [0.0, 300.0], [0.0, 0.0], limit_um=500.0)
    with pytest.raises(ZoneReachError, match="the largest zone_gap_limit_um does not hold it"):
        check_zone_reach([drive], _result([("sun-pinion", slice(0, 2))], [1.0, 1.0]))


def test_a_case_of_another_gap_limit_takes_the_study_of_its_gear_set():
    """The gap limit sets the cells, not the answer, once the reach check holds: 1-GC's own
    limit (its tip corners) does not cost it 1-GB's convergence study; any other numerics
    field still does."""
    import dataclasses

    from cases.study_case import load_study_case
    from studies.uncertainty import match_key, same_match

    gb, gc = load_study_case("1-GB"), load_study_case("1-GC")
    assert gc.numerics.zone_gap_limit_um != gb.numerics.zone_gap_limit_um
    assert same_match(match_key(gc), match_key(gb))
    other = dataclasses.replace(gc, numerics=dataclasses.replace(gc.numerics, penalty_factor=10.0))
    assert not same_match(match_key(other), match_key(gb))
    assert not same_match(None, match_key(gb))

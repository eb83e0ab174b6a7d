"""The run settings are resolved in one place (studies.settings.RunSettings.resolved): the
case file's sizes unless a level is given, a level's own sizes when it is, explicit flank and
fillet levels over either, the case's numerics and positions unless given."""

import dataclasses

from cases.study_case import load_study_case
from meshing.sizing import LEVELS, with_sizes
from studies.settings import RunSettings

GB = load_study_case("1-GB")  # level 1, flank_level 2, fillet_level 2, 5 positions


def test_nothing_given_is_the_case_file():
    run = RunSettings().resolved(GB)
    assert (run.level, run.variant, run.positions) == (1, {"flank_level": 2, "fillet_level": 2}, 5)
    assert run.label == "L1P1F2R2"
    assert run.sizes == with_sizes(1, 2, 2)
    assert run.spacing == LEVELS[2].fine  # the grid follows the flank size
    assert (run.degree, run.penalty_factor) == (GB.numerics.degree, GB.numerics.penalty_factor)


def test_a_level_given_is_its_own_sizes():
    run = RunSettings(level=0).resolved(GB)
    assert (run.level, run.variant, run.sizes, run.label) == (0, {}, 0, "L0P1")
    assert run.spacing == LEVELS[0].fine
    # the case's own level given explicitly is that level's own sizes too (not the case's F2R2)
    assert RunSettings(level=1).resolved(GB).variant == {}


def test_explicit_values_win_and_resolving_twice_changes_nothing():
    run = RunSettings(
        level=1, flank_level=2, degree=2, grid_spacing=0.3, penalty_factor=10.0, positions=3
    ).resolved(GB)
    assert run.variant == {"flank_level": 2} and run.label == "L1P2F2"
    assert (run.spacing, run.penalty_factor, run.positions) == (0.3, 10.0, 3)
    assert run.resolved(GB) is run
    assert RunSettings(fillet_level=0).resolved(GB).variant == {"flank_level": 2, "fillet_level": 0}


def test_explicit_sizes_for_a_size_diagnostic():
    sizes = dataclasses.replace(LEVELS[0], fine=0.5)
    run = RunSettings(level=sizes).resolved(GB)
    assert run.sizes == sizes and run.spacing == 0.5

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


def test_case_options_change_the_case_as_solved_and_name_a_bad_option():
    """CaseOptions (planetary-fe run's options) are applied in one place: a level given drops
    the case's flank and fillet levels from the inputs (the summary's inputs say which sizes
    ran), a scene, root fillets or out of core replaces the case's, and a bad value is an
    InputError naming the option and what is allowed."""
    import pytest

    from studies.case_options import CaseOptions
    from studies.cli import InputError

    study, run = CaseOptions().applied(GB)
    assert study == GB and run == RunSettings().resolved(GB)
    study, run = CaseOptions(level=0, positions=2, scene="system", out_of_core=True).applied(GB)
    assert (study.model.level, study.model.flank_level, study.model.fillet_level) == (0, None, None)
    assert (study.model.scene, study.numerics.out_of_core) == ("system", True)
    assert (run.label, run.positions) == ("L0P1", 2)
    assert study.model.positions == GB.model.positions  # a position is keyed by its roll
    assert CaseOptions(root_fillets="coarse").applied(GB)[0].numerics.root_fillets == "coarse"
    for options, words in (
        (CaseOptions(level=9), "--level"),
        (CaseOptions(positions=0), "--positions 0: must be an integer from 1 to"),
        (CaseOptions(positions=True), "--positions True"),
        (CaseOptions(scene="planet"), "scene = 'planet': must be one of"),
        (CaseOptions(root_fillets="fine"), "root_fillets = 'fine': must be one of"),
    ):
        with pytest.raises(InputError, match=words):
            options.applied(GB)


def test_one_level_range_in_the_case_file_the_options_the_help_and_the_docs(capsys):
    """The case file's [model] level, --level, planetary-fe run --help and the generated
    field reference give the same range (a --level beyond the case file's range was accepted
    and then met a global mesh no machine here holds)."""
    import pytest

    from cases.reference import reference_markdown
    from cases.study_case import MAX_LEVEL
    from studies.case_options import CaseOptions
    from studies.cli import InputError
    from studies.run import main

    assert CaseOptions(level=MAX_LEVEL).applied(GB)[1].level == MAX_LEVEL
    with pytest.raises(InputError, match=f"--level {MAX_LEVEL + 1}: must be an integer from 0"):
        CaseOptions(level=MAX_LEVEL + 1).applied(GB)
    with pytest.raises(SystemExit):
        main(["--help"])
    assert f"mesh level 0-{MAX_LEVEL}," in " ".join(capsys.readouterr().out.split())
    row = next(r for r in reference_markdown("case").splitlines() if r.startswith("| `level`"))
    assert f"0..{MAX_LEVEL}" in row

"""A Poisson ratio near 0.5 on linear elements or a soft line-grid penalty: the run warns; a
case of another Poisson ratio does not take the ± of a convergence study solved at steel's."""

from dataclasses import replace

from cases.study_case import load_study_case
from studies.plausibility import LOCKING_POISSON, input_warnings
from studies.uncertainty import KEY_ADDED, match_key, same_match


def _with(study, nu=None, degree=None):
    if nu is not None:
        study = replace(study, material=replace(study.material, poisson_ratio=nu))
    if degree is not None:
        study = replace(study, numerics=replace(study.numerics, degree=degree))
    return study


def test_a_poisson_ratio_near_one_half_on_linear_elements_warns():
    """Measured on 1-GB at level 0 (studies.plausibility.LOCKING_POISSON): P1 and P2 differ
    by 1.7 % of My_pin at nu = 0.3 and 4.3 % at 0.49; P2 is the remedy, so P2 does not warn."""
    study = load_study_case("1-GB")
    assert not any("lock" in w for w in input_warnings(study))
    (w,) = [w for w in input_warnings(_with(study, nu=0.49)) if "lock" in w]
    assert "material.poisson_ratio = 0.49" in w and "set degree = 2" in w
    assert not any("lock" in w for w in input_warnings(_with(study, nu=LOCKING_POISSON)))
    assert not any("lock" in w for w in input_warnings(_with(study, nu=0.49, degree=2)))


def test_a_case_of_another_poisson_ratio_takes_no_steel_study():
    """A study written before the key held the Poisson ratio was solved on steel (0.3): it
    matches a steel case and no other."""
    study = load_study_case("1-GB")
    old = {k: v for k, v in match_key(study).items() if k not in KEY_ADDED}
    assert same_match(old, match_key(study))
    assert not same_match(old, match_key(_with(study, nu=0.45)))
    assert same_match(match_key(_with(study, nu=0.45)), match_key(_with(study, nu=0.45)))


def test_a_soft_penalty_on_the_line_grid_warns():
    """A line grid at penalty factor 1: measured My_pin 5 % above its factor-1e6 value on
    1-GB at level 0 (studies.plausibility.PENALTY_FACTOR_USUAL); the zone grid's contact is
    exact and takes no warning."""
    study = load_study_case("1-GB")
    line = replace(
        study, numerics=replace(study.numerics, contact_model="line", penalty_factor=1.0)
    )
    (w,) = [w for w in input_warnings(line) if "penalty" in w]
    assert "numerics.penalty_factor = 1 on the line grid" in w
    zone = replace(study, numerics=replace(study.numerics, penalty_factor=1.0))
    assert not any("penalty" in w for w in input_warnings(zone))
    usual = replace(line, numerics=replace(line.numerics, penalty_factor=10.0))
    assert not any("penalty" in w for w in input_warnings(usual))

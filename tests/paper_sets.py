"""The paper's two planetary sets as closed-form inputs, read from the analytic study file
(``cases/analytic/singh2007.toml``) exactly as ``make analytic`` reads them."""

from cases.analytic_study import load_analytic_study


def paper_inputs():
    """(single pinion, double pinion) :class:`gears.analytic.planetary.PlanetaryInput`."""
    a = load_analytic_study()
    return a.single_pinion.planetary_input(), a.double_pinion.planetary_input()


def paper_tables():
    """Every analytical table of :func:`studies.analytic.tables.build_tables`."""
    from studies.analytic.tables import build_tables

    a = load_analytic_study()
    return build_tables(*paper_inputs(), a.bearing_radial_stiffness)

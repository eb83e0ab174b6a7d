"""Unit conversions, named once. Inside the pipeline: mm, N, MPa (N/mm^2), N mm; reports
give moments in N m like the paper."""

N_MM_PER_N_M = 1.0e3  # 1 N m = 1000 N mm


def n_m(n_mm):
    """A moment (or torque) in N mm as N m."""
    return n_mm / N_MM_PER_N_M


def n_mm(n_m_value):
    """A moment (or torque) in N m as N mm."""
    return n_m_value * N_MM_PER_N_M

"""The convergence study: mesh ladders of a case, their reduction (Richardson
extrapolation, GCI), the records kept in the repository and the diagnostics of their sizes."""

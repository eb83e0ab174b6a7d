"""Entry points: the study driver for any case file, the analytic study, meshes,
benchmarks, reports. The top layer: it walks case -> scene -> meshes -> solve -> results ->
report."""

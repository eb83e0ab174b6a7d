# Planetary gear FE study pipeline. `make` sets up the virtualenv and runs the main study;
# `make test` runs the test suite (serial, then the MPI-marked tests under mpiexec -n 2).
SHELL := /bin/bash
.DEFAULT_GOAL := all

VENV    := .venv
PY      := $(VENV)/bin/python
MPIEXEC := $(VENV)/bin/mpiexec
STAMP   := $(VENV)/.installed
RESULTS := results
CASE1   := 1-GA 1-GB 1-GC 1-GB-R
CASE2   := 2B-GA 2B-GB
GEARSETS := case1 case2
PACKAGES := gears cases meshing solvers postprocess studies
NP      ?= 1
# QUIET=1: the study driver prints only warnings and errors (CI logs): `make 1-GA QUIET=1`
QUIET   ?=
STUDY_FLAGS := $(if $(filter 1 yes true,$(QUIET)),--quiet)

# First Python >= 3.12 that actually runs: python3.12.. on PATH (a pyenv shim that is not
# activated fails the check), then pyenv's installed versions.
FIND_PYTHON = for p in python3.12 python3.13 python3.14 \
	    $$HOME/.pyenv/versions/3.12*/bin/python3 $$HOME/.pyenv/versions/3.1[3-9]*/bin/python3; do \
	  if "$$p" -c 'import sys; sys.exit(sys.version_info < (3, 12))' >/dev/null 2>&1; then \
	    command -v "$$p"; exit 0; fi; done; exit 1

.PHONY: all setup test test-serial test-mpi analytic meshes bench-mesh bench-solver lint clean \
	distclean help case1 case1-system case2 $(CASE1) $(CASE2) study bench-case1 bench-study \
	report start-clock

# The main study, one step after the other; the first stamps the start time, the last (the
# recipe) writes results/report.md with the wall time of the whole run (results/bench/make_all.json).
all: start-clock setup analytic meshes case1 case2 ## set up and run the main study: results/report.md
	@$(MAKE) --no-print-directory report STARTED=$(RESULTS)/bench/.make_start

start-clock:
	@mkdir -p $(RESULTS)/bench && date +%s.%N > $(RESULTS)/bench/.make_start

# The one-page report of everything under results/ (links every case report and picture).
report: $(STAMP) ## the whole study on one page: results/report.md
	$(PY) -m studies.paper_report --results $(RESULTS) $(if $(STARTED),--started $(STARTED))

help: ## list the targets
	@grep -E '^[a-zA-Z0-9_-]+:.*## ' $(MAKEFILE_LIST) | awk -F':.*## ' '{printf "  %-14s %s\n", $$1, $$2}'

setup: $(STAMP) ## create the virtualenv and install pinned dependencies

$(STAMP): pyproject.toml
	@py=$$($(FIND_PYTHON)) || { echo "error: Python >= 3.12 not found (looked for python3.12+ on PATH and in ~/.pyenv/versions); install python3.12" >&2; exit 1; }; \
	  echo "using $$py ($$($$py --version))"; \
	  [ -x $(PY) ] || "$$py" -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e '.[dev]'
	@touch $@

test: test-serial test-mpi ## run all tests

test-serial: $(STAMP)
	$(PY) -m pytest -m "not mpi"

# Exit code 5 = no test collected under this marker; not a failure.
test-mpi: $(STAMP)
	$(MPIEXEC) -n 2 $(PY) -m pytest -m mpi -p no:cacheprovider -q; rc=$$?; [ $$rc -eq 0 ] || [ $$rc -eq 5 ]

analytic: $(STAMP) ## closed-form study: results/analytic/{tables.json,report.md,*.png}
	$(PY) -m studies.analytic --out $(RESULTS)/analytic

# One FE study case: `make 1-GB`; `make 1-GB NP=2` runs it on 2 MPI ranks.
$(CASE1) $(CASE2): $(STAMP)
	$(MPIEXEC) -n $(NP) $(PY) -m studies.run $@ --out $(RESULTS) $(STUDY_FLAGS)

# Any case file: `make study CASE=path/to/my_case.toml` (or a name in cases/).
study: $(STAMP) ## one study for any case file: make study CASE=path/to/case.toml [NP=2]
	@[ -n "$(CASE)" ] || { echo "error: give the case file: make study CASE=path/to/case.toml" >&2; exit 2; }
	$(MPIEXEC) -n $(NP) $(PY) -m studies.run $(CASE) --out $(RESULTS) $(STUDY_FLAGS)

# The cases of a group run in one process: their bodies are factorized once and reused.
case1: $(STAMP) ## the four case-1 FE cases and their report: results/case1/report.md
	$(MPIEXEC) -n $(NP) $(PY) -m studies.run $(CASE1) --out $(RESULTS) $(STUDY_FLAGS)
	$(PY) -m studies.case1_report --results $(RESULTS)

case1-system: $(STAMP) ## case 1 in the system scene (elastic carrier): results/case1-system/report.md
	$(MPIEXEC) -n $(NP) $(PY) -m studies.run $(CASE1) --scene system \
	  --out $(RESULTS)/case1-system $(STUDY_FLAGS)
	$(PY) -m studies.pin_errors 1-GB --errors 0 10 25 50 --out $(RESULTS)/case1-system
	$(PY) -m studies.system_report --branch $(RESULTS) --system $(RESULTS)/case1-system \
	  --cases $(CASE1) --pair 1-GB-R 1-GC

# --single: the single-pinion cases the pattern shift is compared with (same bearing).
case2: $(STAMP) ## the case-2 FE cases (double pinion) and their report: results/case2/report.md
	$(MPIEXEC) -n $(NP) $(PY) -m studies.run $(CASE2) --out $(RESULTS) $(STUDY_FLAGS)
	$(PY) -m studies.case2_report --results $(RESULTS) --cases $(CASE2) --single $(CASE1)

bench-study: $(STAMP) ## reuse and MPI speed-ups of the study: results/bench/study.json
	$(PY) -m studies.bench_study --out $(RESULTS)/bench --level 1

meshes: $(STAMP) ## case scenes at the default level: results/meshes/{*.png,*.json}
	$(PY) -m studies.meshes --gearsets $(GEARSETS) --carrier --out $(RESULTS)/meshes

bench-mesh: $(STAMP) ## meshing benchmark: results/bench/meshing.json
	$(PY) -m studies.bench_meshing --gearsets $(GEARSETS) --out $(RESULTS)/bench/meshing.json

bench-solver: $(STAMP) ## contact solver benchmark, serial and 2 ranks: results/bench/solver*.json
	$(PY) -m studies.bench_solver --out $(RESULTS)/bench
	$(MPIEXEC) -n 2 $(PY) -m studies.bench_solver --out $(RESULTS)/bench/mpi2

# Peaks at about 14 GB in the level-0 P2 run; drop `--extra 0:2` on a smaller machine.
bench-case1: $(STAMP) ## case 1 speed against error (1-GB): results/bench/case1_speed_error.{json,png}
	$(PY) -m studies.bench_case1 --out $(RESULTS)/bench --case 1-GB --levels 0 1 2 \
	  --degrees 1 --extra 0:2

# The radial mesh stiffness of the case-1 meshes from the FE (pust2016), level 0 (about 1 min).
.PHONY: radial-stiffness phasing
radial-stiffness: $(STAMP) ## FE radial mesh stiffness, floating-sun threshold: results/radial_stiffness/
	$(PY) -m studies.radial_stiffness --case 1-GB --level 0 --out $(RESULTS)/radial_stiffness

# Planet phasing (parker2000): 3 equally spaced planets, and 4 at 0/91.4/180/271.4 deg (snapped
# to the assemblable 91.43, 271.43), all-planet scene, 12 positions over one mesh cycle, level 0
# (about 15 min on 2 cores).
phasing: $(STAMP) ## planet phasing, all-planet FE over one mesh cycle: results/phasing/
	$(PY) -m studies.phasing --case parker2000-3 --case parker2000-4 0 91.4 180 271.4 \
	  --positions 12 --level 0 --out $(RESULTS)/phasing

# Peer cross-check (issue 16): 1-GA and 1-GC, one position, ours and CalculiX on the same
# meshes (level 0; add LEVELS="0 1" for the default level). Installs calculix-ccx when run as
# root and ccx is missing; the main `make` and `make test` never need it.
.PHONY: bench-peer ccx-setup
PEER_LEVELS ?= 0
ccx-setup:
	@command -v ccx >/dev/null 2>&1 || { \
	  if [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then \
	    echo "installing calculix-ccx (apt-get)"; \
	    DEBIAN_FRONTEND=noninteractive apt-get install -y calculix-ccx >/dev/null || \
	      { apt-get update >/dev/null && DEBIAN_FRONTEND=noninteractive apt-get install -y calculix-ccx >/dev/null; }; \
	  fi; \
	  command -v ccx >/dev/null 2>&1 || { echo "error: CalculiX (ccx) not found and not installable here: run 'apt-get install -y calculix-ccx' as root (Debian/Ubuntu), or put ccx on PATH" >&2; exit 1; }; }

bench-peer: $(STAMP) ccx-setup ## ours against CalculiX on the same meshes: results/bench/peer.{json,md}
	$(PY) -m studies.bench_peer --cases 1-GA 1-GC --levels $(PEER_LEVELS) --out $(RESULTS)/bench

lint: $(STAMP) ## ruff
	$(VENV)/bin/ruff check $(PACKAGES) tests
	$(VENV)/bin/ruff format --check $(PACKAGES) tests

clean: ## remove results and caches, including cached meshes (keeps the virtualenv)
	rm -rf $(RESULTS) .cache .pytest_cache .ruff_cache
	find . -name __pycache__ -type d -prune -exec rm -rf {} +

distclean: clean ## also remove the virtualenv
	rm -rf $(VENV)

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
# The one-branch case runs keep their bodies' LU factors on disk (--out-of-core, the same
# answer to round-off): at the case files' sizes (level 1 with level 2's flanks, contact grid
# and refined fillets) one 2B-GA position holds 15.5 GB in core and 3.2 GB so, at the same
# speed (the convergence records, 2026-11-30). IN_CORE=1 keeps them in memory.
IN_CORE ?=
CASE_FLAGS := $(STUDY_FLAGS) $(if $(filter 1 yes true,$(IN_CORE)),,--out-of-core)
# GNU make exits 2 whatever a recipe's code: the run's own code (docs/cli.md) is said on
# stderr on the way out; scripts that branch on it call .venv/bin/planetary-fe run directly.
RUN_CODE = || { rc=$$?; echo "make: planetary-fe run ended with code $$rc (docs/cli.md: exit codes; make itself exits 2)" >&2; exit $$rc; }

# First Python >= 3.12 that actually runs: python3.12.. on PATH (a pyenv shim that is not
# activated fails the check), then pyenv's installed versions.
FIND_PYTHON = for p in python3.12 python3.13 python3.14 \
	    $$HOME/.pyenv/versions/3.12*/bin/python3 $$HOME/.pyenv/versions/3.1[3-9]*/bin/python3; do \
	  if "$$p" -c 'import sys; sys.exit(sys.version_info < (3, 12))' >/dev/null 2>&1; then \
	    command -v "$$p"; exit 0; fi; done; exit 1

.PHONY: docs all setup test test-serial test-mpi analytic meshes bench-mesh bench-solver lint clean \
	distclean help case1 case1-system case2 case2-system $(CASE1) $(CASE2) study bench-case1 bench-study \
	report start-clock

# The main study, one step after the other; the first stamps the start time, the last (the
# recipe) writes results/report.md with the wall time of the whole run (results/bench/make_all.json).
# The ± of the summaries come from the convergence records in studies/records/convergence/;
# `make` solves no ladder (`make MAIN_CONVERGENCE=convergence-main` runs the ladders first,
# where no record of them exists).
MAIN_CONVERGENCE ?=
all: start-clock setup analytic meshes $(MAIN_CONVERGENCE) case1 case2 ## set up and run the main study: results/report.md
	@$(MAKE) --no-print-directory report STARTED=$(RESULTS)/bench/.make_start

start-clock:
	@mkdir -p $(RESULTS)/bench && date +%s.%N > $(RESULTS)/bench/.make_start

# The one-page report of everything under results/ (links every case report and picture).
report: $(STAMP) ## the whole study on one page: results/report.md
	$(PY) -m studies.paper_report --results $(RESULTS) $(if $(STARTED),--started $(STARTED))

# `## ` marks a target of the product (one run of a case and its report), `### ` a research or
# verification study that uses it, `#### ` a diagnostic or benchmark of the pipeline itself.
help: ## list the targets: the product first, then the studies, then the diagnostics
	@echo "The product (make VARIABLE=value TARGET):"
	@grep -E '^[a-zA-Z0-9_-]+:.*[^#]## ' $(MAKEFILE_LIST) | awk -F':.*## ' '{printf "  %-17s %s\n", $$1, $$2}'
	@printf "  %-17s %s\n" "$(firstword $(CASE1) $(CASE2)) ..." "one shipped case: $(CASE1) $(CASE2) [NP=2] [IN_CORE=1]"
	@echo
	@echo "Research and verification studies:"
	@grep -E '^[a-zA-Z0-9_-]+:.*[^#]### ' $(MAKEFILE_LIST) | awk -F':.*### ' '{printf "  %-17s %s\n", $$1, $$2}'
	@echo
	@echo "Diagnostics and benchmarks:"
	@grep -E '^[a-zA-Z0-9_-]+:.*#### ' $(MAKEFILE_LIST) | awk -F':.*#### ' '{printf "  %-17s %s\n", $$1, $$2}'

setup: $(STAMP) ## create the virtualenv and install pinned dependencies

$(STAMP): pyproject.toml
	@py=$$($(FIND_PYTHON)) || { echo "error: Python >= 3.12 not found (looked for python3.12+ on PATH and in ~/.pyenv/versions); install python3.12" >&2; exit 1; }; \
	  echo "using $$py ($$($$py --version))"; \
	  [ -x $(PY) ] || "$$py" -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e '.[dev]'
	@touch $@

test: test-serial test-mpi ## run all tests

# The serial tests on TEST_WORKERS processes (pytest-xdist; each test is single-threaded):
# --dist loadfile keeps a file's tests on one worker, so its module fixtures are built once.
# TEST_WORKERS=0 runs them in this process. --durations names the slowest tests in the log, so a
# CI run that nears its 90 min says where the time went (CI keeps the log of a failed run).
TEST_WORKERS ?= 2
test-serial: $(STAMP) #### the serial tests only (TEST_WORKERS=2 processes)
	$(PY) -m pytest -m "not mpi" --durations=25 $(if $(filter-out 0,$(TEST_WORKERS)),-n $(TEST_WORKERS) --dist loadfile)

# Exit code 5 = no test collected under this marker; not a failure. Each test file with MPI
# tests runs in its own pair of processes, so the memory one file's tests leave in the ranks
# is not held beside the next file's (the root-stress sectors of level 0, meshed at level
# 1's sizes, made the files run in one process exceed 23 GB).
MPI_TEST_FILES = $(shell grep -l "mark.mpi" tests/test_*.py)
test-mpi: $(STAMP) #### the MPI tests only, each file on 2 ranks
	@for f in $(MPI_TEST_FILES); do \
	  $(MPIEXEC) -n 2 $(PY) -m pytest -m mpi -p no:cacheprovider -q --durations=5 $$f; rc=$$?; \
	  [ $$rc -eq 0 ] || [ $$rc -eq 5 ] || exit $$rc; \
	done

analytic: $(STAMP) ## closed-form study: results/analytic/{tables.json,report.md,*.png}
	$(PY) -m studies.analytic --out $(RESULTS)/analytic

# One FE study case: `make 1-GB`; `make 1-GB NP=2` runs it on 2 MPI ranks.
$(CASE1) $(CASE2): $(STAMP)
	$(MPIEXEC) -n $(NP) $(PY) -m studies.run $@ --out $(RESULTS) $(CASE_FLAGS) $(RUN_CODE)

# Any case file: `make study CASE=path/to/my_case.toml` (or a name in cases/).
study: $(STAMP) ## one study for any case file: make study CASE=path/to/case.toml [NP=2]
	@[ -n "$(CASE)" ] || { echo "error: give the case file: make study CASE=path/to/case.toml" >&2; exit 2; }
	$(MPIEXEC) -n $(NP) $(PY) -m studies.run $(CASE) --out $(RESULTS) $(CASE_FLAGS) $(RUN_CODE)

# The cases of a group run in one process: their bodies are factorized once and reused.
case1: $(STAMP) ## the four case-1 FE cases and their report: results/case1/report.md
	$(MPIEXEC) -n $(NP) $(PY) -m studies.run $(CASE1) --out $(RESULTS) $(CASE_FLAGS) $(RUN_CODE)
	$(PY) -m studies.paper.case1 --results $(RESULTS)

# 1-GB's tilting stiffness over two decades around the paper's (8.8e6 is 1-GC's, 8.8e8 near
# 1-GA's), its radial stiffness kept: the case-1 report's moments against the tilting stiffness
TILTS ?= 8.8e6,2.8e7,8.8e7,2.8e8,8.8e8
case1-sweep: $(STAMP) ### 1-GB's moments against its tilting stiffness (TILTS=...), in the case-1 report
	$(MPIEXEC) -n $(NP) $(VENV)/bin/planetary-fe sweep 1-GB --set bearing.tilting_stiffness=$(TILTS) \
	  --out $(RESULTS) $(CASE_FLAGS) $(RUN_CODE)
	$(PY) -m studies.paper.case1 --results $(RESULTS)

# The system scenes and their branch references run at SYSTEM_LEVEL's own sizes (--level):
# at plain level 1 they already peak at 19-21 GB, so the case files' finer flanks and fillets
# (every pinion's in the system scene) are not used there.
case1-system: $(STAMP) ### case 1 in the system scene (elastic carrier): results/case1-system/report.md
	$(MPIEXEC) -n $(NP) $(PY) -m studies.run $(CASE1) --scene system --level $(SYSTEM_LEVEL) \
	  --out $(RESULTS)/case1-system $(STUDY_FLAGS)
	$(PY) -m studies.pin_errors 1-GB --errors 0 10 25 50 --out $(RESULTS)/case1-system
	$(MPIEXEC) -n $(NP) $(PY) -m studies.run $(CASE1) --root-fillets coarse --level $(SYSTEM_LEVEL) \
	  --out $(RESULTS)/case1-system/branch $(STUDY_FLAGS)
	$(PY) -m studies.paper.system --branch $(RESULTS)/case1-system/branch \
	  --system $(RESULTS)/case1-system --cases $(CASE1) --pair 1-GB-R 1-GC

# The system scenes keep every root fillet coarse (numerics.root_fillets "auto") and read the
# root stress on the submodels of each gear's most loaded mesh; their branch reference runs
# the one-branch scene on the same coarse fillets, so the comparison is like with like.
# Case 2 in the system scene: sun, the three SP-RP pairs, ring and the carrier with six pins
# (an SP and an RP pin per pair), each pinion on its bearing to its own pin. At the case files'
# level 1 (1.0M DOFs, coarse root fillets): 52.5 min serial with the branch reference, one
# process at 21.2 GB resident at its peak (2026-11-27; 8.8 min and 11.2 GB before the root
# stress was read in both scenes); SYSTEM_LEVEL=0 on a smaller machine.
SYSTEM_LEVEL ?= 1
case2-system: $(STAMP) ### case 2 in the system scene (six carrier pins): results/case2-system/report.md
	$(MPIEXEC) -n $(NP) $(PY) -m studies.run $(CASE2) --scene system \
	  --level $(SYSTEM_LEVEL) --out $(RESULTS)/case2-system $(STUDY_FLAGS)
	$(MPIEXEC) -n $(NP) $(PY) -m studies.run $(CASE2) --root-fillets coarse \
	  --level $(SYSTEM_LEVEL) --out $(RESULTS)/case2-system/branch $(STUDY_FLAGS)
	$(PY) -m studies.paper.system --branch $(RESULTS)/case2-system/branch \
	  --system $(RESULTS)/case2-system --cases $(CASE2)

# --single: the single-pinion cases the pattern shift is compared with (same bearing).
case2: $(STAMP) ## the case-2 FE cases (double pinion) and their report: results/case2/report.md
	$(MPIEXEC) -n $(NP) $(PY) -m studies.run $(CASE2) --out $(RESULTS) $(CASE_FLAGS) $(RUN_CODE)
	$(PY) -m studies.paper.case2 --results $(RESULTS) --cases $(CASE2) --single $(CASE1)

bench-study: $(STAMP) #### reuse and MPI speed-ups of the study: results/bench/study.json
	$(PY) -m studies.benchmarks.study --out $(RESULTS)/bench --level 1

meshes: $(STAMP) ## case scenes at the default level: results/meshes/{*.png,*.json}
	$(PY) -m studies.meshes --gearsets $(GEARSETS) --carrier --out $(RESULTS)/meshes

bench-mesh: $(STAMP) #### meshing benchmark: results/bench/meshing.json
	$(PY) -m studies.benchmarks.meshing --gearsets $(GEARSETS) --out $(RESULTS)/bench/meshing.json

bench-solver: $(STAMP) #### contact solver benchmark, serial and 2 ranks: results/bench/solver*.json
	$(PY) -m studies.benchmarks.solver --out $(RESULTS)/bench
	$(MPIEXEC) -n 2 $(PY) -m studies.benchmarks.solver --out $(RESULTS)/bench/mpi2

# Contact models (issue 11): line grid against zone grid on 1-GA and 1-GC at level 0, one
# position, penalty factor swept over three decades; cost per position, line-end loads and
# fine-grid pressure against Hertz.
# Root stress against the fillet size alone (issue 13 item 1): flanks and body of one level,
# the fillets of the loaded teeth refined; peaks at 7 GB at level 1 with 0.12 mm fillets.
FILLETS ?= 0.45 0.3 0.2 0.15 0.12
.PHONY: fillet-study
fillet-study: $(STAMP) ### root stress against fillet size: results/fillet/<case>/fillet_L1_loaded.{json,md}
	@[ -n "$(CASE)" ] || { echo "error: give the case: make fillet-study CASE=1-GB" >&2; exit 2; }
	$(PY) -m studies.fillet $(CASE) --level 1 --fillets $(FILLETS) --loaded-only \
	  --out $(RESULTS)/fillet

# Where a level's root-stress driver error comes from: the global mesh of level DRIVER_LEVEL
# with one size at a time set to the next level's, every root stress read on the level-1
# sector (one process; 1-GB: 436 s and 7.2 GB peak per variant at level 0, 356 s of it the
# four 0.15 mm read sectors; the level-1 variants took 15-16 min beside another run).
DRIVER_LEVEL ?= 0
.PHONY: driver-sizes
driver-sizes: $(STAMP) #### which global size the root-stress driver error follows: results/convergence/<case>/driver_sizes_L<level>[_roll<roll>].{json,md}
	$(PY) -m studies.convergence.driver_sizes --case $(or $(CASE),1-GB) --level $(DRIVER_LEVEL) \
	  --out $(RESULTS)/convergence

# Which sizes a root-stress sector's values follow: one global solution of level
# SECTOR_LEVEL read on sectors of other sizes (the read fillet alone refined by 1.5 twice, and
# the other sizes one level coarser and finer at one fillet size, and the read fillet's ladder
# on curved tets); one process, finished variants kept (1-GB level 1: 8 variants, 4-14 min
# each; the three of the scatter 15.5 min, 2B-GA's 22.5 min).
SECTOR_LEVEL ?= 1
# the K:F variants (empty: the default eight); the scatter alone: SECTOR_VARIANTS="1:0.1 2:0.1 3:0.1"
SECTOR_VARIANTS ?=
# the sun angle (rad) of the position read; 0 is the convergence records' position
SECTOR_ROLL ?= 0
.PHONY: sector-sizes
sector-sizes: $(STAMP) #### which sizes the root-stress sector follows: results/convergence/<case>/sector_sizes_L<level>[_roll<roll>].{json,md}
	$(PY) -m studies.convergence.sector_sizes --case $(or $(CASE),1-GB) --level $(SECTOR_LEVEL) \
	  --roll $(SECTOR_ROLL) $(if $(SECTOR_VARIANTS),--variants $(SECTOR_VARIANTS)) \
	  --out $(RESULTS)/convergence

# The spread of sector-sizes' straight variants at one read fillet (1:0.1 2:0.1 3:0.1 at level
# 1) kept with the case's convergence record: the floor under its root stresses' sector U.
.PHONY: sector-scatter
sector-scatter: $(STAMP) #### keep sector-sizes' scatter with the case's record (solves nothing): studies/records/convergence/<case>/
	$(PY) -m studies.convergence.sector_scatter --case $(or $(CASE),1-GB) --level $(SECTOR_LEVEL) \
	  --roll $(SECTOR_ROLL) --out $(RESULTS)/convergence

# The bodies' linear solvers (issue 13 item 5): exact MUMPS LU, block low-rank MUMPS and
# CG/GAMG on one 1-GB position per level; time, peak memory and the change of every result.
LINEAR_LEVELS ?= 1 2
.PHONY: bench-linear
bench-linear: $(STAMP) #### exact LU vs BLR vs CG/GAMG: results/bench/linear_solver.{json,md}
	$(PY) -m studies.benchmarks.linear --levels $(LINEAR_LEVELS) --out $(RESULTS)/bench

.PHONY: bench-contact
bench-contact: $(STAMP) #### line vs zone contact model: results/bench/contact_grid.json
	$(PY) -m studies.benchmarks.contact --out $(RESULTS)/bench --level 0

# Keep benchmark files in the repository for the docs' performance page: BENCH names the files
# of results/bench without their suffix (their .json, .md and .png are recorded together).
BENCH ?=
.PHONY: record-bench
record-bench: $(STAMP) #### keep benchmark files for the docs: make record-bench BENCH="solver linear_solver"
	@[ -n "$(BENCH)" ] || { echo "error: name the files: make record-bench BENCH=solver" >&2; exit 2; }
	$(PY) -m studies.benchmarks.record $(foreach b,$(BENCH),$(wildcard $(RESULTS)/bench/$(b).json $(RESULTS)/bench/$(b).md $(RESULTS)/bench/$(b).png))

# Convergence study of any case (issue 13): mesh levels 0 1 2 (P1) and level 0 with P2 (the p
# step, skipped with a note when less than 16 GB are free: it peaks at ~14 GB), one mesh
# position, each run in its own process (time, peak memory); Richardson extrapolation of every
# summary scalar, the error and uncertainty of each run, the level to use, a speed-against-
# error chart. OOC="2 0:2" solves those runs with the LU factors on disk (numerics.out_of_core:
# the same answer, less memory, slower solves): case 2, whose level-2 and level-0 P2 factors
# do not fit in 23 GB in core. Finished runs are reused while inputs and code are unchanged. CONV_EXTRA= (empty)
# leaves the P2 run out; POSITIONS=5 studies the summary's means and cycle maxima exactly
# (about 3x the time). SPLIT=1 studies the root stress's driver and submodel errors apart
# (the ladder runs read extra submodels: the sectors beside its own at the case's level, the
# case level's sector elsewhere).
.PHONY: convergence
CONV_EXTRA ?= 0:2
CONV_LEVELS ?= 0 1 2
POSITIONS ?= 1
SPLIT ?=
OOC ?=
convergence: $(STAMP) ### discretisation error of every scalar: make convergence CASE=1-GB -> results/convergence/<case>/
	@[ -n "$(CASE)" ] || { echo "error: give the case: make convergence CASE=1-GB" >&2; exit 2; }
	$(PY) -m studies.convergence $(CASE) --levels $(CONV_LEVELS) --extra $(CONV_EXTRA) \
	  --positions $(POSITIONS) --out $(RESULTS)/convergence \
	  $(if $(filter 1 yes true,$(SPLIT)),--split-root-stress) $(if $(OOC),--out-of-core $(OOC))

# The convergence study behind the ± of the case summaries, in the main `make` (before the
# cases, whose summaries read it), one position each, no P2: 1-GB at levels 0 1 2 with the
# root stress's driver and submodel errors split (peak at level 2, 1.1M DOFs: the fine root
# fillets) serves every case-1 case (same gear set, scene, numerics); 2B-GA at levels 0 1 2,
# split too (the level-1 run reads a level-3 sector for each of its six loaded fillets),
# its level 2 (1.8M DOFs) out of core: 23 GB of factors on disk, 6.7 GB in memory, serves
# case 2.
# The two ladders take about 155 min alone on 2 cores (recorded 2026-11-28), more than
# the rest of the study: their studies are recorded in the repository
# (studies/records/convergence/<case>/, with the commit and source hash they were solved
# with), and `make` runs a ladder only where no record of its gear set, scene, numerics and
# ladder exists; the summaries take the ± of a study solved by
# today's code (results/convergence first, then the records), else say it was not.
# `make convergence-main RECORD=1` solves both ladders again (finished runs under
# results/convergence reused while inputs and code are unchanged) and records them.
# `make MAIN_CONVERGENCE=` leaves both out (summaries then take the records' ±, or say
# `uncertainty: null` and why). P2 only in `make convergence`.
RECORD ?=
# off the ladder: level 1 with level 2's flanks and contact grid (1:1:2), and with level 2's
# refined fillets too (1:1:2:2), the candidates for the default (2026-11-30: 1:1:2:2 meets
# every target for both cases at 1.35x level 1's time, level 2 at 3.2-3.3x; 1:1:2 misses
# 1-GB's Mx_pin); 1:1:2:2 with its factors on disk, as level 2 (2.4-3.2 GB, not 10-16 GB)
CONV_MAIN_EXTRA = 1:1:2 1:1:2:2
CONV_MAIN_FLAGS = $(if $(filter 1 yes true,$(RECORD)),--record,--unless-recorded)
# per run: 1-GB's level 1 reads eight sectors (two finer ones per loaded fillet), over an hour
CONV_MAIN_TIMEOUT ?= 10800
.PHONY: convergence-main
convergence-main: $(STAMP) ### the ladders behind the ±, unless recorded (RECORD=1: solve and record them)
	$(PY) -m studies.convergence 1-GB --levels 0 1 2 --extra $(CONV_MAIN_EXTRA) --split-root-stress \
	  --out-of-core 2 1:1:2:2 --timeout $(CONV_MAIN_TIMEOUT) --out $(RESULTS)/convergence $(CONV_MAIN_FLAGS)
	$(PY) -m studies.convergence 2B-GA --levels 0 1 2 --extra $(CONV_MAIN_EXTRA) --split-root-stress \
	  --out-of-core 2 1:1:2:2 --timeout $(CONV_MAIN_TIMEOUT) --out $(RESULTS)/convergence $(CONV_MAIN_FLAGS)

# After a code change, the cheap evidence that the records still stand: each record's level-0
# run solved again by today's code and compared scalar by scalar (kept in the record; the
# summaries quote it). About 4 min for 1-GB, 5 min for 2B-GA on 2 cores (2026-11-29).
.PHONY: reproduce-records
reproduce-records: $(STAMP) #### solve the records' level-0 runs again by today's code, compare, note it in the records
	$(PY) -m studies.convergence 1-GB --reproduce 0 --timeout $(CONV_MAIN_TIMEOUT) --out $(RESULTS)/convergence
	$(PY) -m studies.convergence 2B-GA --reproduce 0 --timeout $(CONV_MAIN_TIMEOUT) --out $(RESULTS)/convergence

# An off-ladder run solved by today's code and added to a case's record (judged against the
# record's extrapolation; the record's ladder keeps the code that solved it): RUN=L:D (another
# degree), L:D:F (level L with level F's flanks and contact grid, the main ladders' 1:1:2) or
# L:D:F:R (and level R's refined fillets).
RUN ?= 1:1:2
.PHONY: add-to-record
add-to-record: $(STAMP) #### an off-ladder run added to a record: make add-to-record CASE=1-GB RUN=1:1:2 [OOC=1:1:2]
	@[ -n "$(CASE)" ] || { echo "error: give the case: make add-to-record CASE=1-GB RUN=1:1:2" >&2; exit 2; }
	$(PY) -m studies.convergence $(CASE) --add-to-record $(RUN) $(if $(OOC),--out-of-core $(OOC)) \
	  --timeout $(CONV_MAIN_TIMEOUT) --out $(RESULTS)/convergence

# The case-1 speed-against-error benchmark is the convergence study of 1-GB (with P2).
bench-case1: $(STAMP) #### case 1 speed against error: the convergence study of 1-GB, results/convergence/1-GB/
	@$(MAKE) --no-print-directory convergence CASE=1-GB CONV_EXTRA=0:2

# The radial mesh stiffness of the case-1 meshes from the FE (pust2016): with the case's
# contact model (zone) at level RS_LEVEL (1: the level-0 zone grid's fit sits 7-11 % off the
# closed form, level 1's within about 2 %; README) and with the line model, the closed form's
# premise (forces on the plane of action, exact at any level), at level 0 in line/. 45 solves
# each: 30.5 min and 6.7 GB at level 1, 3.5 min at level 0 (2026-11-29, beside other work).
RS_LEVEL ?= 1
.PHONY: radial-stiffness phasing
radial-stiffness: $(STAMP) ### FE radial mesh stiffness, floating-sun threshold: results/radial_stiffness/
	$(PY) -m studies.radial_stiffness --case 1-GB --level $(RS_LEVEL) --out $(RESULTS)/radial_stiffness
	$(PY) -m studies.radial_stiffness --case 1-GB --level 0 --contact-model line \
	  --out $(RESULTS)/radial_stiffness/line

# Planet phasing (parker2000): 3 equally spaced planets, and 4 at 0/91.4/180/271.4 deg (snapped
# to the assemblable 91.43, 271.43), all-planet scene, 12 positions over one mesh cycle, level 0
# (about 15 min on 2 cores).
phasing: $(STAMP) ### planet phasing, all-planet FE over one mesh cycle: results/phasing/
	$(PY) -m studies.phasing --case parker2000-3 --case parker2000-4 0 91.4 180 271.4 \
	  --positions 12 --level 0 --out $(RESULTS)/phasing

# Lead slopes of pinion and sun that re-centre the patterns (|ZS|, |ZR| < 0.5 mm), at the case's level.
.PHONY: lead-correction
lead-correction: $(STAMP) ### lead correction of a case: make lead-correction CASE=1-GB -> results/lead_correction/
	@[ -n "$(CASE)" ] || { echo "error: give the case: make lead-correction CASE=1-GB" >&2; exit 2; }
	$(PY) -m studies.lead_correction --case $(CASE) --out $(RESULTS)/lead_correction

# Peer cross-check (issue 16): 1-GA and 1-GC, one position, ours and CalculiX on the same
# meshes (level 0; PEER_LEVELS="0 1" adds the default level). Installs calculix-ccx when run as
# root and ccx is missing; the main `make` and `make test` never need it.
.PHONY: bench-peer ccx-setup
PEER_LEVELS ?= 0
# e.g. PEER_ARGS="--ccx-penalty-sweep 1000 10 --reuse-ccx" (see studies/peer/driver.py)
PEER_ARGS ?=
ccx-setup: #### install CalculiX (ccx) for bench-peer when it is missing (apt-get as root)
	@command -v ccx >/dev/null 2>&1 || { \
	  if [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then \
	    echo "installing calculix-ccx (apt-get)"; \
	    DEBIAN_FRONTEND=noninteractive apt-get install -y calculix-ccx >/dev/null || \
	      { apt-get update >/dev/null && DEBIAN_FRONTEND=noninteractive apt-get install -y calculix-ccx >/dev/null; }; \
	  fi; \
	  command -v ccx >/dev/null 2>&1 || { echo "error: CalculiX (ccx) not found and not installable here: run 'apt-get install -y calculix-ccx' as root (Debian/Ubuntu), or put ccx on PATH" >&2; exit 1; }; }

bench-peer: $(STAMP) ccx-setup ### ours against CalculiX on the same meshes: results/bench/peer.{json,md}
	$(PY) -m studies.peer --cases 1-GA 1-GC --levels $(PEER_LEVELS) --out $(RESULTS)/bench \
	  $(PEER_ARGS)

# The docs site, offline, warnings as errors (the case-file references are generated from
# cases/reference.py at the start of the build).
docs: $(STAMP) ## the docs site: docs/_build/html/index.html
	$(VENV)/bin/sphinx-build -W --keep-going -q -b html docs docs/_build/html

lint: $(STAMP) ## ruff
	$(VENV)/bin/ruff check $(PACKAGES) tests docs
	$(VENV)/bin/ruff format --check $(PACKAGES) tests docs

clean: ## remove results and caches, including cached meshes (keeps the virtualenv)
	rm -rf $(RESULTS) .cache .pytest_cache .ruff_cache
	find . -name __pycache__ -type d -prune -exec rm -rf {} +

distclean: clean ## also remove the virtualenv
	rm -rf $(VENV)

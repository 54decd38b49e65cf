# graspcampaign — make targets used locally and in CI. `make help` lists them.
PY      ?= python3
VENV    ?= .venv
BIN     := $(VENV)/bin
STAMP   := $(VENV)/.install.stamp
GC      := $(BIN)/graspcampaign
WARM    := $(VENV)/.warm.stamp
KERNELS := $(shell grep -l "cache=True" src/graspcampaign/core/*.py src/graspcampaign/analysis/*.py)
# Python's default, even where the environment turns it off: modules compiled once into
# __pycache__ (git-ignored), so the test workers and each command do not compile every module again
unexport PYTHONDONTWRITEBYTECODE

.PHONY: help install test test-slow test-full smoke demo reproduce extensions report bench lint clean

help:  ## list the targets
	@grep -E '^[a-z-]+:.*## ' $(MAKEFILE_LIST) | sed 's/:.*## /\t/' | expand -t 14

install: $(WARM)  ## create .venv, install the package with its dev, dask, ml and xlsx extras (not bench: MuJoCo), compile the kernels
$(STAMP): pyproject.toml
	$(PY) -m venv $(VENV)
	$(BIN)/pip install --quiet --disable-pip-version-check -e '.[dev,dask,ml,xlsx]'
	@touch $(STAMP)

# numba's on-disk cache of the compiled kernels (next to their sources), filled again whenever a
# kernel source changes, so no test session or study run pays the compilation (docs/decisions.md)
$(WARM): $(STAMP) $(KERNELS)
	@# numba keys a cache entry on its own file only: a kernel compiled with an older version of a
	@# kernel it calls would survive, so every entry is compiled afresh when any kernel changes
	@find src/graspcampaign -path '*__pycache__*' -name '*.nb[ic]' -delete
	$(BIN)/python -m graspcampaign.cli.warm
	@touch $(WARM)

# -n auto: one pytest-xdist worker per core. The fast suite is dealt out test by test and a worker
# that runs dry takes half of the other's queue (worksteal; its module fixtures are cheap, and no
# worker waits idle at the end); the slow tests keep a module's tests on one worker (loadscope, with
# the scheduler of tests/conftest.py, which builds the report tests' shared results tree once, first)
FAST    := -n auto --dist worksteal
XDIST   := -n auto --dist loadscope

test: install  ## fast test suite, parallel over the cores (one worker each)
	$(BIN)/pytest -q $(FAST)

test-slow: install  ## only the slow tests (end to end over every study; CI runs them after test)
	$(BIN)/pytest -q $(XDIST) -m slow

test-full: install  ## every test, slow ones included
	$(BIN)/pytest -q $(XDIST) -m ""

smoke: install  ## run the smoke study and write its report
	$(GC) run smoke --report

demo: install  ## run the baseline grid (Sec. 6.5: 675 scenes x 4 planners, + ferrari_canny) and its report
	$(GC) run baseline_grid --report

# $(call TIMED,command,label,file): run command, append "label seconds" to file, stop on failure
TIMED = t=$$(date +%s); $(1) || exit $$?; \
	echo "== $(2): $$(( $$(date +%s) - t )) s" | tee -a $(3)

# one process runs every study of `list --names` (its workers and their caches serve them all),
# then every report; `graspcampaign reproduce` prints each step's time
reproduce: install  ## the paper's studies at paper scale, then every report; times printed at the end
	@mkdir -p results; f=results/.reproduce_times; : > $$f; start=$$(date +%s); \
	$(GC) reproduce --times $$f || exit $$?; echo "== wall time per step:"; cat $$f; \
	echo "== make reproduce: $$(( $$(date +%s) - start )) s on $$(nproc) cores"

extensions: install  ## after reproduce: the studies beyond the paper (SPEC §8) with their reports, timed
	@mkdir -p results; f=results/.extension_times; : > $$f; \
	for s in $$($(GC) list --names --extensions); do \
	$(call TIMED,$(GC) run $$s --report,$$s,$$f); done; echo "== wall time per study:"; cat $$f

report: install  ## reports for every run under results/
	$(GC) report

bench: install  ## benchmarks: ratios against references measured in the same run
	@for f in benchmarks/bench_*.py; do echo "== $$f"; $(BIN)/python $$f || exit $$?; done

lint: install  ## ruff
	$(BIN)/ruff check src tests benchmarks

clean:  ## remove the virtual environment and caches (results/ is kept)
	rm -rf $(VENV) .pytest_cache .ruff_cache .hypothesis

# Finite-element verification workbench for 2D frictionless elastic contact.
# Two commands matter:  `make run`  (every case + summary report)  and  `make test`.
# Both create the project venv (.venv) by themselves.

SHELL := /bin/bash
.DEFAULT_GOAL := help

VENV   := .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.stamp-$(shell cat requirements.txt 2>/dev/null | cksum | cut -d' ' -f1)
# Kratos Multiphysics lives in a venv of its own (its libraries must not meet dolfinx's MPI and PETSc)
KVENV  := .venv-kratos
KSTAMP := $(KVENV)/.stamp-$(shell cat requirements-kratos.txt 2>/dev/null | cksum | cut -d' ' -f1)
NP     ?= 1
# cases that `make run` solves at once (each case is one process with one thread): the 2 cores of the machine
JOBS   ?= 2
TEST_JOBS ?= 2
# NP is a whole number >= 1 (MPI processes): anything else stops here with one line (make exits 2)
_np_rest := $(NP)
$(foreach d,0 1 2 3 4 5 6 7 8 9,$(eval _np_rest := $$(subst $(d),,$$(_np_rest))))
ifneq ($(strip $(_np_rest))$(words $(NP))$(filter 0%,$(NP)),1)
$(error NP = '$(NP)' is not allowed; allowed: a whole number >= 1 (MPI processes))
endif
MPIRUN := $(if $(filter-out 1,$(NP)),$(VENV)/bin/mpiexec -n $(NP),)
_tj_rest := $(TEST_JOBS)
$(foreach d,0 1 2 3 4 5 6 7 8 9,$(eval _tj_rest := $$(subst $(d),,$$(_tj_rest))))
ifneq ($(strip $(_tj_rest))$(words $(TEST_JOBS))$(filter 0%,$(TEST_JOBS)),1)
$(error TEST_JOBS = '$(TEST_JOBS)' is not allowed; allowed: a whole number >= 1 (pytest workers))
endif

CASES  := $(basename $(notdir $(wildcard cases/*.toml)))
METRICS := $(foreach c,$(CASES),results/$(c)/metrics.json)
SOURCES := $(wildcard analytic/*.py meshes/*.py fem/*.py fem/*/*.py cases/*.py workbench/*.py workbench/*/*.py)
WB     := $(VENV)/bin/workbench
# one thread per process: `make -j2` and MPI ranks share the 2 cores instead of oversubscribing them
export OMP_NUM_THREADS := 1
export OPENBLAS_NUM_THREADS := 1

# The Kratos venv's Python: 3.12 or 3.13 (the versions Kratos 10.4.4 has wheels for), found the same way.
define find_kratos_python
for c in "$$KRATOS_PYTHON" python3.13 python3.12 \
         $$(ls -d $$(pyenv root 2>/dev/null || echo $$HOME/.pyenv)/versions/3.1[23]*/bin/python3 2>/dev/null | sort -rV); do \
  [ -n "$$c" ] || continue; \
  if "$$c" -c 'import sys; sys.exit(0 if sys.version_info[:2] in ((3, 12), (3, 13)) else 1)' >/dev/null 2>&1; then \
    echo "$$c"; exit 0; fi; \
done; exit 1
endef

# Find a Python >= 3.12 that really runs: $PYTHON, then python3.13/python3.12 on PATH
# (pyenv shims exist but may fail), then pyenv's installed versions.
define find_python
for c in "$$PYTHON" python3.13 python3.12 \
         $$(ls -d $$(pyenv root 2>/dev/null || echo $$HOME/.pyenv)/versions/3.1[2-9]*/bin/python3 2>/dev/null | sort -rV); do \
  [ -n "$$c" ] || continue; \
  if "$$c" -c 'import sys; sys.exit(0 if sys.version_info >= (3, 12) else 1)' >/dev/null 2>&1; then \
    echo "$$c"; exit 0; fi; \
done; exit 1
endef

.PHONY: help setup test run ci lint clean collect-alone mutations convergence stability validity concave-map bench report list example check-numbers fuzz faults $(CASES)
.PHONY: finite-halfplanes slow-tests viz-check external external-ccx kratos-venv kratos-check save-baseline save-numbers emulate model-bands

# Exit codes: the workbench exits 1 on a tolerance FAIL (results written) and 2 on bad input (nothing written).
# GNU make itself always exits 2 when a recipe fails, so the recipe names the workbench's own code on the last
# line; call .venv/bin/workbench directly to get the code as the exit status.
explain_exit = s=$$?; case $$s in 0) ;; 1) echo "make: $(1): workbench exit 1 = tolerance FAIL (results written)" >&2;; 2) echo "make: $(1): workbench exit 2 = bad input (nothing written)" >&2;; *) echo "make: $(1): workbench exit $$s" >&2;; esac; exit $$s
SUDO := $(shell [ "$$(id -u)" = 0 ] || echo sudo)

help:
	@echo "make run          every case at its default resolution + results/report.{md,html}"
	@echo "make test         the fast test suite (creates .venv)"
	@echo "make <case>       one case: $(CASES)"
	@echo "make ci           every case at its coarsest level, fails on a tolerance violation"
	@echo "make convergence  error against run time study"
	@echo "make stability    stiff/extreme-case sweep"
	@echo "make validity     where Hertz / the wedge / Ciavarella-Hills hold, model by model -> results/validity/"
	@echo "make finite-halfplanes  the two-half-planes case at finite strain with its error budget (one case of make run)"
	@echo "make concave-map  where Hertz superposition holds over the concave design family -> results/concave_map/"
	@echo "make bench        performance benchmark"
	@echo "make save-baseline  make run, then save its key numbers as this machine's baseline (results/baseline/)"
	@echo "make check-numbers  make run, then every key number against that baseline at 1e-10 (refactor check)"
	@echo "make save-numbers   save the portable sets tests/data/key_numbers_{ci,run}.json from results/ci and results"
	@echo "make emulate      rerun the CI cases as another machine would (mesh, MUMPS ordering, numpy SIMD); LEVEL=run for make run"
	@echo "make example     examples/hertz_contact.py"
	@echo "make viz-check    installs Debian's paraview + xvfb if missing, runs the VTK and view.py checks in pvpython"
	@echo "make external     installs Debian's calculix-ccx and the Kratos venv (.venv-kratos) if missing, runs the workbench,"
	@echo "                  CalculiX and Kratos side by side on five cases, 3 levels each -> results/external_compare/"
	@echo "make kratos-check the Kratos job on the patch test and its writer's tests (creates .venv-kratos)"
	@echo "make model-bands  the workbench's model hierarchy on every case's scene, saved for score's verdict (CASES_BANDS=...)"
	@echo "make external-ccx the CalculiX tests (slow ones too) and external ccx on five cases, 3 levels each (CCX_CASES=...)"
	@echo "make slow-tests   the checks make test leaves out (concave_symmetric's error budget, every test file collected alone)"
	@echo "make fuzz         property-based fuzzing of case files and the command line (many examples)"
	@echo "make faults       concurrent runs, SIGINT/SIGTERM during writes, a full disk -> results/faults/report.md"
	@echo "make mutations    each mutation of tools/mutations.py must make the tests fail (names the catching test)"
	@echo "make collect-alone  every test file collects alone (pytest FILE and python -m pytest FILE)"
	@echo "make lint | clean | setup     (NP=N runs cases on N MPI processes, and studies on N-1 MPI workers)"
	@echo "Everything here calls the one command .venv/bin/workbench (see: .venv/bin/workbench --help)"

setup: $(STAMP)

$(STAMP): requirements.txt pyproject.toml
	@py=$$($(find_python)) || { echo "error: need Python >= 3.12 (set PYTHON=/path/to/python3.12; none found on PATH or under pyenv)" >&2; exit 2; }; \
	 if [ ! -x $(PY) ] || ! $(PY) -c 'import sys; sys.exit(0 if sys.version_info >= (3, 12) else 1)' 2>/dev/null; then \
	   echo "creating $(VENV) with $$py"; rm -rf $(VENV); "$$py" -m venv $(VENV) || exit 2; fi
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -r requirements.txt
	$(PY) -m pip install --quiet --no-deps --no-build-isolation -e .
	$(PY) -c "import dolfinx_solver, dolfinx, gmsh, meshio, scipy; print('dolfinx', dolfinx.__version__, 'gmsh', gmsh.__version__)"
	@rm -f $(VENV)/.stamp-*; touch $@

# two pytest workers (pytest-xdist), one test file per worker at a time (--dist loadfile: a file's module
# fixtures are built once); TEST_JOBS=1 runs the suite in one process
test: setup
	$(PY) -m pytest -q $(if $(filter-out 1,$(TEST_JOBS)),-n $(TEST_JOBS) --dist loadfile,-p no:xdist) tests

# The slow checks `make test` leaves out (each names this target when it skips): concave_symmetric's error budget,
# every test file collected alone (issue 28)
slow-tests: setup
	WORKBENCH_SLOW_TESTS=1 $(PY) -m pytest -q -rs tests/test_error_budget_cases.py tests/test_files_alone.py \
	 tests/test_studies_mpi.py tests/test_two_body_finite.py tests/test_two_body_convective.py tests/test_studies_smallest.py \
	 tests/test_halfplanes_finite.py

lint: setup
	$(VENV)/bin/ruff check .
	$(VENV)/bin/lint-imports

list: setup
	@$(WB) list

$(CASES): %: setup
	$(MPIRUN) $(WB) run $@; $(call explain_exit,$@)

report: setup
	$(WB) report

# Each case writes results/<case>/metrics.json; the pattern rule lets `make -j2 run` work, and a case
# reruns when its file or any source changes. `run` always ends with the summary report, even when a
# case failed (the make exit status still says so). The cases run without pictures (--no-pictures): the
# summary (`workbench report`) draws every case report again, pictures included, so they are drawn once.
results/%/metrics.json: cases/%.toml $(SOURCES) | setup
	$(MPIRUN) $(WB) run $* --no-pictures; $(call explain_exit,$*)

run: setup
	@$(MAKE) --no-print-directory -k -j$(JOBS) $(METRICS); status=$$?; \
	 $(WB) convective-table && $(WB) report; exit $$status

ci: setup
	$(WB) ci; $(call explain_exit,ci)

# a study on NP MPI ranks (1 master + NP-1 workers: mpi4py.futures, no spawn) when NP > 1, else locally
STUDY = $(if $(filter-out 1,$(NP)),$(MPIRUN) $(PY) -m mpi4py.futures -m workbench,$(WB))

convergence: setup
	$(STUDY) convergence

stability: setup
	$(STUDY) stability

# two processes (the study's own pool), or NP MPI ranks; prints its wall time at the end
validity: setup
	$(STUDY) validity

# the two-half-planes case at finite strain alone (also part of make run)
finite-halfplanes: setup
	$(MPIRUN) $(WB) run halfplanes_finite_parabola; $(call explain_exit,finite-halfplanes)

# one FEM run per design, in one process (55 designs x 5 loads; TINY=1: 2 x 2, the machinery)
concave-map: setup
	$(WB) concave-map $(if $(TINY),--tiny)

bench: setup
	$(WB) bench

example: setup
	$(PY) examples/hertz_contact.py

# Same-machine refactor check: every key number of `make run` against a baseline saved on THIS machine at
# 1e-10 relative. Not part of `make test` (another machine's mesh moves numbers by more; that is the portable
# regression of tests/test_cases_end_to_end.py, by number class). The baseline lives in results/ (ignored).
BASELINE ?= results/baseline/key_numbers.json
save-baseline: setup
	@$(MAKE) --no-print-directory run; s=$$?; \
	 $(PY) -m workbench.pipeline.key_numbers save results $(BASELINE) || exit 2; exit $$s

check-numbers: setup
	@test -f $(BASELINE) || { echo "error: no baseline $(BASELINE); save one on this machine first: make save-baseline" >&2; exit 2; }
	@[ -n "$(NO_RUN)" ] || $(MAKE) --no-print-directory run; s=$$?; \
	 $(PY) -m workbench.pipeline.key_numbers compare $(or $(RESULTS),results) $(BASELINE) || exit 1; exit $$s

# The portable saved sets (compared by number class in make test): from the results of `make ci` and `make run`.
save-numbers: setup
	@test -f results/ci/hertz_cylinder/metrics.json && test -f results/hertz_cylinder/metrics.json \
	 || { echo "error: run make ci and make run first (results/ci/*/metrics.json, results/*/metrics.json)" >&2; exit 2; }
	$(PY) -m workbench.pipeline.key_numbers save results/ci tests/data/key_numbers_ci.json
	$(PY) -m workbench.pipeline.key_numbers save results tests/data/key_numbers_run.json

# Another machine, emulated: every case rerun with the mesh geometry perturbed at 1e-14, another MUMPS ordering
# and numpy's SIMD dispatch off; exits 1 if a verdict changes or a number leaves its class tolerance.
LEVEL ?= ci
emulate: setup
	$(PY) -m workbench.pipeline.portability --level $(LEVEL) --out results/emulate/$(LEVEL)

# Property-based fuzzing (hypothesis): `make test` runs the "ci" profile (>= 1000 examples in total), this target
# the "fuzz" profile (10x as many).
fuzz: setup
	HYPOTHESIS_PROFILE=fuzz $(PY) -m pytest -q tests/test_fuzz_cases.py tests/test_fuzz_cli.py tests/test_fuzz_external.py

# Load and faults: 20 concurrent runs on 2 cores, repeated SIGINT/SIGTERM during writes, a full disk (a small
# tmpfs when it can be mounted, else a simulated ENOSPC), score and export interrupted and colliding with run;
# fails unless 0 corrupted and 0 lost.
faults: setup
	$(PY) tests/fault_campaign.py --out results/faults

# The real ParaView client on every case's VTK output and view.py (tests/test_paraview.py), and every HTML
# page of results/ (tests/test_pages.py).
viz-check: setup
	@if ! command -v pvpython >/dev/null || ! command -v xvfb-run >/dev/null; then \
	   echo "installing Debian's paraview and xvfb (apt-get)"; \
	   $(SUDO) apt-get update -qq && DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -qq paraview xvfb \
	   || { echo "error: could not install paraview and xvfb with apt-get" >&2; exit 2; }; fi
	@$(MAKE) --no-print-directory run
	WORKBENCH_VIZ_RESULTS=$(CURDIR)/results $(PY) -m pytest -q -rs tests/test_paraview.py tests/test_pages.py

# The Kratos venv, once per requirements-kratos.txt (a stamp, as the project venv's); one line and exit 2 if it
# cannot be made. Never .venv: workbench/external/kratos.py runs its job in this one.
kratos-venv: $(KSTAMP)

$(KSTAMP): requirements-kratos.txt
	@py=$$($(find_kratos_python)) || { echo "error: the Kratos venv needs Python 3.12 or 3.13 (Kratos 10.4.4 wheels); none found (set KRATOS_PYTHON=/path/to/python3.12)" >&2; exit 2; }; \
	 echo "creating $(KVENV) with $$py"; rm -rf $(KVENV); \
	 { "$$py" -m venv $(KVENV) && $(KVENV)/bin/python -m pip install --quiet -r requirements-kratos.txt \
	   && OMP_NUM_THREADS=1 $(KVENV)/bin/python -c "import KratosMultiphysics.ContactStructuralMechanicsApplication, KratosMultiphysics.LinearSolversApplication" >/dev/null; } \
	 || { echo "error: could not create $(KVENV) from requirements-kratos.txt (pip or the Kratos import failed)" >&2; rm -rf $(KVENV); exit 2; }; \
	 touch $@

# The Kratos job on the patch test (uniformity measured) and the writer's tests; not part of make test's run time
kratos-check: setup kratos-venv
	$(PY) -m pytest -q -rs tests/test_external_mdpa.py tests/test_external_kratos.py

# issue 36: three codes side by side. Installs Debian's calculix-ccx and the Kratos venv (.venv-kratos) if missing,
# runs `workbench external compare` (the workbench, CalculiX, Kratos on the same levels, scored alike) on
# COMPARE_CASES, three levels each -> results/external_compare/report.md (+ results/external_<code>_<case>/),
# then the external codes' tests
COMPARE_CASES ?= hertz_cylinder wedge patch_test elastic_cylinder_dissimilar close_to_conformal
external: setup kratos-venv
	@if ! command -v ccx >/dev/null; then \
	   echo "installing Debian's calculix-ccx (apt-get)"; \
	   $(SUDO) apt-get update -qq && DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -qq calculix-ccx \
	   || { echo "error: could not install calculix-ccx with apt-get" >&2; exit 2; }; fi
	$(WB) external compare $(COMPARE_CASES) --levels 3 --out results; $(call explain_exit,external compare)
	$(PY) -m pytest -q -rs tests/test_external_ccx.py tests/test_external_kratos.py tests/test_external_compare.py

# issue 36: the workbench's model hierarchy on every case's own scene, saved for the scorer's verdict
# (workbench/external/model_bands/<case>.json; CASES_BANDS="a b" for some; minutes per case)
model-bands: setup
	@for c in $(or $(CASES_BANDS),$(CASES)); do echo "model bands: $$c"; $(PY) -m workbench.external.models $$c || exit $$?; done

# issue 36: CalculiX on every case it models. The ccx tests, the slow ones too (the independent wedge on three levels),
# then `workbench external ccx` on the cases of the acceptance, three levels each -> results/external_ccx_<case>/
CCX_CASES ?= hertz_cylinder wedge patch_test elastic_cylinder_dissimilar close_to_conformal
external-ccx: setup
	@if ! command -v ccx >/dev/null; then \
	   echo "installing Debian's calculix-ccx (apt-get)"; \
	   $(SUDO) apt-get update -qq && DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -qq calculix-ccx \
	   || { echo "error: could not install calculix-ccx with apt-get" >&2; exit 2; }; fi
	WORKBENCH_CCX_SLOW=1 $(PY) -m pytest -q -rs tests/test_external_ccx.py tests/test_external_independent.py \
	  tests/test_ccx_independent_wedge.py tests/test_ccx_independent_patch.py
	@rc=0; for c in $(CCX_CASES); do $(WB) external ccx $$c --levels 3 --out results || rc=$$?; done; exit $$rc

clean:
	rm -rf results .pytest_cache .ruff_cache
	find . -name __pycache__ -not -path './.venv/*' -prune -exec rm -rf {} +

# Every test file collects alone, started both ways (`pytest FILE` and `python -m pytest FILE`): issue 28
collect-alone: setup
	@fail=0; for f in tests/test_*.py; do \
	  for run in "$(VENV)/bin/pytest" "$(PY) -m pytest"; do \
	    $$run --collect-only -q -p no:cacheprovider $$f >/dev/null 2>&1 || { echo "FAIL: $$run --collect-only $$f"; fail=1; }; \
	  done; done; \
	 [ $$fail = 0 ] && echo "every test file collects alone (pytest and python -m pytest)"; exit $$fail

# Mutation check (not part of `make test`): each mutation of tools/mutations.py applied to a temporary copy of the
# tree must make the test suite fail; prints which test caught it, exits 1 if one SURVIVED
mutations: setup
	$(PY) tools/mutations.py

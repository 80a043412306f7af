# Build plumbing for the coil_winding_sim catkin package.
#
#   make deps     install missing Debian packages (as root; skipped when all present)
#   make build    build the package in the catkin workspace .ws/ (git-ignored)
#   make run      run the wire_sim tool:  make run [SCENE=config/scenes/x.yaml] [OUT=out/x] [ARGS="..."]
#                 (the scene's method: bdf2 with strike steps in the package's scenes)
#   make reference  the same scene with the converged explicit method (symplectic_euler
#                 at its automatic step), into REF_OUT (default out/reference); compare
#                 with src/tools/compare_runs.py REF_OUT OUT
#   make study    the paper's 2 x 2 study: table and figure in docs/study (STUDY_OUT)
#   make coil-study  gaps and overlaps of a two-layer coil against tension and pitch:
#                 table and cross-sections in docs/study/coil (COIL_STUDY_OUT)
#   make bench    per-step cost against the number of points (Google Benchmark)
#   make work-precision   error against run time of every integrator (docs/performance)
#   make stability        extreme cases x every integrator, checked (docs/STABILITY.md)
#   make robustness       40 random coils, one core, each with a wall-time budget
#                 (docs/ROBUSTNESS.md; ROBUSTNESS_ARGS="--count N --seed S", ROBUSTNESS_BUDGET)
#   make compare  machine run vs simulation:  make compare BAG=run.bag [OUT=out/compare] [ARGS="--align angle"]
#                 or MACHINE=a.bag SIM=b.bag instead of BAG (src/tools/compare_bags.py)
#   make compare-demo   the same on synthetic bags with a known perturbation
#   make calibrate-demo wire_sim calibrate on synthetic recordings with known values
#                 (CALIBRATE_OUT, default out/calibrate_demo)
#   make screenshots    the rviz pictures of README.md and docs/cell.md, taken as their
#                 commands run (Xvfb)
#   make test     build and run all tests; non-zero exit if any test fails
#   make docs-check     README.md at most 300 lines, docs/PERFORMANCE.md at most 400,
#                 every relative link of the documents resolves (src/tools/check_docs.py;
#                 needs no build)
#   make format   clang-format -i all C++ sources (format-check: only check them)
#   make clean    remove the workspace .ws/
#
# Variables: JOBS (default 2), BUILD_TYPE (default Release), SKIP_DEPS=1 skips `deps`,
#            CWS_SIMD (AUTO, ON or OFF; default AUTO): AVX2/FMA code when the build
#            machine runs it (CMakeLists.txt; OFF for binaries copied to older CPUs),
#            TEST_TIMEOUT (seconds, default 1200): ctest timeout for tests that set none
#            themselves (the unit tests set CWS_UNIT_TEST_TIMEOUT=1200 in CMakeLists.txt).

SHELL := /bin/bash
.SHELLFLAGS := -eu -o pipefail -c
.DEFAULT_GOAL := build

# Debian's python3 (with catkin_pkg) must win over e.g. a pyenv python3 on PATH.
export PATH := /usr/bin:/bin:/usr/sbin:/sbin:$(PATH)
PYTHON := /usr/bin/python3

PKG := coil_winding_sim
ROOT := $(abspath $(dir $(lastword $(MAKEFILE_LIST))))
WS := $(ROOT)/.ws
BUILD_DIR := $(WS)/build
DEVEL_DIR := $(WS)/devel
BIN_DIR := $(DEVEL_DIR)/lib/$(PKG)
WIRE_SIM := $(BIN_DIR)/wire_sim
UNIT_TESTS := $(BIN_DIR)/$(PKG)_unit_tests
TEST_RESULTS := $(BUILD_DIR)/test_results

JOBS ?= 2
BUILD_TYPE ?= Release
CWS_SIMD ?= AUTO
TEST_TIMEOUT ?= 1200
OUT ?= out/default
SCENE ?=
ARGS ?=

DEB_PACKAGES := \
  catkin libroscpp-dev libtf2-ros-dev libtf2-eigen-dev libvisualization-msgs-dev \
  libstd-srvs-dev libsensor-msgs-dev librosbag-dev libtopic-tools-dev librostest-dev python3-rostest python3-roslaunch \
  ros-base-dev libdiagnostic-updater-dev libeigen3-dev libyaml-cpp-dev libgtest-dev \
  libbenchmark-dev python3-matplotlib python3-catkin-pkg \
  rviz python3-rostopic python3-rosbag xvfb imagemagick clang-format \
  python3-numpy python3-genpy python3-sensor-msgs python3-geometry-msgs python3-std-msgs \
  python3-rospkg python3-rosunit rosbash slurm-wlm munge \
  ros-robot-state-publisher liburdf-dev \
  libdynamic-reconfigure-config-init-mutex-dev python3-dynamic-reconfigure python3-roslib \
  libactionlib-dev libactionlib-msgs-dev python3-actionlib python3-actionlib-msgs ros-actionlib-msgs \
  libtrajectory-msgs-dev python3-trajectory-msgs libdlib-dev

CATKIN_MAKE := catkin_make --directory $(WS) \
  -DCMAKE_BUILD_TYPE=$(BUILD_TYPE) \
  -DCWS_SIMD=$(CWS_SIMD) \
  -DPYTHON_EXECUTABLE=$(PYTHON) \
  -DCATKIN_ENABLE_TESTING=ON \
  -DCMAKE_EXPORT_COMPILE_COMMANDS=ON

.PHONY: deps build run reference study coil-study bench work-precision stability robustness compare compare-demo calibrate-demo screenshots test format format-check docs-check clean

deps:
ifeq ($(SKIP_DEPS),1)
	@echo "deps: skipped (SKIP_DEPS=1)"
else
	@installed="$$(dpkg-query -W -f='$${Package} $${db:Status-Abbrev}\n' $(DEB_PACKAGES) 2>/dev/null \
	    | awk '$$2 == "ii" {print $$1}' || true)"; \
	missing=""; \
	for p in $(DEB_PACKAGES); do \
	  grep -qx "$$p" <<<"$$installed" || missing="$$missing $$p"; \
	done; \
	if [ -z "$$missing" ]; then \
	  echo "deps: all Debian packages installed"; \
	elif [ "$$(id -u)" -eq 0 ]; then \
	  echo "deps: installing:$$missing"; \
	  export DEBIAN_FRONTEND=noninteractive; \
	  apt-get update; \
	  apt-get install -y $$missing; \
	else \
	  echo "deps: missing Debian packages:$$missing" >&2; \
	  echo "deps: install them as root with:" >&2; \
	  echo "  sudo apt-get update && sudo DEBIAN_FRONTEND=noninteractive apt-get install -y$$missing" >&2; \
	  exit 1; \
	fi
endif

# Workspace layout: .ws/src/coil_winding_sim -> ../.. (this repository).
$(WS)/src/$(PKG):
	mkdir -p $(WS)/src
	ln -sfn ../.. $(WS)/src/$(PKG)

build: deps | $(WS)/src/$(PKG)
	$(CATKIN_MAKE) -j$(JOBS)

run: build
	mkdir -p "$(dir $(OUT))"
	$(WIRE_SIM) run --out "$(OUT)" $(if $(SCENE),--scene "$(SCENE)") $(ARGS)

# The explicit reference of a run (docs/PERFORMANCE.md): the same scene and
# settings with symplectic_euler at its automatic step, 1/4 of the time an
# axial wave needs to cross a segment.
REF_OUT ?= out/reference
reference: build
	mkdir -p "$(dir $(REF_OUT))"
	$(WIRE_SIM) run --out "$(REF_OUT)" $(if $(SCENE),--scene "$(SCENE)") $(ARGS) \
	  --set solver.integrator=symplectic_euler

# Error against run time for every integrator, the paper's 1200 and 600 rpm
# cases (30 N, 2 mm segments): CSVs and figure into docs/performance.
PERF_OUT ?= docs/performance
work-precision: build
	mkdir -p "$(PERF_OUT)"
	$(WIRE_SIM) work-precision --out out/wp_1200 --set wire.segment_length=2e-3 \
	  --set process.core_speed_rpm=1200 $(ARGS)
	$(WIRE_SIM) work-precision --out out/wp_600 --set wire.segment_length=2e-3 $(ARGS)
	cp out/wp_1200/work_precision.csv "$(PERF_OUT)/work_precision_1200rpm.csv"
	cp out/wp_600/work_precision.csv "$(PERF_OUT)/work_precision_600rpm.csv"
	$(PYTHON) src/tools/plot_work_precision.py "$(PERF_OUT)/work_precision.png" \
	  "1200 rpm=out/wp_1200" "600 rpm=out/wp_600"
	$(PYTHON) src/tools/work_precision_table.py "1200 rpm=out/wp_1200" "600 rpm=out/wp_600" \
	  > "$(PERF_OUT)/work_precision_tables.md"

# The stability matrix: every extreme case with every integrator, checked
# against the stated criteria: docs/STABILITY.md and docs/stability/*.csv.
# Fails (after writing them) when a run broke a criterion or its budget.
# A study stopped midway continues where it was (out/stability/runs);
# ARGS=--fresh starts over.
stability: build
	mkdir -p docs/stability
	@rc=0; $(WIRE_SIM) stability --out out/stability --jobs $(JOBS) $(ARGS) || rc=$$?; \
	if [ -f out/stability/STABILITY.md ]; then \
	  cp out/stability/STABILITY.md docs/STABILITY.md; \
	  cp out/stability/stability.csv docs/stability/stability.csv; \
	fi; \
	exit $$rc

# The robustness suite (issue 39): coils drawn by a seeded generator, run
# one at a time on one core, each within ROBUSTNESS_BUDGET seconds of wall
# time, as a sweep (kept cases are not run again; ARGS="--slurm ..." would
# submit them instead). The table: docs/ROBUSTNESS.md and
# docs/robustness/robustness.csv. Then the abuse suite (src/tools/abuse.py):
# faults and extremes, each with its expected outcome, appended to
# docs/ROBUSTNESS.md. Fails when a case did not finish or an abuse case's
# outcome is not the expected one.
ROBUSTNESS_OUT ?= out/robustness
ROBUSTNESS_ARGS ?= --count 40 --seed 1
ROBUSTNESS_BUDGET ?= 200
robustness: build
	mkdir -p $(ROBUSTNESS_OUT) docs/robustness
	$(PYTHON) src/tools/robustness.py cases $(ROBUSTNESS_ARGS) > $(ROBUSTNESS_OUT)/cases.csv
	@rc=0; taskset -c 0 $(WIRE_SIM) sweep --scene config/scenes/two_layers.yaml \
	  --cases $(ROBUSTNESS_OUT)/cases.csv --budget $(ROBUSTNESS_BUDGET) --jobs 1 \
	  --out $(ROBUSTNESS_OUT)/runs $(ARGS) || rc=$$?; \
	$(PYTHON) src/tools/robustness.py report $(ROBUSTNESS_OUT)/runs docs/robustness || rc=1; \
	if [ -f docs/robustness/ROBUSTNESS.md ]; then mv docs/robustness/ROBUSTNESS.md docs/ROBUSTNESS.md; fi; \
	taskset -c 0 $(PYTHON) src/tools/abuse.py run $(WIRE_SIM) $(ROBUSTNESS_OUT)/abuse \
	  --budget $(ROBUSTNESS_BUDGET) || rc=1; \
	$(PYTHON) src/tools/abuse.py report $(ROBUSTNESS_OUT)/abuse docs/ROBUSTNESS.md || rc=1; \
	exit $$rc

# Machine run vs simulation (issue 7): summary.json, summary.md and plots in
# COMPARE_OUT. Needs no build: the tool reads the message definitions stored in the bag.
COMPARE_OUT ?= out/compare
compare: deps
	$(if $(BAG),,$(if $(and $(MACHINE),$(SIM)),,$(error compare: give BAG=run.bag or MACHINE=a.bag SIM=b.bag)))
	$(PYTHON) src/tools/compare_bags.py $(if $(BAG),"$(BAG)",--machine "$(MACHINE)" --sim "$(SIM)") \
	  --out "$(COMPARE_OUT)" $(ARGS)

# The comparison on synthetic bags: tension +2 N with 0.2 N noise, machine 5 ms
# late, profile 0.1 mm out (the example of docs/compare-and-calibrate.md).
compare-demo: deps
	mkdir -p out/compare_demo
	$(PYTHON) src/tools/make_synthetic_bags.py --combined-bag out/compare_demo/synthetic.bag \
	  --tension-offset 2 --tension-noise 0.2 --time-shift 0.005 --profile-offset-mm 0.1
	$(PYTHON) src/tools/compare_bags.py out/compare_demo/synthetic.bag --out out/compare_demo $(ARGS)

# Calibration against synthetic machine recordings with known values
# (src/tools/calibrate_demo.sh: the usual five keys and one without effect),
# into CALIBRATE_OUT (default out/calibrate_demo).
CALIBRATE_OUT ?= out/calibrate_demo
calibrate-demo: build
	WIRE_SIM=$(WIRE_SIM) src/tools/calibrate_demo.sh $(CALIBRATE_OUT)

# The rviz pictures of README.md and docs/cell.md, each taken as its command
# (docs/cell.md) runs (src/tools/rviz_screenshot.sh; test_screenshots takes
# them too).
screenshots: build
	set +u && source $(DEVEL_DIR)/setup.bash && set -u && src/tools/rviz_screenshot.sh docs/rviz_winding_cell.png \
	  real_time_factor:=0
	set +u && source $(DEVEL_DIR)/setup.bash && set -u && src/tools/rviz_screenshot.sh docs/rviz_coil_layers.png \
	  scene:=$(ROOT)/config/scenes/two_layers.yaml \
	  "overrides:=[process.turns=14, process.winding_width=7e-3]" real_time_factor:=0 \
	  rviz_config:=$(ROOT)/rviz/coil.rviz
	set +u && source $(DEVEL_DIR)/setup.bash && set -u && src/tools/rviz_screenshot.sh docs/rviz_user_coil.png \
	  scene:=$(ROOT)/config/scenes/user_coil.yaml real_time_factor:=0 \
	  rviz_config:=$(ROOT)/rviz/coil.rviz

# Per-step cost against the number of points (Google Benchmark).
bench: build
	$(BIN_DIR)/bench_step --benchmark_min_time=0.5 $(ARGS)

# The paper's 2 x 2 case study: table (CSV, Markdown) and figure in STUDY_OUT.
STUDY_OUT ?= docs/study
study: build
	$(WIRE_SIM) study --out "$(STUDY_OUT)" $(if $(SCENE),--scene "$(SCENE)") $(ARGS)
	$(PYTHON) src/tools/plot_study.py "$(STUDY_OUT)"

# Gaps and overlaps of a two-layer coil (docs/COIL_STUDY.md): 3 tensions x 4
# traverse pitches, the runs' outputs in out/coil_study.
COIL_STUDY_OUT ?= docs/study/coil
coil-study: build
	$(PYTHON) src/tools/coil_study.py "$(WIRE_SIM)" "$(COIL_STUDY_OUT)" --jobs 2 \
	  --runs out/coil_study

# Builds the test binaries (catkin target `tests`), then runs every registered test
# (gtest now, rostest later) through ctest. catkin registers each test for ctest via
# run_tests.py --return-code, so a test fails when its process exits non-zero
# (failed case, crash, timeout) or when it wrote no JUnit result file. The sources'
# format (.clang-format) and the documents (docs-check) are checked first.
test: build format-check docs-check
	$(CATKIN_MAKE) -j$(JOBS) tests
	@if [ ! -x "$(UNIT_TESTS)" ]; then \
	  echo "test: unit test binary $(UNIT_TESTS) was not built" >&2; exit 1; \
	fi
	rm -rf "$(TEST_RESULTS)"
	@rc=0; \
	cd "$(BUILD_DIR)"; \
	ctest -V --no-tests=error --timeout $(TEST_TIMEOUT) || rc=$$?; \
	echo "-------------------------------------------------------------------"; \
	catkin_test_results "$(TEST_RESULTS)" || rc=1; \
	if [ "$$rc" -ne 0 ]; then \
	  echo "test: FAILED. Failed gtest cases / tests:" >&2; \
	  grep -h '^\[  FAILED  \] [A-Za-z_]' Testing/Temporary/LastTest*.log 2>/dev/null \
	    | sed -E 's/ \([0-9]+ ms\)$$//' | sort -u >&2 || true; \
	  last_run="$$(grep -h '^\[ RUN      \]' Testing/Temporary/LastTest*.log 2>/dev/null | tail -n 1 || true)"; \
	  [ -z "$$last_run" ] || echo "test: last gtest case started (check it if the binary crashed or timed out): $$last_run" >&2; \
	  echo "test: what the failed cases said:" >&2; \
	  $(PYTHON) $(ROOT)/src/tools/test_failures.py "$(TEST_RESULTS)" >&2 || true; \
	  exit 1; \
	fi; \
	echo "test: all tests passed"

CXX_SOURCES = $(shell find $(addprefix $(ROOT)/,include src test) \
  \( -name '*.cpp' -o -name '*.hpp' -o -name '*.h' -o -name '*.cc' \) 2>/dev/null)

format:
	$(if $(strip $(CXX_SOURCES)),clang-format -i $(CXX_SOURCES),@echo "format: no sources")

format-check:
	$(if $(strip $(CXX_SOURCES)),clang-format --dry-run -Werror $(CXX_SOURCES),@echo "format: no sources")

# The documents cannot grow back (issue 61): README.md at most 300 lines,
# docs/PERFORMANCE.md at most 400, and every relative link (and its #anchor)
# of README.md, docs/*.md and docs/history/*.md names a file that exists.
# Needs no build and no Debian package beyond python3.
docs-check:
	$(PYTHON) $(ROOT)/src/tools/check_docs.py $(ROOT)

clean:
	rm -rf $(WS)

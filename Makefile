# dpn: one-command setup, build and test.
#
#   make setup   .venv (python3 -m venv) with every pin of requirements.txt and of the optional
#                requirements-ray.txt (so the Ray backend's test runs); re-runs only when they
#                change. Then builds the stand-ins of two message packages PyPI has no wheel
#                for (fallback/: tf2_msgs with TFMessage, map_msgs with OccupancyGridUpdate;
#                about 30 s each) into .venv (docs/setup.md)
#   make build   colcon build into build/ install/ log/, then compile_kernels: the kernels
#                compiled into the installed package, so a node's first start loads them
#                (about 25 CPU-s the first time, under 1 s when the sources did not change)
#   make test    build, then colcon test (pytest output on the console) and colcon test-result;
#                fails if any test fails or errors. Every test runs, the slow ones too: this is
#                what CI runs (.ci/run)
#   make test-fast  the same without the tests marked slow (pytest -m 'not slow'; each takes
#                about 5 s or more), for the edit-test loop
#   make demo    build, then one episode over ROS 2: the pybullet world (back_and_forth, 3
#                wanderers, headless) and the dpn navigator as separate processes; prints the
#                outcome and writes out/demo/*.png (DEMO_ARGS: see --help of dpn_navigator.tools.demo)
#   make bench   build, then python tools/bench_core.py $(BENCH_ARGS) with the package
#                importable
#   make bench-ros  build, then python tools/bench_ros.py: simulator real-time factor and
#                the dpn node's scan-to-map latency over ROS 2
#   make benchmark  build, then the paper's test protocol without ROS: dpn-benchmark
#                $(BENCHMARK_ARGS) (default: --profile smoke --out out/benchmark; see its --help)
#   make fuzz    build, then python tools/fuzz_ros.py $(FUZZ_ARGS): the nine failures of
#                issue 11 and 9,000 hypothesis-drawn messages to both node processes over DDS;
#                prints counters, crashes and exit codes (docs/safety.md)
#   make soak    build, then python tools/soak_ros.py $(SOAK_ARGS): both nodes with 10
#                wanderers for 10 minutes (--minutes), new goals as goals are reached; prints
#                the RSS growth of each process [MB/h]: a fitted slope and its 95 % interval
#   make faults  build, then python tools/faults_ros.py $(FAULTS_ARGS): 20 trials each
#                of the time from the last message to the first zero command (sensors stop on
#                wall time, on sim time, the world killed; with the commands after the stop)
#                and of SIGINT/SIGTERM exits, of busy pairs and 0.2-3 s after a node's start
#   make clean   remove build/ install/ log/;  make distclean  also removes .venv/
#
# Needs only python3.11 with its venv module (Debian/Ubuntu: apt-get install python3-venv; a
# python.org or pyenv build has it), make, bash and a C compiler (for the message stand-ins):
# everything else, CMake included, comes from PyPI. The ROS 2
# Jazzy wheels on PyPI are built for CPython 3.11 only.
#
# Knobs: PYTHON (interpreter for the venv), ROS_DOMAIN_ID (default 42), COLCON_BUILD_ARGS (e.g.
# --symlink-install), BENCH_ARGS, BENCH_ROS_ARGS.

SHELL := /bin/bash
# No -u: colcon's setup.bash reads unset variables.
.SHELLFLAGS := -eo pipefail -c
.DEFAULT_GOAL := test
.DELETE_ON_ERROR:

ROOT := $(patsubst %/,%,$(dir $(abspath $(lastword $(MAKEFILE_LIST)))))
PYTHON ?= $(shell command -v python3.11 || command -v python3)
VENV := $(ROOT)/.venv
VENV_BIN := $(VENV)/bin
# Stamp of the last successful install of requirements.txt into .venv.
REQUIREMENTS_STAMP := $(VENV)/.requirements.stamp
# The message stand-ins (fallback/, docs/setup.md): each one's stamp of its install into .venv.
STAND_INS := tf2_msgs map_msgs nav2_msgs
STAND_IN_STAMPS := $(foreach name,$(STAND_INS),$(VENV)/.$(name).stamp)

# colcon and everything it starts run with the venv's python.
export PATH := $(VENV_BIN):$(PATH)
export VIRTUAL_ENV := $(VENV)
export PIP_DISABLE_PIP_VERSION_CHECK := 1
# ROS traffic of tests, benchmarks and demos stays on this machine, in its own domain. A test
# that starts processes should still give them a domain id of its own, so that two runs on one
# machine do not talk to each other.
export ROS_AUTOMATIC_DISCOVERY_RANGE ?= LOCALHOST
export ROS_DOMAIN_ID ?= 42

COLCON := $(VENV_BIN)/colcon
COLCON_BUILD_ARGS ?=
# Extra arguments of colcon test (make test-fast sets them).
COLCON_TEST_ARGS ?=
BENCH_ARGS ?=
BENCHMARK_ARGS ?= --profile smoke --out out/benchmark
DEMO_ARGS ?=
FUZZ_ARGS ?=
SOAK_ARGS ?=
FAULTS_ARGS ?=
# Sets AMENT_PREFIX_PATH, PYTHONPATH and the rest for the installed package.
SOURCE_INSTALL := source $(ROOT)/install/setup.bash

.PHONY: setup build test test-fast demo bench bench-ros benchmark fuzz soak faults clean distclean help

help:
	@sed -n '1,/^$$/s/^# \{0,1\}//p' $(ROOT)/Makefile

setup: $(REQUIREMENTS_STAMP) $(STAND_IN_STAMPS)

$(VENV_BIN)/python:
	@$(PYTHON) -c 'import sys; sys.exit(sys.version_info[:2] != (3, 11))' || { \
	  echo "make: $(PYTHON) is not Python 3.11; the ROS 2 Jazzy wheels need 3.11:" \
	       "run make PYTHON=/path/to/python3.11" >&2; exit 1; }
	$(PYTHON) -m venv $(VENV) || { rm -rf $(VENV); \
	  echo "make: '$(PYTHON) -m venv' failed; on Debian/Ubuntu: apt-get install python3-venv" >&2; \
	  exit 1; }

$(REQUIREMENTS_STAMP): $(ROOT)/requirements.txt $(ROOT)/requirements-ray.txt \
    $(ROOT)/requirements-tf2-fallback.txt | $(VENV_BIN)/python
	$(VENV_BIN)/python -m pip install --progress-bar off -r $(ROOT)/requirements.txt \
	  -r $(ROOT)/requirements-ray.txt -r $(ROOT)/requirements-tf2-fallback.txt
	touch $@

# The stand-ins (tf2_msgs with TFMessage only, map_msgs with OccupancyGridUpdate only; the
# standard definitions) built with the wheels' rosidl generators and installed into .venv, an
# ament prefix like the one the ROS wheels install into: rclpy, the ament index and the loader
# find them there with no environment to source. fallback/ holds a COLCON_IGNORE, so a colcon
# build of this repository (the apt Jazzy path) never sees them.
.SECONDEXPANSION:
$(STAND_IN_STAMPS): $(VENV)/.%.stamp: $$(wildcard $(ROOT)/fallback/$$*/*.* $(ROOT)/fallback/$$*/msg/* $(ROOT)/fallback/$$*/action/*) \
    $(ROOT)/fallback/wheel_include_dirs.cmake \
    $(REQUIREMENTS_STAMP)
	rm -rf $(VENV)/build/$*
	$(VENV_BIN)/cmake -S $(ROOT)/fallback/$* -B $(VENV)/build/$* \
	  -DCMAKE_INSTALL_PREFIX=$(VENV) -DCMAKE_PREFIX_PATH=$(VENV) \
	  -DPython3_EXECUTABLE=$(VENV_BIN)/python -DCMAKE_BUILD_TYPE=Release -DBUILD_TESTING=OFF
	$(VENV_BIN)/cmake --build $(VENV)/build/$* -j 2
	$(VENV_BIN)/cmake --install $(VENV)/build/$*
	$(VENV_BIN)/python -c 'import $*.$(if $(filter nav2_msgs,$*),action,msg)'
	touch $@

build: setup
	cd $(ROOT) && $(COLCON) build $(COLCON_BUILD_ARGS)
	cd $(ROOT) && $(SOURCE_INSTALL) && $(ROOT)/install/dpn_navigator/lib/dpn_navigator/compile_kernels

# colcon test runs pytest in this directory with the package's install prefix on
# AMENT_PREFIX_PATH and PYTHONPATH (no need to source install/setup.bash). It exits 0 when tests
# fail (it only flags them) and non-zero when pytest could not run (e.g. a collection error);
# colcon test-result exits non-zero when a result holds a failure or an error. Both always run, so
# the per-test report is printed, and either failing fails the target. The last line is a plain
# "colcon: N passed, N failed, N skipped".
test: build
	@echo '$(COLCON) test --event-handlers console_direct+ $(COLCON_TEST_ARGS) && $(COLCON) test-result --verbose'
	@cd $(ROOT); \
	set +e; \
	$(COLCON) test --event-handlers console_direct+ $(COLCON_TEST_ARGS); \
	test_rc=$$?; \
	$(COLCON) test-result --verbose | tee build/test-result.txt; \
	result_rc=$$?; \
	sed -nE 's/^Summary: ([0-9]+) tests?, ([0-9]+) errors?, ([0-9]+) failures?, ([0-9]+) skipped$$/\1 \2 \3 \4/p' \
	  build/test-result.txt | \
	  { read -r total errors failures skipped && \
	    echo "colcon: $$((total - errors - failures - skipped)) passed, $$((errors + failures)) failed, $$skipped skipped"; }; \
	if [ "$$test_rc" -ne 0 ] || [ "$$result_rc" -ne 0 ]; then \
	  echo "make test: FAILED (colcon test exit $$test_rc, colcon test-result exit $$result_rc)" >&2; \
	  exit 1; \
	fi

test-fast: COLCON_TEST_ARGS = --pytest-args -m 'not slow'
test-fast: test

demo: build
	cd $(ROOT) && $(SOURCE_INSTALL) && python -m dpn_navigator.tools.demo $(DEMO_ARGS)

bench: build
	cd $(ROOT) && $(SOURCE_INSTALL) && python tools/bench_core.py $(BENCH_ARGS)

bench-ros: build
	cd $(ROOT) && $(SOURCE_INSTALL) && python tools/bench_ros.py $(BENCH_ROS_ARGS)

benchmark: build
	cd $(ROOT) && $(SOURCE_INSTALL) && \
	  $(ROOT)/install/dpn_navigator/lib/dpn_navigator/dpn-benchmark $(BENCHMARK_ARGS)

fuzz: build
	cd $(ROOT) && $(SOURCE_INSTALL) && python tools/fuzz_ros.py $(FUZZ_ARGS)

soak: build
	cd $(ROOT) && $(SOURCE_INSTALL) && python tools/soak_ros.py $(SOAK_ARGS)

faults: build
	cd $(ROOT) && $(SOURCE_INSTALL) && python tools/faults_ros.py $(FAULTS_ARGS)

clean:
	rm -rf $(ROOT)/build $(ROOT)/install $(ROOT)/log

distclean: clean
	rm -rf $(VENV)

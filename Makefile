# rope_sim_ros: one local environment (.venv) with ROS 2 Jazzy from PyPI wheels, built with colcon.
PYTHON ?= python3
VENV := .venv
BIN := $(CURDIR)/$(VENV)/bin
# ament_index (message packages, our share/) lives in the venv prefix with the PyPI wheels.
export AMENT_PREFIX_PATH := $(CURDIR)/install/rope_sim_ros:$(CURDIR)/$(VENV)
export ROS_AUTOMATIC_DISCOVERY_RANGE := LOCALHOST
export PYTHONPATH := $(CURDIR)
export PYTHONDONTWRITEBYTECODE := 1

.PHONY: venv build demo test lint bench clean study-demo

venv: $(VENV)/.installed

$(VENV)/.installed: requirements.txt requirements-dev.txt
	$(PYTHON) -m venv $(VENV)
	$(BIN)/pip install --quiet --upgrade pip
	$(BIN)/pip install --quiet -r requirements-dev.txt
	touch $@

build: venv
	$(BIN)/colcon --log-base log build --paths . --build-base build --install-base install \
		--event-handlers console_cohesion- status-

demo: build
	$(BIN)/python -m rope_sim_ros.offline.demo

# The kernels the tests load from the source tree, compiled once: copied from install/ when
# `make build` compiled them from these sources (4 s, not 2-5 minutes), else compiled here; the
# colcon build of the tests then copies them into its install instead of compiling them.
SEED := $(if $(wildcard install/rope_sim_ros),--seed-from install/rope_sim_ros)

# test/conftest.py gives the run its own ROS_DOMAIN_ID (1..101) unless one is set.
# The tests that need no node process run side by side, a worker a core (each worker its
# own ROS_DOMAIN_ID); then those that run the installed nodes on the wall clock (marked
# `alone` by test/conftest.py), one at a time: their timing is what they test.
test: venv
	$(BIN)/python -m rope_sim_ros.mooring.precompile $(SEED)
	$(BIN)/python -m pytest -q -n auto -m 'not alone' test
	$(BIN)/python -m pytest -q -m alone test

lint: venv
	$(BIN)/python -m pytest -q test/test_flake8.py test/test_pep257.py test/test_copyright.py

# A study of 54 cases of the berth on a local cluster (docs/study.md): results and plots in
# out/study_demo. The kernels are prepared first, once, for every worker to load.
study-demo: venv
	$(BIN)/python -m rope_sim_ros.mooring.precompile $(SEED)
	$(BIN)/python -m rope_sim_ros study examples/study/berth_study.yaml --out out/study_demo

bench: venv
	$(BIN)/python benchmarks/physics_vs_moordyn.py
	$(BIN)/python benchmarks/water_vs_moordyn.py
	$(BIN)/python benchmarks/line_handling.py

clean:
	rm -rf build install log

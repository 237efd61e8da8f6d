# wingcrack: `make demo` and `make test` set everything up themselves on a
# bare Debian 12 machine (apt packages, venv, C++ build) and then run.
SHELL := /bin/bash
VENV := .venv
PY := $(VENV)/bin/python
# Debian's cmake/python come first: DOLFINx lives in Debian's python3.
export PATH := $(CURDIR)/$(VENV)/bin:/usr/bin:/bin:$(PATH)
export OMP_NUM_THREADS ?= 1

# libopenblas0-serial: Debian's alternatives then point libblas/liblapack (numpy,
# scipy, MUMPS) at OpenBLAS instead of the reference BLAS (faster: the benchmarks,
# docs/developer/performance.md). Serial: one thread per MPI rank.
# openmpi-bin: mpirun, for `mpirun -n N wingcrack run` and its test.
APT_PACKAGES := python3-dolfinx-real python3-gmsh libeigen3-dev pybind11-dev \
  libgtest-dev googletest python3-scipy python3-matplotlib python3-pil python3-meshio \
  python3-tqdm python3-pytest python3-venv python3-dev cmake g++ make ninja-build \
  libopenblas0-serial openmpi-bin \
  python3-nbclient python3-nbformat python3-ipykernel \
  python3-sphinx python3-myst-parser python3-nbsphinx pandoc libjs-mathjax
KERNEL_FILES := $(wildcard cpp_kernels/*/*.cpp cpp_kernels/include/wingcrack/*.hpp) CMakeLists.txt pyproject.toml
STAMP := $(VENV)/.wingcrack-installed
# The editable install maps each Python module to its file once: a module added, moved or
# removed needs a new install. The list below changes only then (its file is rewritten only
# when it differs), so an edit inside a module does not reinstall.
MODULES := $(sort $(wildcard wingcrack/*.py wingcrack/*/*.py meshing/*.py procs/*.py))
MODULE_LIST := $(VENV)/.wingcrack-modules
# Jupyter kernel that runs the venv's python (sees DOLFINx and wingcrack): notebooks/
KERNELSPEC := $(VENV)/share/jupyter/kernels/wingcrack/kernel.json

.PHONY: docs setup apt venv demo test test-fast test-cpp test-cpp-sanitize test-py bench soak clean FORCE

setup: apt $(STAMP) $(KERNELSPEC)

apt:
	@missing=$$(for p in $(APT_PACKAGES); do dpkg-query -W -f='$${Status}\n' $$p 2>/dev/null | grep -q "ok installed" || echo $$p; done); \
	if [ -n "$$missing" ]; then \
	  echo "installing Debian packages:" $$missing; \
	  SUDO=$$( [ $$(id -u) -eq 0 ] || echo sudo ); \
	  $$SUDO apt-get update -q && DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -q --no-install-recommends $$missing; \
	fi

$(PY):
	/usr/bin/python3 -m venv --system-site-packages $(VENV)

$(MODULE_LIST): FORCE | $(PY)
	@echo "$(MODULES)" | cmp -s - $@ || echo "$(MODULES)" > $@

FORCE:

$(STAMP): $(PY) $(KERNEL_FILES) $(MODULE_LIST) requirements-dev.txt constraints.txt
	$(PY) -m pip install -q -c constraints.txt -r requirements-dev.txt
	$(PY) -m pip install -q --no-build-isolation --no-deps -c constraints.txt -e .
	$(PY) -c "import numpy, dolfinx, wingcrack_kernels, wingcrack.case; assert numpy.__version__.startswith('1.24'), numpy.__version__"
	touch $@

$(KERNELSPEC): $(STAMP)
	PYDEVD_DISABLE_FILE_VALIDATION=1 $(PY) -m ipykernel install --sys-prefix --name wingcrack \
	  --display-name "Python (wingcrack)" --env PYDEVD_DISABLE_FILE_VALIDATION 1 > /dev/null

demo: setup
	$(VENV)/bin/wingcrack run cases/brazilian_disc_45.toml -o results/brazilian_disc_45 --force

test: setup test-cpp test-cpp-sanitize test-py docs

# The site (docs/, MyST Markdown) in build/docs/html; every warning is an error. The
# notebooks are shown with the outputs of their executed copies in build/notebooks/
# (the notebook test keeps them; a missing or stale one is executed here).
docs: setup
	$(PY) benchmarks/doc_tables.py
	$(PY) docs/executed_notebooks.py
	$(PY) -m sphinx -b html -W --keep-going -n -q docs build/docs/html

test-cpp: apt
	cmake -S . -B build/cpp -G Ninja -DWINGCRACK_PYTHON=OFF -DWINGCRACK_TESTS=ON -DCMAKE_BUILD_TYPE=Release > /dev/null
	cmake --build build/cpp
	cd build/cpp && ctest --output-on-failure

# The same GoogleTest suite built with AddressSanitizer and UBSan (Debug, so
# Eigen's own index assertions are on too); any finding stops the test with
# a non-zero exit.
SANITIZE_ENV := ASAN_OPTIONS=halt_on_error=1:detect_leaks=1:abort_on_error=0 \
  UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
test-cpp-sanitize: apt
	cmake -S . -B build/asan -G Ninja -DWINGCRACK_PYTHON=OFF -DWINGCRACK_TESTS=ON -DWINGCRACK_SANITIZE=ON -DCMAKE_BUILD_TYPE=Debug > /dev/null
	$(SANITIZE_ENV) cmake --build build/asan
	cd build/asan && $(SANITIZE_ENV) ctest --output-on-failure

test-py: setup
	$(PY) -m pytest -q

# the tests not marked slow (tests/conftest.py): about 2 minutes
test-fast: setup
	$(PY) -m pytest -q -m "not slow"

# 200 random fracture networks, 10 steps each (make test runs 20), and 500 geometries on
# the edge of the mesher's rules, each refused by the check or computed (make test runs 50)
soak: setup
	WINGCRACK_SOAK_SEEDS=200 WINGCRACK_PROPERTY_EXAMPLES=500 $(PY) -m pytest -q tests/robustness/test_random_networks.py \
	  tests/robustness/test_admissibility_property.py

bench: setup
	$(PY) benchmarks/run.py --large

clean:
	rm -rf build results

# flexbearing — every target sets itself up on a fresh Debian 12 machine (root, or sudo).
#   make demo      the paper's case end to end (results in out/demo/)
#   make test      the fast test suite
#   make lint      the linter (ruff, pyflakes rules: unused and undefined names) over the code, tests, benchmarks, docs
#   make test-pypi the FE and command-line tests on the PyPI stack (Python 3.12, dolfinx 0.11)
#   make test-all  every test, the slow verification included (installs ParaView, xvfb, Chromium)
#   make viewers   ParaView, xvfb and Chromium: the report's .pvsm, --movie and --pdf
#   make bench     the benchmarks in benchmarks/ (work–precision, wall times)
#   make bench-work-precision   work–precision of whole runs of the four paper scenes (~40-60 min,
#                  resumable; QUICK=1: a 5 ms smoke run) -> benchmarks/results/work_precision.*
#   make cost-model   one right-hand side split by part, step-size limit, scaling -> cost_model.md
#   make stress    the numerical stability stress test (benchmarks/results/stress_test.{md,json})

SHELL := /bin/bash
SYSPY := /usr/bin/python3
VENV  := .venv
PY    := $(VENV)/bin/python
SUDO  := $(shell [ "$$(id -u)" = 0 ] || echo sudo)

# Debian 12 packages: the FE stack and the scientific Python stack. Never pip-installed.
# calculix-ccx is a verification tool, not a runtime need: the independent FE check of the cage's
# stress and frequencies (flexbearing/verification/calculix_check.py, the slow tests of `make test-all`,
# benchmarks/calculix_check.py) runs CalculiX on the project's own mesh.
APT_PACKAGES := python3-dolfinx-real python3-gmsh python3-meshio python3-numpy python3-scipy \
    python3-numba python3-h5py python3-matplotlib python3-tqdm python3-dask python3-distributed \
    python3-xarray python3-netcdf4 python3-h5netcdf \
    python3-pytest python3-hypothesis python3-venv python3-setuptools python3-wheel python3-pip mpi-default-bin \
    calculix-ccx
# Optimised BLAS/LAPACK (Debian's OpenBLAS, the same archive): installing it switches the
# libblas.so.3 / liblapack.so.3 alternatives from the reference netlib BLAS, so numpy, scipy and
# PETSc/MUMPS use it. It is what makes a new cage geometry a reduced cage in ~20 s instead of ~45 s
# (the block eigensolver and MUMPS's dense fronts: benchmarks/results/reduce_design_loop.md).
# Optional: without it every result is the same to rounding and the reduction picks the
# single-vector eigensolver (flexbearing.common.blas); so a machine that cannot install it still
# sets up. flexbearing runs it on one thread (flexbearing/__init__.py says why).
OPTIONAL_APT_PACKAGES := libopenblas0-pthread
# Small pure-Python PyPI packages, pinned, installed with --no-deps into the venv.
# ruff: the linter of `make lint` and CI (a standalone binary wheel, no Python dependencies).
PIP_PACKAGES := rainflow==3.2.0 ruff==0.17.5

# Viewers of the report and the ParaView scene, for the slow tests that open them
# (tests/test_viewers.py) and for `flexbearing report --pdf / --series` (bearing.pvsm, --movie).
# Not needed to run or report: without them the .pvsm, the movie and the PDF are left out.
VIEWER_PACKAGES := paraview xvfb chromium

.PHONY: setup viewers demo lint test test-pypi test-all bench bench-work-precision cost-model stress clean

# $(call apt_install,PACKAGES): install those of the Debian packages that are missing
define apt_install
	@missing=$$(for p in $(1); do dpkg-query -W -f='$${Status}\n' $$p 2>/dev/null | grep -q "install ok installed" || echo $$p; done); \
	if [ -n "$$missing" ]; then \
	  echo "installing Debian packages: $$missing"; \
	  DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -qq $$missing 2>/dev/null || \
	  { $(SUDO) apt-get update -qq && DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -qq $$missing; }; \
	fi
	@mkdir -p $(VENV) && touch $@
endef

# $(call apt_install_optional,PACKAGES): the same, but a package that cannot be installed (no
# network, no root) is reported and skipped instead of stopping the setup
define apt_install_optional
	@missing=$$(for p in $(1); do dpkg-query -W -f='$${Status}\n' $$p 2>/dev/null | grep -q "install ok installed" || echo $$p; done); \
	if [ -n "$$missing" ]; then \
	  echo "installing optional Debian packages: $$missing"; \
	  DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -qq $$missing 2>/dev/null || \
	  { $(SUDO) apt-get update -qq && DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -qq $$missing; } || \
	  echo "warning: could not install $$missing (optional: the same results, a slower cage reduction)"; \
	fi
	@mkdir -p $(VENV) && touch $@
endef

$(VENV)/.apt-stamp: Makefile
	$(call apt_install,$(APT_PACKAGES))
	$(call apt_install_optional,$(OPTIONAL_APT_PACKAGES))

$(VENV)/.install-stamp: $(VENV)/.apt-stamp pyproject.toml
	@[ -x $(PY) ] || $(SYSPY) -m venv --system-site-packages $(VENV)
	@$(PY) -m pip install -q --no-build-isolation --no-deps -e .
	@# rainflow (ASTM E1049-85 5.4.4 rainflow counting, pure Python, no dependencies) for the cage's
	@# fatigue (flexbearing.analysis.fatigue); --no-deps so pip never touches the Debian numpy
	@# ruff (pinned, a standalone binary wheel): the linter of `make lint`
	@$(PY) -m pip install -q --no-deps $(PIP_PACKAGES)
	@$(PY) -c "import dolfinx, numba, gmsh, h5py, slepc4py, distributed, xarray, rainflow; print('flexbearing environment ready: dolfinx', dolfinx.__version__, '| numba', numba.__version__, '| gmsh', gmsh.__version__)"
	@touch $@

setup: $(VENV)/.install-stamp

$(VENV)/.viewers-stamp: Makefile
	$(call apt_install,$(VIEWER_PACKAGES))

viewers: $(VENV)/.viewers-stamp

demo: setup
	$(VENV)/bin/flexbearing demo -o out/demo

lint: setup
	$(VENV)/bin/ruff check --output-format concise flexbearing tests benchmarks docs

# The fast suite twice, so that a tolerance fitted to one processor's or one BLAS's rounding fails
# here and not only on someone else's machine (issue 42: three numerical environments in two passes):
#   pass 1: the machine as it is: its instruction set, and the BLAS/LAPACK the libblas.so.3
#           alternative gives (Debian's OpenBLAS when `setup` could install it, with its kernels for
#           this processor; OPENBLAS_CORETYPE is never set here);
#   pass 2: numba and numpy's dispatched kernels on the generic x86-64 instruction set
#           (.ci/on-other-isa, .ci/other_isa.py) AND Debian's reference (netlib) BLAS/LAPACK first on
#           LD_LIBRARY_PATH (flexbearing.common.blas.DEBIAN_REFERENCE_BLAS_DIRS): other rounding in
#           the compiled kernels and in every matrix product, factorisation and eigen solve at once.
#           (Where libopenblas0-pthread is not installed pass 1 already runs the reference BLAS.)
test: setup
	$(PY) -m pytest -q -m "not slow" -p no:cacheprovider
	LD_LIBRARY_PATH="$$($(PY) -c 'from flexbearing.common.blas import DEBIAN_REFERENCE_BLAS_DIRS as d; print(":".join(d))')$${LD_LIBRARY_PATH:+:$$LD_LIBRARY_PATH}" \
	  .ci/on-other-isa $(PY) -m pytest -q -m "not slow" -p no:cacheprovider

# The same program on the PyPI stack (dolfinx 0.11 from the dolfinx-solver-real wheel, gmsh 4.15,
# numba/numpy/scipy from PyPI; flexbearing.common.fe_stack): a fresh venv of Python 3.12 (pyenv's
# 3.12.1 where pyenv is there, else python3.12 on the PATH), `pip install ".[fem,test]"` as a user
# would (not editable: the package's file list and data are tested too), then the FE and
# command-line tests with the venv's own pytest command (not `python -m pytest`, which would put
# the source tree first on sys.path), so they import the installed copy. Not the
# whole suite twice: the physics kernels are the same code on both, the Debian pass runs them all.
PYPI_VENV  := .venv-pypi-test
PYPI_TESTS := tests/test_fe_stack.py tests/test_cage_mesh.py tests/test_modes.py tests/test_craig_bampton.py \
    tests/test_block_lanczos.py tests/test_guide_loads.py tests/test_invariants.py tests/test_reduced_cage.py \
    tests/test_cad_cage_named.py tests/test_cli.py tests/test_user_errors_generated.py tests/test_run.py
test-pypi:
	@py=$$(PYENV_VERSION=3.12.1 command -v python3.12 2>/dev/null || \
	       ls -d $${PYENV_ROOT:-$$HOME/.pyenv}/versions/3.12*/bin/python3.12 2>/dev/null | tail -1); \
	[ -n "$$py" ] && PYENV_VERSION=3.12.1 $$py -c "import sys; assert sys.version_info >= (3, 12)" 2>/dev/null || \
	  { echo "make test-pypi: needs Python 3.12 (python3.12 on the PATH, e.g. pyenv install 3.12.1): not found"; exit 1; }; \
	rm -rf $(PYPI_VENV) && PYENV_VERSION=3.12.1 $$py -m venv $(PYPI_VENV)
	$(PYPI_VENV)/bin/python -m pip install -q --disable-pip-version-check ".[fem,test]"
	@cd / && $(abspath $(PYPI_VENV))/bin/python -c "import flexbearing; from flexbearing.common.fe_stack import \
	    versions; print('PyPI stack:', versions(), 'flexbearing from', flexbearing.__file__)"
	$(PYPI_VENV)/bin/pytest -q -m "not slow" -p no:cacheprovider $(PYPI_TESTS)

test-all: setup viewers
	$(PY) -m pytest -q -p no:cacheprovider

bench: setup
	@for b in benchmarks/bench_*.py; do echo "== $$b"; $(PY) $$b || exit 1; done

bench-work-precision: setup
	nice -n 10 $(PY) benchmarks/bench_work_precision.py $(if $(QUICK),--quick)

cost-model: setup
	nice -n 10 $(PY) benchmarks/cost_model.py

stress: setup
	nice -n 5 $(PY) benchmarks/stress_test.py

clean:
	rm -rf $(VENV) $(PYPI_VENV) out cache *.egg-info

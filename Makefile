# Set-up and checks on a fresh Debian machine (run as root, or with sudo for apt-get).
# Every target is idempotent and quick when nothing is missing.
VENV   := .venv
PY     := $(VENV)/bin/python
DEBS   := coinor-libipopt-dev liblapack-dev libblas-dev libmumps-seq-dev pkg-config
DEBS_TEST := chromium
STAMP  := $(VENV)/.installed
DEMO   := $(firstword $(wildcard instances/portal.dat) instances/wall33.dat)

.PHONY: setup demo test test-fast docs debs debs-test clean

setup: debs $(STAMP)

# Debian's Ipopt 3.11 (a library: cyipopt compiles against it) and the LAPACK/MUMPS it links.
debs:
	@missing=""; for p in $(DEBS); do dpkg -s $$p >/dev/null 2>&1 || missing="$$missing $$p"; done; \
	if [ -n "$$missing" ]; then \
	  echo "installing Debian packages:$$missing"; \
	  SUDO=""; [ "$$(id -u)" = 0 ] || SUDO=sudo; \
	  $$SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq $$missing; \
	fi

$(STAMP): setup.cfg pyproject.toml
	@test -x $(PY) || python3 -m venv $(VENV)
	$(PY) -m pip install -q --upgrade pip
	$(PY) -m pip install -q -e '.[test]'
	@touch $(STAMP)

demo: setup
	$(PY) scripts/solve.py $(DEMO)

# a real headless browser for the test of the 3D HTML view
debs-test:
	@$(MAKE) --no-print-directory debs DEBS="$(DEBS_TEST)"

test: setup debs-test
	$(PY) -m pytest -q

# The documentation site (Sphinx, Markdown pages through MyST), warnings as errors; the API
# pages are generated afresh from the package's modules each time.
docs: setup $(VENV)/.installed-docs
	rm -rf docs/api/generated
	$(PY) -m sphinx -W --keep-going -q -b html docs docs/_build/html
	@echo "open docs/_build/html/index.html"

$(VENV)/.installed-docs: setup.cfg pyproject.toml
	$(PY) -m pip install -q -e '.[docs]'
	@touch $@

# everything but the tests marked slow (processes, clusters, long solves): under a minute
test-fast: setup
	$(PY) -m pytest -q -m "not slow"

clean:
	rm -rf $(VENV) results *.egg-info docs/_build docs/api/generated

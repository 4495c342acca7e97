# ShroudedBlade: `make run` (main job) and `make test` set up everything on a fresh machine.
PY      := .venv/bin/python
STAMP   := .venv/.installed
FMU     := build/ShroudedBlade.fmu
JOBS    ?= 2

.PHONY: run test test-slow bench crosscheck fmu venv clean sysdeps javadeps

# System packages (Debian) the default tests and `make crosscheck` need, installed only when missing:
# libtbb12 for ecospy's libecosc.so; a JDK 17 and Maven for the FMI4j driver (crosscheck/java).
# no "Entering/Leaving directory" lines from the sub-makes
MAKEFLAGS += --no-print-directory

APT := $(shell [ "$$(id -u)" = 0 ] && echo apt-get || echo sudo apt-get)
sysdeps:
	@{ ldconfig -p 2>/dev/null || /sbin/ldconfig -p; } | grep -q 'libtbb\.so\.12' || { $(APT) update -qq && DEBIAN_FRONTEND=noninteractive $(APT) install -y -qq libtbb12 > /dev/null; }
javadeps:
	@{ command -v mvn && command -v javac; } > /dev/null || { $(APT) update -qq && DEBIAN_FRONTEND=noninteractive $(APT) install -y -qq openjdk-17-jdk-headless maven > /dev/null; }

venv: $(STAMP)
$(STAMP): pyproject.toml
	@echo "setting up .venv (pip install -e '.[test,cluster,crosscheck,docs]')"
	@python3 -m venv .venv
	@$(PY) -m pip install --quiet --upgrade pip
	@$(PY) -m pip install --quiet -e '.[test,cluster,crosscheck,docs]'
	@touch $(STAMP)

# the compiler's lines go to build/build.log, shown whole only when the build fails
fmu: $(STAMP)
	@echo "building the FMUs (cmake; log: build/build.log)"
	@cmake -S . -B build -DCMAKE_BUILD_TYPE=Release > /dev/null
	@cmake --build build -j $(JOBS) -- --no-print-directory > build/build.log 2>&1 || { cat build/build.log; exit 1; }

run: fmu
	@echo "harness run --out results"
	@$(PY) -m harness run --out results

test: fmu sysdeps
	$(PY) -m pytest

test-slow: fmu sysdeps javadeps
	$(PY) -m pytest -m 'slow or sanitizer'

bench: fmu
	$(PY) -m harness bench

# all importers (incl. FMI4j via Maven), the agreement table (crosscheck/agreement.md) and the
# cross-check deliverables under crosscheck/fmus and crosscheck/results
crosscheck: fmu sysdeps javadeps
	$(PY) -m harness crosscheck --deliverables

clean:
	rm -rf build build-* .pytest_cache

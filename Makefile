# ShroudedBlade: `make run` (main job) and `make test` set up everything on a fresh machine.
PY      := .venv/bin/python
STAMP   := .venv/.installed
FMU     := build/ShroudedBlade.fmu
JOBS    ?= 2

.PHONY: run test test-slow bench crosscheck fmu venv clean

venv: $(STAMP)
$(STAMP): pyproject.toml
	python3 -m venv .venv
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e '.[test]'
	touch $(STAMP)

fmu: $(STAMP)
	cmake -S . -B build -DCMAKE_BUILD_TYPE=Release > /dev/null
	cmake --build build -j $(JOBS)

run: fmu
	$(PY) -m harness run

test: fmu
	$(PY) -m pytest

test-slow: fmu
	$(PY) -m pytest -m slow

bench: fmu
	$(PY) -m harness bench

crosscheck: fmu
	$(PY) -m harness crosscheck

clean:
	rm -rf build build-* .pytest_cache

# Entry points: deps, build, test, experiments, bench (see README.md).
PYTHON  ?= /usr/bin/python3
BUILD   ?= build
JOBS    ?= 2
PROFILE ?= small
RESULTS ?= results
SEMLB   := $(BUILD)/cli/semlb
MANIFESTS := $(wildcard experiments/*.yaml)

export OMPI_ALLOW_RUN_AS_ROOT=1
export OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1

.PHONY: deps build test experiments analysis bench clean

deps:
	bash scripts/install-deps.sh

build: deps
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release
	cmake --build $(BUILD) -j$(JOBS)

test: build
	ctest --test-dir $(BUILD) --output-on-failure -j$(JOBS)

experiments: build
	@set -e; for m in $(MANIFESTS); do \
	  $(SEMLB) sweep $$m --profile $(PROFILE) --results $(RESULTS); \
	done
	$(MAKE) --no-print-directory analysis

analysis:
	$(PYTHON) analysis/report.py --results $(RESULTS)

bench: build
	$(SEMLB) bench policies --ranks 16

clean:
	rm -rf $(BUILD)

# lsds: the two commands of the README. Both do all set-up on a fresh Debian 12 machine.
#   make demo   install deps, build, generate the example collection, run the main tools on it
#   make test   install deps, build, run the whole ctest suite
PRESET ?= release
BUILD_DIR := build/$(PRESET)
JOBS ?= $(shell nproc)

.PHONY: all deps configure build test demo format clean bench

all: build

deps:
	@./scripts/install-deps.sh

configure: deps
	@cmake --preset $(PRESET) >/dev/null

build: configure
	@cmake --build --preset $(PRESET) -j $(JOBS)

test: build
	@ctest --preset $(PRESET) -j $(JOBS)

demo: build
	@./scripts/demo.sh $(BUILD_DIR)/tools/lsds

bench: build
	@./scripts/install-deps.sh --bench
	@./scripts/bench.sh $(BUILD_DIR)

format:
	@git ls-files '*.h' '*.cc' | xargs clang-format -i

clean:
	@rm -rf build

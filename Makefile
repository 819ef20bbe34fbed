# lsds: the two commands of the README. Both do all set-up on a fresh Debian 12 machine.
#   make demo   install deps, build, generate the example collection, run the main tools on it
#   make test   install deps, build, run the whole ctest suite
#   make install PREFIX=~/.local   build and install the lsds binary into PREFIX/bin
PRESET ?= release
BUILD_DIR := build/$(PRESET)
JOBS ?= $(shell nproc)
PREFIX ?= /usr/local

.PHONY: all deps configure build test demo install format clean bench

all: build

deps:
	@./scripts/install-deps.sh

# The configure log is shown only when configuring fails.
configure: deps
	@mkdir -p $(BUILD_DIR)
	@cmake --preset $(PRESET) >$(BUILD_DIR)/configure.log 2>&1 || { cat $(BUILD_DIR)/configure.log; exit 1; }

build: configure
	@cmake --build --preset $(PRESET) -j $(JOBS)

test: build
	@ctest --preset $(PRESET) -j $(JOBS)

demo: build
	@./scripts/demo.sh $(BUILD_DIR)/tools/lsds

install: build
	@cmake --install $(BUILD_DIR) --prefix $(PREFIX)

bench: build
	@./scripts/install-deps.sh --bench
	@./scripts/bench.sh $(BUILD_DIR)

format:
	@git ls-files '*.h' '*.cc' | xargs clang-format -i

clean:
	@rm -rf build

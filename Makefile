# lsds: the two commands of the README. Both do all set-up on a fresh Debian 12 machine.
#   make demo   install deps, build, generate the example collection, run the main tools on it
#   make test   install deps, build, run the whole ctest suite
#   make install PREFIX=~/.local   build and install the lsds binary into PREFIX/bin
PRESET ?= release
BUILD_DIR := build/$(PRESET)
JOBS ?= $(shell nproc)
PREFIX ?= /usr/local

.PHONY: all deps configure build test test-asan tidy tidy-all demo docs-images install format format-check clean bench

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

# The whole suite under ASan + UBSan + LeakSanitizer, with the fuzz targets and their smoke runs
# (the debug preset: clang, -O2), in build/debug. intercept_tls_get_addr=0: LeakSanitizer's tracer
# crashes at exit now and then while scanning the dynamic TLS of dlopen'ed plug-ins (Embree's and
# TBB's threads; google/sanitizers#1322), which aborted a passing run; leaks are still checked.
test-asan: deps
	@mkdir -p build/debug
	@cmake --preset debug >build/debug/configure.log 2>&1 || { cat build/debug/configure.log; exit 1; }
	@cmake --build --preset debug -j $(JOBS)
	@ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:intercept_tls_get_addr=0 \
	  UBSAN_OPTIONS=print_stacktrace=1 ctest --preset debug -j $(JOBS)

# clang-tidy (.clang-tidy) over the product files changed since the last clean full pass (the
# commit in .ci/tidy-clean; CI runs this); `make tidy-all` checks every product file.
tidy: configure
	@./scripts/tidy.sh $(BUILD_DIR)

tidy-all: configure
	@./scripts/tidy.sh $(BUILD_DIR) --all

demo: build
	@./scripts/demo.sh $(BUILD_DIR)/tools/lsds

# The reference renderer / Blender Cycles figures of docs/generator.md (needs Blender; not in `test`).
docs-images: build
	@./scripts/docs_images.sh $(BUILD_DIR)/tools/lsds

install: build
	@cmake --install $(BUILD_DIR) --prefix $(PREFIX)

bench: build
	@./scripts/install-deps.sh --bench
	@./scripts/bench.sh $(BUILD_DIR)

format:
	@git ls-files '*.h' '*.cc' | xargs clang-format -i

# Fails when a C++ file differs from .clang-format's layout (CI runs it before the suite).
format-check: deps
	@git ls-files '*.h' '*.cc' | xargs clang-format --dry-run --Werror

clean:
	@rm -rf build

#!/usr/bin/env bash
# `make bench`: run every benchmark of bench/ with its default sizes and print their figures.
# Benchmarks are not tests: they assert nothing, they measure. Pass sizes to each binary directly for
# the full-size runs (see bench/README.md).
set -euo pipefail
build="${1:?usage: scripts/bench.sh BUILD_DIR}"
shopt -s nullglob
found=0
for bench in "$build"/bench/bench_*; do
  [ -x "$bench" ] || continue
  found=1
  echo "== $(basename "$bench")"
  "$bench"
  echo
done
[ "$found" = 1 ] || echo "no benchmarks built"

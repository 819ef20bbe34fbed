#!/usr/bin/env bash
# `make tidy`: clang-tidy (.clang-tidy) over the product's C++ files, failing on any finding.
#
#   scripts/tidy.sh BUILD_DIR          the files changed since the last clean full pass
#                                      (the commit in .ci/tidy-clean), as CI runs it
#   scripts/tidy.sh BUILD_DIR --all    every product file (about 13 CPU s a file: ~20 min on
#                                      2 cores); when it is clean, record HEAD in .ci/tidy-clean
#
# Why not every file in CI: the headers (Eigen, OpenEXR, Embree, nlohmann-json) make each file
# cost seconds, so a full pass does not fit beside the two suites in CI's time. A changed header
# brings in the .cc files of the same name; the full pass catches the rest.
set -euo pipefail
build="${1:?usage: scripts/tidy.sh BUILD_DIR [--all]}"
mode="${2:-changed}"
cd "$(dirname "$0")/.."
[ -f "$build/compile_commands.json" ] || { echo "tidy: no $build/compile_commands.json (configure first)" >&2; exit 2; }

# The product folders: the core, the features, the binary (docs/architecture.md), the fuzz harnesses.
product=(libs generator validators importers converters report bundles backproject export_layers perturb scaleout synth evaluate tools python fuzz)
if [ "$mode" = "--all" ]; then
  mapfile -t files < <(git ls-files "${product[@]/%//*.cc}")
else
  base="$(cat .ci/tidy-clean)"
  # A shallow clone may not hold the commit: say so and check nothing rather than fail the run.
  if ! git cat-file -e "$base^{commit}" 2>/dev/null; then
    echo "tidy: SKIPPED: .ci/tidy-clean names $base, which this clone does not hold (shallow?)" >&2
    exit 0
  fi
  mapfile -t changed < <(git diff --name-only --diff-filter=AM "$base" -- "${product[@]}" | grep -E '\.(cc|h)$' || true)
  files=()
  for f in "${changed[@]}"; do
    case "$f" in
      *.cc) files+=("$f") ;;
      *.h) [ -f "${f%.h}.cc" ] && files+=("${f%.h}.cc") ;;
    esac
  done
fi
# Only files the build compiles (the libFuzzer harnesses are built by the sanitizer build alone).
mapfile -t files < <(printf '%s\n' "${files[@]}" | sort -u | python3 -c '
import json, os, sys
known = {os.path.relpath(e["file"]) for e in json.load(open(sys.argv[1]))}
print("\n".join(f for f in sys.stdin.read().split() if f in known))' "$build/compile_commands.json")
if [ "${#files[@]}" -eq 0 ] || [ -z "${files[0]}" ]; then
  echo "tidy: no product file changed since the last clean pass"
  exit 0
fi
echo "tidy: ${#files[@]} file(s)"
printf '%s\n' "${files[@]}" |
  xargs -P "$(nproc)" -n 1 clang-tidy -p "$build" --quiet --warnings-as-errors='*'

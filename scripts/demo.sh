#!/usr/bin/env bash
# `make demo`: make the example collection and run the main tools on it.
# Usage: scripts/demo.sh PATH/TO/lsds
set -euo pipefail
lsds="${1:?usage: scripts/demo.sh PATH/TO/lsds}"
out="${LSDS_DEMO_DIR:-demo}"
mkdir -p "$out"

echo "== lsds synth: a synthetic collection with exact truth (24 frames, 512x512)"
"$lsds" synth "$out/synthetic" --frames 24 --size 512x512 --force
echo
echo "== lsds info"
"$lsds" info "$out/synthetic"
echo
echo "demo collections are in $out/"

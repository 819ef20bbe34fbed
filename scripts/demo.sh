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
echo "== lsds generate: the Embree reference renderer (built-in demo scene, 24 frames, 512x512, 4 spp)"
"$lsds" generate --demo --demo-frames 24 --demo-size 512x512 -o "$out/generated" --force
echo
echo "== lsds info"
"$lsds" info "$out/generated"
echo
echo "demo collections are in $out/"

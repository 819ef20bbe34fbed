#!/bin/bash
# `lsds generate --demo` against Blender Cycles on the same frames, whole processes, interleaved:
# each repeat runs every lsds binary given, then Cycles (bench/peers/cycles_demo.py), and prints
# one line per run: size, repeat, who, wall s, user s, system s (GNU time). Two lsds binaries (a
# baseline and a change) are compared side by side in one run, under the same load.
#
#   bench/generate_vs_cycles.sh SIZE FRAMES REPEATS OUT_DIR LSDS [LSDS ...]
#   bench/generate_vs_cycles.sh 512 8 3 /tmp/pairs build/release/tools/lsds
set -euo pipefail
if [ $# -lt 5 ]; then
  sed -n 2,8p "$0" >&2
  exit 2
fi
size=$1 frames=$2 repeats=$3 out=$4
shift 4
here=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$out"
for repeat in $(seq "$repeats"); do
  k=0
  for lsds in "$@"; do
    k=$((k + 1))
    /usr/bin/time -f "$size $repeat lsds$k %e %U %S" -o "$out/time.txt" \
      "$lsds" generate --demo --demo-frames "$frames" --demo-size "${size}x${size}" --spp 4 \
      --compact -o "$out/lsds$k" --force -q
    cat "$out/time.txt"
    rm -rf "$out/lsds$k"
  done
  mkdir -p "$out/cycles"
  /usr/bin/time -f "$size $repeat cycles %e %U %S" -o "$out/time.txt" \
    blender -b --factory-startup -noaudio --python "$here/peers/cycles_demo.py" -- \
    "$size" "$size" "$frames" 4 "$out/cycles" 0 >"$out/blender.log" 2>&1
  cat "$out/time.txt"
  rm -rf "$out/cycles"
done
rm -f "$out/time.txt" "$out/blender.log"

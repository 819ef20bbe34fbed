#!/usr/bin/env bash
# `make docs-images`: regenerates the side-by-side figures of docs/generator.md ("Blender Cycles"):
# the two frames of examples/field_day.lscene seen through examples/field_day_figures.lcap, rendered
# by the reference renderer and by Blender Cycles (`--renderer cycles`, 16 samples each), each
# through `lsds convert --images png` (its default tone curve, filmic at EV 0), into
#   docs/images/generator_cycles_{oblique,nadir}_{reference,cycles}.png
# and the figure of the built-in classes (examples/builtin_assets.lscene through
# examples/builtin_assets.lcap, reference renderer, spp 4, seed 3) into
#   docs/images/generator_builtin_assets.png
# It prints each renderer's CPU seconds (the figure docs/generator.md quotes). Needs Blender on
# PATH (or give --blender PATH after the lsds path). Not part of `make test`: Cycles takes about 15
# CPU seconds and the PNGs are committed.
# Usage: scripts/docs_images.sh PATH/TO/lsds [--blender PATH]
set -euo pipefail
lsds="$(realpath "${1:?usage: scripts/docs_images.sh PATH/TO/lsds [--blender PATH]}")"
shift
cd "$(dirname "$0")/.."
scene=examples/field_day.lscene
capture=examples/field_day_figures.lcap
images=docs/images
work="$(mktemp -d "${TMPDIR:-/tmp}/lsds-docs-images.XXXXXX")"
trap 'rm -rf "$work"' EXIT

for renderer in reference cycles; do
  TIMEFORMAT="$renderer: %U s user + %S s sys CPU, %R s wall (lsds generate, both frames)"
  time "$lsds" generate "$scene" "$capture" --spp 16 --renderer "$renderer" "$@" \
    -o "$work/$renderer" -q
  "$lsds" convert "$work/$renderer" --to yolo --images png -o "$work/$renderer-png" -q
  # convert names the frames of the capture's one sequence 000000.png (oblique), 000001.png (nadir).
  for view in 0:oblique 1:nadir; do
    png="$work/$renderer-png/images/train/00000${view%%:*}.png"
    target="$images/generator_cycles_${view#*:}_$renderer.png"
    cp "$png" "$target.partial"
    mv "$target.partial" "$target"
    echo "wrote $target"
  done
done

"$lsds" generate examples/builtin_assets.lscene examples/builtin_assets.lcap --spp 4 --seed 3 \
  -o "$work/assets" -q
"$lsds" convert "$work/assets" --to yolo --images png -o "$work/assets-png" -q
cp "$work/assets-png/images/train/000000.png" "$images/generator_builtin_assets.png.partial"
mv "$images/generator_builtin_assets.png.partial" "$images/generator_builtin_assets.png"
echo "wrote $images/generator_builtin_assets.png"

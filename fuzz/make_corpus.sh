#!/bin/sh
# Builds the seed corpora of the fuzz targets from generated collections
# (fuzz/README.md): `lsds synth` (4x4, two frames: every standard layer, flat
# and deep) and `lsds generate --demo` (8x6, spp 4: the renderer's own
# compressions). The synth collection is also kept whole as
# fuzz/seed_collection, the layers validate_fuzzer checks against.
#   fuzz/make_corpus.sh LSDS
set -eu
lsds="$1"
here=$(cd "$(dirname "$0")" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$lsds" synth "$work/synth" --count 2 --size 4x4 --samples-per-axis 2 >/dev/null
"$lsds" generate --demo --demo-frames 1 --demo-size 8x6 --spp 4 -o "$work/demo" -q
rm -rf "$here/corpus" "$here/seed_collection"
mkdir -p "$here/corpus/flat_exr" "$here/corpus/deep_exr" "$here/corpus/collection" \
         "$here/corpus/validate"
for source in synth demo; do
  for layer in "$work/$source"/*/; do
    name=$(basename "$layer")
    file=$(ls "$layer" | head -n 1)
    if [ "$name" = bundle ]; then
      cp "$layer/$file" "$here/corpus/deep_exr/$source-$name.exr"
    else
      cp "$layer/$file" "$here/corpus/flat_exr/$source-$name.exr"
    fi
  done
  cp "$work/$source/collection.json" "$here/corpus/collection/$source-collection.json"
  cp "$work/$source/metadata.json" "$here/corpus/collection/$source-metadata.json"
done
cp "$work/synth/collection.json" "$here/corpus/validate/synth-collection.json"
cp -r "$work/synth" "$here/seed_collection"
du -sh "$here/corpus" "$here/seed_collection"

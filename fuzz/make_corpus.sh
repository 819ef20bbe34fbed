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
         "$here/corpus/validate" "$here/corpus/report"
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
# report_fuzzer: what lsds validate and lsds bundles write, and a report with a
# finding of every location field.
mkdir -p "$here/corpus/report"
"$lsds" bundles "$work/synth" -o "$here/corpus/report/synth-bundle-stats.json" >/dev/null
"$lsds" validate "$work/synth" --format json -o "$here/corpus/report/synth-validate-report.json" \
  2>/dev/null || [ $? -eq 1 ]
cat > "$here/corpus/report/findings-validate-report.json" <<'JSON'
{"format": "lsds-validate-report", "format_version": "1.0", "collection": "C",
 "verdict": "fail", "fail_on": "error", "frames": 2, "files_decoded": 0,
 "bytes_decoded": 0, "seconds": 0, "counts": {"error": 2, "warning": 0, "info": 0},
 "checks": [{"id": "layer.depth-finite", "severity": "error", "tolerance": "", "count": 3,
   "findings": [{"severity": "error", "check": "layer.depth-finite", "object": "box#0",
     "location": {"file": "depth/000001.exr", "json_pointer": "/frames/1", "line": 3,
       "column": 4, "frame": 1, "pixel": [3, 4]}, "message": "depth is NaN <&>"},
     {"severity": "error", "check": "layer.depth-finite", "location": {"frame": 0},
      "message": "m"}]}],
 "statistics": {"depth-error": {"max": 1, "rms": 0.5, "count": 2}}}
JSON
cp -r "$work/synth" "$here/seed_collection"
du -sh "$here/corpus" "$here/seed_collection"

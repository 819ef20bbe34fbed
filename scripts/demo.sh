#!/usr/bin/env bash
# `make demo`: render the example collection from its LSCENE/LCAP description and run the main tools
# on it. Everything goes into demo/ (or $LSDS_DEMO_DIR); a second run replaces it. The names differ
# from those of the README tour (plan.json, survey, report.xml, yolo, bundle-stats.json, cloud.ply, survey-npy,
# seed 7), so the tour runs after the demo, from the repository or from demo/, without a collision.
# Usage: scripts/demo.sh PATH/TO/lsds
set -euo pipefail
lsds="${1:?usage: scripts/demo.sh PATH/TO/lsds}"
out="${LSDS_DEMO_DIR:-demo}"
collection="$out/demo-survey"
rm -rf "$out"
mkdir -p "$out"

step() { printf '\n== %s\n' "$*"; }

step "lsds plan: expand the scene and capture into the frame plan"
"$lsds" plan examples/uav_survey.lscene examples/demo_survey.lcap --seed 7 -o "$out/demo-plan.json"
echo "wrote $out/demo-plan.json"

step "lsds generate: render 24 frames at 512x512, 4 samples per pixel (Embree)"
"$lsds" generate examples/uav_survey.lscene examples/demo_survey.lcap --seed 7 --spp 4 -o "$collection"

step "lsds info"
"$lsds" info "$collection"

step "lsds validate: schemas, layers, cross-layer truth, camera geometry"
"$lsds" validate "$collection" --format text -o "$out/demo-validate.txt"
tail -n 3 "$out/demo-validate.txt"

step "lsds convert: YOLO and COCO"
"$lsds" convert "$collection" --to yolo,coco -o "$out/demo-export"

step "lsds bundles: mixed pixels from the pixel bundles"
"$lsds" bundles "$collection" -o "$out/demo-bundle-stats.json"

step "lsds backproject: one fused point cloud, checked against the world-position layer"
"$lsds" backproject "$collection" -o "$out/demo-cloud.ply" --fuse --voxel 0.25 --check | tail -n 2

step "lsds perturb-metadata: GNSS-like noise, 0.5 m and 1 degree, with its effect in pixels"
"$lsds" perturb-metadata "$collection" --sigma 0.5,1 --seed 1 --report

step "lsds evaluate --coverage: how the collection fills the conditions a model is scored by"
"$lsds" evaluate "$collection" --coverage -o "$out/demo-coverage.json" >"$out/demo-coverage.txt"
head -n 12 "$out/demo-coverage.txt"

step "Python: import lsds (docs/python.md) reads the same frames as NumPy arrays"
PYTHONPATH="$(dirname "$lsds")/../python" /usr/bin/python3 -c '
import sys, lsds
c = lsds.open(sys.argv[1]); f = c[0]
print(len(c), "frames; frame 0:", f.layer("depth").shape, f.layer("depth").dtype, "depth,",
      len(f.objects), "objects")
noisy = lsds.open(sys.argv[1], metadata="metadata.perturbed-1.json")[0].metadata
print("metadata variants:", [v["file"] for v in c.metadata_variants],
      "; frame 0 measured attitude off by %.2f deg" % noisy["error"]["rotation_deg"])' "$collection"

step "lsds report: one offline page with the contact sheet, layers, distributions and validation"
"$lsds" report "$collection" -o "$out/demo-report.html" --validate --bundle-stats "$out/demo-bundle-stats.json"

printf '\ndemo outputs are in %s/\n' "$out"

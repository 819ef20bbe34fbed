#include "converters/options.h"

#include <algorithm>
#include <cmath>

#include "converters/registry.h"
#include "converters/split.h"
#include "converters/tiles.h"
#include "libs/util/error.h"
#include "libs/util/strings.h"

namespace lsds::convert {

// Not yet cut at its seams (docs/architecture.md, "Long functions").
// NOLINTNEXTLINE(readability-function-cognitive-complexity)
void ConvertOptions::Check() const {
  if (formats.empty()) throw Error("no target format", Location("--to"));
  const std::vector<std::string> names = ConverterNames();
  for (const std::string& format : formats) {
    if (std::find(names.begin(), names.end(), format) == names.end()) {
      throw Error("unknown format '" + format + "'" + DidYouMean(format, names) + "; one of " +
                      Join(names, ", "),
                  Location("--to"));
    }
  }
  for (size_t i = 0; i < formats.size(); ++i) {
    for (size_t j = 0; j < i; ++j) {
      const bool both_yolo = formats[i].rfind("yolo", 0) == 0 && formats[j].rfind("yolo", 0) == 0;
      if (formats[i] == formats[j] || both_yolo) {
        throw Error("'" + formats[j] + "' and '" + formats[i] + "' write the same files",
                    Location("--to"));
      }
    }
  }
  if (images != "png" && images != "jpg" && images != "none") {
    throw Error("expected png, jpg or none, got '" + images + "'", Location("--images"));
  }
  if (!std::isfinite(display.exposure_ev)) throw Error("not a number", Location("--exposure"));
  if (!(min_transmittance >= 0 && min_transmittance <= 1)) {
    throw Error("must be in [0, 1]", Location("--min-transmittance"));
  }
  if (!(min_visibility >= 0 && min_visibility <= 1)) {
    throw Error("must be in [0, 1]", Location("--min-visibility"));
  }
  if (min_pixels < 1) throw Error("must be >= 1", Location("--min-pixels"));
  if (segmentation != "rle" && segmentation != "polygon") {
    throw Error("expected rle or polygon, got '" + segmentation + "'", Location("--segmentation"));
  }
  if (!(occluded_below >= 0 && occluded_below <= 1)) {
    throw Error("must be in [0, 1]", Location("--occluded-below"));
  }
  if (mot_classes != "order" && mot_classes != "mot17") {
    throw Error("expected order or mot17, got '" + mot_classes + "'", Location("--mot-classes"));
  }
  if (mot_box != "projected" && mot_box != "visible") {
    throw Error("expected projected or visible, got '" + mot_box + "'", Location("--mot-box"));
  }
  if (!(dota_difficult_below >= 0 && dota_difficult_below <= 1)) {
    throw Error("must be in [0, 1]", Location("--dota-difficult-below"));
  }
  if (!(dota_difficult_size >= 0 && std::isfinite(dota_difficult_size))) {
    throw Error("must be >= 0", Location("--dota-difficult-size"));
  }
  if (!(dota_min_size >= 0 && std::isfinite(dota_min_size))) {
    throw Error("must be >= 0", Location("--dota-min-size"));
  }
  // MMRotate 0.x builds the image name as <stem>.png whatever the files are
  // (mmrotate/datasets/dota.py:82-84), and DOTA's own images are PNG.
  if (images == "jpg" && std::find(formats.begin(), formats.end(), "dota") != formats.end()) {
    throw Error("dota images are png (MMRotate reads <stem>.png); use --images png or none",
                Location("--images"));
  }
  if (frames.begin < 0 || frames.end < frames.begin) {
    throw Error("expected 0 <= A <= B", Location("--frames"));
  }
  if (batch_size < 1) throw Error("must be >= 1", Location("--batch"));
  ParseSplit(split);
  ParseTileGrid(*this);
  if (output.empty()) throw Error("no output folder", Location("-o"));
}

}  // namespace lsds::convert

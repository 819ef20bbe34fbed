#include "converters/options.h"

#include <algorithm>
#include <cmath>

#include "converters/registry.h"
#include "converters/split.h"
#include "converters/tiles.h"
#include "libs/util/error.h"
#include "libs/util/strings.h"

namespace lsds::convert {

namespace {

// Each format once; the YOLO formats share their files (data.yaml, labels/).
void CheckFormats(const std::vector<std::string>& formats) {
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
}

// "expected a, b or c, got 'value'" unless `value` is one of `choices`.
void RequireChoice(const std::string& value,
                   const std::vector<std::string>& choices,
                   const char* flag) {
  if (std::find(choices.begin(), choices.end(), value) != choices.end()) return;
  std::string expected = choices.front();
  for (size_t i = 1; i < choices.size(); ++i)
    expected += (i + 1 == choices.size() ? " or " : ", ") + choices[i];
  throw Error("expected " + expected + ", got '" + value + "'", Location(flag));
}

// NaN fails too.
void RequireFraction(double value, const char* flag) {
  if (!(value >= 0 && value <= 1)) throw Error("must be in [0, 1]", Location(flag));
}

// NaN and infinity fail too.
void RequireFiniteNonNegative(double value, const char* flag) {
  if (!(value >= 0 && std::isfinite(value))) throw Error("must be >= 0", Location(flag));
}

}  // namespace

void ConvertOptions::Check() const {
  CheckFormats(formats);
  RequireChoice(images, {"png", "jpg", "none"}, "--images");
  if (!std::isfinite(display.exposure_ev)) throw Error("not a number", Location("--exposure"));
  RequireFraction(min_transmittance, "--min-transmittance");
  RequireFraction(min_visibility, "--min-visibility");
  if (min_pixels < 1) throw Error("must be >= 1", Location("--min-pixels"));
  RequireChoice(segmentation, {"rle", "polygon"}, "--segmentation");
  RequireFraction(occluded_below, "--occluded-below");
  RequireChoice(mot_classes, {"order", "mot17"}, "--mot-classes");
  RequireChoice(mot_box, {"projected", "visible"}, "--mot-box");
  RequireFraction(dota_difficult_below, "--dota-difficult-below");
  RequireFiniteNonNegative(dota_difficult_size, "--dota-difficult-size");
  RequireFiniteNonNegative(dota_min_size, "--dota-min-size");
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

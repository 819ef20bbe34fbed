// lsds convert COLLECTION --to
// yolo|yolo-seg|yolo-obb|dota|coco|cvat|cvat-video|mot|visdrone|visdrone-vid -o OUT [...]
// (docs/convert.md)
#include <iostream>

#include "converters/convert.h"
#include "converters/registry.h"
#include "libs/collection/collection_guard.h"
#include "libs/collection/collection_reader.h"
#include "libs/imaging/srgb_image.h"
#include "libs/util/error.h"
#include "libs/util/strings.h"
#include "tools/command.h"
#include "tools/shared_flags.h"

namespace lsds {

// The flag declarations, one statement per flag (docs/architecture.md, "Long functions").
// NOLINTNEXTLINE(readability-function-size,readability-function-cognitive-complexity)
int RunConvert(int argc, char** argv) {
  CLI::App app(
      "Convert a collection's truth into YOLO, DOTA, COCO, CVAT, MOT or VisDrone files "
      "(docs/convert.md).",
      "lsds convert");
  convert::ConvertOptions options;
  std::string collection, output, formats, tonemap = "filmic";
  bool clip_truncated = false;
  app.add_option("COLLECTION", collection, "collection folder (holds collection.json)")->required();
  app.add_option("--to",
                 formats,
                 "target format(s), comma separated: " + Join(convert::ConverterNames(), ", "))
      ->required();
  app.add_option("-o,--output", output, "output folder (built atomically)")->required();
  app.add_option("--images", options.images, "images to write: png, jpg or none")
      ->capture_default_str();
  app.add_option("--exposure", options.display.exposure_ev, "exposure in EV: linear * 2^EV")
      ->capture_default_str();
  app.add_option("--tonemap", tonemap, "filmic (ACES fit, default), reinhard or clamp")
      ->capture_default_str();
  app.add_option("--jpeg-quality", options.display.jpeg_quality, "JPEG quality 1..100")
      ->capture_default_str();
  app.add_option(
         "--split", options.split, "splits by stable hash of the sequence, e.g. train=0.8,val=0.2")
      ->capture_default_str();
  app.add_option("--min-visibility", options.min_visibility, "drop objects less visible than this")
      ->capture_default_str();
  app.add_option("--min-transmittance",
                 options.min_transmittance,
                 "drop objects whose atmospheric transmittance is below this")
      ->capture_default_str();
  app.add_option("--min-pixels", options.min_pixels, "drop objects with fewer visible pixels")
      ->capture_default_str();
  app.add_option("--classes",
                 options.classes,
                 "FILE or LIST of SOURCE[=NAME]: keep, rename and merge "
                 "classes (default: all)");
  app.add_flag("--keep-classes",
               options.keep_classes,
               "list every selected class, also those without a kept object "
               "(default: drop them; ids stay contiguous)");
  app.add_flag("--clip-truncated",
               clip_truncated,
               "keep objects cut by the image border, boxed by their visible "
               "part (the default)");
  app.add_flag("--drop-truncated", options.drop_truncated, "drop objects cut by the image border");
  app.add_option("--segmentation", options.segmentation, "coco: rle or polygon")
      ->capture_default_str();
  app.add_option("--occluded-below",
                 options.occluded_below,
                 "cvat: occluded=\"1\" when visibility is below this")
      ->capture_default_str();
  app.add_option(
      "--tile",
      options.tile,
      "cut every frame into tiles of W x H pixels (W: square), each an image of its own");
  app.add_option("--overlap",
                 options.overlap,
                 "with --tile: pixels shared by neighbouring tiles, P or P% of the tile size")
      ->capture_default_str();
  app.add_option("--tile-min-fraction",
                 options.tile_min_fraction,
                 "with --tile: keep an object in a tile holding at least this share of its pixels")
      ->capture_default_str();
  app.add_option("--mot-classes",
                 options.mot_classes,
                 "mot: order (class = output index + 1) or mot17 (MOT17 ids by class name)")
      ->capture_default_str();
  app.add_option("--mot-box",
                 options.mot_box,
                 "mot: projected (amodal, clipped to the image) or visible (tight) boxes")
      ->capture_default_str();
  app.add_option("--dota-difficult-below",
                 options.dota_difficult_below,
                 "dota: difficult 1 when visibility is below this")
      ->capture_default_str();
  app.add_option("--dota-difficult-size",
                 options.dota_difficult_size,
                 "dota: difficult 1 when the box's longer side is below this (px)")
      ->capture_default_str();
  app.add_option("--dota-min-size",
                 options.dota_min_size,
                 "dota: drop boxes with a side below this (px; MMRotate drops them under 2)")
      ->capture_default_str();
  app.add_flag("--dota-header",
               options.dota_header,
               "dota: write the imagesource:/gsd: lines (MMRotate cannot read them)");
  app.add_option("--batch", options.batch_size, "frames in flight (bounds memory)")
      ->capture_default_str();
  CommonFlags common;
  AddCommonFlags(app, &common, "replace a non-empty output folder");
  return RunCommand(app, common, argc, argv, [&] {
    if (clip_truncated && options.drop_truncated) {
      throw Error("--clip-truncated and --drop-truncated exclude each other",
                  Location("--drop-truncated"));
    }
    if (!imaging::ParseToneMap(tonemap, &options.display.tonemap)) {
      throw Error("expected filmic, reinhard or clamp, got '" + tonemap + "'",
                  Location("--tonemap"));
    }
    if (options.display.jpeg_quality < 1 || options.display.jpeg_quality > 100) {
      throw Error("must be in 1..100", Location("--jpeg-quality"));
    }
    options.frames = SelectCollectionFrames(common.frames, collection);
    options.force = common.force;
    OutputGuard guard("lsds convert");
    // "Not a collection" says more than "the output lies inside the folder".
    CheckCollectionFolder(collection);
    GuardCollection(&guard, collection, CollectionAccess::kReadOnly);
    if (std::filesystem::is_regular_file(options.classes))
      guard.AddInput(options.classes, "classes file");
    guard.CheckOutput(output, "-o");
    options.collection = collection;
    options.output = output;
    options.formats = Split(formats, ',');
    const convert::ConvertResult result = convert::Convert(options);
    if (!common.quiet) {
      std::cout << "converted " << result.frames << " frames to " << formats << " in " << output
                << " (" << result.images_written << " images)\n"
                << result.loss.ToText();
    }
    return kExitOk;
  });
}

}  // namespace lsds

// Options of `lsds convert` (docs/convert.md): one struct that checks itself.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "libs/imaging/srgb_image.h"
#include "libs/util/frame_selection.h"

namespace lsds::convert {

struct ConvertOptions {
  std::filesystem::path collection;
  std::filesystem::path output;
  std::vector<std::string> formats;  // registry names; several share one output
                                     // folder and its images
  std::string images = "png";        // png | jpg | none
  imaging::DisplayOptions display;
  std::string split = "train=1";
  double min_visibility = 0;     // keep objects with visibility >= this
  double min_transmittance = 0;  // keep objects seen through at least this
  int64_t min_pixels = 1;        // keep objects with at least this many visible pixels
  std::string classes;           // --classes FILE|LIST; empty: every class of the collection
  // List every selected class, also those no kept object has (default: only
  // the classes that occur, re-indexed 0..K-1).
  bool keep_classes = false;
  bool drop_truncated = false;        // drop objects cut by the image border (in_frame < 1)
  std::string segmentation = "rle";   // coco: rle | polygon
  double occluded_below = 1.0;        // cvat: occluded="1" when visibility < this
  std::string mot_classes = "order";  // mot: order (output index + 1) | mot17 (MOT17 ids by name)
  std::string mot_box = "projected";  // mot: projected (amodal) | visible
  // dota (docs/convert.md, "dota"): `difficult` = 1 when visibility < this or
  // the oriented box's longer side < dota_difficult_size pixels; boxes with a
  // side under dota_min_size pixels are dropped (MMRotate drops them).
  double dota_difficult_below = 0.5;
  double dota_difficult_size = 15;
  double dota_min_size = 2;
  bool dota_header = false;  // write the `imagesource:` / `gsd:` lines
  FrameRange frames;         // convert the frames with index in this range
  bool force = false;
  size_t batch_size = 64;  // frames in flight: bounds memory
  bool progress = true;

  // Tiles (docs/convert.md, "Tiles"): --tile W[xH] cuts every frame into
  // tiles of W x H pixels, neighbours sharing --overlap pixels ("P") or a
  // percentage of the tile size ("P%"); empty: no tiles.
  std::string tile;
  std::string overlap = "0";
  double tile_min_fraction = 0.5;  // keep an object in a tile holding >= this share of its pixels

  // Throws lsds::Error (exit 2) naming the flag at fault.
  void Check() const;
  std::string ImageExtension() const { return images == "jpg" ? ".jpg" : ".png"; }
};

}  // namespace lsds::convert

// Tiles (docs/convert.md, "Tiles"): every frame cut into overlapping tiles,
// each an image of its own for the converters. Tiling is a transformation of
// FrameContext: a tile is a FrameContext whose frame, objects, masks and boxes
// are in the tile's coordinates, so every format works on tiles unchanged.
// A frame's tiles are made and dropped with the frame (streaming).
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "converters/class_map.h"
#include "converters/converter.h"
#include "converters/loss_report.h"
#include "converters/options.h"
#include "libs/imaging/srgb_image.h"
#include "libs/util/atomic_file.h"

namespace lsds::convert {

namespace loss {
inline constexpr const char* kTileBelowFraction =
    "tiles: object left out of a tile holding less than --tile-min-fraction of its pixels";
inline constexpr const char* kTileTruncated =
    "tiles: object kept in a tile, truncated by the tile border";
inline constexpr const char* kInNoTile = "tiles: object in no tile (cut in every tile)";
}  // namespace loss

// The tiling options, parsed and checked.
struct TileGrid {
  int width = 0, height = 0;  // 0: no tiles
  int overlap_x = 0, overlap_y = 0;
  // An object appears in a tile when the tile holds at least this share of
  // its mask pixels (1 with --drop-truncated: only whole objects).
  double min_fraction = 0.5;

  bool enabled() const { return width > 0; }
};

// From options.tile, options.overlap and options.tile_min_fraction; throws
// lsds::Error naming the flag at fault. Disabled when options.tile is empty.
TileGrid ParseTileGrid(const ConvertOptions& options);

// The first pixels of the tiles along an axis of `image_size` pixels, by the
// rule of DOTA_devkit ImgSplit.py (SplitSingle, lines 185-230 at commit
// 9938855, github:CAPTAIN-WHU/DOTA_devkit): steps of tile - overlap from
// 0; the tile that would reach or pass the image edge is moved back to end on
// it, and is the last. One tile (the whole axis) when the image is no larger
// than a tile.
std::vector<int> TileStarts(int image_size, int tile_size, int overlap);

struct TileRect {
  int x = 0, y = 0, width = 0, height = 0;  // in the frame's pixels
};

// The tiles of a `image_width` x `image_height` frame, row by row (y, then x).
std::vector<TileRect> TileRects(const TileGrid& grid, int image_width, int image_height);

// One tile of a frame and what the converters see of it.
struct Tile {
  TileRect rect;
  // The source frame seen through the tile: its camera's principal point
  // moved and size cut to the tile, its sequence "<sequence>_<x>_<y>" (a tiled
  // video is one video per tile position), its objects those kept in the tile
  // in tile coordinates. `context.frame` points here.
  Frame frame;
  FrameContext context;
  std::vector<double>
      tile_fractions;  // per context.objects: mask pixels in the tile / in the frame
};

// Tiles, images and the tile map of one conversion.
class Tiler {
 public:
  // Starts tiles.json in `root`, the folder being written.
  Tiler(const ConvertOptions& options, const ClassMap& classes, std::filesystem::path root);

  const TileGrid& grid() const { return grid_; }
  int64_t CountTiles(const Frame& frame) const;

  // The tiles of a prepared frame (whose objects carry masks), numbered from
  // `first_image_index`; writes the tile images cut from `display` (the frame's
  // sRGB image; none when empty). Thread-safe.
  std::vector<std::unique_ptr<Tile>> Cut(const FrameContext& frame,
                                         const cv::Mat& display,
                                         int64_t first_image_index,
                                         LossReport* loss) const;

  // Serial, in output order: appends the tile to the tile map.
  void Record(const FrameContext& source, const Tile& tile);
  // Writes tiles.json (schemas/tiles.schema.json).
  void Finish();

 private:
  TileGrid grid_;
  const ClassMap& classes_;
  std::filesystem::path root_;
  std::string image_ext_;
  imaging::DisplayOptions display_options_;
  std::unique_ptr<AtomicFile> map_;
  int64_t recorded_ = 0;
};

}  // namespace lsds::convert

#include "converters/tiles.h"

#include <algorithm>
#include <cmath>
#include <regex>

#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>

#include "converters/format_util.h"
#include "libs/imaging/srgb_image.h"
#include "libs/util/error.h"

namespace lsds::convert {

namespace {

using nlohmann::json;

int ParsePositive(const std::string& text, const char* flag) {
  try {
    size_t used = 0;
    const long value = std::stol(text, &used);
    if (used == text.size() && value > 0 && value <= (1 << 20)) return static_cast<int>(value);
  } catch (const std::exception&) {
  }
  throw Error("expected W or WxH, positive whole pixels, got '" + text + "'", Location(flag));
}

Box2d Shifted(const Box2d& box, double dx, double dy) {
  return {box.x0 + dx, box.y0 + dy, box.x1 + dx, box.y1 + dy};
}

OrientedBox2d Shifted(OrientedBox2d box, double dx, double dy) {
  for (Eigen::Vector2d& corner : box.corners) corner += Eigen::Vector2d(dx, dy);
  return box;
}

// The direction `box`'s first corner stands for: out of the box through the
// edge from corners[0] to corners[1] (docs/format.md, "Oriented boxes"). With
// it the heading corner of a cut box is the one on the same side as the
// frame's.
Eigen::Vector2d FirstEdgeDirection(const OrientedBox2d& box) {
  return (box.corners[0] + box.corners[1]) / 2 - box.Center();
}

// The visible oriented box of a tile's cropped mask (tile coordinates),
// measured by MaskOrientedBox on the mask as an id layer of its own.
std::optional<OrientedBox2d> CroppedMaskOrientedBox(const masks::BoxMask& mask,
                                                    const OrientedBox2d& in_frame) {
  std::vector<uint32_t> ids(static_cast<size_t>(mask.width()) * mask.height());
  for (int y = 0; y < mask.height(); ++y) {
    for (int x = 0; x < mask.width(); ++x)
      ids[static_cast<size_t>(y) * mask.width() + x] = mask.mask.at<uint8_t>(y, x);
  }
  const std::optional<OrientedBox2d> box =
      MaskOrientedBox(ids.data(),
                      mask.width(),
                      mask.height(),
                      1,
                      Box2d{0, 0, double(mask.width()), double(mask.height())});
  if (!box) return std::nullopt;
  return WithHeadingCornerFirst(Shifted(*box, mask.left, mask.top), FirstEdgeDirection(in_frame));
}

}  // namespace

TileGrid ParseTileGrid(const ConvertOptions& options) {
  TileGrid grid;
  if (options.tile.empty()) {
    if (options.overlap != "0") throw Error("only with --tile", Location("--overlap"));
    return grid;
  }
  const size_t x = options.tile.find('x');
  grid.width = ParsePositive(options.tile.substr(0, x), "--tile");
  grid.height =
      x == std::string::npos ? grid.width : ParsePositive(options.tile.substr(x + 1), "--tile");

  const std::string& overlap = options.overlap;
  const bool percent = !overlap.empty() && overlap.back() == '%';
  double value = -1;
  try {
    size_t used = 0;
    const std::string number = percent ? overlap.substr(0, overlap.size() - 1) : overlap;
    value = std::stod(number, &used);
    if (used != number.size() || (!percent && value != std::floor(value))) value = -1;
  } catch (const std::exception&) {
  }
  if (!(value >= 0)) {
    throw Error("expected whole pixels P or a percentage of the tile P%, got '" + overlap + "'",
                Location("--overlap"));
  }
  grid.overlap_x = percent ? static_cast<int>(std::lround(value / 100 * grid.width)) : int(value);
  grid.overlap_y = percent ? static_cast<int>(std::lround(value / 100 * grid.height)) : int(value);
  if (grid.overlap_x >= grid.width || grid.overlap_y >= grid.height) {
    throw Error("the overlap (" + std::to_string(grid.overlap_x) + "x" +
                    std::to_string(grid.overlap_y) + " pixels) must be smaller than the tile (" +
                    std::to_string(grid.width) + "x" + std::to_string(grid.height) + ")",
                Location("--overlap"));
  }
  if (!(options.tile_min_fraction > 0 && options.tile_min_fraction <= 1)) {
    throw Error("must be in (0, 1]", Location("--tile-min-fraction"));
  }
  grid.min_fraction = options.drop_truncated ? 1.0 : options.tile_min_fraction;
  return grid;
}

std::vector<int> TileStarts(int image_size, int tile_size, int overlap) {
  std::vector<int> starts;
  for (int start = 0;; start += tile_size - overlap) {
    if (start + tile_size >= image_size) {
      starts.push_back(std::max(image_size - tile_size, 0));
      return starts;
    }
    starts.push_back(start);
  }
}

std::vector<TileRect> TileRects(const TileGrid& grid, int image_width, int image_height) {
  std::vector<TileRect> rects;
  const int width = std::min(grid.width, image_width);
  const int height = std::min(grid.height, image_height);
  for (int y : TileStarts(image_height, grid.height, grid.overlap_y)) {
    for (int x : TileStarts(image_width, grid.width, grid.overlap_x))
      rects.push_back({x, y, width, height});
  }
  return rects;
}

Tiler::Tiler(const ConvertOptions& options, const ClassMap& classes, std::filesystem::path root)
    : grid_(ParseTileGrid(options)),
      classes_(classes),
      root_(std::move(root)),
      image_ext_(options.ImageExtension()),
      display_options_(options.display) {
  map_ = OpenForWrite(root_ / "tiles.json");
  const json head = {{"format", "lsds-tiles"},
                     {"format_version", "1.0"},
                     {"tile", {grid_.width, grid_.height}},
                     {"overlap", {grid_.overlap_x, grid_.overlap_y}},
                     {"min_fraction", grid_.min_fraction}};
  std::string text = head.dump();
  text.pop_back();  // the closing "}": the tiles follow
  map_->stream() << text << ",\"tiles\":[";
}

int64_t Tiler::CountTiles(const Frame& frame) const {
  return static_cast<int64_t>(
      TileRects(grid_, frame.camera.intrinsics.width, frame.camera.intrinsics.height).size());
}

namespace {

// A tile of `frame` at `rect`: the frame without its objects (`head`), its
// camera shifted to the tile, named after the tile's corner.
std::unique_ptr<Tile> StartTile(const FrameContext& frame,
                                const Frame& head,
                                const TileRect& rect,
                                const std::string& image_ext,
                                int64_t image_index) {
  auto tile = std::make_unique<Tile>();
  tile->rect = rect;
  const std::string suffix = "_" + std::to_string(rect.x) + "_" + std::to_string(rect.y);
  tile->frame = head;
  tile->frame.sequence += suffix;
  PinholeCamera& camera = tile->frame.camera.intrinsics;
  camera.width = rect.width, camera.height = rect.height;
  camera.cx -= rect.x, camera.cy -= rect.y;

  FrameContext& ctx = tile->context;
  ctx.frame = &tile->frame;
  ctx.split = frame.split;
  ctx.stem = frame.stem + suffix;
  ctx.image_name = ctx.stem + image_ext;
  ctx.width = rect.width, ctx.height = rect.height;
  ctx.image_index = image_index;
  return tile;
}

// The mask cut to the tile, tight again, in tile coordinates: `part` is the
// view of the mask over `overlap` (the mask's box and the tile's, in frame
// coordinates), with `count` pixels set.
masks::BoxMask CutMask(const cv::Mat& part,
                       const cv::Rect& overlap,
                       const TileRect& rect,
                       int64_t count) {
  // From the points: OpenCV 4.6's boundingRect of an 8-bit image is short
  // for some narrow images (a 2 x 1 image of two 1s gives width 1).
  std::vector<cv::Point> points;
  cv::findNonZero(part, points);
  const cv::Rect tight = cv::boundingRect(points);
  masks::BoxMask cut;
  cut.left = overlap.x + tight.x - rect.x;
  cut.top = overlap.y + tight.y - rect.y;
  cut.mask = part(tight).clone();
  cut.pixel_count = count;
  cut.image_width = rect.width, cut.image_height = rect.height;
  return cut;
}

// The object's truth in the tile's frame: its visible box `box` (of the cut
// mask `cut`), its projected boxes shifted, its oriented box shifted when
// the object is `whole` in the tile, else measured on the cut mask.
ObjectTruth TruthInTile(const ObjectTruth& in_frame,
                        const masks::BoxMask& cut,
                        const Box2d& box,
                        double fraction,
                        bool whole,
                        const TileRect& rect) {
  const double dx = -rect.x, dy = -rect.y;
  ObjectTruth truth = in_frame;
  truth.bbox = box;
  truth.visible_pixels = cut.pixel_count;
  // The share of the amodal silhouette inside the tile is not known; the
  // share inside the frame times the visible share inside the tile
  // estimates it (exact for an unoccluded object whole in the frame).
  truth.in_frame = in_frame.in_frame * fraction;
  if (truth.bbox_projected)
    truth.bbox_projected =
        Shifted(*truth.bbox_projected, dx, dy).ClippedTo(rect.width, rect.height);
  if (truth.bbox_oriented_projected)
    truth.bbox_oriented_projected = Shifted(*truth.bbox_oriented_projected, dx, dy);
  if (truth.bbox_oriented) {
    truth.bbox_oriented = whole ? Shifted(*truth.bbox_oriented, dx, dy)
                                : CroppedMaskOrientedBox(cut, *truth.bbox_oriented);
  }
  return truth;
}

// Adds the part of `object` inside `tile` to it (its truth, its cut mask and
// its kept object, the pointers set by the caller); false when the object has
// no pixel in the tile or too small a share of them (a loss).
bool AddObjectPart(const KeptObject& object,
                   const TileGrid& grid,
                   const ClassMap& classes,
                   Tile* tile,
                   std::vector<KeptObject>* kept,
                   LossReport* loss) {
  const TileRect& rect = tile->rect;
  const cv::Rect tile_rect(rect.x, rect.y, rect.width, rect.height);
  const masks::BoxMask& mask = *object.mask;
  const cv::Rect overlap = cv::Rect(mask.left, mask.top, mask.width(), mask.height()) & tile_rect;
  if (overlap.empty()) return false;
  const cv::Mat part =
      mask.mask(overlap - cv::Point(mask.left, mask.top));  // view, in mask coordinates
  const int64_t count = cv::countNonZero(part);
  if (count == 0) return false;  // no pixel in the tile: not even a loss
  const std::string& name = classes.classes()[object.class_index].name;
  const double fraction = static_cast<double>(count) / static_cast<double>(mask.pixel_count);
  if (fraction < grid.min_fraction) {
    loss->Add(loss::kTileBelowFraction, name);
    return false;
  }
  if (count < mask.pixel_count) loss->Add(loss::kTileTruncated, name);

  masks::BoxMask cut = CutMask(part, overlap, rect, count);
  const Box2d box{double(cut.left),
                  double(cut.top),
                  double(cut.left + cut.width()),
                  double(cut.top + cut.height())};
  const bool whole = count == mask.pixel_count;
  KeptObject out;
  out.class_index = object.class_index;
  out.box = box;
  if (object.oriented) {
    out.oriented = whole ? Shifted(*object.oriented, -rect.x, -rect.y)
                         : CroppedMaskOrientedBox(cut, *object.oriented);
  }
  tile->frame.objects.push_back(TruthInTile(*object.truth, cut, box, fraction, whole, rect));
  tile->context.mask_storage.push_back(std::move(cut));
  kept->push_back(out);
  tile->tile_fractions.push_back(fraction);
  return true;
}

}  // namespace

std::vector<std::unique_ptr<Tile>> Tiler::Cut(const FrameContext& frame,
                                              const cv::Mat& display,
                                              int64_t first_image_index,
                                              LossReport* loss) const {
  // The frame without its objects, copied once: each tile starts from it.
  Frame head = *frame.frame;
  head.objects.clear();
  std::vector<bool> in_some_tile(frame.objects.size(), false);
  std::vector<std::unique_ptr<Tile>> tiles;
  for (const TileRect& rect : TileRects(grid_, frame.width, frame.height)) {
    std::unique_ptr<Tile> tile = StartTile(
        frame, head, rect, image_ext_, first_image_index + static_cast<int64_t>(tiles.size()));
    FrameContext& ctx = tile->context;
    std::vector<KeptObject> kept;
    for (size_t i = 0; i < frame.objects.size(); ++i) {
      if (AddObjectPart(frame.objects[i], grid_, classes_, tile.get(), &kept, loss))
        in_some_tile[i] = true;
    }
    // Pointers last: the vectors do not move any more.
    for (size_t k = 0; k < kept.size(); ++k) {
      kept[k].truth = &tile->frame.objects[k];
      kept[k].mask = &ctx.mask_storage[k];
    }
    ctx.objects = std::move(kept);

    if (!display.empty()) {
      const cv::Rect tile_rect(rect.x, rect.y, rect.width, rect.height);
      imaging::WriteImage(
          root_ / "images" / ctx.split / ctx.image_name, display(tile_rect), display_options_);
    }
    tiles.push_back(std::move(tile));
  }
  for (size_t i = 0; i < frame.objects.size(); ++i) {
    if (!in_some_tile[i])
      loss->Add(loss::kInNoTile, classes_.classes()[frame.objects[i].class_index].name);
  }
  return tiles;
}

void Tiler::Record(const FrameContext& source, const Tile& tile) {
  json objects = json::array();
  for (size_t k = 0; k < tile.context.objects.size(); ++k) {
    objects.push_back({{"instance_id", tile.context.objects[k].truth->instance_id},
                       {"tile_fraction", tile.tile_fractions[k]}});
  }
  const json entry = {{"image", tile.context.image_name},
                      {"split", tile.context.split},
                      {"frame", source.frame->index},
                      {"frame_image", source.image_name},
                      {"x", tile.rect.x},
                      {"y", tile.rect.y},
                      {"width", tile.rect.width},
                      {"height", tile.rect.height},
                      {"objects", std::move(objects)}};
  map_->stream() << (recorded_++ ? ",\n" : "\n") << entry.dump();
}

void Tiler::Finish() {
  map_->stream() << "\n]}\n";
  map_->Commit();
}

}  // namespace lsds::convert

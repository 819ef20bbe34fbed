#include "converters/convert.h"

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <set>

#include <tbb/parallel_for.h>

#include "converters/class_map.h"
#include "converters/converter.h"
#include "converters/registry.h"
#include "converters/split.h"
#include "converters/tiles.h"
#include "libs/collection/collection_reader.h"
#include "libs/collection/rig.h"
#include "libs/exr/flat_image.h"
#include "libs/imaging/srgb_image.h"
#include "libs/masks/instance_masks.h"
#include "libs/util/atomic_file.h"
#include "libs/util/error.h"
#include "libs/util/progress.h"
#include "libs/util/strings.h"

namespace lsds::convert {

namespace fs = std::filesystem;

namespace {

// The loss-report reason of the first filter that drops `object` (in the
// order the loss report lists them), or nullptr when the object is kept.
const char* DropReason(const ObjectTruth& object,
                       const ConvertOptions& options,
                       const ClassMap& classes) {
  if (!object.bbox || object.bbox->empty() || object.visible_pixels <= 0) return loss::kNotVisible;
  if (!classes.Map(object.class_id)) return loss::kClassNotSelected;
  if (object.visibility < options.min_visibility) return loss::kMinVisibility;
  // Seen through so much fog that nobody can see it (format 1.1; objects
  // without the field count as clear air).
  if (options.min_transmittance > 0 &&
      object.transmittance.value_or(1.0) < options.min_transmittance)
    return loss::kMinTransmittance;
  if (object.visible_pixels < options.min_pixels) return loss::kMinPixels;
  if (options.drop_truncated && object.in_frame < 1.0) return loss::kTruncated;
  return nullptr;
}

struct Driver {
  const ConvertOptions& options;
  const CollectionReader& reader;
  const ClassMap& classes;
  const std::vector<SplitPart>& splits;
  const SplitPlan& split_plan;
  fs::path root;
  std::string rgb_layer;       // empty with --images none
  std::string instance_layer;  // empty when no format needs masks or oriented boxes, or absent
  bool needs_masks = false;
  bool needs_oriented = false;
  std::atomic<int64_t> images_written{0};

  std::string ClassName(uint32_t id) const {
    const ClassInfo* c = reader.header().FindClass(id);
    return c ? c->name : "class " + std::to_string(id);
  }

  // With `display`, the frame's sRGB image is left there (for the tiles)
  // instead of written.
  // Not yet cut at its seams (docs/architecture.md, "Long functions").
  // NOLINTNEXTLINE(readability-function-size,readability-function-cognitive-complexity)
  void Prepare(const Frame& frame, FrameContext* ctx, LossReport* loss, cv::Mat* display) {
    ctx->frame = &frame;
    ctx->split = split_plan.SplitOf(frame.index);
    ctx->stem = FrameFileStem(frame);  // "000004_left" in a rig: unique per camera
    ctx->image_name = ctx->stem + options.ImageExtension();
    ctx->width = frame.camera.intrinsics.width;
    ctx->height = frame.camera.intrinsics.height;
    ctx->image_index = frame.index;
    loss->CountFrame(ctx->split);

    if (!rgb_layer.empty()) {
      const exr::FlatImage rgb = reader.ReadFlatLayer(frame, rgb_layer, {"R", "G", "B"});
      if (display != nullptr) {
        *display = imaging::ToSrgb8(rgb, options.display);
      } else {
        imaging::WriteImage(root / "images" / ctx->split / ctx->image_name,
                            imaging::ToSrgb8(rgb, options.display),
                            options.display);
        ++images_written;
      }
    }

    // Filters, in the order the loss report lists them; an object is counted
    // once, by the first filter that drops it.
    std::vector<std::pair<const ObjectTruth*, int>> kept;
    for (const ObjectTruth& object : frame.objects) {
      if (const char* reason = DropReason(object, options, classes)) {
        loss->Add(reason, ClassName(object.class_id));
      } else {
        kept.emplace_back(&object, *classes.Map(object.class_id));
      }
    }

    // The instanceid layer is read for masks, and for oriented boxes the
    // truth does not hold (collections before format 1.2).
    const bool measure_oriented =
        needs_oriented && std::any_of(kept.begin(), kept.end(), [](const auto& k) {
          return !k.first->bbox_oriented.has_value();
        });
    exr::FlatImage ids;
    const uint32_t* id_data = nullptr;
    if ((needs_masks || measure_oriented) && !kept.empty()) {
      if (instance_layer.empty()) {
        throw Error("frame " + std::to_string(frame.index) +
                        " has objects without bbox_oriented and the collection has no instanceid "
                        "layer to measure them on",
                    Location(reader.collection_path().string()));
      }
      ids = reader.ReadFlatLayer(frame, instance_layer, {"id"});
      id_data = ids.Get("id").uints.data();
    }

    std::vector<const masks::BoxMask*> object_masks(kept.size(), nullptr);
    if (needs_masks && !kept.empty()) {
      const auto bounds = masks::ComputeIdBounds(id_data, ids.width(), ids.height());
      ctx->mask_storage.resize(kept.size());
      for (size_t i = 0; i < kept.size(); ++i) {
        const auto it = bounds.find(kept[i].first->instance_id);
        if (it == bounds.end()) continue;
        ctx->mask_storage[i] = masks::ExtractMask(
            id_data, ids.width(), ids.height(), kept[i].first->instance_id, it->second);
        object_masks[i] = &ctx->mask_storage[i];
      }
    }

    // The visible oriented box: the truth's (heading corner first where
    // known), else the minimum-area rectangle of the instance's pixels.
    std::vector<std::optional<OrientedBox2d>> oriented(kept.size());
    if (needs_oriented) {
      for (size_t i = 0; i < kept.size(); ++i) {
        const ObjectTruth& object = *kept[i].first;
        oriented[i] =
            object.bbox_oriented
                ? object.bbox_oriented
                : MaskOrientedBox(
                      id_data, ids.width(), ids.height(), object.instance_id, *object.bbox);
      }
    }

    for (size_t i = 0; i < kept.size(); ++i) {
      const ObjectTruth& object = *kept[i].first;
      const std::string& name = classes.classes()[kept[i].second].name;
      if ((needs_masks && object_masks[i] == nullptr) || (needs_oriented && !oriented[i])) {
        loss->Add(loss::kNoMask, ClassName(object.class_id));
        continue;
      }
      KeptObject out;
      out.truth = &object;
      out.class_index = kept[i].second;
      out.box = object.bbox->ClippedTo(ctx->width, ctx->height);
      if (!(out.box == *object.bbox)) loss->Add(loss::kBoxClipped, name);
      if (out.box.empty()) {
        loss->Add(loss::kNotVisible, ClassName(object.class_id));
        continue;
      }
      out.mask = object_masks[i];
      out.oriented = oriented[i];
      if (out.mask != nullptr) {
        const Box2d mask_box{double(out.mask->left),
                             double(out.mask->top),
                             double(out.mask->left + out.mask->width()),
                             double(out.mask->top + out.mask->height())};
        if (!out.box.Contains(mask_box)) loss->Add(loss::kMaskBoxMismatch, name);
      }
      if (object.in_frame < 1.0) loss->Add(loss::kClippedAtBorder, name);
      loss->Add(loss::kKept, name);
      ctx->objects.push_back(out);
    }
  }
};

}  // namespace

// Not yet cut at its seams (docs/architecture.md, "Long functions").
// NOLINTNEXTLINE(readability-function-size,readability-function-cognitive-complexity)
ConvertResult Convert(const ConvertOptions& options) {
  options.Check();
  const CollectionReader reader(options.collection);
  const CollectionHeader& header = reader.header();
  const ClassMap selected = options.classes.empty()
                                ? ClassMap::All(header.classes)
                                : ClassMap::Parse(options.classes, header.classes);
  const std::vector<SplitPart> splits = ParseSplit(options.split);

  std::vector<std::unique_ptr<Converter>> converters;
  bool needs_masks = false, needs_oriented = false;
  for (const std::string& format : options.formats) {
    converters.push_back(MakeConverter(format));
    needs_masks = needs_masks || converters.back()->NeedsMasks();
    needs_oriented = needs_oriented || converters.back()->NeedsOrientedBoxes();
  }
  // Tiles measure each object's share in a tile on its mask.
  needs_masks = needs_masks || !options.tile.empty();

  auto in_range = [&](const Frame& frame) { return options.frames.Contains(frame.index); };
  // Splits are planned over all the frames first, so that no requested split
  // is left empty (docs/convert.md, "Splits").
  // The same pass finds the classes some kept object has: the others are not
  // listed (unless --keep-classes), so YOLO ids are contiguous and no
  // consumer sees a class without a single label (docs/convert.md, "Classes").
  std::vector<SplitFrame> split_frames;
  std::set<uint32_t> used_classes;
  reader.ForEachFrame([&](const Frame& frame) {
    if (!in_range(frame)) return;
    split_frames.push_back({frame.index, SplitGroup(frame)});
    for (const ObjectTruth& object : frame.objects)
      if (DropReason(object, options, selected) == nullptr) used_classes.insert(object.class_id);
  });
  const SplitPlan split_plan = PlanSplits(splits, split_frames);
  const ClassMap classes = options.keep_classes ? selected : selected.OnlyUsed(used_classes);

  // Refuse early (before any work) and build under a temporary name.
  AtomicDirectory out(options.output, options.force);
  Driver driver{options,
                reader,
                classes,
                splits,
                split_plan,
                out.temp_path(),
                "",
                "",
                needs_masks,
                needs_oriented};
  if (options.images != "none") {
    const LayerInfo* rgb = header.FindLayerBySemantic("rgb");
    if (rgb == nullptr) {
      throw Error("the collection has no rgb layer; use --images none",
                  Location(reader.collection_path().string()));
    }
    driver.rgb_layer = rgb->name;
    for (const SplitPart& split : splits)
      fs::create_directories(out.temp_path() / "images" / split.name);
  }
  if (const LayerInfo* ids = header.FindLayerBySemantic("instanceid")) {
    if (needs_masks || needs_oriented) driver.instance_layer = ids->name;
  } else if (needs_masks) {
    throw Error("the collection has no instanceid layer, which masks are made from",
                Location(reader.collection_path().string()));
  }

  ConvertSetup setup;
  setup.root = out.temp_path();
  setup.final_root = fs::absolute(options.output).lexically_normal();
  setup.header = &header;
  setup.classes = &classes;
  setup.splits = splits;
  setup.options = &options;
  for (auto& converter : converters) converter->Begin(setup);
  std::unique_ptr<Tiler> tiler;
  if (!options.tile.empty()) tiler = std::make_unique<Tiler>(options, classes, out.temp_path());
  int64_t next_tile_index = 0;
  // The images of a prepared frame: the frame itself, or its tiles.
  auto images_of = [&](const FrameContext& frame, const std::vector<std::unique_ptr<Tile>>& tiles) {
    std::vector<const FrameContext*> images;
    if (!tiler) images.push_back(&frame);
    for (const auto& tile : tiles) images.push_back(&tile->context);
    return images;
  };

  ConvertResult result;
  Progress progress("convert", static_cast<int64_t>(reader.frames_in_file()));
  std::vector<Frame> batch;
  batch.reserve(options.batch_size);
  auto flush = [&] {
    const size_t n = batch.size();
    std::vector<FrameContext> contexts(n);
    std::vector<LossReport> losses(n);
    std::vector<std::vector<std::unique_ptr<FramePiece>>> pieces(n);
    std::vector<std::vector<std::unique_ptr<Tile>>> tiles(n);
    std::vector<int64_t> first_tile(n, 0);  // tile numbers in output order, known before cutting
    for (size_t i = 0; tiler && i < n; ++i) {
      first_tile[i] = next_tile_index;
      next_tile_index += tiler->CountTiles(batch[i]);
    }
    tbb::parallel_for(size_t{0}, n, [&](size_t i) {
      cv::Mat display;
      driver.Prepare(batch[i], &contexts[i], &losses[i], tiler ? &display : nullptr);
      if (tiler) {
        tiles[i] = tiler->Cut(contexts[i], display, first_tile[i], &losses[i]);
        if (!display.empty()) driver.images_written += static_cast<int64_t>(tiles[i].size());
      }
      for (const FrameContext* image : images_of(contexts[i], tiles[i])) {
        for (const auto& converter : converters) {
          pieces[i].push_back(converter->EncodeFrame(*image, &losses[i]));
        }
      }
      if (options.progress) progress.Add();
    });
    for (size_t i = 0; i < n; ++i) {
      result.loss.Merge(losses[i]);
      size_t piece = 0;
      for (const FrameContext* image : images_of(contexts[i], tiles[i])) {
        for (auto& converter : converters) {
          converter->AddFrame(*image, std::move(pieces[i][piece++]));
        }
      }
      for (const auto& tile : tiles[i]) tiler->Record(contexts[i], *tile);
    }
    result.frames += static_cast<int64_t>(n);
    batch.clear();
  };
  reader.ForEachFrame([&](const Frame& frame) {
    if (!options.frames.Contains(frame.index)) return;
    batch.push_back(frame);
    if (batch.size() == options.batch_size) flush();
  });
  flush();
  for (auto& converter : converters) converter->Finish();
  if (tiler) tiler->Finish();

  WriteFileAtomic(out.temp_path() / "loss_report.txt", result.loss.ToText());
  WriteFileAtomic(out.temp_path() / "loss_report.json", result.loss.ToJson().dump(2) + "\n");
  out.Commit();
  result.images_written = driver.images_written;
  return result;
}

}  // namespace lsds::convert

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

  // A kept object of the frame and the index of its class in the output.
  using KeptTruth = std::pair<const ObjectTruth*, int>;

  // The frame's instanceid layer, when read (`data` null when not).
  struct InstanceIds {
    exr::FlatImage image;
    const uint32_t* data = nullptr;
  };

  // With `display`, the frame's sRGB image is left there (for the tiles)
  // instead of written.
  void Prepare(const Frame& frame, FrameContext* ctx, LossReport* loss, cv::Mat* display) {
    ctx->frame = &frame;
    ctx->split = split_plan.SplitOf(frame.index);
    ctx->stem = FrameFileStem(frame);  // "000004_left" in a rig: unique per camera
    ctx->image_name = ctx->stem + options.ImageExtension();
    ctx->width = frame.camera.intrinsics.width;
    ctx->height = frame.camera.intrinsics.height;
    ctx->image_index = frame.index;
    loss->CountFrame(ctx->split);

    if (!rgb_layer.empty()) Image(frame, *ctx, display);
    const std::vector<KeptTruth> kept = Filter(frame, loss);
    InstanceIds ids;
    ReadInstanceIds(frame, kept, &ids);
    const std::vector<const masks::BoxMask*> object_masks = Masks(kept, ids, ctx);
    const std::vector<std::optional<OrientedBox2d>> oriented = OrientedBoxes(kept, ids);
    for (size_t i = 0; i < kept.size(); ++i) Keep(kept[i], object_masks[i], oriented[i], ctx, loss);
  }

  // The frame's sRGB image: written, or left in `display`.
  void Image(const Frame& frame, const FrameContext& ctx, cv::Mat* display) {
    const exr::FlatImage rgb = reader.ReadFlatLayer(frame, rgb_layer, {"R", "G", "B"});
    if (display != nullptr) {
      *display = imaging::ToSrgb8(rgb, options.display);
    } else {
      imaging::WriteImage(root / "images" / ctx.split / ctx.image_name,
                          imaging::ToSrgb8(rgb, options.display),
                          options.display);
      ++images_written;
    }
  }

  // Filters, in the order the loss report lists them; an object is counted
  // once, by the first filter that drops it.
  std::vector<KeptTruth> Filter(const Frame& frame, LossReport* loss) const {
    std::vector<KeptTruth> kept;
    for (const ObjectTruth& object : frame.objects) {
      if (const char* reason = DropReason(object, options, classes)) {
        loss->Add(reason, ClassName(object.class_id));
      } else {
        kept.emplace_back(&object, *classes.Map(object.class_id));
      }
    }
    return kept;
  }

  // The instanceid layer is read for masks, and for oriented boxes the
  // truth does not hold (collections before format 1.2).
  void ReadInstanceIds(const Frame& frame,
                       const std::vector<KeptTruth>& kept,
                       InstanceIds* ids) const {
    const bool measure_oriented =
        needs_oriented && std::any_of(kept.begin(), kept.end(), [](const auto& k) {
          return !k.first->bbox_oriented.has_value();
        });
    if (!(needs_masks || measure_oriented) || kept.empty()) return;
    if (instance_layer.empty()) {
      throw Error("frame " + std::to_string(frame.index) +
                      " has objects without bbox_oriented and the collection has no instanceid "
                      "layer to measure them on",
                  Location(reader.collection_path().string()));
    }
    ids->image = reader.ReadFlatLayer(frame, instance_layer, {"id"});
    ids->data = ids->image.Get("id").uints.data();
  }

  // The kept objects' masks, in the context's storage (null for an object
  // without pixels, or when no format needs masks).
  std::vector<const masks::BoxMask*> Masks(const std::vector<KeptTruth>& kept,
                                           const InstanceIds& ids,
                                           FrameContext* ctx) const {
    std::vector<const masks::BoxMask*> object_masks(kept.size(), nullptr);
    if (!needs_masks || kept.empty()) return object_masks;
    const int width = ids.image.width(), height = ids.image.height();
    const auto bounds = masks::ComputeIdBounds(ids.data, width, height);
    ctx->mask_storage.resize(kept.size());
    for (size_t i = 0; i < kept.size(); ++i) {
      const auto it = bounds.find(kept[i].first->instance_id);
      if (it == bounds.end()) continue;
      ctx->mask_storage[i] =
          masks::ExtractMask(ids.data, width, height, kept[i].first->instance_id, it->second);
      object_masks[i] = &ctx->mask_storage[i];
    }
    return object_masks;
  }

  // The visible oriented box: the truth's (heading corner first where
  // known), else the minimum-area rectangle of the instance's pixels.
  std::vector<std::optional<OrientedBox2d>> OrientedBoxes(const std::vector<KeptTruth>& kept,
                                                          const InstanceIds& ids) const {
    std::vector<std::optional<OrientedBox2d>> oriented(kept.size());
    if (!needs_oriented) return oriented;
    for (size_t i = 0; i < kept.size(); ++i) {
      const ObjectTruth& object = *kept[i].first;
      oriented[i] = object.bbox_oriented ? object.bbox_oriented
                                         : MaskOrientedBox(ids.data,
                                                           ids.image.width(),
                                                           ids.image.height(),
                                                           object.instance_id,
                                                           *object.bbox);
    }
    return oriented;
  }

  // A kept object into the frame's objects, with the losses it counts in.
  void Keep(const KeptTruth& kept,
            const masks::BoxMask* mask,
            const std::optional<OrientedBox2d>& oriented,
            FrameContext* ctx,
            LossReport* loss) const {
    const ObjectTruth& object = *kept.first;
    const std::string& name = classes.classes()[kept.second].name;
    if ((needs_masks && mask == nullptr) || (needs_oriented && !oriented)) {
      loss->Add(loss::kNoMask, ClassName(object.class_id));
      return;
    }
    KeptObject out;
    out.truth = &object;
    out.class_index = kept.second;
    out.box = object.bbox->ClippedTo(ctx->width, ctx->height);
    if (!(out.box == *object.bbox)) loss->Add(loss::kBoxClipped, name);
    if (out.box.empty()) {
      loss->Add(loss::kNotVisible, ClassName(object.class_id));
      return;
    }
    out.mask = mask;
    out.oriented = oriented;
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
};

// The converters of the requested formats, and what they need of a frame.
struct Converters {
  std::vector<std::unique_ptr<Converter>> list;
  bool needs_masks = false;
  bool needs_oriented = false;
};

Converters MakeConverters(const ConvertOptions& options,
                          std::vector<std::unique_ptr<Converter>> also) {
  Converters converters;
  for (const std::string& format : options.formats)
    converters.list.push_back(MakeConverter(format));
  for (auto& converter : also) converters.list.push_back(std::move(converter));
  for (const auto& converter : converters.list) {
    converters.needs_masks = converters.needs_masks || converter->NeedsMasks();
    converters.needs_oriented = converters.needs_oriented || converter->NeedsOrientedBoxes();
  }
  // Tiles measure each object's share in a tile on its mask.
  converters.needs_masks = converters.needs_masks || !options.tile.empty();
  return converters;
}

// Splits are planned over all the frames first, so that no requested split
// is left empty (docs/convert.md, "Splits").
// The same pass finds the classes some kept object has: the others are not
// listed (unless --keep-classes), so YOLO ids are contiguous and no
// consumer sees a class without a single label (docs/convert.md, "Classes").
SplitPlan PlanFrames(const CollectionReader& reader,
                     const ConvertOptions& options,
                     const ClassMap& selected,
                     const std::vector<SplitPart>& splits,
                     std::set<uint32_t>* used_classes) {
  std::vector<SplitFrame> split_frames;
  reader.ForEachFrame([&](const Frame& frame) {
    if (!options.frames.Contains(frame.index)) return;
    split_frames.push_back({frame.index, SplitGroup(frame)});
    for (const ObjectTruth& object : frame.objects)
      if (DropReason(object, options, selected) == nullptr) used_classes->insert(object.class_id);
  });
  return PlanSplits(splits, split_frames);
}

// The layers the driver reads: rgb (unless --images none, with the image
// folders made) and instanceid (for masks and oriented boxes).
void ChooseLayers(const CollectionReader& reader, const fs::path& root, Driver* driver) {
  const CollectionHeader& header = reader.header();
  if (driver->options.images != "none") {
    const LayerInfo* rgb = header.FindLayerBySemantic("rgb");
    if (rgb == nullptr) {
      throw Error("the collection has no rgb layer; use --images none",
                  Location(reader.collection_path().string()));
    }
    driver->rgb_layer = rgb->name;
    for (const SplitPart& split : driver->splits)
      fs::create_directories(root / "images" / split.name);
  }
  if (const LayerInfo* ids = header.FindLayerBySemantic("instanceid")) {
    if (driver->needs_masks || driver->needs_oriented) driver->instance_layer = ids->name;
  } else if (driver->needs_masks) {
    throw Error("the collection has no instanceid layer, which masks are made from",
                Location(reader.collection_path().string()));
  }
}

// Converts the selected frames in batches: each batch prepared and encoded
// in parallel, then added to the converters in file order, so the output is
// deterministic.
class BatchConverter {
 public:
  BatchConverter(const ConvertOptions& options,
                 Driver* driver,
                 const std::vector<std::unique_ptr<Converter>>& converters,
                 Tiler* tiler,
                 Progress* progress,
                 ConvertResult* result)
      : options_(options),
        driver_(*driver),
        converters_(converters),
        tiler_(tiler),
        progress_(*progress),
        result_(*result) {}

  void Flush(std::vector<Frame>* batch);

 private:
  // One batch in the making, by frame.
  struct Prepared {
    explicit Prepared(size_t n) : contexts(n), losses(n), pieces(n), tiles(n), first_tile(n, 0) {}
    std::vector<FrameContext> contexts;
    std::vector<LossReport> losses;
    std::vector<std::vector<std::unique_ptr<FramePiece>>> pieces;
    std::vector<std::vector<std::unique_ptr<Tile>>> tiles;
    std::vector<int64_t> first_tile;  // tile numbers in output order, known before cutting
  };

  // The images of a prepared frame: the frame itself, or its tiles.
  std::vector<const FrameContext*> ImagesOf(const FrameContext& frame,
                                            const std::vector<std::unique_ptr<Tile>>& tiles) const {
    std::vector<const FrameContext*> images;
    if (tiler_ == nullptr) images.push_back(&frame);
    for (const auto& tile : tiles) images.push_back(&tile->context);
    return images;
  }

  void Encode(const Frame& frame, size_t i, Prepared* prepared);

  const ConvertOptions& options_;
  Driver& driver_;
  const std::vector<std::unique_ptr<Converter>>& converters_;
  Tiler* tiler_;
  Progress& progress_;
  ConvertResult& result_;
  int64_t next_tile_index_ = 0;
};

// Thread-safe: the frame prepared (and cut into tiles) and encoded.
void BatchConverter::Encode(const Frame& frame, size_t i, Prepared* prepared) {
  FrameContext& context = prepared->contexts[i];
  LossReport& loss = prepared->losses[i];
  std::vector<std::unique_ptr<Tile>>& tiles = prepared->tiles[i];
  cv::Mat display;
  driver_.Prepare(frame, &context, &loss, tiler_ ? &display : nullptr);
  if (tiler_) {
    tiles = tiler_->Cut(context, display, prepared->first_tile[i], &loss);
    if (!display.empty()) driver_.images_written += static_cast<int64_t>(tiles.size());
  }
  for (const FrameContext* image : ImagesOf(context, tiles)) {
    for (const auto& converter : converters_)
      prepared->pieces[i].push_back(converter->EncodeFrame(*image, &loss));
  }
  if (options_.progress) progress_.Add();
}

void BatchConverter::Flush(std::vector<Frame>* batch) {
  const size_t n = batch->size();
  Prepared prepared(n);
  for (size_t i = 0; tiler_ && i < n; ++i) {
    prepared.first_tile[i] = next_tile_index_;
    next_tile_index_ += tiler_->CountTiles((*batch)[i]);
  }
  tbb::parallel_for(size_t{0}, n, [&](size_t i) { Encode((*batch)[i], i, &prepared); });
  for (size_t i = 0; i < n; ++i) {
    result_.loss.Merge(prepared.losses[i]);
    size_t piece = 0;
    for (const FrameContext* image : ImagesOf(prepared.contexts[i], prepared.tiles[i])) {
      for (const auto& converter : converters_)
        converter->AddFrame(*image, std::move(prepared.pieces[i][piece++]));
    }
    for (const auto& tile : prepared.tiles[i]) tiler_->Record(prepared.contexts[i], *tile);
  }
  result_.frames += static_cast<int64_t>(n);
  batch->clear();
}

}  // namespace

ConvertResult Convert(const ConvertOptions& options) { return Convert(options, {}); }

ConvertResult Convert(const ConvertOptions& options, std::vector<std::unique_ptr<Converter>> also) {
  options.Check();
  const CollectionReader reader(options.collection);
  const CollectionHeader& header = reader.header();
  const ClassMap selected = options.classes.empty()
                                ? ClassMap::All(header.classes)
                                : ClassMap::Parse(options.classes, header.classes);
  const std::vector<SplitPart> splits = ParseSplit(options.split);
  const Converters converters = MakeConverters(options, std::move(also));
  std::set<uint32_t> used_classes;
  const SplitPlan split_plan = PlanFrames(reader, options, selected, splits, &used_classes);
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
                converters.needs_masks,
                converters.needs_oriented};
  ChooseLayers(reader, out.temp_path(), &driver);

  ConvertSetup setup;
  setup.root = out.temp_path();
  setup.final_root = fs::absolute(options.output).lexically_normal();
  setup.header = &header;
  setup.classes = &classes;
  setup.splits = splits;
  setup.options = &options;
  for (const auto& converter : converters.list) converter->Begin(setup);
  std::unique_ptr<Tiler> tiler;
  if (!options.tile.empty()) tiler = std::make_unique<Tiler>(options, classes, out.temp_path());

  ConvertResult result;
  Progress progress("convert", static_cast<int64_t>(reader.frames_in_file()));
  BatchConverter batches(options, &driver, converters.list, tiler.get(), &progress, &result);
  std::vector<Frame> batch;
  batch.reserve(options.batch_size);
  reader.ForEachFrame([&](const Frame& frame) {
    if (!options.frames.Contains(frame.index)) return;
    batch.push_back(frame);
    if (batch.size() == options.batch_size) batches.Flush(&batch);
  });
  batches.Flush(&batch);
  for (const auto& converter : converters.list) converter->Finish();
  if (tiler) tiler->Finish();

  WriteFileAtomic(out.temp_path() / "loss_report.txt", result.loss.ToText());
  WriteFileAtomic(out.temp_path() / "loss_report.json", result.loss.ToJson().dump(2) + "\n");
  out.Commit();
  result.images_written = driver.images_written;
  return result;
}

}  // namespace lsds::convert

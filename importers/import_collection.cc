#include "importers/import_collection.h"

#include <algorithm>
#include <optional>
#include <unordered_map>

#include "importers/derived_truth.h"
#include "importers/registry.h"
#include "libs/collection/collection_builder.h"
#include "libs/collection/layer_layouts.h"
#include "libs/collection/object_truth.h"
#include "libs/collection/worldposition_layout.h"
#include "libs/exr/encoder_settings.h"
#include "libs/util/atomic_file.h"
#include "libs/util/error.h"
#include "libs/util/strings.h"
#include "libs/util/text_check.h"

namespace lsds::import {

namespace fs = std::filesystem;

namespace {

bool IsWithin(const fs::path& inner, const fs::path& outer) {
  const auto mismatch = std::mismatch(outer.begin(), outer.end(), inner.begin(), inner.end());
  return mismatch.first == outer.end();
}

void RefuseOverlap(const fs::path& source, const fs::path& output) {
  const fs::path s = fs::weakly_canonical(source);
  const fs::path o = fs::weakly_canonical(output);
  if (IsWithin(o, s) || IsWithin(s, o))
    throw Error(
        "the output must neither be, lie inside nor contain the "
        "source '" +
            source.string() + "'",
        Location(output.string()));
}

// Runs an importer's step. The importers read every field through the checked
// accessors of source_json.h; a JSON access they missed (a value of another
// type deep in a structure) still stops the import as bad input at the source
// and frame, not as an internal error.
template <typename F>
auto Guarded(const fs::path& source, std::optional<int64_t> frame, F&& step) {
  try {
    return step();
  } catch (const nlohmann::json::exception& e) {
    Location where(source.string());
    where.frame = frame;
    throw Error(std::string("malformed source data: ") + e.what(), where);
  }
}

// The truth entries of a frame's targets, measured on its id layer (object_truth.h), the
// unoccluded pixels those of the OBB. A visibility the source states (SourceFrame::stated)
// replaces the derived one; a source without an id layer (Replicator without instance segmentation)
// gives the 2D box it states itself; the rest comes from the OBB, where there is one.
std::vector<ObjectTruth> MeasureFrameObjects(const SourceFrame& source_frame,
                                             const PinholeCamera& camera,
                                             const Rigid3d& cam_from_world) {
  std::vector<ObjectTruth> objects;
  const auto id_layer = source_frame.flat.find("instanceid");
  IdLayerView ids;
  std::unordered_map<uint32_t, InstanceMask> masks;
  if (id_layer != source_frame.flat.end()) {
    const exr::FlatImage& instances = id_layer->second;
    ids = {instances.Get("id").uints.data(), instances.width(), instances.height()};
    masks = MeasureInstanceMasks(ids.ids, ids.width, ids.height);
  }
  for (const ObjectIdentity& target : source_frame.targets) {
    const auto mask = masks.find(target.instance_id);
    UnoccludedCounter count_unoccluded;
    if (ids.ids != nullptr && target.obb)
      count_unoccluded = [&](const Box2d& bounds) {
        return CountObbPixels(*target.obb, camera, cam_from_world, bounds);
      };
    std::optional<ObjectTruth> object =
        MeasureObjectTruth(target,
                           camera,
                           cam_from_world,
                           ids,
                           mask == masks.end() ? nullptr : &mask->second,
                           count_unoccluded);
    const auto stated = source_frame.stated.find(target.instance_id);
    const bool box_stated = stated != source_frame.stated.end() && stated->second.bbox;
    if (!object && ids.ids == nullptr && !target.obb && box_stated) {
      // No id layer to find it on and no OBB to project: an object without a 3D box is where
      // the source's own 2D box says (format.md "Objects without a 3D box"); its in_frame and
      // visibility are not measured (1) unless the source states them below.
      object.emplace();
      object->instance_id = target.instance_id;
      object->class_id = target.class_id;
      object->name = target.name;
      object->asset = target.asset;
      object->in_frame = object->visibility = 1;
    }
    if (!object) continue;
    if (stated != source_frame.stated.end()) {
      if (ids.ids == nullptr && stated->second.bbox) object->bbox = stated->second.bbox;
      if (stated->second.visibility) object->visibility = *stated->second.visibility;
      if (stated->second.in_frame) object->in_frame = *stated->second.in_frame;
    }
    objects.push_back(std::move(*object));
  }
  return objects;
}

}  // namespace

ImportResult ImportCollection(const std::string& format,
                              const fs::path& source,
                              const fs::path& output,
                              const ImportOptions& options,
                              bool force) {
  std::unique_ptr<Importer> importer = MakeImporter(format);
  std::error_code ec;
  if (!fs::exists(source, ec)) throw Error("source does not exist", Location(source.string()));
  RefuseOverlap(source, output);
  RefuseToOverwrite(output, force);
  const SourceDescription description =
      Guarded(source, std::nullopt, [&] { return importer->Open(source, options); });
  if (description.frame_count < 1)
    throw Error("the source has no frames", Location(source.string()));

  auto provides = [&](const char* semantic) {
    return std::count(description.semantics.begin(), description.semantics.end(), semantic) != 0;
  };
  const bool has_depth = provides("depth");
  // A source with only some passes imports what is there (docs/import.md,
  // "Import what is there"); the layers it lacks are named once, here.
  const bool has_ids = provides("instanceid");
  ImportResult result;
  result.warnings = description.warnings;
  std::vector<std::string> lacking;
  for (const char* semantic : {"rgb", "depth", "instanceid", "classid"})
    if (!provides(semantic)) lacking.emplace_back(semantic);
  if (!lacking.empty())
    result.warnings.push_back(
        "the source has no " + Join(lacking, ", ") + " pass: the collection holds the layers " +
        "that exist (" + Join(description.semantics, ", ") + (has_depth ? ", worldposition" : "") +
        ")" + (has_ids ? "" : "; per-object truth only as far as the source states it"));
  std::vector<std::string> semantics = description.semantics;
  std::map<std::string, std::string> origin = description.truth_origin;
  if (has_depth && !std::count(semantics.begin(), semantics.end(), "worldposition")) {
    semantics.push_back("worldposition");
    origin["worldposition"] = "derived";
  }
  // Per-object truth measured here on the imported id layer
  // (object_truth.h); the unoccluded pixels are those of the OBB.
  for (const char* field : {"bbox", "visible_pixels", "bbox_projected", "in_frame", "visibility"})
    origin.emplace(field, has_ids ? "derived" : "absent");
  for (const std::string& semantic : StandardLayerSemantics()) {
    if (!std::count(semantics.begin(), semantics.end(), semantic))
      origin.emplace(semantic, "absent");
  }

  CollectionHeader header;
  header.provenance.generator = "lsds import";
  header.provenance.generator_version = LSDS_VERSION;
  header.provenance.import = {{"format", importer->name()},
                              {"source", Utf8Escaped(fs::absolute(source).string())},
                              {"source_conventions", description.source_conventions},
                              {"truth_origin", origin}};
  header.classes = description.classes;
  for (const std::string& semantic : semantics)
    header.layers.push_back(StandardLayer(semantic, description.depth_kind));
  ApplyLayerLayouts(options.layouts, &header);
  header.metadata = {{kMetadataFile, false, "measured metadata, equal to truth"}};
  header.frame_count = description.frame_count;

  exr::SetEncoderSettings(1, 0);  // as lsds generate encodes (bench/README.md, bench_import)
  AtomicDirectory out(output, force);
  const fs::path& root = out.temp_path();
  for (const LayerInfo& layer : header.layers) fs::create_directories(root / layer.name);
  CollectionBuilder builder(root, header);
  for (int64_t k = 0; k < description.frame_count; ++k) {
    SourceFrame source_frame = Guarded(source, k, [&] { return importer->ReadFrame(k); });
    const Rigid3d cam_from_world = CamFromWorld(source_frame.camera);
    if (has_depth && !source_frame.flat.count("worldposition")) {
      // The rule of the residual worldposition layout
      // (libs/collection/worldposition_layout.h), so a derived layer stores as
      // zeros there.
      const exr::FlatImage& depth = source_frame.flat.at("depth");
      WorldPositionPrediction prediction;
      prediction.depth = depth.Get("Z").floats;
      prediction.width = depth.width();
      prediction.height = depth.height();
      prediction.depth_kind = description.depth_kind;
      prediction.camera = source_frame.camera;
      source_frame.flat["worldposition"] = PredictWorldPosition(prediction);
    }
    Frame frame;
    frame.index = k;
    frame.time = source_frame.time;
    frame.sequence = source_frame.sequence;
    frame.shot = source_frame.shot;
    frame.camera = source_frame.camera;
    frame.objects =
        MeasureFrameObjects(source_frame, source_frame.camera.intrinsics, cam_from_world);
    frame.files = WriteFrameLayers(
        root, header, k, frame.camera, {&source_frame.flat, nullptr, std::nullopt, std::nullopt});
    result.objects += static_cast<int64_t>(frame.objects.size());
    builder.Append(frame);
  }
  builder.Commit();
  out.Commit();
  result.frames = description.frame_count;
  return result;
}

}  // namespace lsds::import

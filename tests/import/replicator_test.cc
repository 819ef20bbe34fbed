// lsds import replicator: a Replicator BasicWriter folder synthesized from an
// analytic scene (replicator_fixture.h: a y-up stage in centimetres) imports
// with --up-axis y into a collection whose truth equals the scene's known
// truth, validates clean and converts to COCO masks equal to the fixture's
// instance segmentation and YOLO boxes equal to the truth.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <optional>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "importers/import_collection.h"
#include "libs/collection/collection_reader.h"
#include "libs/exr/flat_image.h"
#include "libs/util/error.h"
#include "libs/util/npy.h"
#include "tests/import/import_checks.h"
#include "tests/import/replicator_fixture.h"
#include "tests/test_util.h"

namespace lsds::testing {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::string FrameName(const char* stem, size_t k, const char* ext) {
  char text[96];
  std::snprintf(text, sizeof text, "%s_%04zu.%s", stem, k, ext);
  return text;
}

class ReplicatorImportTest : public ::testing::Test {
 protected:
  TempDir dir_;
  synth::Spec spec_ = ObliqueImportSpec();
};

TEST_F(ReplicatorImportTest, TruthEqualsTheAnalyticScene) {
  const fs::path folder = dir_ / "replicator";
  WriteReplicatorFixture(folder, spec_);
  const fs::path out = dir_ / "collection";
  import::ImportOptions options;
  options.up_axis = "y";
  import::ImportCollection("replicator", folder, out, options, false);
  const CollectionReader reader(out);
  std::vector<Frame> frames;
  reader.ForEachFrame([&](const Frame& f) { frames.push_back(f); });
  ASSERT_EQ(frames.size(), spec_.cam_from_world.size());
  for (size_t k = 0; k < frames.size(); ++k) {
    const synth::RenderedFrame truth = synth::RenderFrame(spec_, static_cast<int>(k));
    const Frame& frame = frames[k];
    SCOPED_TRACE("frame " + std::to_string(k));
    // Row-vector view matrix, OpenGL camera, y-up stage in cm -> OpenCV, ENU m.
    ExpectCameraNear(frame.camera, truth.truth.camera, 1e-12, 1e-12);
    ASSERT_EQ(frame.objects.size(), truth.truth.objects.size());
    for (size_t i = 0; i < frame.objects.size(); ++i) {
      const ObjectTruth& got = frame.objects[i];
      const ObjectTruth& want = truth.truth.objects[i];
      EXPECT_EQ(got.instance_id, want.instance_id);
      EXPECT_EQ(got.class_id, want.class_id - 1);  // no "ground" class here
      // bounding_box_3d records are float32 (in cm): within their precision.
      ExpectObjectNear(got, want, 1e-6);
    }
    // The writer's own tight 2D boxes (inclusive pixel indices) are the
    // imported boxes, derived again from the instance layer.
    const fs::path tight = folder / FrameName("bounding_box_2d_tight", k, "npy");
    const NpyArray boxes = ReadNpy(tight);
    ASSERT_EQ(boxes.size(),
              static_cast<int64_t>(std::count_if(frame.objects.begin(),
                                                 frame.objects.end(),
                                                 [](const ObjectTruth& o) { return o.bbox; })));
    for (int64_t row = 0; row < boxes.size(); ++row) {
      const ObjectTruth* object = nullptr;
      for (const ObjectTruth& o : frame.objects)
        if (o.bbox && object == nullptr && o.bbox->x0 == boxes.Get(row, boxes.Field("x_min", "")) &&
            o.bbox->y0 == boxes.Get(row, boxes.Field("y_min", "")))
          object = &o;
      ASSERT_NE(object, nullptr) << "row " << row;
      EXPECT_EQ(object->bbox->x1, boxes.Get(row, boxes.Field("x_max", "")) + 1);
      EXPECT_EQ(object->bbox->y1, boxes.Get(row, boxes.Field("y_max", "")) + 1);
    }
    const auto read = [&](const std::string& layer) {
      return exr::ReadFlatExr(reader.LayerPath(frame, layer));
    };
    EXPECT_EQ(read("instanceid").Get("id").uints, TargetIds(truth));
    // float32 centimetres back to metres.
    const std::vector<float> depth = read("depth").Get("Z").floats;
    const std::vector<float>& want = truth.flat.at("depth").Get("Z").floats;
    // Read through the collection's reader: X, Y, Z whatever the layer's layout.
    const exr::FlatImage position = reader.ReadFlatLayer(frame, "worldposition", {"X", "Y", "Z"});
    const exr::FlatImage& want_position = truth.flat.at("worldposition");
    for (size_t p = 0; p < depth.size(); ++p) {
      if (!std::isfinite(want[p])) {
        EXPECT_TRUE(std::isinf(depth[p]));
        continue;
      }
      EXPECT_NEAR(depth[p], want[p], 2e-7 * want[p]);
      for (const char* c : {"X", "Y", "Z"})
        EXPECT_NEAR(position.Get(c).floats[p], want_position.Get(c).floats[p], 4e-6 * want[p]);
    }
  }
  const json header = json::parse(ReadText(out / "collection.json"));
  const json& origin = header["provenance"]["import"]["truth_origin"];
  EXPECT_EQ(origin["obb"], "imported");
  EXPECT_EQ(origin["bundle"], "absent");
}

TEST_F(ReplicatorImportTest, ValidatesCleanAndConverts) {
  const fs::path folder = dir_ / "replicator";
  WriteReplicatorFixture(folder, spec_);
  ExpectImportValidatesAndConverts(
      "replicator",
      folder,
      dir_.path(),
      spec_.width,
      spec_.height,
      [&](int k) { return TargetIds(synth::RenderFrame(spec_, k)); },
      "--up-axis y");
}

// Two render products of the spec's first two frames in `layout` import as two sequences named
// after the products, frame by frame equal to the single-product import.
void ExpectTwoProductsImport(const fs::path& dir, ReplicatorLayout layout) {
  synth::Spec spec = ObliqueImportSpec();
  spec.cam_from_world.resize(2);
  const fs::path root = dir / "replicator";
  layout.products = {"Replicator", "Replicator_01"};
  WriteReplicatorFixture(root, spec, layout);
  const fs::path out = ExpectImportValidatesAndConverts(
      "replicator",
      root,
      dir,
      spec.width,
      spec.height,
      [&](int k) { return TargetIds(synth::RenderFrame(spec, k % 2)); },
      "--up-axis y");
  std::vector<Frame> frames;
  CollectionReader(out).ForEachFrame([&](const Frame& f) { frames.push_back(f); });
  ASSERT_EQ(frames.size(), 4u);
  for (size_t k = 0; k < frames.size(); ++k) {
    SCOPED_TRACE("frame " + std::to_string(k));
    EXPECT_EQ(frames[k].sequence, k < 2 ? "Replicator" : "Replicator_01");
    const synth::RenderedFrame truth = synth::RenderFrame(spec, static_cast<int>(k % 2));
    ExpectCameraNear(frames[k].camera, truth.truth.camera, 1e-12, 1e-12);
    ASSERT_EQ(frames[k].objects.size(), truth.truth.objects.size());
    for (size_t i = 0; i < frames[k].objects.size(); ++i)
      ExpectObjectNear(frames[k].objects[i], truth.truth.objects[i], 1e-6);
  }
}

// Several render products: BasicWriter.write() puts each product's files in
// <product>/<annotator>/ (the default, use_common_output_dir=False).
TEST_F(ReplicatorImportTest, SeveralRenderProductsAreOneSequenceEach) {
  ExpectTwoProductsImport(dir_.path(), {});
  EXPECT_TRUE(fs::exists(dir_ / "replicator" / "Replicator_01" / "bounding_box_3d" /
                         "bounding_box_3d_0001.npy"));
}

// use_common_output_dir=True: <annotator>/<product>_<file> (rgb/Replicator_01_rgb_0000.png).
TEST_F(ReplicatorImportTest, TheCommonOutputDirLayoutImports) {
  ReplicatorLayout layout;
  layout.common_output_dir = true;
  ExpectTwoProductsImport(dir_.path(), layout);
  EXPECT_TRUE(fs::exists(dir_ / "replicator" / "rgb" / "Replicator_01_rgb_0001.png"));
}

// on_time triggers prefix the frame number with their counts (rgb_1_0000.png); the counts name
// the sequence.
TEST_F(ReplicatorImportTest, OnTimeTriggerNamesImport) {
  synth::Spec spec = spec_;
  spec.cam_from_world.resize(2);
  const fs::path folder = dir_ / "replicator";
  ReplicatorLayout layout;
  layout.trigger_prefix = "1_";
  WriteReplicatorFixture(folder, spec, layout);
  ASSERT_TRUE(fs::exists(folder / "rgb_1_0001.png"));
  const fs::path out = ExpectImportValidatesAndConverts(
      "replicator",
      folder,
      dir_.path(),
      spec.width,
      spec.height,
      [&](int k) { return TargetIds(synth::RenderFrame(spec, k)); },
      "--up-axis y");
  std::vector<Frame> frames;
  CollectionReader(out).ForEachFrame([&](const Frame& f) { frames.push_back(f); });
  ASSERT_EQ(frames.size(), 2u);
  for (size_t k = 0; k < frames.size(); ++k) {
    EXPECT_EQ(frames[k].sequence, "replicator#1");
    ExpectCameraNear(
        frames[k].camera, synth::RenderFrame(spec, static_cast<int>(k)).truth.camera, 1e-12, 1e-12);
  }
}

// Without instance segmentation (rgb, camera_params and 3D boxes, as in real captures that
// turn it off): the objects are the 3D boxes, their boxes the writer's bounding_box_2d_tight,
// their visibility 1 - occlusionRatio; no id layers.
TEST_F(ReplicatorImportTest, WithoutInstanceSegmentationTheBoxesAreTheObjects) {
  const fs::path folder = dir_ / "replicator";
  ReplicatorLayout layout;
  layout.instance_segmentation = false;
  WriteReplicatorFixture(folder, spec_, layout);
  const fs::path out = dir_ / "collection";
  const CommandResult imported = RunCommandLine(
      LsdsBinary() + " import replicator " + folder.string() + " --up-axis y -o " + out.string());
  ASSERT_EQ(imported.exit_code, 0) << imported.output;
  EXPECT_NE(imported.output.find("warning: no instance_segmentation"), std::string::npos)
      << imported.output;
  const CommandResult validate =
      RunCommandLine(LsdsBinary() + " validate --fail-on warning " + out.string());
  EXPECT_EQ(validate.exit_code, 0) << validate.output;
  const CollectionReader reader(out);
  EXPECT_EQ(reader.header().FindLayerBySemantic("instanceid"), nullptr);
  std::vector<Frame> frames;
  reader.ForEachFrame([&](const Frame& f) { frames.push_back(f); });
  ASSERT_EQ(frames.size(), spec_.cam_from_world.size());
  int64_t boxes = 0;
  double max_visibility_error = 0;
  for (size_t k = 0; k < frames.size(); ++k) {
    SCOPED_TRACE("frame " + std::to_string(k));
    const synth::RenderedFrame truth = synth::RenderFrame(spec_, static_cast<int>(k));
    ExpectCameraNear(frames[k].camera, truth.truth.camera, 1e-12, 1e-12);
    ASSERT_EQ(frames[k].objects.size(), truth.truth.objects.size());
    for (size_t i = 0; i < frames[k].objects.size(); ++i) {
      const ObjectTruth& got = frames[k].objects[i];
      const ObjectTruth& want = truth.truth.objects[i];
      EXPECT_EQ(got.instance_id, want.instance_id);
      EXPECT_EQ(got.bbox, want.bbox);  // the tight box, exact
      boxes += got.bbox.has_value();
      ASSERT_EQ(got.bbox_projected.has_value(), want.bbox_projected.has_value());
      if (want.bbox_projected) {  // from the float32 OBB
        for (double d : {got.bbox_projected->x0 - want.bbox_projected->x0,
                         got.bbox_projected->y1 - want.bbox_projected->y1}) {
          EXPECT_LT(std::abs(d), 1e-3);
        }
      }
      if (want.visible_pixels > 0)  // occlusionRatio is float32
        max_visibility_error =
            std::max(max_visibility_error, std::abs(got.visibility - want.visibility));
      EXPECT_LT((got.obb->center - want.obb->center).norm(), 1e-6);
    }
  }
  EXPECT_GT(boxes, 0);
  EXPECT_LT(max_visibility_error, 1e-7);
  const json header = json::parse(ReadText(out / "collection.json"));
  const json& origin = header["provenance"]["import"]["truth_origin"];
  EXPECT_EQ(origin["bbox"], "imported");
  EXPECT_EQ(origin["visibility"], "imported");
  EXPECT_EQ(origin["visible_pixels"], "absent");
  // COCO's masks need the id layer: refused with the reason.
  const CommandResult coco =
      RunCommandLine(LsdsBinary() + " convert " + out.string() + " --to coco --images none -o " +
                     (dir_ / "coco").string());
  EXPECT_NE(coco.exit_code, 0);
  EXPECT_NE(coco.output.find("no instanceid layer"), std::string::npos) << coco.output;
}

// A prim with a tight 2D box and no 3D box (a semantic filter leaving the crate out of
// bounding_box_3d) is an object without a 3D box (format.md "Objects without a 3D box"): no obb
// and no projected box; with instance segmentation its box and pixel count are measured on the
// id layer and equal the writer's bounding_box_2d_tight record, its visibility is
// 1 - occlusionRatio of that record, in_frame not measured (1). The collection validates clean
// and COCO exports the box at the record's coordinates, without an obb.
TEST_F(ReplicatorImportTest, APrimWithOnlyATightBoxIsAnObjectWithoutA3dBox) {
  const fs::path folder = dir_ / "replicator";
  ReplicatorLayout layout;
  layout.without_3d_box = {"crate#0"};
  WriteReplicatorFixture(folder, spec_, layout);
  const fs::path out = dir_ / "collection";
  const CommandResult imported = RunCommandLine(
      LsdsBinary() + " import replicator " + folder.string() + " --up-axis y -o " + out.string());
  ASSERT_EQ(imported.exit_code, 0) << imported.output;
  EXPECT_NE(imported.output.find("bounding_box_2d_tight box(es) of 'crate' have no "
                                 "bounding_box_3d box: objects without a 3D box"),
            std::string::npos)
      << imported.output;
  const fs::path annotations = ExpectValidatesAndConvertsToCoco(out, dir_ / "coco");
  ASSERT_FALSE(annotations.empty());
  const json coco = json::parse(ReadText(annotations));
  std::map<int64_t, int> frame_of_image;
  for (const json& image : coco["images"])
    frame_of_image[image["id"].get<int64_t>()] =
        std::stoi(fs::path(image["file_name"].get<std::string>()).stem().string());

  const CollectionReader reader(out);
  std::vector<Frame> frames;
  reader.ForEachFrame([&](const Frame& f) { frames.push_back(f); });
  ASSERT_EQ(frames.size(), spec_.cam_from_world.size());
  const std::string crate = "/World/crate#0";
  int crates = 0;
  for (size_t k = 0; k < frames.size(); ++k) {
    SCOPED_TRACE("frame " + std::to_string(k));
    const synth::RenderedFrame truth = synth::RenderFrame(spec_, static_cast<int>(k));
    // The source's own annotation of the crate: its bounding_box_2d_tight record.
    const NpyArray boxes = ReadNpy(folder / FrameName("bounding_box_2d_tight", k, "npy"));
    const json prims =
        json::parse(ReadText(folder / FrameName("bounding_box_2d_tight_prim_paths", k, "json")));
    std::optional<int64_t> row;
    for (size_t r = 0; r < prims.size(); ++r)
      if (prims[r] == crate) row = static_cast<int64_t>(r);
    const ObjectTruth* got = nullptr;
    for (const ObjectTruth& o : frames[k].objects)
      if (o.name == crate) got = &o;
    const ObjectTruth* want = nullptr;
    for (const ObjectTruth& o : truth.truth.objects)
      if (o.name == "crate#0") want = &o;
    ASSERT_EQ(got != nullptr, row.has_value());  // an object exactly where the writer boxed it
    // The other objects keep their 3D boxes, as without the filter.
    EXPECT_EQ(frames[k].objects.size(),
              truth.truth.objects.size() - (want != nullptr && !row.has_value() ? 1 : 0));
    for (const ObjectTruth& o : frames[k].objects)
      EXPECT_EQ(o.obb.has_value(), o.name != crate) << o.name;
    if (!row) continue;
    ++crates;
    ASSERT_NE(want, nullptr);
    const double x_min = boxes.Get(*row, boxes.Field("x_min", ""));
    const double y_min = boxes.Get(*row, boxes.Field("y_min", ""));
    const double x_max = boxes.Get(*row, boxes.Field("x_max", ""));
    const double y_max = boxes.Get(*row, boxes.Field("y_max", ""));
    const double occluded = boxes.Get(*row, boxes.Field("occlusionRatio", ""));
    ASSERT_TRUE(got->bbox.has_value());
    EXPECT_EQ(*got->bbox, (Box2d{x_min, y_min, x_max + 1, y_max + 1}));
    EXPECT_EQ(got->visible_pixels, want->visible_pixels);
    EXPECT_EQ(got->class_id, want->class_id - 1);  // no "ground" class here
    EXPECT_FALSE(got->bbox_projected.has_value());
    EXPECT_NEAR(got->visibility, 1 - occluded, 1e-15);
    EXPECT_NEAR(got->visibility, want->visibility, 1e-7);  // float32 occlusionRatio
    EXPECT_EQ(got->in_frame, 1);
    // COCO: [x, y, width, height] of the record's inclusive pixel indices, no obb.
    int found = 0;
    for (const json& a : coco["annotations"]) {
      if (frame_of_image.at(a["image_id"].get<int64_t>()) != static_cast<int>(k) ||
          a["lsds"]["instance_id"] != got->instance_id)
        continue;
      ++found;
      EXPECT_EQ(a["bbox"], json::array({x_min, y_min, x_max - x_min + 1, y_max - y_min + 1}));
      EXPECT_FALSE(a["lsds"].contains("obb"));
    }
    EXPECT_EQ(found, 1);
  }
  EXPECT_GE(crates, 3);
}

// The same without instance segmentation: the crate's box is the record's own (no id layer to
// measure one on, so no visible_pixels), its class from bounding_box_2d_tight_labels; the
// collection validates clean and converts to YOLO.
TEST_F(ReplicatorImportTest, WithoutInstanceSegmentationATightBoxAloneIsAnObjectToo) {
  const fs::path folder = dir_ / "replicator";
  ReplicatorLayout layout;
  layout.instance_segmentation = false;
  layout.without_3d_box = {"crate#0"};
  WriteReplicatorFixture(folder, spec_, layout);
  const fs::path out = dir_ / "collection";
  const CommandResult imported = RunCommandLine(
      LsdsBinary() + " import replicator " + folder.string() + " --up-axis y -o " + out.string());
  ASSERT_EQ(imported.exit_code, 0) << imported.output;
  const CommandResult validate =
      RunCommandLine(LsdsBinary() + " validate --fail-on warning " + out.string());
  EXPECT_EQ(validate.exit_code, 0) << validate.output;
  const CommandResult yolo =
      RunCommandLine(LsdsBinary() + " convert " + out.string() + " --to yolo --images none -o " +
                     (dir_ / "yolo").string());
  EXPECT_EQ(yolo.exit_code, 0) << yolo.output;
  const CollectionReader reader(out);
  std::vector<Frame> frames;
  reader.ForEachFrame([&](const Frame& f) { frames.push_back(f); });
  ASSERT_EQ(frames.size(), spec_.cam_from_world.size());
  int crates = 0;
  for (size_t k = 0; k < frames.size(); ++k) {
    SCOPED_TRACE("frame " + std::to_string(k));
    const NpyArray boxes = ReadNpy(folder / FrameName("bounding_box_2d_tight", k, "npy"));
    const json prims =
        json::parse(ReadText(folder / FrameName("bounding_box_2d_tight_prim_paths", k, "json")));
    std::optional<int64_t> row;
    for (size_t r = 0; r < prims.size(); ++r)
      if (prims[r] == "/World/crate#0") row = static_cast<int64_t>(r);
    const ObjectTruth* got = nullptr;
    for (const ObjectTruth& o : frames[k].objects)
      if (o.name == "/World/crate#0") got = &o;
    ASSERT_EQ(got != nullptr, row.has_value());
    if (!row) continue;
    ++crates;
    const double x_min = boxes.Get(*row, boxes.Field("x_min", ""));
    const double y_min = boxes.Get(*row, boxes.Field("y_min", ""));
    EXPECT_EQ(got->bbox,
              (Box2d{x_min,
                     y_min,
                     boxes.Get(*row, boxes.Field("x_max", "")) + 1,
                     boxes.Get(*row, boxes.Field("y_max", "")) + 1}));
    EXPECT_FALSE(got->obb.has_value());
    EXPECT_FALSE(got->bbox_projected.has_value());
    EXPECT_EQ(got->visible_pixels, 0);
    EXPECT_EQ(got->class_id, 2u);  // "crate": classes box, crate
    EXPECT_NEAR(got->visibility, 1 - boxes.Get(*row, boxes.Field("occlusionRatio", "")), 1e-15);
  }
  EXPECT_GE(crates, 3);
}

// A prim with a negative scale (three wall wires of the warehouse stage in real BasicWriter
// output): the record's transform is mirrored, the box is the same set of points.
TEST_F(ReplicatorImportTest, AMirroredBoxTransformIsTheSameBox) {
  synth::Spec spec = spec_;
  spec.cam_from_world.resize(1);
  const fs::path folder = dir_ / "replicator";
  WriteReplicatorFixture(folder, spec);
  import::ImportOptions options;
  options.up_axis = "y";
  import::ImportCollection("replicator", folder, dir_ / "plain", options, false);
  const fs::path boxes_path = folder / "bounding_box_3d_0000.npy";
  NpyArray boxes = ReadNpy(boxes_path);
  const NpyField& transform = boxes.Field("transform", "");
  for (int row = 0; row < boxes.size(); ++row)
    for (int r = 0; r < 3; ++r) {  // the row-vector matrix's first row: local x in the stage
      float v = 0;
      char* at = boxes.data.data() + row * boxes.record_size + transform.offset + r * 4;
      std::memcpy(&v, at, 4);
      v = -v;
      std::memcpy(at, &v, 4);
    }
  WriteNpy(boxes_path,
           "[('semanticId', '<u4'), ('x_min', '<f4'), ('y_min', '<f4'), ('z_min', '<f4'), "
           "('x_max', '<f4'), ('y_max', '<f4'), ('z_max', '<f4'), ('transform', '<f4', (4, 4)), "
           "('occlusionRatio', '<f4')]",
           boxes.shape,
           boxes.data);
  import::ImportCollection("replicator", folder, dir_ / "mirrored", options, false);
  std::vector<Frame> plain, mirrored;
  CollectionReader(dir_ / "plain").ForEachFrame([&](const Frame& f) { plain.push_back(f); });
  CollectionReader(dir_ / "mirrored").ForEachFrame([&](const Frame& f) { mirrored.push_back(f); });
  ASSERT_EQ(plain.size(), 1u);
  ASSERT_EQ(mirrored[0].objects.size(), plain[0].objects.size());
  for (size_t i = 0; i < plain[0].objects.size(); ++i) {
    const OrientedBox& a = *plain[0].objects[i].obb;
    const OrientedBox& b = *mirrored[0].objects[i].obb;
    EXPECT_LT((a.center - b.center).norm(), 1e-9);
    const auto ca = a.Corners();
    const auto cb = b.Corners();
    for (const Eigen::Vector3d& corner : ca) {
      double nearest = 1e9;
      for (const Eigen::Vector3d& other : cb) nearest = std::min(nearest, (corner - other).norm());
      EXPECT_LT(nearest, 1e-6);
    }
  }
}

TEST_F(ReplicatorImportTest, TheWrongUpAxisGivesAnotherWorldNotACrash) {
  // Without --up-axis y the stage is read as z up: the same images, the world
  // turned; the import still succeeds (the files cannot tell).
  synth::Spec spec = spec_;
  spec.cam_from_world.resize(1);
  const fs::path folder = dir_ / "replicator";
  WriteReplicatorFixture(folder, spec);
  const fs::path out = dir_ / "collection";
  import::ImportCollection("replicator", folder, out, {}, false);
  const CollectionReader reader(out);
  reader.ForEachFrame([&](const Frame& f) {
    EXPECT_GT((f.camera.cam_from_world_rotation -
               synth::RenderFrame(spec, 0).truth.camera.cam_from_world_rotation)
                  .norm(),
              0.5);
  });
}

TEST_F(ReplicatorImportTest, AColourMissingFromTheMappingNamesThePixel) {
  synth::Spec spec = spec_;
  spec.cam_from_world.resize(1);
  const fs::path folder = dir_ / "replicator";
  WriteReplicatorFixture(folder, spec);
  json mapping = json::parse(ReadText(folder / "instance_segmentation_mapping_0000.json"));
  mapping.erase("(0, 0, 0, 255)");
  std::ofstream(folder / "instance_segmentation_mapping_0000.json") << mapping.dump();
  const CommandResult result =
      RunCommandLine(LsdsBinary() + " import replicator " + folder.string() + " --up-axis y -o " +
                     (dir_ / "out").string());
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.output.find("instance_segmentation_0000.png"), std::string::npos)
      << result.output;
  EXPECT_NE(result.output.find("(0, 0, 0, 255)"), std::string::npos) << result.output;
  EXPECT_FALSE(fs::exists(dir_ / "out"));
}

TEST_F(ReplicatorImportTest, ATruncatedNpyIsALocatedError) {
  synth::Spec spec = spec_;
  spec.cam_from_world.resize(1);
  const fs::path folder = dir_ / "replicator";
  WriteReplicatorFixture(folder, spec);
  const fs::path depth = folder / "distance_to_image_plane_0000.npy";
  const std::string bytes = ReadText(depth);
  std::ofstream(depth, std::ios::binary) << bytes.substr(0, bytes.size() - 7);
  const CommandResult result =
      RunCommandLine(LsdsBinary() + " import replicator " + folder.string() + " --up-axis y -o " +
                     (dir_ / "out").string());
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.output.find("distance_to_image_plane_0000.npy"), std::string::npos)
      << result.output;
  EXPECT_NE(result.output.find("header says"), std::string::npos) << result.output;
}

}  // namespace
}  // namespace lsds::testing

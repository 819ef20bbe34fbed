#include "tests/import/replicator_fixture.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "libs/util/npy.h"
#include "tests/import/fixture_images.h"

namespace lsds::testing {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {
// BasicWriter's file names: f"{stem}_{self._sequence_id}{self._frame_id:0{padding}}.{ext}",
// the sequence id holding the on_time triggers' counts ("1_").
std::string Name(const char* stem, const std::string& trigger_prefix, int k, const char* ext) {
  char text[96];
  std::snprintf(text, sizeof text, "%s_%s%04d.%s", stem, trigger_prefix.c_str(), k, ext);
  return text;
}
template <typename T>
void Put(std::string* bytes, T value) {
  char raw[sizeof(T)];
  std::memcpy(raw, &value, sizeof(T));
  bytes->append(raw, sizeof(T));
}
// A column-vector 4x4 matrix as USD stores it: row vectors, so its transpose,
// row-major.
json RowMajorTransposed(const Eigen::Matrix4d& m) {
  json out = json::array();
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) out.push_back(m(c, r));
  return out;
}
std::string ColourKey(const cv::Vec4b& rgba) {
  return "(" + std::to_string(rgba[0]) + ", " + std::to_string(rgba[1]) + ", " +
         std::to_string(rgba[2]) + ", " + std::to_string(rgba[3]) + ")";
}
}  // namespace

void WriteReplicatorFixture(const fs::path& folder,
                            const synth::Spec& spec,
                            const ReplicatorLayout& layout) {
  fs::create_directories(folder);
  // One product: every file in `folder`. Several: BasicWriter.write() puts each product's
  // files in os.path.join(render_product_name, annotator_name), the annotator's name without
  // its "_fast" suffix.
  std::string product;
  // With use_common_output_dir: os.path.join(annotator_name, render_product_name) + "_".
  const auto at = [&](const char* annotator, const std::string& name) {
    if (layout.products.empty()) return folder / name;
    if (layout.common_output_dir) {
      fs::create_directories(folder / annotator);
      return folder / annotator / (product + "_" + name);
    }
    const fs::path dir = folder / product / annotator;
    fs::create_directories(dir);
    return dir / name;
  };
  const std::string& prefix = layout.trigger_prefix;
  const int w = spec.width, h = spec.height;
  const double mpu = kReplicatorMetersPerUnit;
  // Stage (y up) from ENU: the inverse of the importer's (x, -z, y).
  Eigen::Matrix3d enu_from_stage;
  enu_from_stage << 1, 0, 0, 0, 0, -1, 0, 1, 0;
  const Eigen::Matrix3d stage_from_enu = enu_from_stage.transpose();
  const Eigen::Matrix3d gl_from_cv = Eigen::Vector3d(1, -1, -1).asDiagonal();
  // Classes by label, semanticId = position in this list.
  std::vector<std::string> labels;
  for (const ClassInfo& c : spec.classes)
    if (c.name != "ground") labels.push_back(c.name);
  auto label_of = [&](uint32_t class_id) {
    for (const ClassInfo& c : spec.classes)
      if (c.id == class_id) return c.name;
    return std::string();
  };
  auto semantic_id = [&](const std::string& label) {
    return static_cast<uint32_t>(std::find(labels.begin(), labels.end(), label) - labels.begin());
  };
  json labels_json = json::object();
  for (size_t s = 0; s < labels.size(); ++s)
    labels_json[std::to_string(s)] = {{"class", labels[s]}};
  const cv::Vec4b background(0, 0, 0, 0), unlabelled(0, 0, 0, 255);

  const std::vector<std::string> products =
      layout.products.empty() ? std::vector<std::string>{""} : layout.products;
  for (const std::string& product_name : products)
    for (int k = 0; k < static_cast<int>(spec.cam_from_world.size()); ++k) {
      product = product_name;
      const synth::RenderedFrame frame = synth::RenderFrame(spec, k);
      const CameraTruth& camera = frame.truth.camera;
      const PinholeCamera& in = camera.intrinsics;
      Eigen::Matrix4d view = Eigen::Matrix4d::Identity();
      view.topLeftCorner<3, 3>() = gl_from_cv * camera.cam_from_world_rotation * enu_from_stage;
      view.topRightCorner<3, 1>() = gl_from_cv * camera.cam_from_world_translation / mpu;
      const double n = 1, f = 1e6;
      Eigen::Matrix4d projection = Eigen::Matrix4d::Zero();
      projection(0, 0) = 2 * in.fx / w;
      projection(1, 1) = 2 * in.fy / h;
      projection(0, 2) = 1 - 2 * in.cx / w;
      projection(1, 2) = 2 * in.cy / h - 1;
      projection(2, 2) = -(f + n) / (f - n);
      projection(2, 3) = -2 * f * n / (f - n);
      projection(3, 2) = -1;
      const double focal_mm = 18.15;
      const double aperture_mm = focal_mm * w / in.fx;
      const json params = {{"cameraAperture", {aperture_mm, aperture_mm * h / w}},
                           {"cameraApertureOffset", {0.0, 0.0}},
                           {"cameraFisheyeLensP", json::array()},
                           {"cameraFisheyeLensS", json::array()},
                           {"cameraFisheyeMaxFOV", 0.0},
                           {"cameraFisheyeNominalHeight", 0},
                           {"cameraFisheyeNominalWidth", 0},
                           {"cameraFisheyeOpticalCentre", {0.0, 0.0}},
                           {"cameraFisheyePolynomial", {0.0, 0.0, 0.0, 0.0, 0.0}},
                           {"cameraFocalLength", focal_mm},
                           {"cameraFocusDistance", 400.0},
                           {"cameraFStop", 0.0},
                           {"cameraModel", "pinhole"},
                           {"cameraNearFar", {n, f}},
                           {"cameraProjection", RowMajorTransposed(projection)},
                           {"cameraViewTransform", RowMajorTransposed(view)},
                           {"metersPerSceneUnit", mpu},
                           {"renderProductResolution", {w, h}}};
      std::ofstream(at("camera_params", Name("camera_params", prefix, k, "json")))
          << params.dump(2);

      // RGB, distance to the image plane (scene units), instance colours.
      cv::Mat colours(h, w, CV_8UC4);
      const exr::FlatImage& colour = frame.flat.at("rgb");
      const std::vector<float>& z = frame.flat.at("depth").Get("Z").floats;
      const std::vector<uint32_t>& ids = frame.flat.at("instanceid").Get("id").uints;
      std::string depth_bytes;
      json mapping = json::object(), semantics = json::object();
      mapping[ColourKey(background)] = "BACKGROUND";
      semantics[ColourKey(background)] = {{"class", "BACKGROUND"}};
      mapping[ColourKey(unlabelled)] = "UNLABELLED";
      semantics[ColourKey(unlabelled)] = {{"class", "UNLABELLED"}};
      for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
          const size_t p = colour.Index(i, j);
          Put(&depth_bytes,
              std::isfinite(z[p]) ? static_cast<float>(z[p] / mpu)
                                  : std::numeric_limits<float>::infinity());
          cv::Vec4b c = std::isfinite(z[p]) ? unlabelled : background;
          for (const synth::Box& box : spec.boxes)
            if (ids[p] == box.instance_id) {
              c = cv::Vec4b(static_cast<uint8_t>(40 * box.instance_id),
                            static_cast<uint8_t>(255 - 30 * box.instance_id),
                            static_cast<uint8_t>(90 + box.instance_id),
                            255);
              mapping[ColourKey(c)] = "/World/" + box.name;
              semantics[ColourKey(c)] = {{"class", label_of(box.class_id)}};
            }
          colours.at<cv::Vec4b>(j, i) = {c[2], c[1], c[0], c[3]};  // BGRA
        }
      cv::imwrite((at("rgb", Name("rgb", prefix, k, "png"))).string(), SrgbPng(colour, true));
      if (layout.instance_segmentation) {
        cv::imwrite(
            at("instance_segmentation", Name("instance_segmentation", prefix, k, "png")).string(),
            colours);
        std::ofstream(
            at("instance_segmentation", Name("instance_segmentation_mapping", prefix, k, "json")))
            << mapping.dump();
        std::ofstream(at("instance_segmentation",
                         Name("instance_segmentation_semantics_mapping", prefix, k, "json")))
            << semantics.dump();
      }
      WriteNpy(at("distance_to_image_plane", Name("distance_to_image_plane", prefix, k, "npy")),
               "'<f4'",
               {h, w},
               depth_bytes);

      // 3D boxes: a unit cube mesh (local extents +-0.5) scaled, rotated and
      // moved by the prim's row-vector local-to-world transform.
      std::string boxes3d, boxes2d;
      json prim_paths = json::array(), prim_paths_2d = json::array();
      int64_t boxes3d_count = 0;
      for (const synth::Box& box : spec.boxes) {
        const bool has_3d =
            std::find(layout.without_3d_box.begin(), layout.without_3d_box.end(), box.name) ==
            layout.without_3d_box.end();
        const OrientedBox obb = box.Obb();
        Eigen::Matrix4d world_from_local = Eigen::Matrix4d::Identity();
        world_from_local.topLeftCorner<3, 3>() =
            stage_from_enu * obb.world_from_box * (2 * obb.half_extents / mpu).asDiagonal();
        world_from_local.topRightCorner<3, 1>() = stage_from_enu * obb.center / mpu;
        // occlusionRatio: the occluded share of the object's pixels; -1 where the object is not
        // in view.
        float occluded = -1;
        for (const ObjectTruth& o : frame.truth.objects)
          if (o.instance_id == box.instance_id && o.visible_pixels > 0)
            occluded = static_cast<float>(1 - o.visibility);
        if (has_3d) {
          Put(&boxes3d, semantic_id(label_of(box.class_id)));
          for (float v : {-0.5f, -0.5f, -0.5f, 0.5f, 0.5f, 0.5f}) Put(&boxes3d, v);
          for (int r = 0; r < 4; ++r)
            for (int c = 0; c < 4; ++c) Put(&boxes3d, static_cast<float>(world_from_local(c, r)));
          Put(&boxes3d, occluded);
          prim_paths.push_back("/World/" + box.name);
          ++boxes3d_count;
        }
        // bounding_box_2d_tight: inclusive pixel indices of the visible pixels.
        for (const ObjectTruth& o : frame.truth.objects)
          if (o.instance_id == box.instance_id && o.bbox) {
            Put(&boxes2d, semantic_id(label_of(box.class_id)));
            Put(&boxes2d, static_cast<int32_t>(o.bbox->x0));
            Put(&boxes2d, static_cast<int32_t>(o.bbox->y0));
            Put(&boxes2d, static_cast<int32_t>(o.bbox->x1) - 1);
            Put(&boxes2d, static_cast<int32_t>(o.bbox->y1) - 1);
            Put(&boxes2d, static_cast<float>(1 - o.visibility));
            prim_paths_2d.push_back("/World/" + box.name);
          }
      }
      WriteNpy(at("bounding_box_3d", Name("bounding_box_3d", prefix, k, "npy")),
               "[('semanticId', '<u4'), ('x_min', '<f4'), ('y_min', '<f4'), "
               "('z_min', '<f4'), ('x_max', '<f4'), ('y_max', '<f4'), "
               "('z_max', '<f4'), ('transform', '<f4', (4, 4)), "
               "('occlusionRatio', '<f4')]",
               {boxes3d_count},
               boxes3d);
      std::ofstream(at("bounding_box_3d", Name("bounding_box_3d_labels", prefix, k, "json")))
          << labels_json.dump();
      std::ofstream(at("bounding_box_3d", Name("bounding_box_3d_prim_paths", prefix, k, "json")))
          << prim_paths.dump();
      WriteNpy(at("bounding_box_2d_tight", Name("bounding_box_2d_tight", prefix, k, "npy")),
               "[('semanticId', '<u4'), ('x_min', '<i4'), ('y_min', '<i4'), "
               "('x_max', '<i4'), ('y_max', '<i4'), ('occlusionRatio', '<f4')]",
               {static_cast<int64_t>(prim_paths_2d.size())},
               boxes2d);
      std::ofstream(
          at("bounding_box_2d_tight", Name("bounding_box_2d_tight_labels", prefix, k, "json")))
          << labels_json.dump();
      std::ofstream(
          at("bounding_box_2d_tight", Name("bounding_box_2d_tight_prim_paths", prefix, k, "json")))
          << prim_paths_2d.dump();
    }
}

}  // namespace lsds::testing

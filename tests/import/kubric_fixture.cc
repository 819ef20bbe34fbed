#include "tests/import/kubric_fixture.h"

#include <cmath>
#include <cstdio>
#include <fstream>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "importers/indexed_png.h"
#include "tests/import/fixture_images.h"

namespace lsds::testing {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {
std::string Name(const char* stem, int k, const char* ext) {
  char text[64];
  std::snprintf(text, sizeof text, "%s_%05d.%s", stem, k, ext);
  return text;
}
json Row(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }
}  // namespace

void WriteKubricFixture(const fs::path& scene, const synth::Spec& spec) {
  fs::create_directories(scene);
  const int w = spec.width, h = spec.height;
  const int frames = static_cast<int>(spec.cam_from_world.size());
  json positions = json::array(), quaternions = json::array();
  json instances = json::array();
  for (size_t b = 0; b < spec.boxes.size(); ++b) {
    const std::string& name = spec.boxes[b].name;
    instances.push_back({{"asset_id", name},
                         {"shape", name.substr(0, name.find('#'))},
                         {"bboxes_3d", json::array()}});
  }
  PinholeCamera intrinsics;
  for (int k = 0; k < frames; ++k) {
    const synth::RenderedFrame frame = synth::RenderFrame(spec, k);
    const CameraTruth& camera = frame.truth.camera;
    intrinsics = camera.intrinsics;
    // Blender camera axes: OpenCV's x, -y, -z.
    const Eigen::Matrix3d world_from_blender_cam =
        camera.cam_from_world_rotation.transpose() *
        Eigen::Vector3d(1, -1, -1).asDiagonal().toDenseMatrix();
    const Eigen::Quaterniond q(world_from_blender_cam);
    positions.push_back(
        Row(-(camera.cam_from_world_rotation.transpose() * camera.cam_from_world_translation)));
    quaternions.push_back({q.w(), q.x(), q.y(), q.z()});
    // core/objects.py bbox_3d: itertools.product over (min, max) of x, y, z.
    for (size_t b = 0; b < spec.boxes.size(); ++b) {
      const OrientedBox obb = spec.boxes[b].Obb();
      json corners = json::array();
      for (int ix = 0; ix < 2; ++ix)
        for (int iy = 0; iy < 2; ++iy)
          for (int iz = 0; iz < 2; ++iz) {
            const Eigen::Vector3d local(ix ? 1 : -1, iy ? 1 : -1, iz ? 1 : -1);
            corners.push_back(
                Row(obb.center + obb.world_from_box * local.cwiseProduct(obb.half_extents)));
          }
      instances[b]["bboxes_3d"].push_back(corners);
    }
    cv::Mat depth(h, w, CV_32FC1);
    import::IndexImage segmentation;
    segmentation.width = w, segmentation.height = h;
    segmentation.index.assign(static_cast<size_t>(w) * h, 0);
    const exr::FlatImage& colour = frame.flat.at("rgb");
    const std::vector<float>& z = frame.flat.at("depth").Get("Z").floats;
    const std::vector<uint32_t>& ids = frame.flat.at("instanceid").Get("id").uints;
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < w; ++i) {
        const size_t p = colour.Index(i, j);
        depth.at<float>(j, i) = std::isfinite(z[p]) ? z[p] : 1e10f;
        for (size_t b = 0; b < spec.boxes.size(); ++b)
          if (ids[p] == spec.boxes[b].instance_id)
            segmentation.index[static_cast<size_t>(j) * w + i] = static_cast<uint8_t>(b + 1);
      }
    cv::imwrite((scene / Name("rgba", k, "png")).string(), SrgbPng(frame.flat.at("rgb"), true));
    cv::imwrite((scene / Name("depth", k, "tiff")).string(), depth);
    // kb.write_palette_png with plotting.hls_palette(max + 1): any distinct
    // colours; the importer reads indices.
    std::vector<uint8_t> palette;
    for (size_t n = 0; n <= spec.boxes.size(); ++n)
      for (int c = 0; c < 3; ++c) palette.push_back(static_cast<uint8_t>((n * 67 + c * 101) % 256));
    import::WriteIndexedPng(scene / Name("segmentation", k, "png"), segmentation, palette);
  }
  json metadata = {
      {"flags", {{"resolution", w}, {"frame_end", frames}}},
      {"metadata",
       {{"resolution", {w, h}},
        {"frame_rate", 1.0 / spec.frame_interval},
        {"step_rate", 240},
        {"gravity", {0, 0, -10}},
        {"num_frames", frames},
        {"num_instances", spec.boxes.size()}}},
      {"camera",
       {{"focal_length", 35.0},
        {"sensor_width", 35.0 * w / intrinsics.fx},
        {"field_of_view", 2 * std::atan(0.5 * w / intrinsics.fx)},
        {"positions", positions},
        {"quaternions", quaternions},
        // PerspectiveCamera.intrinsics with width = height = 1.
        {"K",
         {{intrinsics.fx / w, 0.0, -0.5}, {0.0, -intrinsics.fy / h, -0.5}, {0.0, 0.0, -1.0}}}}},
      {"instances", instances}};
  std::ofstream(scene / "metadata.json") << metadata.dump(2);
  std::ofstream(scene / "data_ranges.json")
      << json({{"forward_flow", {{"min", 0.0}, {"max", 0.0}}},
               {"backward_flow", {{"min", 0.0}, {"max", 0.0}}}})
             .dump(2);
}

}  // namespace lsds::testing

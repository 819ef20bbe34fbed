#include "tests/import/bop_fixture.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "tests/import/fixture_images.h"

namespace lsds::testing {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {
std::string Stem(int id) {
  char text[16];
  std::snprintf(text, sizeof text, "%06d", id);
  return text;
}
json Flat(const Eigen::Matrix3d& m) {
  json out = json::array();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) out.push_back(m(r, c));
  return out;
}
json Flat(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

// The depth PNG's value of pixel p as BlenderProc's writer stores it
// (BopWriterUtility.py: depth_mm / depth_scale, then save_depth clips to
// 65535 and rounds): the sky and everything beyond the range are 65535.
uint16_t StoredDepthUnits(const synth::RenderedFrame& frame, size_t p) {
  const double units = frame.flat.at("depth").Get("Z").floats[p] * 1000.0 / kBopDepthScale;
  return static_cast<uint16_t>(std::round(std::min(units, 65535.0)));
}
}  // namespace

fs::path WriteBopFixture(const fs::path& dataset,
                         const synth::Spec& spec,
                         const BopWriterRule& rule) {
  const fs::path scene = dataset / "train_pbr" / "000000";
  for (const char* sub : {"rgb", "depth", "mask_visib"}) fs::create_directories(scene / sub);
  fs::create_directories(dataset / "models");
  json models = json::object();
  for (size_t b = 0; b < spec.boxes.size(); ++b) {
    const Eigen::Vector3d half = spec.boxes[b].half_extents * 1000.0;
    const double diameter = 2 * half.norm();
    models[std::to_string(b + 1)] = {{"diameter", diameter},
                                     {"min_x", -half.x()},
                                     {"min_y", -half.y()},
                                     {"min_z", -half.z()},
                                     {"size_x", 2 * half.x()},
                                     {"size_y", 2 * half.y()},
                                     {"size_z", 2 * half.z()}};
  }
  std::ofstream(dataset / "models" / "models_info.json") << models.dump(2);

  json cameras = json::object(), gts = json::object(), infos = json::object();
  const int w = spec.width, h = spec.height;
  for (int k = 0; k < static_cast<int>(spec.cam_from_world.size()); ++k) {
    const synth::RenderedFrame frame = synth::RenderFrame(spec, k);
    const CameraTruth& camera = frame.truth.camera;
    const PinholeCamera& in = camera.intrinsics;
    Eigen::Matrix3d K = Eigen::Matrix3d::Identity();
    K(0, 0) = in.fx, K(1, 1) = in.fy;
    K(0, 2) = in.cx - 0.5, K(1, 2) = in.cy - 0.5;  // pixel-centre convention
    const Eigen::Matrix3d& R = camera.cam_from_world_rotation;
    const Eigen::Vector3d& t = camera.cam_from_world_translation;
    cameras[std::to_string(k)] = {{"cam_K", Flat(K)},
                                  {"cam_R_w2c", Flat(R)},
                                  {"cam_t_w2c", Flat(Eigen::Vector3d(t * 1000.0))},
                                  {"depth_scale", kBopDepthScale}};
    json gt = json::array(), info = json::array();
    const std::vector<uint32_t>& ids = frame.flat.at("instanceid").Get("id").uints;
    for (size_t b = 0; b < spec.boxes.size(); ++b) {
      const OrientedBox obb = spec.boxes[b].Obb();
      gt.push_back({{"cam_R_m2c", Flat(Eigen::Matrix3d(R * obb.world_from_box))},
                    {"cam_t_m2c", Flat(Eigen::Vector3d((R * obb.center + t) * 1000.0))},
                    {"obj_id", b + 1}});
      cv::Mat mask(h, w, CV_8UC1, cv::Scalar(0));
      int visible = 0, all = 0;
      if (rule.bop19_delta_m) {
        // The object alone, and the bop19 test on distances along the ray.
        synth::Spec alone = spec;
        alone.ground = false;
        alone.boxes = {spec.boxes[b]};
        const synth::RenderedFrame own = synth::RenderFrame(alone, k);
        const std::vector<float>& own_depth = own.flat.at("depth").Get("Z").floats;
        for (int j = 0; j < h; ++j)
          for (int i = 0; i < w; ++i) {
            const size_t p = static_cast<size_t>(j) * w + i;
            if (!std::isfinite(own_depth[p])) continue;
            ++all;
            const double scale = in.RayThroughPixelCenter(i, j).norm();
            const double d_model = own_depth[p] * scale;
            const double d_test = StoredDepthUnits(frame, p) * kBopDepthScale / 1000.0 * scale;
            if (d_model - d_test <= *rule.bop19_delta_m || d_test == 0) {
              mask.at<uint8_t>(j, i) = 255;
              ++visible;
            }
          }
      } else {
        for (int j = 0; j < h; ++j)
          for (int i = 0; i < w; ++i)
            if (ids[static_cast<size_t>(j) * w + i] == spec.boxes[b].instance_id) {
              mask.at<uint8_t>(j, i) = 255;
              ++visible;
            }
      }
      cv::imwrite(
          (scene / "mask_visib" / (Stem(k) + "_" + Stem(static_cast<int>(b)) + ".png")).string(),
          mask);
      double visib_fract = 0;
      for (const ObjectTruth& o : frame.truth.objects)
        if (o.instance_id == spec.boxes[b].instance_id) visib_fract = o.visibility;
      if (rule.bop19_delta_m) visib_fract = all > 0 ? visible / static_cast<double>(all) : 0.0;
      info.push_back({{"px_count_visib", visible}, {"visib_fract", visib_fract}});
    }
    gts[std::to_string(k)] = gt;
    infos[std::to_string(k)] = info;
    const exr::FlatImage& colour = frame.flat.at("rgb");
    const cv::Mat rgb = SrgbPng(colour, false);
    cv::Mat depth(h, w, CV_16UC1);
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < w; ++i)
        depth.at<uint16_t>(j, i) = StoredDepthUnits(frame, colour.Index(i, j));
    cv::imwrite((scene / "rgb" / (Stem(k) + ".png")).string(), rgb);
    cv::imwrite((scene / "depth" / (Stem(k) + ".png")).string(), depth);
  }
  std::ofstream(scene / "scene_camera.json") << cameras.dump(2);
  std::ofstream(scene / "scene_gt.json") << gts.dump(2);
  std::ofstream(scene / "scene_gt_info.json") << infos.dump(2);
  return scene;
}

}  // namespace lsds::testing

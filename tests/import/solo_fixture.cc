#include "tests/import/solo_fixture.h"

#include <cmath>
#include <fstream>
#include <set>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "libs/exr/flat_image.h"
#include "tests/import/fixture_images.h"

namespace lsds::testing {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {
json Row(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }
json Xyzw(const Eigen::Matrix3d& r) {
  const Eigen::Quaterniond q(r);
  return {q.x(), q.y(), q.z(), q.w()};
}
}  // namespace

void WriteSoloFixture(const fs::path& dataset, const synth::Spec& spec, int split) {
  fs::create_directories(dataset);
  const int w = spec.width, h = spec.height;
  Eigen::Matrix3d unity_from_enu;  // swap y and z: its own inverse
  unity_from_enu << 1, 0, 0, 0, 0, 1, 0, 1, 0;
  const Eigen::Matrix3d unity_cam_from_cv = Eigen::Vector3d(1, -1, 1).asDiagonal();
  const Eigen::Matrix3d flip_z = Eigen::Vector3d(1, 1, -1).asDiagonal();
  json spec_json = json::array();
  for (const ClassInfo& c : spec.classes)
    if (c.name != "ground") spec_json.push_back({{"label_id", c.id}, {"label_name", c.name}});
  const json definitions = {
      {"annotationDefinitions",
       {{{"@type", "type.unity.com/unity.solo.InstanceSegmentationAnnotation"},
         {"id", "instance segmentation"},
         {"description", "Produces an instance segmentation image"},
         {"spec", spec_json}},
        {{"@type", "type.unity.com/unity.solo.BoundingBox3DAnnotation"},
         {"id", "bounding box 3D"},
         {"description", "Produces 3D bounding box ground truth data"},
         {"spec", spec_json}},
        {{"@type", "type.unity.com/unity.solo.DepthAnnotation"},
         {"id", "Depth"},
         {"description", "Generates a 32-bit depth image"}}}}};
  std::ofstream(dataset / "annotation_definitions.json") << definitions.dump(2);
  std::ofstream(dataset / "metadata.json") << json({{"unityVersion", "2022.3"},
                                                    {"perceptionVersion", "1.0.0"},
                                                    {"totalFrames", spec.cam_from_world.size()},
                                                    {"totalSequences", 2}})
                                                  .dump(2);
  std::ofstream(dataset / "sensor_definitions.json")
      << json({{"sensorDefinitions",
                {{{"@type", "type.unity.com/unity.solo.RGBCamera"},
                  {"id", "camera"},
                  {"modality", "camera"},
                  {"captureTriggerMode", "Scheduled"},
                  {"simulationDeltaTime", spec.frame_interval},
                  {"firstCaptureFrame", 0.0},
                  {"framesBetweenCaptures", 0}}}}})
             .dump(2);
  std::ofstream(dataset / "metric_definitions.json")
      << json({{"metricDefinitions", json::array()}}).dump(2);

  for (int k = 0; k < static_cast<int>(spec.cam_from_world.size()); ++k) {
    const int sequence = k < split ? 0 : 1;
    const int step = k < split ? k : k - split;
    const fs::path folder = dataset / ("sequence." + std::to_string(sequence));
    fs::create_directories(folder);
    const std::string prefix = "step" + std::to_string(step) + ".";
    const synth::RenderedFrame frame = synth::RenderFrame(spec, k);
    const CameraTruth& camera = frame.truth.camera;
    const PinholeCamera& in = camera.intrinsics;
    const Eigen::Matrix3d world_from_cv = camera.cam_from_world_rotation.transpose();
    const Eigen::Matrix3d world_from_unity_cam = unity_from_enu * world_from_cv * unity_cam_from_cv;
    const Eigen::Vector3d position =
        unity_from_enu * (-(world_from_cv * camera.cam_from_world_translation));
    const double n = 0.3, f = 1000;
    const json matrix = {2 * in.fx / w,
                         0.0,
                         0.0,
                         0.0,
                         2 * in.fy / h,
                         0.0,
                         1 - 2 * in.cx / w,
                         2 * in.cy / h - 1,
                         -(f + n) / (f - n)};

    cv::Mat colours(h, w, CV_8UC4);
    exr::FlatImage depth(w, h);
    for (const char* c : {"R", "G", "B", "A"}) depth.AddChannel(c, exr::PixelType::kFloat);
    const exr::FlatImage& colour = frame.flat.at("rgb");
    const std::vector<float>& z = frame.flat.at("depth").Get("Z").floats;
    const std::vector<uint32_t>& ids = frame.flat.at("instanceid").Get("id").uints;
    json instances = json::array();
    std::set<uint32_t> seen;
    auto colour_of = [](size_t b) {
      return cv::Vec4b(
          static_cast<uint8_t>(255 - 50 * b), static_cast<uint8_t>(30 + 60 * b), 200, 255);
    };
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < w; ++i) {
        const size_t p = colour.Index(i, j);
        const float d = std::isfinite(z[p]) ? z[p] : 0.0f;
        for (const char* c : {"R", "G", "B"}) depth.Get(c).floats[p] = d;
        depth.Get("A").floats[p] = 1;
        cv::Vec4b c(0, 0, 0, 255);
        for (size_t b = 0; b < spec.boxes.size(); ++b)
          if (ids[p] == spec.boxes[b].instance_id) {
            c = colour_of(b);
            if (seen.insert(static_cast<uint32_t>(b)).second)
              instances.push_back(
                  {{"instanceId", kSoloInstanceBase + b},
                   {"labelId", spec.boxes[b].class_id},
                   {"labelName", spec.boxes[b].name.substr(0, spec.boxes[b].name.find('#'))},
                   {"color", {c[0], c[1], c[2], c[3]}}});
          }
        colours.at<cv::Vec4b>(j, i) = {c[2], c[1], c[0], c[3]};
      }
    cv::imwrite((folder / (prefix + "camera.png")).string(), SrgbPng(colour, true));
    cv::imwrite((folder / (prefix + "camera.instance segmentation.png")).string(), colours);
    exr::WriteFlatExr(folder / (prefix + "camera.Depth.exr"), depth);

    json boxes = json::array();
    for (size_t b = 0; b < spec.boxes.size(); ++b) {
      const OrientedBox obb = spec.boxes[b].Obb();
      // Box axes in Unity's world must be a rotation: ENU axes taken to Unity
      // are left-handed, so z is negated (the same box).
      const Eigen::Matrix3d unity_world_from_box = unity_from_enu * obb.world_from_box * flip_z;
      boxes.push_back(
          {{"instanceId", kSoloInstanceBase + b},
           {"labelId", spec.boxes[b].class_id},
           {"labelName", spec.boxes[b].name.substr(0, spec.boxes[b].name.find('#'))},
           {"translation",
            Row(world_from_unity_cam.transpose() * (unity_from_enu * obb.center - position))},
           {"size", Row(2 * obb.half_extents)},
           {"rotation", Xyzw(world_from_unity_cam.transpose() * unity_world_from_box)},
           {"velocity", {0, 0, 0}},
           {"acceleration", {0, 0, 0}}});
    }
    const json capture = {{"@type", "type.unity.com/unity.solo.RGBCamera"},
                          {"id", "camera"},
                          {"description", "PerceptionCamera"},
                          {"position", Row(position)},
                          {"rotation", Xyzw(world_from_unity_cam)},
                          {"velocity", {0, 0, 0}},
                          {"acceleration", {0, 0, 0}},
                          {"filename", prefix + "camera.png"},
                          {"imageFormat", "Png"},
                          {"dimension", {static_cast<double>(w), static_cast<double>(h)}},
                          {"projection", "Perspective"},
                          {"matrix", matrix},
                          {"annotations",
                           {{{"@type", "type.unity.com/unity.solo.InstanceSegmentationAnnotation"},
                             {"id", "instance segmentation"},
                             {"sensorId", "camera"},
                             {"description", "Produces an instance segmentation image"},
                             {"imageFormat", "Png"},
                             {"dimension", {static_cast<double>(w), static_cast<double>(h)}},
                             {"filename", prefix + "camera.instance segmentation.png"},
                             {"instances", instances}},
                            {{"@type", "type.unity.com/unity.solo.BoundingBox3DAnnotation"},
                             {"id", "bounding box 3D"},
                             {"sensorId", "camera"},
                             {"description", "Produces 3D bounding box ground truth data"},
                             {"values", boxes}},
                            {{"@type", "type.unity.com/unity.solo.DepthAnnotation"},
                             {"id", "Depth"},
                             {"sensorId", "camera"},
                             {"description", "Generates a 32-bit depth image"},
                             {"measurementStrategy", "Depth"},
                             {"imageFormat", "Exr"},
                             {"dimension", {static_cast<double>(w), static_cast<double>(h)}},
                             {"filename", prefix + "camera.Depth.exr"}}}}};
    const json frame_data = {{"frame", k},
                             {"sequence", sequence},
                             {"step", step},
                             // Seconds: SimulationState.SequenceTime (Time.deltaTime sums).
                             {"timestamp", step * spec.frame_interval},
                             {"metadata", json::object()},
                             {"captures", {capture}},
                             {"metrics", json::array()}};
    std::ofstream(folder / (prefix + "frame_data.json")) << frame_data.dump(2);
  }
}

}  // namespace lsds::testing

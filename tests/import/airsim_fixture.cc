#include "tests/import/airsim_fixture.h"

#include <cmath>
#include <cstdio>
#include <fstream>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "importers/pfm.h"
#include "libs/geometry/world_frame.h"
#include "tests/import/fixture_images.h"

namespace lsds::testing {

namespace fs = std::filesystem;
using nlohmann::json;

import::AirSimMount AirSimFixtureMount(){import::AirSimMount mount;
mount.position_in_body = {0.3, -0.1, 0.2};
mount.pitch = -60, mount.yaw = 10, mount.roll = 2;
return mount;
}  // namespace lsds::testing

std::map<uint32_t, std::array<uint8_t, 3>> AirSimFixtureColours() {
  return {{1000, {153, 108, 6}}, {1, {112, 105, 191}}, {2, {89, 121, 72}}, {3, {190, 225, 64}}};
}

void WriteAirSimFixture(const fs::path& folder, const synth::Spec& spec) {
  fs::create_directories(folder / "images");
  const WorldFrame ned = WorldFrame::Make("NED", "m");
  const import::AirSimMount mount = AirSimFixtureMount();
  const auto colours = AirSimFixtureColours();
  // settings.json: the camera mount and capture settings.
  json capture = json::array();
  for (int type : {0, 1, 5})
    capture.push_back({{"ImageType", type},
                       {"Width", spec.width},
                       {"Height", spec.height},
                       {"FOV_Degrees", spec.hfov_deg}});
  const json settings = {{"SettingsVersion", 1.2},
                         {"SimMode", "Multirotor"},
                         {"Vehicles",
                          {{"Drone1",
                            {{"VehicleType", "SimpleFlight"},
                             {"Cameras",
                              {{kAirSimCamera,
                                {{"X", mount.position_in_body.x()},
                                 {"Y", mount.position_in_body.y()},
                                 {"Z", mount.position_in_body.z()},
                                 {"Pitch", mount.pitch},
                                 {"Roll", mount.roll},
                                 {"Yaw", mount.yaw},
                                 {"CaptureSettings", capture}}}}}}}}}};
  std::ofstream(folder / "settings.json") << settings.dump(2);
  // The sidecar: colours -> ids, OBBs in NED.
  json classes = json::array();
  for (const ClassInfo& c : spec.classes) classes.push_back({{"id", c.id}, {"name", c.name}});
  json objects = json::array();
  const auto& ground = colours.at(1000);
  objects.push_back({{"name", "Ground"},
                     {"color", {ground[0], ground[1], ground[2]}},
                     {"instance_id", 1000},
                     {"class_id", 1}});
  for (const synth::Box& box : spec.boxes) {
    const OrientedBox obb = box.Obb();
    const Eigen::Vector3d centre = ned.WorldFromEnuMetres(obb.center);
    const Eigen::Matrix3d axes = ned.enu_from_frame.transpose() * obb.world_from_box;
    json rotation = json::array();
    for (int r = 0; r < 3; ++r) rotation.push_back({axes(r, 0), axes(r, 1), axes(r, 2)});
    const auto& colour = colours.at(box.instance_id);
    objects.push_back(
        {{"name", box.name},
         {"asset", "box"},
         {"color", {colour[0], colour[1], colour[2]}},
         {"instance_id", box.instance_id},
         {"class_id", box.class_id},
         {"obb",
          {{"center", {centre.x(), centre.y(), centre.z()}},
           {"half_extents", {obb.half_extents.x(), obb.half_extents.y(), obb.half_extents.z()}},
           {"rotation", rotation}}}});
  }
  std::ofstream(folder / "lsds_objects.json") << json{
      {"format", "lsds-airsim-objects"},
      {"version", 1},
      {"vehicle", "Drone1"},
      {"camera", kAirSimCamera},
      {"depth", "DepthPlanar"},
      {"sky_depth_m", 1e6},
      {"classes", classes},
      {"objects", objects}}.dump(2);

  std::ofstream rec(folder / "airsim_rec.txt");
  rec << "VehicleName\tTimeStamp\tPOS_X\tPOS_Y\tPOS_Z\tQ_W\tQ_X\tQ_Y\tQ_Z\t"
         "ImageFile\n";
  const int w = spec.width, h = spec.height;
  for (int k = 0; k < static_cast<int>(spec.cam_from_world.size()); ++k) {
    const synth::RenderedFrame frame = synth::RenderFrame(spec, k);
    const long long stamp = 1700000000000LL + 100LL * k;  // ms, 0.1 s apart
    const std::string tail = "_" + std::to_string(stamp);
    const std::string prefix = std::string("img_Drone1_") + kAirSimCamera;
    const std::string scene_name = prefix + "_0" + tail + ".png";
    const std::string depth_name = prefix + "_1" + tail + ".pfm";
    const std::string seg_name = prefix + "_5" + tail + ".png";
    const exr::FlatImage& rgb = frame.flat.at("rgb");
    const cv::Mat scene = SrgbPng(rgb, false);
    cv::Mat seg(h, w, CV_8UC3, cv::Scalar(0, 0, 0));
    const std::vector<uint32_t>& ids = frame.flat.at("instanceid").Get("id").uints;
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < w; ++i) {
        const size_t p = rgb.Index(i, j);
        if (ids[p] != 0) {
          const auto& c = colours.at(ids[p]);
          seg.at<cv::Vec3b>(j, i) = {c[2], c[1], c[0]};  // OpenCV: BGR
        }
      }
    cv::imwrite((folder / "images" / scene_name).string(), scene);
    cv::imwrite((folder / "images" / seg_name).string(), seg);
    import::PfmImage depth{w, h, 1, frame.flat.at("depth").Get("Z").floats};
    for (float& v : depth.values)
      if (std::isinf(v)) v = 1e6f;  // the sky: far, finite (sky_depth_m)
    import::WritePfm(folder / "images" / depth_name, depth, import::PfmRows::kTopFirst);
    Eigen::Vector3d position;
    Eigen::Quaterniond q;
    import::AirSimVehicleOfCamFromEnu(spec.cam_from_world[k], mount, &position, &q);
    char line[512];
    std::snprintf(line,
                  sizeof line,
                  "Drone1\t%lld\t%.17g\t%.17g\t%.17g\t%.17g\t%.17g\t%.17g\t%.17g\t",
                  stamp,
                  position.x(),
                  position.y(),
                  position.z(),
                  q.w(),
                  q.x(),
                  q.y(),
                  q.z());
    rec << line << scene_name << ";" << depth_name << ";" << seg_name << "\n";
  }
}

}  // namespace lsds::testing

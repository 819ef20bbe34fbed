#include "generator/demo_plan.h"

#include <cmath>
#include <string>

#include "generator/scene/perlin.h"
#include "generator/scene/terrain.h"
#include "libs/geometry/attitude.h"

namespace lsds::gen {

Plan MakeDemoPlan(const DemoOptions& options) {
  Plan plan;
  plan.seed = options.seed;
  // The demo has no scene text: its source is the command that makes it,
  // with every parameter, so that two demos differ in their provenance (lsds
  // merge refuses shards of different runs by it).
  plan.scene_source = "# built-in demo scene: lsds generate --demo --demo-frames " +
                      std::to_string(options.frames) + " --demo-size " +
                      std::to_string(options.width) + "x" + std::to_string(options.height) + " (" +
                      std::to_string(options.objects) + " objects)";
  const char* classes[] = {
      "terrain", "barrel", "tire", "jerrycan", "rock", "bush", "person", "cube"};
  for (uint32_t i = 0; i < 8; ++i) plan.classes.push_back({i + 1, classes[i]});
  plan.sky.cloud_type = "cumulus";
  plan.sky.cloud_density = 0.4;
  plan.sun.elevation_deg = 45.0;
  plan.sun.azimuth_deg = 150.0;
  plan.sun.illuminance_lux = 100000.0;  // lux
  plan.fog_density = 0.002;
  plan.terrain.present = true;
  plan.terrain.size = {300, 300};
  plan.terrain.perlin_amplitude = 3.0;
  plan.terrain.perlin_frequency = 0.02;
  plan.terrain.perlin_seed = HashCombine(options.seed, 1);
  plan.terrain.material = "grassy";
  plan.terrain.class_id = 1;
  plan.terrain.instance_id = 1000;

  uint64_t state = HashCombine(options.seed, 2);
  auto uniform = [&state](double lo, double hi) {
    state = HashCombine(state, 0x2545f4914f6cdd1dull);
    return lo + (hi - lo) * (static_cast<double>(state >> 11) / 9007199254740992.0);
  };
  const struct {
    const char* name;
    uint32_t class_id;
    Eigen::Vector3d extent;
  } kinds[] = {{"barrel", 2, {0.6, 0.6, 0.9}},
               {"tire", 3, {0.65, 0.22, 0.65}},
               {"jerrycan", 4, {0.17, 0.35, 0.47}},
               {"rock", 5, {1.2, 0.9, 0.6}},
               {"bush", 6, {1.8, 1.6, 1.3}},
               {"person", 7, {0.45, 0.3, 1.75}},
               {"cube", 8, {2.0, 2.0, 2.0}}};
  for (int i = 0; i < options.objects; ++i) {
    const auto& kind = kinds[i % 7];
    PlannedObject o;
    o.symbol = kind.name;
    o.name = std::string(kind.name) + "#" + std::to_string(i);
    o.class_name = kind.name;
    o.class_id = kind.class_id;
    o.instance_id = static_cast<uint32_t>(i + 1);
    const double scale = uniform(0.8, 1.25);
    o.extent = kind.extent * scale;
    const double x = uniform(-16, 16), y = uniform(-16, 6 + 2.0 * options.frames);
    const double yaw = uniform(0, 2 * M_PI);
    o.world_from_object = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    // Standing on the terrain: the box's base at the terrain height under its
    // centre.
    o.position = {x, y, TerrainHeight(plan.terrain, x, y) + o.extent.z() / 2 - 0.05};
    plan.objects.push_back(o);
  }
  // The last barrel rolls along x: a scene change per frame, so motion vectors
  // show object motion.
  const std::string mover = plan.objects.empty() ? "" : plan.objects[0].name;

  const PinholeCamera camera =
      PinholeCamera::FromHorizontalFov(options.width, options.height, 70.0);
  for (int f = 0; f < options.frames; ++f) {
    PlannedFrame frame;
    frame.index = f;
    frame.time = 0.1 * f;
    frame.sequence = "P1(1)";
    frame.shot = 0;  // one continuous flight
    frame.camera = camera;
    const Eigen::Vector3d position(0, -26 + 2.0 * f, 25);
    frame.cam_from_world = CamFromEnu(position, Attitude{0, -60, 0});
    if (!mover.empty()) {
      ObjectChange change;
      change.object = mover;
      const Eigen::Vector3d p = plan.objects[0].position + Eigen::Vector3d(0.3 * f, 0, 0);
      change.position = Eigen::Vector3d(
          p.x(),
          p.y(),
          TerrainHeight(plan.terrain, p.x(), p.y()) + plan.objects[0].extent.z() / 2 - 0.05);
      frame.changes.push_back(change);
    }
    plan.frames.push_back(frame);
  }
  return plan;
}

}  // namespace lsds::gen

#include "generator/lang/capture/camera_setup.h"

#include <algorithm>
#include <map>
#include <string>
#include <vector>

#include "generator/lang/rig.h"
#include "generator/lang/vocabulary.h"
#include "libs/collection/model.h"
#include "libs/util/strings.h"

namespace lsds {
namespace {

// fps, heights and clearance: what the platform sets beside the intrinsics.
void ReadPlatformSettings(const Node& settings, CameraSetup* setup) {
  if (const Node f = settings.Find("fps"))
    setup->fps = ReadInRange(f, KindVocabulary("camera_settings").Key("fps"));
  if (const Node h = settings.Find("heights")) {
    const std::string v = ReadString(h);
    if (v != "agl" && v != "datum")
      h.Fail("heights is agl (above the terrain) or datum (world z), not '" + v + "'");
    setup->heights_agl = v == "agl";
  }
  if (const Node c = settings.Find("clearance")) {
    if (c->is_string() && ReadString(c) == "off") {
      setup->clearance_m.reset();  // the user's explicit opt-out
    } else {
      setup->clearance_m = ReadNumber(c);
      if (!(*setup->clearance_m >= 0) || *setup->clearance_m > 1e4)
        c.Fail("clearance must be a distance in [0, 10000] m, or off");
    }
  }
}

// The paper's names of the layers it always writes (section 6: "object IDs, depth, shadows, surface
// normals, motion vectors, and world locations"; folders named like "worlddepth"), by canonical
// key.
const std::map<std::string, std::string>& PaperLayerNames() {
  static const std::map<std::string, std::string> names = {{"worlddepth", "depth"},
                                                           {"objectids", "classid"},
                                                           {"objectid", "classid"},
                                                           {"shadows", "shadow"},
                                                           {"surfacenormals", "normal"},
                                                           {"normals", "normal"},
                                                           {"motionvectors", "motion"},
                                                           {"worldlocations", "worldposition"},
                                                           {"worldlocation", "worldposition"}};
  return names;
}

// `capture:{layers:[...], folder: name}`: the layers to write, each a known layer once.
// A paper name stands for its layer.
nlohmann::json ReadCaptureSettings(const Node& n) {
  lsds::CheckKeys(n, KindVocabulary("capture_settings"), "capture settings");
  nlohmann::json settings = nlohmann::json::object();
  if (const Node layers = n.Find("layers")) {
    if (!layers->is_array() || layers->empty())
      layers.Fail("layers is a list of layer names, e.g. [rgb,depth]");
    std::vector<std::string> names;
    const auto& known = StandardLayerSemantics();
    for (size_t i = 0; i < layers->size(); ++i) {
      std::string name = ReadString(layers.Item(i));
      const auto paper = PaperLayerNames().find(CanonicalKey(name));
      if (paper != PaperLayerNames().end()) name = paper->second;
      if (std::find(known.begin(), known.end(), name) == known.end())
        layers.Item(i).Fail("unknown layer '" + name + "'" + DidYouMean(name, known) +
                            "; layers: " + Join(known, ", "));
      if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
    }
    settings["layers"] = names;
  }
  for (const char* folder_key : {"folder", "output"})
    if (const Node f = n.Find(folder_key)) {
      const std::string folder = ReadString(f);
      if (folder.empty()) f.Fail("the output folder name is empty");
      settings["folder"] = folder;
    }
  return settings;
}

}  // namespace

PlannedExposure ReadExposure(const Node& settings) {
  PlannedExposure e;
  const KindSpec& vocabulary = KindVocabulary("camera_settings");
  auto read = [&](const Node& n, const char* key) { return ReadInRange(n, vocabulary.Key(key)); };
  if (const Node n = settings.Find("iso")) e.iso = read(n, "iso");
  if (const Node n = settings.Find("fnumber")) e.f_number = read(n, "f_number");
  if (const Node n = settings.Find("shutter")) {
    e.shutter_s = read(n, "shutter");
    if (!e.f_number) n.Fail("a manual exposure by shutter needs f_number too (or give ev100)");
  }
  if (const Node n = settings.Find("ev100")) {
    if (e.shutter_s || e.iso || e.f_number)
      n.Fail("give ev100 or shutter, f_number and iso, not both");
    e.ev100 = read(n, "ev100");
  }
  if (const Node n = settings.Find("exposurecompensation"))
    e.compensation_ev = read(n, "exposure_compensation");
  if (const Node n = FindKey(settings, vocabulary, "focus_distance"))
    e.focus_distance_m = read(n, "focus_distance");
  if (const Node n = settings.Find("sensorwidth")) e.sensor_width_mm = read(n, "sensor_width");
  return e;
}

CameraSetup ReadCameraSetup(const Definition* camera, Plan* plan) {
  CameraSetup setup;
  setup.camera = camera;
  if (!camera) return setup;
  const Node& b = camera->body;
  IntrinsicSettings intrinsics;
  const KindSpec& vocabulary = KindVocabulary("camera");
  if (const Node settings = FindKey(b, vocabulary, "csettings")) {
    lsds::CheckKeys(settings, KindVocabulary("camera_settings"), "camera settings");
    intrinsics.Read(settings);
    plan->exposure = ReadExposure(settings);
    setup.intrinsics = intrinsics.Camera();
    ReadPlatformSettings(settings, &setup);
  }
  // Several cameras on the platform: each frame of the paths becomes one time step with a frame
  // per rig camera (docs/languages.md, "Camera rigs").
  if (const Node r = b.Find("rig")) plan->rig = ReadRig(r, intrinsics);
  if (const Node n = FindKey(b, vocabulary, "ppmaterial")) {
    if (!n->is_array()) n.Fail("post-process materials are a list [Name, ...]");
    for (size_t i = 0; i < n->size(); ++i) plan->post_process.push_back(ReadString(n.Item(i)));
  }
  if (const Node n = FindKey(b, vocabulary, "capture"))
    plan->capture_settings = ReadCaptureSettings(n);
  return setup;
}

}  // namespace lsds

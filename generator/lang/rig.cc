#include "generator/lang/rig.h"

#include <cmath>

#include "generator/lang/vocabulary.h"
#include "libs/collection/rig.h"
#include "libs/geometry/attitude.h"
#include "libs/util/strings.h"

namespace lsds {

const std::vector<std::string>& IntrinsicSettingKeys() {
  static const std::vector<std::string> keys = [] {
    const KindSpec& settings = KindVocabulary("camera_settings");
    std::vector<std::string> out;
    for (const std::string& name : settings.KeysWithRole("intrinsic"))
      for (const std::string& spelling : settings.Key(name).Spellings()) out.push_back(spelling);
    return out;
  }();
  return keys;
}

void IntrinsicSettings::Read(const Node& settings) {
  for (const char* key : {"res", "resolution"}) {
    if (const Node r = settings.Find(key)) {
      if (!r->is_array() || r->size() != 2) r.Fail("resolution is [width, height]");
      const double rw = ReadNumber(r.Item(0)), rh = ReadNumber(r.Item(1));
      if (rw < 1 || rh < 1 || rw > 65536 || rh > 65536 || rw != std::floor(rw) ||
          rh != std::floor(rh))
        r.Fail("resolution must be whole numbers in [1, 65536]");
      width = static_cast<int>(rw);
      height = static_cast<int>(rh);
    }
  }
  if (const Node f = settings.Find("fov")) {
    fov_deg = ReadNumber(f);
    if (fov_deg <= 0 || fov_deg >= 180) f.Fail("fov must be in (0, 180) degrees");
  }
  if (const Node s = settings.Find("sensorwidth")) sensor_mm = ReadNumber(s);
  if (const Node f = settings.Find("focallength")) {
    focal_mm = ReadNumber(f);
    if (*focal_mm <= 0 || sensor_mm <= 0) f.Fail("focal_length and sensor_width must be > 0 (mm)");
  }
}

PinholeCamera IntrinsicSettings::Camera() const {
  PinholeCamera camera = PinholeCamera::FromHorizontalFov(width, height, fov_deg);
  if (focal_mm) camera.fx = camera.fy = *focal_mm / sensor_mm * width;
  return camera;
}

Rigid3d RigFromCam(const Eigen::Vector3d& position, const Attitude& attitude) {
  // The relative attitude turns the camera's FRD body in the platform's FRD
  // body; both OpenCV frames are those bodies with their axes renamed.
  const Eigen::Matrix3d rig_from_cam =
      BodyFromCam().transpose() * NedFromBody(attitude).toRotationMatrix() * BodyFromCam();
  return Rigid3d(Eigen::Quaterniond(rig_from_cam).normalized(), position);
}

Rig ReadRig(const Node& rig_node, const IntrinsicSettings& platform) {
  if (!rig_node->is_object() || rig_node->empty())
    rig_node.Fail("a rig names its cameras: rig:{left:{position:[-0.1,0,0]}, ...}");
  Rig rig;
  for (const auto& [name, body] : rig_node.Members()) {
    if (!IsRigCameraName(name))
      body.FailKey("rig camera name '" + name +
                   "': use 1-32 letters, digits, '_' or '-' (it is part of file names)");
    if (rig.Find(name)) body.FailKey("rig camera '" + name + "' is defined twice");
    if (!body->is_object())
      body.Fail("a rig camera is {position:[x,y,z], attitude:[roll,pitch,yaw], csettings:{...}}");
    const KindSpec& vocabulary = KindVocabulary("rig_camera");
    CheckKeys(body, vocabulary, "rig camera " + name);
    Rng crisp(0);  // rig poses are fixed: intervals are not allowed
    Eigen::Vector3d position = Eigen::Vector3d::Zero();
    if (const Node p = body.Find("position")) {
      if (!p->is_array() || p->size() != 3) p.Fail("position is [x, y, z] in metres");
      for (size_t i = 0; i < 3; ++i)
        if (!p.Item(i)->is_number()) p.Item(i).Fail("a rig offset is a number (metres)");
      position = SampleVec3(p, crisp);
    }
    Attitude attitude;
    if (const Node a = FindKey(body, vocabulary, "attitude")) {
      if (!a->is_array() || a->size() != 3) a.Fail("attitude is [roll, pitch, yaw] in degrees");
      for (size_t i = 0; i < 3; ++i)
        if (!a.Item(i)->is_number()) a.Item(i).Fail("a rig attitude is a number (degrees)");
      const Eigen::Vector3d rpy = SampleVec3(a, crisp);
      attitude = Attitude{rpy.x(), rpy.y(), rpy.z()};
    }
    IntrinsicSettings settings = platform;
    if (const Node s = FindKey(body, vocabulary, "csettings")) {
      s.CheckKeys(
          IntrinsicSettingKeys(),
          "settings of rig camera " + name + " (fps, clearance and heights are the platform's)");
      settings.Read(s);
    }
    RigCamera camera;
    camera.name = name;
    camera.intrinsics = settings.Camera();
    camera.cam_from_rig = RigFromCam(position, attitude).Inverse();
    rig.cameras.push_back(camera);
  }
  return rig;
}

}  // namespace lsds

#include "libs/collection/rig.h"

#include <cctype>

#include "libs/util/strings.h"

namespace lsds {

std::string FrameFileStem(int64_t index, const std::optional<std::string>& rig_camera) {
  std::string stem = FrameStem(index);
  if (rig_camera) stem += "_" + *rig_camera;
  return stem;
}

bool ContinuesShot(const Frame& previous, const Frame& frame) {
  if (CameraStreamOf(previous) != CameraStreamOf(frame)) return false;
  const bool same_shot = frame.shot && previous.shot ? *frame.shot == *previous.shot
                                                     : previous.sequence == frame.sequence;
  if (!same_shot) return false;
  if (frame.step && previous.step) return *previous.step + 1 == *frame.step;
  return previous.index + 1 == frame.index;
}

bool IsRigCameraName(const std::string& name) {
  if (name.empty() || name.size() > 32) return false;
  for (const char c : name)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-') return false;
  return true;
}

const RigCamera* Rig::Find(const std::string& name) const {
  for (const RigCamera& c : cameras)
    if (c.name == name) return &c;
  return nullptr;
}

}  // namespace lsds

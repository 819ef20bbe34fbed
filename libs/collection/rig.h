// Camera rigs (docs/format.md, "Camera rigs"): several cameras on one
// platform, one frame record per camera per time step. What every reader
// needs to treat a rig collection right: the file stem of a frame and which
// earlier frame continues it (motion is measured within one camera's stream).
#pragma once

#include <optional>
#include <string>

#include "libs/collection/model.h"

namespace lsds {

// The file stem of a frame's layer files and of converted images: the frame
// index, zero-padded to six digits, then `_CAMERA` for a rig frame
// ("000004_left"), so that flat folders stay flat and names stay unique.
std::string FrameFileStem(int64_t index, const std::optional<std::string>& rig_camera);
inline std::string FrameFileStem(const Frame& frame) {
  return FrameFileStem(frame.index, frame.rig_camera);
}

// The stream a frame belongs to for frame-to-frame checks: its rig camera,
// "" for a collection with one camera.
inline std::string CameraStreamOf(const Frame& frame) { return frame.rig_camera.value_or(""); }

// Whether `frame` directly follows `previous` within one continuous shot of one
// camera: the same camera stream, the same shot (the same sequence in 1.0
// collections, which have no shots), and the next time step of that camera
// (the next frame index when the collection is not a rig).
bool ContinuesShot(const Frame& previous, const Frame& frame);

// A camera name a rig may use: letters, digits, '_' and '-', 1-32 characters
// (it is part of file names).
bool IsRigCameraName(const std::string& name);

}  // namespace lsds

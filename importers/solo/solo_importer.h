// Unity Perception's SOLO dataset (docs/import.md, "Unity Perception SOLO"):
// annotation_definitions.json (the label specs: label_id, label_name) and
// sequence.N/stepK.frame_data.json, each with captures[] of which the first
// RGBCamera is read: position (m, Unity world: left-handed, y up), rotation
// serialized [x, y, z, w], the 3x3 of Unity's OpenGL projection matrix
// (column-major), the PNG it names, and its annotations: InstanceSegmentation
// (colour PNG + instances[] with instanceId, labelId, color), BoundingBox3D
// (translation, size, [x, y, z, w] rotation in the camera's frame) and Depth
// (EXR, channel R, metres; `measurementStrategy` Depth = planar, Range = along
// the ray). The step's `timestamp` is in seconds; before 1.0 there is none and
// sensor_definitions.json's schedule gives the time. Classes are the labels the
// frames use (all defined ones with --all-labels). Converted to ENU (x, z, y), the OpenCV camera
// and pixel-edge intrinsics.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "importers/importer.h"
#include "libs/util/confined_path.h"

namespace lsds::import {

// When the RGB sensor captures, from sensor_definitions.json: frames before Perception 1.0
// carry no `timestamp`, so a step's time is the one the sensor's schedule gives it.
struct CaptureSchedule {
  bool scheduled = false;          // captureTriggerMode "Scheduled"
  double delta_time = 0;           // simulationDeltaTime, seconds per simulated frame
  double first_capture_frame = 0;  // firstCaptureFrame
  int64_t frames_between = 0;      // framesBetweenCaptures

  // SimulationState.cs: the first capture at firstCaptureFrame * renderingDeltaTime, each
  // next one (framesBetweenCaptures + 1) * renderingDeltaTime later. Unscheduled (manual)
  // captures have no clock: the step number stands for the time.
  double TimeOfStep(int64_t step) const {
    if (!scheduled) return static_cast<double>(step);
    return delta_time * (first_capture_frame + static_cast<double>(step * (frames_between + 1)));
  }
};

class SoloImporter : public Importer {
 public:
  std::string name() const override { return "solo"; }
  SourceDescription Open(const std::filesystem::path& source,
                         const ImportOptions& options) override;
  SourceFrame ReadFrame(int64_t index) override;

 private:
  struct Step {
    int64_t sequence = 0, step = 0;
    std::filesystem::path file;
  };
  // The stages of Open: the steps of every sequence (and the shots), then the
  // depth of the first frame.
  void FindSteps(const std::filesystem::path& source);
  void FindDepth();

  std::optional<ConfinedFolder> root_;  // every file read is confined to it
  std::vector<Step> steps_;             // by sequence, then step
  std::vector<int64_t> shot_of_step_;
  std::vector<uint32_t> class_ids_;  // every label defined, sorted
  CaptureSchedule schedule_;
  bool has_depth_ = false;
  DepthKind depth_kind_ = DepthKind::kPlanar;
};

}  // namespace lsds::import

// Per-frame checks: every EXR of the frame is opened and decoded once, then the
// layer, cross-layer and camera checks all read the decoded images.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "libs/collection/model.h"
#include "validators/checks.h"
#include "validators/finding.h"
#include "validators/report.h"

namespace lsds::validate {

struct FrameInput {
  Frame frame;
  size_t position = 0;  // index in the "frames" array (for JSON pointers)
  // The previous frame of the same shot (format 1.1; of the same sequence in
  // 1.0), if it is the adjacent frame of the collection.
  std::optional<CameraTruth> previous_camera;
  // The previous frame's object boxes by instance id (with previous_camera):
  // a pixel of an object whose box moved is expected to move with it.
  std::map<uint32_t, OrientedBox> previous_boxes;
  // The frame starts its shot (format 1.1: shot == index): no valid motion.
  bool shot_start = false;
};

struct FrameOutcome {
  std::vector<Finding> findings;
  std::set<uint32_t> pixel_classes;  // class ids seen in the classid layer
  int64_t files_decoded = 0;
  int64_t bytes_decoded = 0;
  std::vector<std::pair<std::string, Statistic>> statistics;
  CheckSeconds check_seconds;  // CheckTimer
};

struct FrameCheckContext {
  std::filesystem::path root;
  const CollectionHeader* header = nullptr;
  const CheckSelection* checks = nullptr;
  int camera_grid = 24;
};

FrameOutcome CheckFrame(const FrameCheckContext& context, const FrameInput& input);

}  // namespace lsds::validate

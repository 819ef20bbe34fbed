// The report's distributions over every selected frame of a collection,
// accumulated one frame at a time (docs/report.md says what each one counts).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "libs/collection/model.h"
#include "report/frame_camera.h"
#include "report/histogram.h"

namespace lsds::report {

struct Distributions {
  std::vector<Histogram> histograms;     // in display order
  std::map<uint32_t, size_t> class_bin;  // class id -> bin of "class"
  int64_t frames = 0;
  int64_t objects = 0;           // object entries listed in the frames
  int64_t visible_objects = 0;   // of those, with at least one visible pixel
  std::string metadata_variant;  // the perturbed variant measured, if any

  const Histogram& Get(const std::string& id) const;  // throws when unknown
  Histogram& Get(const std::string& id);
};

// Empty histograms with the bins of docs/report.md; "class" has one bin per
// class of `header`, in table order.
Distributions MakeDistributions(const CollectionHeader& header);

// Folds one frame in. Per visible object (visible_pixels > 0): class, box size
// (longer side of the tight box, px), visible pixels, distance to the OBB
// centre (m). Per listed object: visibility and in-frame fraction. Per frame:
// altitude, off-nadir angle, GSD (cm/px), sun elevation (when the frame's
// scene state gives it).
void AddFrame(const CollectionHeader& header,
              const Frame& frame,
              const FrameCamera& camera,
              Distributions* distributions);

// Folds in the realized error of one frame of a perturbed metadata variant
// (docs/perturb-metadata.md): position error length in ENU metres and rotation
// angle in degrees. Frames without recorded errors count as invalid.
void AddMetadataError(const MetadataFrame& frame, Distributions* distributions);

}  // namespace lsds::report

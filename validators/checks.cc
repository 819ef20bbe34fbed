#include "validators/checks.h"

#include <algorithm>

#include "libs/util/strings.h"

namespace lsds::validate {

const char* SeverityName(Severity severity) {
  switch (severity) {
    case Severity::kInfo:
      return "info";
    case Severity::kWarning:
      return "warning";
    case Severity::kError:
      return "error";
  }
  return "error";
}

bool ParseSeverity(const std::string& name, Severity* severity) {
  if (name == "info") {
    *severity = Severity::kInfo;
  } else if (name == "warning") {
    *severity = Severity::kWarning;
  } else if (name == "error") {
    *severity = Severity::kError;
  } else {
    return false;
  }
  return true;
}

// A declarative table: the check registry, one entry per check.
// NOLINTNEXTLINE(readability-function-size,readability-function-cognitive-complexity)
const std::vector<CheckInfo>& AllChecks() {
  using S = Severity;
  static const std::vector<CheckInfo> checks = {
      {"schema",
       S::kError,
       "every JSON file (collection.json, metadata files) matches its schema",
       "exact"},
      {"structure.frame-count", S::kError, "frame_count equals the number of frames", "exact"},
      {"structure.frame-order",
       S::kError,
       "frame indices strictly increase and times do not decrease",
       "exact"},
      {"structure.duplicate-frame", S::kError, "no frame index appears twice", "exact"},
      {"structure.rig",
       S::kError,
       "in a rig collection every frame names a rig camera and a time step, has that camera's "
       "intrinsics, and the cameras of one step share one platform pose (cam_from_rig)",
       "1e-6 relative / 1e-6 rad"},
      {"structure.tables",
       S::kError,
       "class ids and layer names are unique; layer declarations are "
       "consistent",
       "exact"},
      {"structure.missing-file",
       S::kError,
       "every frame has an existing file for every required layer",
       "exact"},
      {"structure.unknown-layer", S::kError, "frame files name only declared layers", "exact"},
      {"structure.stray-file",
       S::kWarning,
       "layer folders hold no file that no frame references",
       "exact"},
      {"structure.class-id", S::kError, "object class ids are in the class table", "exact"},
      {"structure.duplicate-instance",
       S::kError,
       "an instance id appears at most once among a frame's objects",
       "exact"},
      {"structure.metadata",
       S::kError,
       "metadata files exist and have one frame per collection frame, same "
       "indices",
       "exact"},
      {"structure.handedness",
       S::kError,
       "the determinant of each cam_from_world rotation matches the declared "
       "world handedness",
       "1e-6"},
      {"structure.truth-origin",
       S::kInfo,
       "an imported collection's truth fields that the source could not "
       "provide (absent) or that are estimated (a derived visibility), from "
       "provenance.import.truth_origin",
       "exact"},
      {"structure.cycles-agreement",
       S::kError,
       "a collection whose rgb Blender Cycles rendered (--renderer cycles): Cycles' depth and "
       "object index passes agreed with the depth and instanceid layers "
       "(provenance.render.cycles_agreement)",
       "relative depth <= 1e-3, id mismatch share <= 0.01"},
      {"layer.readable",
       S::kError,
       "EXR opens, is within the size limits (checked before decoding) and "
       "decodes",
       "exact"},
      {"layer.dimensions", S::kError, "EXR size equals the frame's camera resolution", "exact"},
      {"layer.channels", S::kError, "EXR channel names and pixel types are as declared", "exact"},
      {"layer.id-type",
       S::kError,
       "id layers (classid, instanceid, bundle ids) are uint typed",
       "exact"},
      {"layer.rgb-range", S::kError, "RGB values are finite and >= 0", "exact"},
      {"layer.depth-finite", S::kError, "depth is finite and >= 0, or +inf (sky)", "exact"},
      {"layer.normal-unit",
       S::kError,
       "normals are unit length, or (0,0,0) for sky",
       "| |n| - 1 | <= 1e-3"},
      {"layer.worldposition-finite",
       S::kError,
       "world positions are finite, or +inf on all three channels (sky)",
       "exact"},
      {"layer.shadow-range", S::kError, "shadow ratio in [0, 1]", "exact"},
      {"layer.motion-range",
       S::kError,
       "screen-normalized motion is finite (it may exceed [0, 1]), or NaN on "
       "both channels (no valid motion)",
       "exact"},
      {"layer.motion-reference",
       S::kError,
       "a residual motion file was measured against the shot's previous frame: "
       "the previous camera its header names is that frame's camera (none on a "
       "shot's first frame)",
       "1e-9, relative to 1 or the value"},
      {"layer.classid-known",
       S::kError,
       "classid layer values are 0 or in the class table",
       "exact"},
      {"layer.bundle",
       S::kError,
       "bundle has >= 1 sample per covered pixel, finite depth, sample "
       "positions in [0, 1]",
       "exact"},
      {"cross.bbox-tight",
       S::kError,
       "an object's tight bbox equals the extent of its instance mask (null "
       "when not visible)",
       "exact"},
      {"cross.visible-pixels",
       S::kError,
       "visible_pixels equals the instance mask pixel count",
       "exact"},
      {"cross.obb-contains-bbox",
       S::kError,
       "the projection of the object's OBB through the declared camera "
       "contains its tight bbox",
       "1 px"},
      {"cross.oriented-box",
       S::kError,
       "an object's visible oriented box (format 1.2) covers every pixel of its "
       "instance mask with the minimal area, and is absent without pixels; both "
       "oriented boxes are rectangles with clockwise corners",
       "1e-6 px; area 1e-6 relative"},
      {"cross.worldpos-depth",
       S::kError,
       "world position equals the depth back-projected through the declared "
       "camera (max and "
       "RMS error reported)",
       "1e-4 * depth + 1e-4 world units"},
      {"cross.class-instance",
       S::kError,
       "each instance's pixels carry its declared class in the classid layer",
       "exact"},
      {"cross.bundle-centre",
       S::kError,
       "bundle sample 0 (nearest the centre) agrees with the single-value id "
       "layers",
       "exact"},
      {"cross.motion-pose",
       S::kWarning,
       "motion of static pixels equals the reprojection through the previous "
       "frame's camera",
       "2e-3 screen units on >= 90% of pixels"},
      {"cross.motion-invalid",
       S::kError,
       "motion is NaN on the first frame of a shot and where the previous "
       "frame's camera did not see the point (behind it or outside its image)",
       "exact on shot starts; >= 90% of unseen pixels"},
      {"cross.metadata-pose",
       S::kWarning,
       "metadata pose equals truth unless the metadata file is declared "
       "perturbed (the "
       "difference is reported as a statistic)",
       "1e-6 world units / 1e-6 deg"},
      {"camera.fov",
       S::kError,
       "intrinsics solved (Ceres) from world-position correspondences match "
       "the declared "
       "focal length / FOV",
       "0.5% of fx, fy"},
      {"camera.principal-point",
       S::kError,
       "solved principal point matches the declared one",
       "0.5 px"},
      {"camera.depth-unit",
       S::kError,
       "depth / expected depth ratio is 1, not a unit factor (100: cm vs m, "
       "1000: mm vs m)",
       "0.1%"},
      {"camera.depth-kind",
       S::kError,
       "depth matches its declared kind (planar vs perspective)",
       "0.1%"},
      {"camera.handedness",
       S::kError,
       "the world-position layer is not explained by a mirrored world axis "
       "(flipped "
       "handedness)",
       "0.5 px"},
      {"camera.image-flip",
       S::kError,
       "the layers are not stored upside down or mirrored",
       "0.5 px"},
      {"camera.pose",
       S::kError,
       "the declared camera reprojects the world-position layer onto its pixel "
       "centres",
       "0.5 px RMS"},
      {"requirements.met",
       S::kError,
       "every frame (time step, with a rig) with an LCAP demand met it in the rendered truth",
       "exact"},
      {"requirements.quota",
       S::kError,
       "each LCAP quota's achieved count per bin is its planned count, within the quota's "
       "tolerance",
       "the quota's tolerance x frames"},
      {"stats.class-unused",
       S::kWarning,
       "every class of the table has instances or pixels",
       "exact"},
      {"stats.zero-visible-target",
       S::kInfo,
       "objects kept as targets have visible pixels",
       "exact"},
      {"stats.empty-frame", S::kInfo, "every frame has at least one object", "exact"},
      {"stats.class-imbalance",
       S::kWarning,
       "object counts of the most and least frequent used classes differ by < "
       "100x",
       "100x"},
  };
  return checks;
}

const CheckInfo& GetCheck(const std::string& id) {
  for (const CheckInfo& check : AllChecks()) {
    if (check.id == id) return check;
  }
  throw Error("internal: unknown check id '" + id + "'");
}

namespace {
std::vector<std::string> AllNames() {
  std::vector<std::string> names = {"all"};
  for (const CheckInfo& check : AllChecks()) {
    names.push_back(check.id);
    const std::string group = check.id.substr(0, check.id.find('.'));
    if (names.back() != group && std::find(names.begin(), names.end(), group) == names.end()) {
      names.push_back(group);
    }
  }
  return names;
}
}  // namespace

CheckSelection CheckSelection::All() {
  CheckSelection selection;
  for (const CheckInfo& check : AllChecks()) selection.ids_.insert(check.id);
  return selection;
}

CheckSelection CheckSelection::Of(const std::vector<std::string>& ids) {
  CheckSelection selection;
  for (const std::string& id : ids) selection.ids_.insert(GetCheck(id).id);
  return selection;
}

CheckSelection CheckSelection::Parse(const std::string& list) {
  auto trim = [](std::string text) {
    while (!text.empty() && text.front() == ' ') text.erase(text.begin());
    while (!text.empty() && text.back() == ' ') text.pop_back();
    return text;
  };
  CheckSelection selection;
  bool first = true;
  // Entries apply left to right: NAME adds, -NAME removes; a list that starts
  // with -NAME starts from all checks ("-camera" = "all,-camera").
  for (const std::string& raw : Split(list, ',')) {
    std::string entry = trim(raw);
    if (entry.empty()) continue;
    const bool exclude = entry.front() == '-';
    if (exclude) entry = trim(entry.substr(1));
    if (first && exclude) selection = All();
    first = false;
    std::string group = entry;
    if (group.size() > 2 && group.compare(group.size() - 2, 2, ".*") == 0) {
      group.resize(group.size() - 2);
    }
    std::vector<std::string> matched;
    for (const CheckInfo& check : AllChecks()) {
      if (entry == "all" || entry == "*" || check.id == entry || check.id == group ||
          check.id.compare(0, group.size() + 1, group + ".") == 0) {
        matched.push_back(check.id);
      }
    }
    if (matched.empty()) {
      throw Error("--checks: unknown check '" + entry + "'" + DidYouMean(entry, AllNames()) +
                  "; see docs/validate.md for the list");
    }
    for (const std::string& id : matched) {
      if (exclude)
        selection.ids_.erase(id);
      else
        selection.ids_.insert(id);
    }
  }
  if (selection.ids_.empty()) throw Error("--checks: '" + list + "' selects no check");
  return selection;
}

bool CheckSelection::HasGroup(const std::string& group) const {
  for (const std::string& id : ids_) {
    if (id.compare(0, group.size() + 1, group + ".") == 0 || id == group) return true;
  }
  return false;
}

}  // namespace lsds::validate

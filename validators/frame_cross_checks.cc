#include "validators/frame_checker.h"

#include <cmath>
#include <map>
#include <unordered_map>
#include <utility>

#include "libs/geometry/oriented_box.h"
#include "libs/geometry/oriented_box2d.h"
#include "validators/camera_checks.h"

namespace lsds::validate::detail {

namespace {

std::string PointText(const Eigen::Vector2d& p) {
  return "(" + Fmt(p.x()) + ", " + Fmt(p.y()) + ")";
}

// Why `box` is not a rectangle with clockwise corners on the image (y down),
// or "" when it is. Sides may have zero length (the amodal box of an OBB seen
// edge-on); tolerances are 1e-6 relative to the box's size.
std::string RectangleProblem(const OrientedBox2d& box) {
  const auto& c = box.corners;
  for (const Eigen::Vector2d& corner : c)
    if (!corner.allFinite()) return "a corner is not finite";
  const double size = std::max(1.0, (c[2] - c[0]).norm());
  if ((c[0] + c[2] - c[1] - c[3]).norm() > 1e-6 * size)
    return "its corners are not a parallelogram (corner 3 is not corner 0 + corner 2 - corner 1)";
  const Eigen::Vector2d side_a = c[1] - c[0], side_b = c[2] - c[1];
  if (std::abs(side_a.dot(side_b)) > 1e-6 * size * size) return "its sides are not perpendicular";
  // The z of side_a x side_b: positive when the turn is clockwise as seen on
  // the image, y pointing down.
  if (side_a.x() * side_b.y() - side_a.y() * side_b.x() < -1e-6 * size * size)
    return "its corners run counter-clockwise on the image";
  return "";
}

// Objects whose box moved since the previous frame (LCAP moves and changes), by instance id:
// the box now and the box then.
using MovedBoxes = std::map<uint32_t, std::pair<OrientedBox, OrientedBox>>;

MovedBoxes MovedSincePrevious(const FrameInput& input) {
  MovedBoxes moved;
  for (const ObjectTruth& o : input.frame.objects) {
    const auto before = input.previous_boxes.find(o.instance_id);
    if (!o.obb || before == input.previous_boxes.end()) continue;
    const OrientedBox& b = before->second;
    if (b.center != o.obb->center || b.half_extents != o.obb->half_extents ||
        b.world_from_box != o.obb->world_from_box)
      moved[o.instance_id] = {*o.obb, b};
  }
  return moved;
}

// Where `point` of instance `id` was in the previous frame: the points of a moved object move
// with its box, from the unit box of now to the box of then; other points stay.
Eigen::Vector3d PointThen(const MovedBoxes& moved, uint32_t id, const Eigen::Vector3d& point) {
  const auto m = moved.find(id);
  if (m == moved.end()) return point;
  const OrientedBox &now = m->second.first, &then = m->second.second;
  const Eigen::Vector3d unit = (now.world_from_box.transpose() * (point - now.center))
                                   .cwiseQuotient(now.half_extents.cwiseMax(1e-12));
  return then.world_from_box * unit.cwiseProduct(then.half_extents) + then.center;
}

// Where a static point was in the previous image (`before`); a point behind that
// camera or more than a pixel outside its image was not seen there.
bool SeenBy(const CameraTruth& previous, const Eigen::Vector3d& point, Eigen::Vector2d* before) {
  const PinholeCamera& camera = previous.intrinsics;
  const Eigen::Vector3d in_previous =
      previous.cam_from_world_rotation * point + previous.cam_from_world_translation;
  if (!(in_previous.z() > 0)) return false;
  *before = camera.ImageFromCam(in_previous);
  return before->x() > -1 && before->x() < camera.width + 1 && before->y() > -1 &&
         before->y() < camera.height + 1;
}

}  // namespace

// Each object's truth against the id layers (its mask: tight bbox, visible pixels, one class),
// its oriented boxes, and its OBB projected through the declared camera.
void FrameChecker::CheckObjects() {
  const std::vector<uint32_t>* ids = Ids("instanceid");
  std::unordered_map<uint32_t, ObjectMask> masks = MeasureObjectMasks(ids, Ids("classid"));
  const bool can_project = frame_.camera.cam_from_world_rotation.determinant() > 0;
  const Rigid3d cam_from_world = CamFromWorld(frame_.camera);
  for (size_t k = 0; k < frame_.objects.size(); ++k) {
    const ObjectTruth& object = frame_.objects[k];
    const std::string pointer = "/objects/" + std::to_string(k);
    const ClassInfo* info = header_.FindClass(object.class_id);
    const std::string who = "instance " + std::to_string(object.instance_id) +
                            (object.name.empty() ? "" : " '" + object.name + "'") +
                            (info ? " (" + info->name + ")" : "");
    if (ids) CheckObjectMask(object, pointer, who, masks[object.instance_id]);
    if (Selected("cross.oriented-box")) {
      CheckOrientedBoxes(
          object, pointer, who, ids ? masks[object.instance_id].extent : InstanceMask{});
    }
    if (object.bbox && object.obb && can_project && Selected("cross.obb-contains-bbox")) {
      CheckObbContainsBbox(object, pointer, who, cam_from_world);
    }
  }
}

// Every object's mask in the instance id layer, with the pixels whose class is not the
// object's (when the class id layer is there too).
std::unordered_map<uint32_t, ObjectMask> FrameChecker::MeasureObjectMasks(
    const std::vector<uint32_t>* ids, const std::vector<uint32_t>* classes) const {
  std::unordered_map<uint32_t, ObjectMask> masks;
  std::unordered_map<uint32_t, uint32_t> class_of;
  for (const ObjectTruth& object : frame_.objects) {
    masks[object.instance_id];
    class_of[object.instance_id] = object.class_id;
  }
  if (ids) {
    for (const auto& [id, extent] : MeasureInstanceMasks(*ids, width_, height_)) {
      const auto it = masks.find(id);
      if (it != masks.end()) it->second.extent = extent;
    }
  }
  if (!ids || !classes) return masks;
  for (int y = 0; y < height_; ++y) {
    for (int x = 0; x < width_; ++x) {
      const size_t p = static_cast<size_t>(y) * width_ + x;
      const auto it = masks.find((*ids)[p]);
      if (it == masks.end()) continue;
      if ((*classes)[p] != class_of[(*ids)[p]]) {
        it->second.wrong_class.Add(x, y, "classid " + std::to_string((*classes)[p]));
      }
    }
  }
  return masks;
}

// The object's bbox and visible pixels are its mask's; the mask's pixels are of its class.
void FrameChecker::CheckObjectMask(const ObjectTruth& object,
                                   const std::string& pointer,
                                   const std::string& who,
                                   const ObjectMask& m) {
  std::optional<Box2d> extent;
  if (m.extent.pixels > 0) extent = m.extent.box;
  auto box_text = [](const std::optional<Box2d>& b) {
    return b ? "[" + Fmt(b->x0) + ", " + Fmt(b->y0) + ", " + Fmt(b->x1) + ", " + Fmt(b->y1) + "]"
             : std::string("null");
  };
  const bool equal =
      extent.has_value() == object.bbox.has_value() && (!extent || *extent == *object.bbox);
  if (!equal) {
    Emit("cross.bbox-tight",
         JsonLocation(pointer + "/bbox"),
         "bbox is " + box_text(object.bbox) + " but the instance mask in " + FileOf("instanceid") +
             " spans " + box_text(extent),
         who);
  }
  if (m.extent.pixels != object.visible_pixels) {
    Emit("cross.visible-pixels",
         JsonLocation(pointer + "/visible_pixels"),
         "visible_pixels is " + std::to_string(object.visible_pixels) + " but the mask has " +
             std::to_string(m.extent.pixels) + " pixels",
         who);
  }
  if (m.wrong_class.count > 0 && Selected("cross.class-instance")) {
    Emit("cross.class-instance",
         Location::Pixel(FileOf("classid"), frame_.index, m.wrong_class.x, m.wrong_class.y),
         std::to_string(m.wrong_class.count) +
             " pixel(s) of the instance carry another class than " +
             std::to_string(object.class_id) + "; first: " + m.wrong_class.first_detail,
         who);
  }
}

// The OBB projected through the declared camera (clipped to the image) contains the bbox.
void FrameChecker::CheckObbContainsBbox(const ObjectTruth& object,
                                        const std::string& pointer,
                                        const std::string& who,
                                        const Rigid3d& cam_from_world) {
  const auto projected = ProjectedBounds(*object.obb, frame_.camera.intrinsics, cam_from_world);
  const Box2d clipped = projected ? projected->ClippedTo(width_, height_) : Box2d{};
  if (!projected || !clipped.Contains(*object.bbox, 1.0)) {
    Emit("cross.obb-contains-bbox",
         JsonLocation(pointer + "/bbox"),
         "the OBB projected through the declared camera covers [" + Fmt(clipped.x0) + ", " +
             Fmt(clipped.y0) + ", " + Fmt(clipped.x1) + ", " + Fmt(clipped.y1) +
             "], which does not contain the tight bbox [" + Fmt(object.bbox->x0) + ", " +
             Fmt(object.bbox->y0) + ", " + Fmt(object.bbox->x1) + ", " + Fmt(object.bbox->y1) + "]",
         who);
  }
}

// The oriented boxes of format 1.2 (docs/format.md, "Oriented boxes"); an
// object without them (older collections) has nothing to check.
void FrameChecker::CheckOrientedBoxes(const ObjectTruth& object,
                                      const std::string& pointer,
                                      const std::string& who,
                                      const InstanceMask& extent) {
  for (const auto& [key, box] :
       {std::pair{"bbox_oriented", &object.bbox_oriented},
        std::pair{"bbox_oriented_projected", &object.bbox_oriented_projected}}) {
    if (!*box) continue;
    if (const std::string problem = RectangleProblem(**box); !problem.empty())
      Emit("cross.oriented-box",
           JsonLocation(pointer + "/" + key),
           std::string(key) + " is not a rectangle with clockwise corners: " + problem,
           who);
  }
  const std::vector<uint32_t>* ids = Ids("instanceid");
  if (!ids || !object.bbox_oriented) return;
  const OrientedBox2d& box = *object.bbox_oriented;
  const Location where = JsonLocation(pointer + "/bbox_oriented");
  if (extent.pixels == 0) {
    Emit("cross.oriented-box",
         where,
         "bbox_oriented is given but the instance mask in " + FileOf("instanceid") +
             " has no pixel (it is absent for an object that is not visible)",
         who);
    return;
  }
  // Coverage: a rectangle is convex, so it covers a row's pixels when it
  // covers the outer corners of the row's first and last pixel.
  const int x0 = static_cast<int>(extent.box.x0), x1 = static_cast<int>(extent.box.x1);
  for (int y = static_cast<int>(extent.box.y0); y < static_cast<int>(extent.box.y1); ++y) {
    const uint32_t* row = ids->data() + static_cast<size_t>(y) * width_;
    int first = -1, last = -1;
    for (int x = x0; x < x1; ++x) {
      if (row[x] != object.instance_id) continue;
      if (first < 0) first = x;
      last = x;
    }
    if (first < 0) continue;
    for (const int x : {first, last}) {
      for (const Eigen::Vector2d& corner : {Eigen::Vector2d(x, y),
                                            Eigen::Vector2d(x + 1, y),
                                            Eigen::Vector2d(x, y + 1),
                                            Eigen::Vector2d(x + 1, y + 1)}) {
        if (box.Contains(corner, 1e-6)) continue;
        Emit("cross.oriented-box",
             where,
             "bbox_oriented does not cover pixel (" + std::to_string(x) + ", " + std::to_string(y) +
                 ") of the instance mask in " + FileOf("instanceid") + ": its corner " +
                 PointText(corner) + " lies outside",
             who);
        return;
      }
    }
  }
  // Minimal area: that of the minimum-area rectangle of the mask (a covering
  // box is never smaller, up to rounding).
  const std::optional<OrientedBox2d> minimal =
      MaskOrientedBox(ids->data(), width_, height_, object.instance_id, extent.box);
  if (minimal && std::abs(box.Area() - minimal->Area()) > 1e-6 * minimal->Area()) {
    Emit("cross.oriented-box",
         where,
         "bbox_oriented has area " + Fmt(box.Area()) +
             " px^2 but the minimum-area rectangle of the instance mask in " +
             FileOf("instanceid") + " has " + Fmt(minimal->Area()),
         who);
  }
}

void FrameChecker::CheckWorldPositionVsDepth() {
  if (!Selected("cross.worldpos-depth")) return;
  const std::vector<float>* z = Channel("depth", 0);
  const auto *px = Channel("worldposition", 0), *py = Channel("worldposition", 1),
             *pz = Channel("worldposition", 2);
  const LayerInfo* depth_layer = Layer("depth");
  if (!z || !px || !py || !pz || !depth_layer) return;
  const DepthKind kind = depth_layer->depth_kind.value_or(DepthKind::kPlanar);
  const PinholeCamera& camera = frame_.camera.intrinsics;
  const Eigen::Matrix3d world_from_cam = frame_.camera.cam_from_world_rotation.inverse();
  const Eigen::Vector3d t = frame_.camera.cam_from_world_translation;
  Statistic error;
  PixelTally bad;
  for (int y = 0; y < height_; ++y) {
    for (int x = 0; x < width_; ++x) {
      const size_t p = static_cast<size_t>(y) * width_ + x;
      const float d = (*z)[p];
      const Eigen::Vector3d point((*px)[p], (*py)[p], (*pz)[p]);
      const bool sky_depth = d == INFINITY;
      const bool sky_point = !point.allFinite();
      if (sky_depth || sky_point) {
        if (sky_depth != sky_point)
          bad.Add(x, y, sky_depth ? "sky depth, finite position" : "finite depth, sky position");
        continue;
      }
      if (!std::isfinite(d)) continue;  // layer.depth-finite
      const Eigen::Vector3d in_cam = UnprojectDepth(camera, {x + 0.5, y + 0.5}, d, kind);
      const Eigen::Vector3d back_projected = world_from_cam * (in_cam - t);
      const double e = (back_projected - point).norm();
      error.max = std::max(error.max, e);
      error.sum_squares += e * e;
      ++error.count;
      if (!(e <= 1e-4 * d + 1e-4)) {
        bad.Add(x, y, "error " + Fmt(e) + " at depth " + Fmt(d));
      }
    }
  }
  outcome_.statistics.push_back({"cross.worldpos-depth.error", error});
  if (bad.count > 0) {
    Emit("cross.worldpos-depth",
         Location::Pixel(FileOf("worldposition"), frame_.index, bad.x, bad.y),
         std::to_string(bad.count) + " pixel(s) whose world position is not the " +
             DepthKindName(kind) + " depth of " + FileOf("depth") +
             " back-projected through the declared camera (max error " + Fmt(error.max) + ", RMS " +
             Fmt(error.rms()) + " world units); first: " + bad.first_detail);
  }
}

// The first frame of a shot has nothing to move from: every motion value must be NaN.
void FrameChecker::CheckShotStartMotion(const std::vector<float>& mx,
                                        const std::vector<float>& my) {
  PixelTally bad;
  for (int y = 0; y < height_; ++y)
    for (int x = 0; x < width_; ++x) {
      const size_t p = static_cast<size_t>(y) * width_ + x;
      if (!std::isnan(mx[p]) || !std::isnan(my[p]))
        bad.Add(x, y, "motion (" + Fmt(mx[p]) + ", " + Fmt(my[p]) + ")");
    }
  EmitTally("cross.motion-invalid",
            FileOf("motion"),
            bad,
            "with a motion value on the first frame of a shot (expected NaN)");
}

// The motion of each pixel against the camera motion since the previous frame: a static
// world point moves by the pose change alone; a point the previous camera did not see must be
// marked NaN.
void FrameChecker::CheckMotion() {
  const auto *mx = Channel("motion", 0), *my = Channel("motion", 1);
  if (!mx || !my) return;
  if (input_.shot_start && Selected("cross.motion-invalid")) CheckShotStartMotion(*mx, *my);
  if (!input_.previous_camera) return;
  const bool check_pose = Selected("cross.motion-pose");
  const bool check_invalid = Selected("cross.motion-invalid");
  if (!check_pose && !check_invalid) return;
  const auto *px = Channel("worldposition", 0), *py = Channel("worldposition", 1),
             *pz = Channel("worldposition", 2);
  if (!px || !py || !pz) return;
  const CameraTruth& previous = *input_.previous_camera;
  const MovedBoxes moved = MovedSincePrevious(input_);
  const std::vector<uint32_t>* instances = moved.empty() ? nullptr : Ids("instanceid");
  int64_t checked = 0, unseen = 0;
  PixelTally bad, unmarked;
  for (int y = 0; y < height_; ++y) {
    for (int x = 0; x < width_; ++x) {
      const size_t p = static_cast<size_t>(y) * width_ + x;
      Eigen::Vector3d point((*px)[p], (*py)[p], (*pz)[p]);
      if (!point.allFinite()) continue;
      const bool marked = std::isnan((*mx)[p]);
      if (instances) point = PointThen(moved, (*instances)[p], point);
      Eigen::Vector2d before(0, 0);
      if (!SeenBy(previous, point, &before)) {
        ++unseen;
        if (!marked)
          unmarked.Add(x,
                       y,
                       "motion (" + Fmt((*mx)[p]) + ", " + Fmt((*my)[p]) +
                           ") for a point the previous camera did not see");
        continue;
      }
      if (marked) continue;  // disoccluded or moved: no static expectation
      const Eigen::Vector2d shift = Eigen::Vector2d(x + 0.5, y + 0.5) - before;
      const double ex = 0.5 + 0.5 * shift.x() / width_, ey = 0.5 + 0.5 * shift.y() / height_;
      ++checked;
      if (std::abs((*mx)[p] - ex) > 2e-3 || std::abs((*my)[p] - ey) > 2e-3) {
        bad.Add(x,
                y,
                "motion (" + Fmt((*mx)[p]) + ", " + Fmt((*my)[p]) + "), pose change says (" +
                    Fmt(ex) + ", " + Fmt(ey) + ")");
      }
    }
  }
  // Moving objects legitimately differ; a large share of disagreeing pixels is
  // a defect.
  if (check_pose && checked > 0 && bad.count > checked / 10) {
    Emit("cross.motion-pose",
         Location::Pixel(FileOf("motion"), frame_.index, bad.x, bad.y),
         std::to_string(bad.count) + " of " + std::to_string(checked) +
             " pixels disagree with the camera motion since the previous "
             "frame; first: " +
             bad.first_detail);
  }
  if (check_invalid && unseen > 0 && unmarked.count > unseen / 10) {
    Emit("cross.motion-invalid",
         Location::Pixel(FileOf("motion"), frame_.index, unmarked.x, unmarked.y),
         std::to_string(unmarked.count) + " of " + std::to_string(unseen) +
             " pixels that the previous frame's camera did not see carry a "
             "motion value instead of NaN; first: " +
             unmarked.first_detail);
  }
}

void FrameChecker::CheckCamera() {
  if (!context_.checks->HasGroup("camera")) return;
  const FlatImage* worldposition = Flat("worldposition");
  const LayerInfo* wp_layer = Layer("worldposition");
  if (!worldposition || !wp_layer || wp_layer->channels.size() < 3) return;
  CameraCheckInput in;
  in.frame = &frame_;
  in.worldposition = worldposition;
  in.worldposition_file = FileOf("worldposition");
  if (const LayerInfo* depth_layer = Layer("depth"); depth_layer && Flat("depth")) {
    in.depth = Flat("depth");
    in.depth_channel = depth_layer->channels[0].name;
    in.depth_file = FileOf("depth");
    in.depth_kind = depth_layer->depth_kind.value_or(DepthKind::kPlanar);
  }
  in.grid = context_.camera_grid;
  const double rms = CheckCameraGeometry(in, *context_.checks, &outcome_.findings);
  if (rms >= 0) {
    Statistic s;
    s.max = rms, s.sum_squares = rms * rms, s.count = 1;
    outcome_.statistics.push_back({"camera.reprojection_rms_px", s});
  }
}

}  // namespace lsds::validate::detail

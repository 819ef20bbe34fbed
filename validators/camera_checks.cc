#include "validators/camera_checks.h"

#include "libs/util/strings.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "libs/util/plugin.h"
#include "validators/camera_solver_abi.h"

namespace lsds::validate {

namespace {

constexpr double kPixelTolerance = 0.5;   // RMS reprojection error accepted, pixels
constexpr double kFocalTolerance = 5e-3;  // relative
constexpr double kDepthTolerance = 1e-3;  // relative

std::string Fmt(double v, int precision = 4) { return FormatNumber(v, precision); }

double HfovDeg(double fx, int width) {
  return 2 * std::atan(width / (2 * std::abs(fx))) * 180 / M_PI;
}

struct Correspondences {
  std::vector<Eigen::Vector2d> pixels;  // pixel centres
  std::vector<Eigen::Vector3d> points;  // world
  std::vector<double> depths;           // depth layer value (NaN when absent)
  std::vector<Eigen::Vector2i> where;
};

double RmsReprojection(const Correspondences& c,
                       const PinholeCamera& camera,
                       const Eigen::Matrix3d& r,
                       const Eigen::Vector3d& t,
                       const Eigen::Vector3d& point_sign = Eigen::Vector3d::Ones(),
                       bool flip_u = false,
                       bool flip_v = false) {
  double sum = 0;
  for (size_t k = 0; k < c.points.size(); ++k) {
    const Eigen::Vector3d in_cam = r * c.points[k].cwiseProduct(point_sign) + t;
    Eigen::Vector2d pixel = c.pixels[k];
    if (flip_u) pixel.x() = camera.width - pixel.x();
    if (flip_v) pixel.y() = camera.height - pixel.y();
    double e2 = 1e12;
    if (in_cam.z() > 0) e2 = (camera.ImageFromCam(in_cam) - pixel).squaredNorm();
    sum += std::min(e2, 1e12);
  }
  return c.points.empty() ? 0 : std::sqrt(sum / c.points.size());
}

}  // namespace

CameraSolution SolveCamera(const std::vector<Eigen::Vector2d>& pixels,
                           const std::vector<Eigen::Vector3d>& points_in_world,
                           const CameraSolution& initial,
                           bool solve_pose) {
  return PluginTable<CameraSolverTable>(
             kCameraSolverPlugin, kCameraSolverEntry, kCameraSolverAbiVersion)
      .solve(pixels, points_in_world, initial, solve_pose);
}

namespace {

double Median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

// The units a depth layer is often written in by mistake: the factor of the depth to the
// distance, and what it means.
const std::vector<std::pair<double, std::string>>& DepthUnitMistakes() {
  static const std::vector<std::pair<double, std::string>> mistakes = {
      {100,
       "centimetres in a metre collection (or metres in a cm one, "
       "0.01)"},
      {1000, "millimetres in a metre collection"},
      {10, "millimetres in a centimetre collection"},
      {0.01, "metres in a centimetre collection"},
      {0.001, "metres in a millimetre collection"},
      {0.1, "centimetres in a millimetre collection"}};
  return mistakes;
}

// One frame's camera geometry check. Its stages, each a method: sample the world-position
// layer on a grid; check the depth against the declared pose; if the declared camera does not
// reproject the points, look for the explanation from the simplest (a mirrored axis or
// image) to the costliest (solve the intrinsics, then intrinsics and pose).
class CameraGeometryCheck {
 public:
  CameraGeometryCheck(const CameraCheckInput& input,
                      const CheckSelection& checks,
                      std::vector<Finding>* findings)
      : input_(input),
        checks_(checks),
        findings_(findings),
        frame_(*input.frame),
        camera_(frame_.camera.intrinsics),
        r_(frame_.camera.cam_from_world_rotation),
        t_(frame_.camera.cam_from_world_translation) {}

  double Run() {
    const exr::FlatChannel* depth = SampleCorrespondences();
    if (c_.points.size() < 8) return -1;
    // Depth against the declared pose: needs only the pose, so it is independent
    // of the intrinsics.
    if (depth) CheckDepth();
    declared_rms_ = RmsReprojection(c_, camera_, r_, t_);
    if (declared_rms_ <= kPixelTolerance) return declared_rms_;
    if (FindMirror()) return declared_rms_;
    SolveAndExplain();
    return declared_rms_;
  }

 private:
  // The world-position points (and depths) at the centres of a grid of pixels; returns the
  // depth channel, nullptr without a usable one. Leaves c_ empty without world positions.
  const exr::FlatChannel* SampleCorrespondences() {
    const exr::FlatImage& wp = *input_.worldposition;
    const exr::FlatChannel* cx = wp.Find("X");
    const exr::FlatChannel* cy = wp.Find("Y");
    const exr::FlatChannel* cz = wp.Find("Z");
    if (!cx || !cy || !cz || cx->floats.empty() || cy->floats.empty() || cz->floats.empty())
      return nullptr;
    const exr::FlatChannel* depth =
        input_.depth ? input_.depth->Find(input_.depth_channel) : nullptr;
    if (depth && depth->floats.size() != input_.depth->pixel_count()) depth = nullptr;
    const int grid = std::max(4, input_.grid);
    const int w = wp.width(), h = wp.height();
    for (int b = 0; b < grid; ++b) {
      for (int a = 0; a < grid; ++a) {
        const int x = std::min(w - 1, static_cast<int>((a + 0.5) * w / grid));
        const int y = std::min(h - 1, static_cast<int>((b + 0.5) * h / grid));
        const size_t p = wp.Index(x, y);
        const Eigen::Vector3d point(cx->floats[p], cy->floats[p], cz->floats[p]);
        if (!point.allFinite()) continue;
        c_.pixels.push_back({x + 0.5, y + 0.5});
        c_.points.push_back(point);
        c_.depths.push_back(depth ? depth->floats[p] : NAN);
        c_.where.push_back({x, y});
      }
    }
    return depth;
  }

  void Emit(const std::string& id, const std::string& file, const std::string& message) {
    if (!checks_.Has(id)) return;
    Location where(file);
    where.frame = frame_.index;
    findings_->push_back({GetCheck(id).severity, id, where, "", message});
  }

  // The median ratio of the depth to the planar and to the perspective distance of the points
  // says whether the depth is in another unit or of the other kind.
  void CheckDepth() {
    std::vector<double> planar_ratio, perspective_ratio;
    for (size_t k = 0; k < c_.points.size(); ++k) {
      const double d = c_.depths[k];
      if (!std::isfinite(d) || d <= 0) continue;
      const Eigen::Vector3d in_cam = r_ * c_.points[k] + t_;
      if (in_cam.z() <= 0) continue;
      planar_ratio.push_back(d / in_cam.z());
      perspective_ratio.push_back(d / in_cam.norm());
    }
    if (planar_ratio.size() < 8) return;
    const bool planar = input_.depth_kind == DepthKind::kPlanar;
    const double declared = Median(planar ? planar_ratio : perspective_ratio);
    const double other = Median(planar ? perspective_ratio : planar_ratio);
    if (!(std::abs(declared - 1) > kDepthTolerance)) return;  // a NaN ratio stops here too
    if (CheckDepthUnit(declared, other)) return;
    if (std::abs(other - 1) <= kDepthTolerance) {
      const DepthKind actual = planar ? DepthKind::kPerspective : DepthKind::kPlanar;
      Emit("camera.depth-kind",
           input_.depth_file,
           std::string("depth is declared ") + DepthKindName(input_.depth_kind) +
               " but the data is " + DepthKindName(actual) + " (median ratio to " +
               DepthKindName(input_.depth_kind) + " distance " + Fmt(declared, 6) + ", to " +
               DepthKindName(actual) + " " + Fmt(other, 6) + ")");
    }
  }

  // A ratio (to either distance) within 1% of a unit mistake's factor; returns whether found.
  bool CheckDepthUnit(double declared, double other) {
    for (const auto& [factor, name] : DepthUnitMistakes()) {
      for (double candidate : {declared, other}) {
        if (std::abs(candidate / factor - 1) < 0.01) {
          Emit("camera.depth-unit",
               input_.depth_file,
               "depth is " + Fmt(candidate, 6) +
                   " x the distance to the world-position points: " + "depth looks like " + name);
          return true;
        }
      }
    }
    return false;
  }

  // 1. Mirrors: a world axis (handedness) or an image axis flipped explain the
  // data exactly. Returns whether one did.
  bool FindMirror() {
    const char* axis_names[3] = {"x", "y", "z"};
    for (int axis = 0; axis < 3; ++axis) {
      Eigen::Vector3d sign = Eigen::Vector3d::Ones();
      sign[axis] = -1;
      const double rms = RmsReprojection(c_, camera_, r_, t_, sign);
      if (rms <= kPixelTolerance) {
        Emit("camera.handedness",
             input_.worldposition_file,
             std::string("the world-position layer has its ") + axis_names[axis] +
                 " axis mirrored: negating " + axis_names[axis] + " reprojects with RMS " +
                 Fmt(rms) + " px, the data as stored " + Fmt(declared_rms_) +
                 " px (flipped handedness or axis)");
        return true;
      }
    }
    for (int flip = 1; flip <= 3; ++flip) {
      const bool flip_u = flip & 1, flip_v = flip & 2;
      const double rms =
          RmsReprojection(c_, camera_, r_, t_, Eigen::Vector3d::Ones(), flip_u, flip_v);
      if (rms <= kPixelTolerance) {
        Emit("camera.image-flip",
             input_.worldposition_file,
             std::string("the layers are stored ") +
                 (flip_u && flip_v ? "rotated by 180 degrees"
                  : flip_v         ? "upside down (image y flipped)"
                                   : "mirrored (image x flipped)") +
                 ": flipped they reproject with RMS " + Fmt(rms) + " px, as stored " +
                 Fmt(declared_rms_) + " px");
        return true;
      }
    }
    return false;
  }

  // 2. Intrinsics with the declared pose, then intrinsics and pose together.
  void SolveAndExplain() {
    if (r_.determinant() <= 0) {
      Emit("camera.pose",
           input_.worldposition_file,
           "the declared camera reprojects the world-position layer with RMS " +
               Fmt(declared_rms_) +
               " px; the rotation is not proper (left-handed world), no solve "
               "attempted");
      return;
    }
    CameraSolution initial;
    initial.fx = camera_.fx;
    initial.fy = camera_.fy;
    initial.cx = camera_.cx;
    initial.cy = camera_.cy;
    initial.cam_from_world_rotation = r_;
    initial.cam_from_world_translation = t_;
    CameraSolution solution = SolveCamera(c_.pixels, c_.points, initial, /*solve_pose=*/false);
    bool pose_solved = false;
    if (!solution.solved || solution.rms_px > kPixelTolerance) {
      solution = SolveCamera(c_.pixels,
                             c_.points,
                             solution.solved ? solution : initial,
                             /*solve_pose=*/true);
      pose_solved = true;
    }
    if (!solution.solved || solution.rms_px > kPixelTolerance) {
      Emit("camera.pose",
           input_.worldposition_file,
           "no pinhole camera explains the world-position layer: the declared "
           "camera reprojects it with RMS " +
               Fmt(declared_rms_) + " px, the best solved one with " + Fmt(solution.rms_px) +
               " px");
      return;
    }
    const bool explained = ExplainIntrinsics(solution);
    if (pose_solved || !explained) ReportPose(solution);
  }

  // The solved intrinsics against the declared ones; returns whether they explain the data.
  bool ExplainIntrinsics(const CameraSolution& solution) {
    const double fx_ratio = solution.fx / camera_.fx, fy_ratio = solution.fy / camera_.fy;
    bool explained = false;
    if (std::abs(fx_ratio - 1) > kFocalTolerance || std::abs(fy_ratio - 1) > kFocalTolerance) {
      const std::string camera_text = "declared camera fx " + Fmt(camera_.fx, 6) + ", fy " +
                                      Fmt(camera_.fy, 6) + " (hfov " +
                                      Fmt(camera_.HorizontalFovDeg(), 5) + " deg)";
      std::string message = camera_text + " but the world-position layer says fx " +
                            Fmt(solution.fx, 6) + ", fy " + Fmt(solution.fy, 6) + " (hfov " +
                            Fmt(HfovDeg(solution.fx, camera_.width), 5) + " deg; solved RMS " +
                            Fmt(solution.rms_px) + " px)";
      for (double unit : {1000.0, 25.4, 10.0}) {
        for (double ratio : {fx_ratio, 1 / fx_ratio}) {
          if (std::abs(ratio / unit - 1) < 0.05) {
            message += "; the ratio " + Fmt(fx_ratio, 6) +
                       " suggests a focal length in the wrong unit (mm vs px?)";
          }
        }
      }
      Emit("camera.fov", input_.worldposition_file, message);
      explained = true;
    }
    if (std::abs(solution.cx - camera_.cx) > 0.5 || std::abs(solution.cy - camera_.cy) > 0.5) {
      Emit("camera.principal-point",
           input_.worldposition_file,
           "declared principal point (" + Fmt(camera_.cx, 6) + ", " + Fmt(camera_.cy, 6) +
               ") but the world-position layer says (" + Fmt(solution.cx, 6) + ", " +
               Fmt(solution.cy, 6) + ")");
      explained = true;
    }
    return explained;
  }

  // How far the solved pose is from the declared one.
  void ReportPose(const CameraSolution& solution) {
    const Eigen::Matrix3d delta = solution.cam_from_world_rotation * r_.transpose();
    const double angle = std::acos(std::clamp((delta.trace() - 1) / 2, -1.0, 1.0)) * 180 / M_PI;
    const Eigen::Vector3d declared_centre = -r_.transpose() * t_;
    const Eigen::Vector3d solved_centre =
        -solution.cam_from_world_rotation.transpose() * solution.cam_from_world_translation;
    Emit("camera.pose",
         input_.worldposition_file,
         "the declared pose does not explain the world-position layer (RMS " + Fmt(declared_rms_) +
             " px): the solved camera is rotated by " + Fmt(angle) +
             " deg and its centre moved by " + Fmt((solved_centre - declared_centre).norm()) +
             " world units");
  }

  const CameraCheckInput& input_;
  const CheckSelection& checks_;
  std::vector<Finding>* findings_;
  const Frame& frame_;
  const PinholeCamera& camera_;
  const Eigen::Matrix3d& r_;
  const Eigen::Vector3d& t_;
  Correspondences c_;
  double declared_rms_ = 0;
};

}  // namespace

double CheckCameraGeometry(const CameraCheckInput& input,
                           const CheckSelection& checks,
                           std::vector<Finding>* findings) {
  return CameraGeometryCheck(input, checks, findings).Run();
}

}  // namespace lsds::validate

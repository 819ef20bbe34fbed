#include "validators/camera_checks.h"

#include "libs/util/strings.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <ceres/ceres.h>
#include <ceres/rotation.h>

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

struct ReprojectionCost {
  ReprojectionCost(const Eigen::Vector2d& pixel, const Eigen::Vector3d& point)
      : pixel_(pixel), point_(point) {}
  template <typename T>
  bool operator()(const T* intrinsics, const T* rotation, const T* translation, T* residual) const {
    const T point[3] = {T(point_.x()), T(point_.y()), T(point_.z())};
    T in_cam[3];
    ceres::AngleAxisRotatePoint(rotation, point, in_cam);
    for (int i = 0; i < 3; ++i) in_cam[i] += translation[i];
    if (in_cam[2] <= T(1e-9)) in_cam[2] = T(1e-9);
    residual[0] = intrinsics[0] * in_cam[0] / in_cam[2] + intrinsics[2] - T(pixel_.x());
    residual[1] = intrinsics[1] * in_cam[1] / in_cam[2] + intrinsics[3] - T(pixel_.y());
    return true;
  }
  Eigen::Vector2d pixel_;
  Eigen::Vector3d point_;
};

}  // namespace

CameraSolution SolveCamera(const std::vector<Eigen::Vector2d>& pixels,
                           const std::vector<Eigen::Vector3d>& points_in_world,
                           const CameraSolution& initial,
                           bool solve_pose) {
  double intrinsics[4] = {initial.fx, initial.fy, initial.cx, initial.cy};
  double rotation[3];
  const Eigen::Matrix3d r = initial.cam_from_world_rotation;
  ceres::RotationMatrixToAngleAxis(ceres::ColumnMajorAdapter3x3(r.data()), rotation);
  double translation[3] = {initial.cam_from_world_translation.x(),
                           initial.cam_from_world_translation.y(),
                           initial.cam_from_world_translation.z()};
  ceres::Problem problem;
  for (size_t k = 0; k < pixels.size(); ++k) {
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<ReprojectionCost, 2, 4, 3, 3>(
                                 new ReprojectionCost(pixels[k], points_in_world[k])),
                             new ceres::CauchyLoss(1.0),
                             intrinsics,
                             rotation,
                             translation);
  }
  if (!solve_pose) {
    problem.SetParameterBlockConstant(rotation);
    problem.SetParameterBlockConstant(translation);
  }
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = 200;
  options.function_tolerance = 1e-14;
  options.parameter_tolerance = 1e-14;
  options.gradient_tolerance = 1e-16;
  options.num_threads = 1;  // frames already run in parallel
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);

  CameraSolution out;
  out.solved = summary.IsSolutionUsable();
  out.fx = intrinsics[0], out.fy = intrinsics[1], out.cx = intrinsics[2], out.cy = intrinsics[3];
  Eigen::Matrix3d solved_rotation;
  ceres::AngleAxisToRotationMatrix(rotation, ceres::ColumnMajorAdapter3x3(solved_rotation.data()));
  out.cam_from_world_rotation = solved_rotation;
  out.cam_from_world_translation = Eigen::Vector3d(translation[0], translation[1], translation[2]);
  double sum = 0;
  for (size_t k = 0; k < pixels.size(); ++k) {
    const Eigen::Vector3d in_cam =
        solved_rotation * points_in_world[k] + out.cam_from_world_translation;
    const Eigen::Vector2d uv(out.fx * in_cam.x() / in_cam.z() + out.cx,
                             out.fy * in_cam.y() / in_cam.z() + out.cy);
    sum += in_cam.z() > 0 ? (uv - pixels[k]).squaredNorm() : 1e12;
  }
  out.rms_px = pixels.empty() ? 0 : std::sqrt(sum / pixels.size());
  return out;
}

double CheckCameraGeometry(const CameraCheckInput& input,
                           const CheckSelection& checks,
                           std::vector<Finding>* findings) {
  const Frame& frame = *input.frame;
  const PinholeCamera& camera = frame.camera.intrinsics;
  const Eigen::Matrix3d& r = frame.camera.cam_from_world_rotation;
  const Eigen::Vector3d& t = frame.camera.cam_from_world_translation;
  const exr::FlatImage& wp = *input.worldposition;
  const exr::FlatChannel* cx = wp.Find("X");
  const exr::FlatChannel* cy = wp.Find("Y");
  const exr::FlatChannel* cz = wp.Find("Z");
  if (!cx || !cy || !cz || cx->floats.empty() || cy->floats.empty() || cz->floats.empty())
    return -1;
  const exr::FlatChannel* depth = input.depth ? input.depth->Find(input.depth_channel) : nullptr;
  if (depth && depth->floats.size() != input.depth->pixel_count()) depth = nullptr;

  Correspondences c;
  const int grid = std::max(4, input.grid);
  const int w = wp.width(), h = wp.height();
  for (int b = 0; b < grid; ++b) {
    for (int a = 0; a < grid; ++a) {
      const int x = std::min(w - 1, static_cast<int>((a + 0.5) * w / grid));
      const int y = std::min(h - 1, static_cast<int>((b + 0.5) * h / grid));
      const size_t p = wp.Index(x, y);
      const Eigen::Vector3d point(cx->floats[p], cy->floats[p], cz->floats[p]);
      if (!point.allFinite()) continue;
      c.pixels.push_back({x + 0.5, y + 0.5});
      c.points.push_back(point);
      c.depths.push_back(depth ? depth->floats[p] : NAN);
      c.where.push_back({x, y});
    }
  }
  if (c.points.size() < 8) return -1;

  auto emit = [&](const std::string& id, const std::string& file, const std::string& message) {
    if (!checks.Has(id)) return;
    Location where(file);
    where.frame = frame.index;
    findings->push_back({GetCheck(id).severity, id, where, "", message});
  };
  const std::string camera_text = "declared camera fx " + Fmt(camera.fx, 6) + ", fy " +
                                  Fmt(camera.fy, 6) + " (hfov " +
                                  Fmt(camera.HorizontalFovDeg(), 5) + " deg)";

  // Depth against the declared pose: needs only the pose, so it is independent
  // of the intrinsics.
  if (depth) {
    std::vector<double> planar_ratio, perspective_ratio;
    for (size_t k = 0; k < c.points.size(); ++k) {
      const double d = c.depths[k];
      if (!std::isfinite(d) || d <= 0) continue;
      const Eigen::Vector3d in_cam = r * c.points[k] + t;
      if (in_cam.z() <= 0) continue;
      planar_ratio.push_back(d / in_cam.z());
      perspective_ratio.push_back(d / in_cam.norm());
    }
    auto median = [](std::vector<double> v) {
      std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
      return v[v.size() / 2];
    };
    if (planar_ratio.size() >= 8) {
      const double declared =
          median(input.depth_kind == DepthKind::kPlanar ? planar_ratio : perspective_ratio);
      const double other =
          median(input.depth_kind == DepthKind::kPlanar ? perspective_ratio : planar_ratio);
      if (std::abs(declared - 1) > kDepthTolerance) {
        bool unit = false;
        for (const auto& [factor, name] : std::vector<std::pair<double, std::string>>{
                 {100,
                  "centimetres in a metre collection (or metres in a cm one, "
                  "0.01)"},
                 {1000, "millimetres in a metre collection"},
                 {10, "millimetres in a centimetre collection"},
                 {0.01, "metres in a centimetre collection"},
                 {0.001, "metres in a millimetre collection"},
                 {0.1, "centimetres in a millimetre collection"}}) {
          for (double candidate : {declared, other}) {
            if (std::abs(candidate / factor - 1) < 0.01 && !unit) {
              unit = true;
              emit("camera.depth-unit",
                   input.depth_file,
                   "depth is " + Fmt(candidate, 6) +
                       " x the distance to the world-position points: " + "depth looks like " +
                       name);
            }
          }
        }
        if (!unit && std::abs(other - 1) <= kDepthTolerance) {
          const DepthKind actual =
              input.depth_kind == DepthKind::kPlanar ? DepthKind::kPerspective : DepthKind::kPlanar;
          emit("camera.depth-kind",
               input.depth_file,
               std::string("depth is declared ") + DepthKindName(input.depth_kind) +
                   " but the data is " + DepthKindName(actual) + " (median ratio to " +
                   DepthKindName(input.depth_kind) + " distance " + Fmt(declared, 6) + ", to " +
                   DepthKindName(actual) + " " + Fmt(other, 6) + ")");
        }
      }
    }
  }

  const double declared_rms = RmsReprojection(c, camera, r, t);
  if (declared_rms <= kPixelTolerance) return declared_rms;

  // 1. Mirrors: a world axis (handedness) or an image axis flipped explain the
  // data exactly.
  const char* axis_names[3] = {"x", "y", "z"};
  for (int axis = 0; axis < 3; ++axis) {
    Eigen::Vector3d sign = Eigen::Vector3d::Ones();
    sign[axis] = -1;
    const double rms = RmsReprojection(c, camera, r, t, sign);
    if (rms <= kPixelTolerance) {
      emit("camera.handedness",
           input.worldposition_file,
           std::string("the world-position layer has its ") + axis_names[axis] +
               " axis mirrored: negating " + axis_names[axis] + " reprojects with RMS " + Fmt(rms) +
               " px, the data as stored " + Fmt(declared_rms) + " px (flipped handedness or axis)");
      return declared_rms;
    }
  }
  for (int flip = 1; flip <= 3; ++flip) {
    const bool flip_u = flip & 1, flip_v = flip & 2;
    const double rms = RmsReprojection(c, camera, r, t, Eigen::Vector3d::Ones(), flip_u, flip_v);
    if (rms <= kPixelTolerance) {
      emit("camera.image-flip",
           input.worldposition_file,
           std::string("the layers are stored ") +
               (flip_u && flip_v ? "rotated by 180 degrees"
                : flip_v         ? "upside down (image y flipped)"
                                 : "mirrored (image x flipped)") +
               ": flipped they reproject with RMS " + Fmt(rms) + " px, as stored " +
               Fmt(declared_rms) + " px");
      return declared_rms;
    }
  }

  // 2. Intrinsics with the declared pose, then intrinsics and pose together.
  if (r.determinant() <= 0) {
    emit("camera.pose",
         input.worldposition_file,
         "the declared camera reprojects the world-position layer with RMS " + Fmt(declared_rms) +
             " px; the rotation is not proper (left-handed world), no solve "
             "attempted");
    return declared_rms;
  }
  CameraSolution initial;
  initial.fx = camera.fx, initial.fy = camera.fy, initial.cx = camera.cx, initial.cy = camera.cy;
  initial.cam_from_world_rotation = r;
  initial.cam_from_world_translation = t;
  CameraSolution solution = SolveCamera(c.pixels, c.points, initial, /*solve_pose=*/false);
  bool pose_solved = false;
  if (!solution.solved || solution.rms_px > kPixelTolerance) {
    solution = SolveCamera(c.pixels,
                           c.points,
                           solution.solved ? solution : initial,
                           /*solve_pose=*/true);
    pose_solved = true;
  }
  if (!solution.solved || solution.rms_px > kPixelTolerance) {
    emit("camera.pose",
         input.worldposition_file,
         "no pinhole camera explains the world-position layer: the declared "
         "camera reprojects it with RMS " +
             Fmt(declared_rms) + " px, the best solved one with " + Fmt(solution.rms_px) + " px");
    return declared_rms;
  }
  const double fx_ratio = solution.fx / camera.fx, fy_ratio = solution.fy / camera.fy;
  bool explained = false;
  if (std::abs(fx_ratio - 1) > kFocalTolerance || std::abs(fy_ratio - 1) > kFocalTolerance) {
    std::string message = camera_text + " but the world-position layer says fx " +
                          Fmt(solution.fx, 6) + ", fy " + Fmt(solution.fy, 6) + " (hfov " +
                          Fmt(HfovDeg(solution.fx, camera.width), 5) + " deg; solved RMS " +
                          Fmt(solution.rms_px) + " px)";
    for (double unit : {1000.0, 25.4, 10.0}) {
      for (double ratio : {fx_ratio, 1 / fx_ratio}) {
        if (std::abs(ratio / unit - 1) < 0.05) {
          message += "; the ratio " + Fmt(fx_ratio, 6) +
                     " suggests a focal length in the wrong unit (mm vs px?)";
        }
      }
    }
    emit("camera.fov", input.worldposition_file, message);
    explained = true;
  }
  if (std::abs(solution.cx - camera.cx) > 0.5 || std::abs(solution.cy - camera.cy) > 0.5) {
    emit("camera.principal-point",
         input.worldposition_file,
         "declared principal point (" + Fmt(camera.cx, 6) + ", " + Fmt(camera.cy, 6) +
             ") but the world-position layer says (" + Fmt(solution.cx, 6) + ", " +
             Fmt(solution.cy, 6) + ")");
    explained = true;
  }
  if (pose_solved || !explained) {
    const Eigen::Matrix3d delta = solution.cam_from_world_rotation * r.transpose();
    const double angle = std::acos(std::clamp((delta.trace() - 1) / 2, -1.0, 1.0)) * 180 / M_PI;
    const Eigen::Vector3d declared_centre = -r.transpose() * t;
    const Eigen::Vector3d solved_centre =
        -solution.cam_from_world_rotation.transpose() * solution.cam_from_world_translation;
    emit("camera.pose",
         input.worldposition_file,
         "the declared pose does not explain the world-position layer (RMS " + Fmt(declared_rms) +
             " px): the solved camera is rotated by " + Fmt(angle) +
             " deg and its centre moved by " + Fmt((solved_centre - declared_centre).norm()) +
             " world units");
  }
  return declared_rms;
}

}  // namespace lsds::validate

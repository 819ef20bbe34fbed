// The camera-solver plug-in: SolveCamera (validators/camera_checks.h) with Ceres, the only code of
// the product that links it. Built as a CMake MODULE (docs/architecture.md, "Plug-ins").
#include <cmath>

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include "validators/camera_solver_abi.h"

namespace lsds::validate {
namespace {

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

CameraSolution Solve(const std::vector<Eigen::Vector2d>& pixels,
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

const CameraSolverTable kTable = {kCameraSolverAbiVersion, Solve};

}  // namespace
}  // namespace lsds::validate

extern "C" __attribute__((visibility("default"))) const lsds::validate::CameraSolverTable*
lsds_camera_solver_table() {
  return &lsds::validate::kTable;
}

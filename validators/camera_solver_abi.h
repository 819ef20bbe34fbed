// The boundary between lsds and its camera-solver plug-in (validators/camera_solver_plugin.cc),
// the only code that links Ceres (and through it glog, gflags, SuiteSparse and the BLAS/LAPACK
// stack). The camera checks (camera_checks.h) call it only when the declared camera does not
// explain a frame's layers, so `lsds validate` on a good collection never loads it. One extern "C"
// entry point returns a table of function pointers; both sides are built in one tree with the
// same Eigen and libstdc++, so std::vector and Eigen matrices cross by reference.
#pragma once

#include <vector>

#include <Eigen/Core>

namespace lsds::validate {

// A pinhole camera solved from correspondences.
struct CameraSolution {
  bool solved = false;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  Eigen::Matrix3d cam_from_world_rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d cam_from_world_translation = Eigen::Vector3d::Zero();
  double rms_px = 0;
};

// Raised whenever the table's layout or meaning changes; the loader refuses any other value.
constexpr int kCameraSolverAbiVersion = 1;

struct CameraSolverTable {
  int abi_version;
  // SolveCamera's contract (camera_checks.h).
  CameraSolution (*solve)(const std::vector<Eigen::Vector2d>& pixels,
                          const std::vector<Eigen::Vector3d>& points_in_world,
                          const CameraSolution& initial,
                          bool solve_pose);
};

constexpr const char* kCameraSolverPlugin = "lsds_camera_solver.so";
constexpr const char* kCameraSolverEntry = "lsds_camera_solver_table";

}  // namespace lsds::validate

// Defined by the plug-in; looked up with dlsym by kCameraSolverEntry.
extern "C" const lsds::validate::CameraSolverTable* lsds_camera_solver_table();

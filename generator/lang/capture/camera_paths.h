// The camera's path generators (docs/languages.md, "Paths"): create hemi, grid and increment
// points, random poses, waypoints (a list of poses or a smooth flight), create point and create
// path; how many
// frames a path instance has and the camera pose of each.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "generator/lang/capture/camera_setup.h"
#include "generator/lang/capture/flight.h"
#include "generator/lang/capture/object_track.h"
#include "generator/lang/requirements.h"

namespace lsds {

// The canonical key of a path generator: `increment point` is `increment_points`.
std::string PathKind(const std::string& key);

class CameraPaths {
 public:
  // `plan` gives the terrain and the objects a pose may look at; `first_target` is the object a
  // hemi without a centre circles (the camera's first target); `capture` (may be null) the paths a
  // grid's point blueprint may name.
  CameraPaths(const CameraSetup& setup,
              const Plan& plan,
              uint64_t seed,
              std::string first_target,
              const Program* capture = nullptr)
      : setup_(setup),
        plan_(plan),
        seed_(seed),
        first_target_(std::move(first_target)),
        capture_(capture) {}

  // The number of frames of a path instance, checked; a count interval is drawn from the seed, on
  // the stream of the instance's place `segment` in the timeline.
  int64_t FrameCount(const Definition& path, uint64_t segment);
  // The same with the count interval drawn from `count_rng`.
  int64_t FrameCount(const Definition& path, Rng& count_rng);

  // A path other than a smooth flight as the track of an object's centre (object_track.h): the
  // centres of its poses in frame order, drawn from `rng` once (for the whole leg), with the arcs
  // of a hemi's rings; untimed. Object centres in it (a hemi centre, a look_at) are as planned.
  ObjectTrack Track(const Definition& path, Rng& rng);

  // Pose `i` of the path instance at place `segment`, drawn from `rng`; `velocity` is set on a
  // smooth flight. `demand` (may be null) is the frame's quota demand: a random pose's altitude
  // and off-nadir angle are drawn within its bins (importance sampling). `moved` are the frame's
  // scene changes: a look_at or hemi centre on an object aims where the object is on this frame.
  Rigid3d Pose(const Definition& path,
               int64_t i,
               Rng& rng,
               uint64_t segment,
               std::optional<Eigen::Vector3d>* velocity,
               const FrameDemand* demand,
               const std::vector<ObjectChange>& moved = {});

  // The first frame of the shot of pose `i` of a path instance starting at frame `first`
  // (docs/format.md, "Motion"): waypoints are flown in one shot, a grid in one shot per altitude
  // level (its rows are flown serpentine, the climb to the next level is a jump); every pose of
  // hemi, random and create point is a shot of its own.
  int64_t ShotStart(const Definition& path, int64_t first, int64_t i) const;

  // A rig camera's velocity at pose `i` of the smooth flight at place `segment`: the platform's
  // velocity plus the lever arm turning with the attitude, by a central difference of the camera
  // centre along the curve.
  Eigen::Vector3d RigCameraVelocity(const Definition& path,
                                    uint64_t segment,
                                    int64_t i,
                                    const Rigid3d& cam_from_rig);

 private:
  const Flight& FlightOf(const Node& g, uint64_t segment);
  Rigid3d HemiPose(const Node& g,
                   int64_t i,
                   Rng& rng,
                   const std::vector<ObjectChange>& moved) const;
  Rigid3d GridPose(const Node& g, int64_t i, Rng& rng) const;
  // The create point block a grid's `point` gives (inline or a path symbol), checked; null without.
  Node PointBlueprint(const Node& g) const;
  Rigid3d RandomPose(const Node& g, Rng& rng, const FrameDemand* demand) const;
  Rigid3d WaypointPose(const Node& w, Rng& rng, const std::vector<ObjectChange>& moved) const;
  Rigid3d PointPose(const Node& g, Rng& rng, const std::vector<ObjectChange>& moved) const;
  Rigid3d SpacePose(const Node& g, Rng& rng) const;
  Eigen::Vector3d Datum(Eigen::Vector3d p) const;
  Eigen::Vector3d Point(const Node& n, Rng& rng, const std::vector<ObjectChange>& moved) const;
  // Where the (first copy of the) object `symbol` is: planned, or as `moved` last placed it.
  Eigen::Vector3d ObjectCenter(const Node& where,
                               const std::string& symbol,
                               const std::vector<ObjectChange>& moved) const;

  const CameraSetup& setup_;
  const Plan& plan_;
  uint64_t seed_;
  std::string first_target_;
  const Program* capture_;
  std::map<uint64_t, Flight> flights_;  // by path instance (segment)
};

// A create path's space, checked: its low and high corners.
std::pair<Eigen::Vector3d, Eigen::Vector3d> SpaceOf(const Node& g);

// Grid axes: x and y positions and altitudes above the terrain (grid), or the points of
// `increment points` (start, step, count).
std::array<std::vector<double>, 3> GridAxes(const Node& g);

}  // namespace lsds

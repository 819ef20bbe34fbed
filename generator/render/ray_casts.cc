#include "generator/render/ray_casts.h"

#include <algorithm>
#include <limits>

#include "generator/render/embree_abi.h"

namespace lsds::gen {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// Lane i of a packet (RTCRay4/8/16) as the float ray the one-ray calls trace.
template <class RayN>
void SetLane(RayN* ray,
             int i,
             const Eigen::Vector3d& origin,
             const Eigen::Vector3d& direction,
             float tfar = kInf) {
  ray->org_x[i] = static_cast<float>(origin.x());
  ray->org_y[i] = static_cast<float>(origin.y());
  ray->org_z[i] = static_cast<float>(origin.z());
  ray->dir_x[i] = static_cast<float>(direction.x());
  ray->dir_y[i] = static_cast<float>(direction.y());
  ray->dir_z[i] = static_cast<float>(direction.z());
  ray->tnear[i] = 0.f;
  ray->tfar[i] = tfar;
  ray->mask[i] = 0xffffffffu;
  ray->flags[i] = 0;
  ray->time[i] = 0.f;
  ray->id[i] = 0;
}

// One packet of N lanes (RTCRayHitN with rtcIntersectN, N = 4, 8, 16); lanes
// past `count` are invalid.
template <int N, class RayHitN, class Intersect>
void TraceLanes(RTCScene rtc_scene,
                const Eigen::Vector3d& origin,
                const Eigen::Vector3d* directions,
                int count,
                RTCIntersectContext* context,
                Intersect intersect,
                EmbreeHit* out) {
  alignas(64) RayHitN rh;
  alignas(64) int valid[N];
  for (int i = 0; i < N; ++i) {
    valid[i] = i < count ? -1 : 0;
    SetLane(&rh.ray, i, origin, directions[i < count ? i : 0]);
    rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
  }
  intersect(valid, rtc_scene, context, &rh);
  for (int i = 0; i < count; ++i)
    out[i] = {rh.hit.geomID[i], rh.hit.primID[i], rh.hit.u[i], rh.hit.v[i], rh.ray.tfar[i]};
}

// One occlusion packet of N lanes (RTCRayN with rtcOccludedN, N = 4, 8, 16);
// lanes past `count` or not wanted are invalid. Lane i is rays.Lane(i).
template <int N, class RayN, class Rays, class OccludedN>
void OccludedLanes(RTCScene rtc_scene,
                   const Rays& rays,
                   const uint8_t* wanted,
                   int count,
                   RTCIntersectContext* context,
                   OccludedN occluded,
                   uint8_t* out) {
  alignas(64) RayN ray;
  alignas(64) int valid[N];
  for (int i = 0; i < N; ++i) {
    valid[i] = i < count && wanted[i] ? -1 : 0;
    // An invalid lane's ray may never have been set: it gets zeros.
    if (valid[i]) {
      rays.Lane(&ray, i);
    } else {
      SetLane(&ray, i, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ());
    }
  }
  occluded(valid, rtc_scene, context, &ray);
  for (int i = 0; i < count; ++i) out[i] = valid[i] && ray.tfar[i] < 0;
}

// `count` occlusion rays, kPacket at a time (rtcOccluded4/8/16).
template <class Rays>
void OccludedInPackets(RTCScene rtc_scene,
                       const Rays& rays,
                       const uint8_t* wanted,
                       int count,
                       RTCIntersectContext* context,
                       uint8_t* out) {
  for (int k = 0; k < count; k += kPacket) {
    const int n = std::min(kPacket, count - k);
    const auto from = rays.From(k);
    if (n <= 4) {
      OccludedLanes<4, RTCRay4>(
          rtc_scene, from, wanted + k, n, context, Embree().occluded4, out + k);
    } else if (n <= 8) {
      OccludedLanes<8, RTCRay8>(
          rtc_scene, from, wanted + k, n, context, Embree().occluded8, out + k);
    } else {
      OccludedLanes<16, RTCRay16>(
          rtc_scene, from, wanted + k, n, context, Embree().occluded16, out + k);
    }
  }
}

// Rays from `origins` in one direction, unbounded (shadow rays).
struct ParallelRays {
  const Eigen::Vector3d* origins;
  const Eigen::Vector3d& direction;
  ParallelRays From(int k) const { return {origins + k, direction}; }
  template <class RayN>
  void Lane(RayN* ray, int i) const {
    SetLane(ray, i, origins[i], direction);
  }
};

// Rays from one origin along `directions`, each `lengths` long.
struct Segments {
  const Eigen::Vector3d& origin;
  const Eigen::Vector3d* directions;
  const float* lengths;
  Segments From(int k) const { return {origin, directions + k, lengths + k}; }
  template <class RayN>
  void Lane(RayN* ray, int i) const {
    SetLane(ray, i, origin, directions[i], lengths[i]);
  }
};

// Rays from `origins` along `directions`, each `lengths` long.
struct OriginSegments {
  const Eigen::Vector3d* origins;
  const Eigen::Vector3d* directions;
  const float* lengths;
  OriginSegments From(int k) const { return {origins + k, directions + k, lengths + k}; }
  template <class RayN>
  void Lane(RayN* ray, int i) const {
    SetLane(ray, i, origins[i], directions[i], lengths[i]);
  }
};

}  // namespace

int BlockPixels(int block_row, int block_col, int width, int height, int* x, int* y) {
  int count = 0;
  const int y0 = block_row * kBlock, x0 = block_col * kBlock;
  for (int row = y0; row < std::min(y0 + kBlock, height); ++row) {
    for (int col = x0; col < std::min(x0 + kBlock, width); ++col) {
      x[count] = col;
      y[count] = row;
      ++count;
    }
  }
  return count;
}

void InitCoherentContext(RTCIntersectContext* context) {
  rtcInitIntersectContext(context);
  context->flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
}

void TraceRays(RTCScene rtc_scene,
               const Eigen::Vector3d& origin,
               const Eigen::Vector3d* directions,
               int count,
               RTCIntersectContext* context,
               EmbreeHit* out) {
  for (int k = 0; k < count; k += kPacket) {
    const int n = std::min(kPacket, count - k);
    if (n <= 4) {
      TraceLanes<4, RTCRayHit4>(
          rtc_scene, origin, directions + k, n, context, Embree().intersect4, out + k);
    } else if (n <= 8) {
      TraceLanes<8, RTCRayHit8>(
          rtc_scene, origin, directions + k, n, context, Embree().intersect8, out + k);
    } else {
      TraceLanes<16, RTCRayHit16>(
          rtc_scene, origin, directions + k, n, context, Embree().intersect16, out + k);
    }
  }
}

EmbreeHit TraceOne(RTCScene rtc_scene,
                   const Eigen::Vector3d& origin,
                   const Eigen::Vector3d& direction,
                   RTCIntersectContext* context) {
  RTCRayHit rh;
  rh.ray.org_x = static_cast<float>(origin.x());
  rh.ray.org_y = static_cast<float>(origin.y());
  rh.ray.org_z = static_cast<float>(origin.z());
  rh.ray.dir_x = static_cast<float>(direction.x());
  rh.ray.dir_y = static_cast<float>(direction.y());
  rh.ray.dir_z = static_cast<float>(direction.z());
  rh.ray.tnear = 0.f;
  rh.ray.tfar = kInf;
  rh.ray.mask = 0xffffffffu;
  rh.ray.flags = 0;
  rh.ray.time = 0.f;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  Embree().intersect1(rtc_scene, context, &rh);
  return {rh.hit.geomID, rh.hit.primID, rh.hit.u, rh.hit.v, rh.ray.tfar};
}

bool Occluded(RTCScene rtc_scene,
              const Eigen::Vector3d& origin,
              const Eigen::Vector3d& direction,
              RTCIntersectContext* context,
              float length) {
  RTCRay ray;
  ray.org_x = static_cast<float>(origin.x());
  ray.org_y = static_cast<float>(origin.y());
  ray.org_z = static_cast<float>(origin.z());
  ray.dir_x = static_cast<float>(direction.x());
  ray.dir_y = static_cast<float>(direction.y());
  ray.dir_z = static_cast<float>(direction.z());
  ray.tnear = 0.f;
  ray.tfar = length;
  ray.mask = 0xffffffffu;
  ray.flags = 0;
  ray.time = 0.f;
  Embree().occluded1(rtc_scene, context, &ray);
  return ray.tfar < 0;  // Embree sets tfar to -inf on a hit
}

void OccludedRays(RTCScene rtc_scene,
                  const Eigen::Vector3d* origins,
                  const Eigen::Vector3d& direction,
                  const uint8_t* wanted,
                  int count,
                  RTCIntersectContext* context,
                  uint8_t* out) {
  OccludedInPackets(rtc_scene, ParallelRays{origins, direction}, wanted, count, context, out);
}

bool DisocclusionRay(const Eigen::Vector3d& previous_centre,
                     const Eigen::Vector3d& point,
                     Eigen::Vector3d* direction,
                     float* length) {
  const Eigen::Vector3d to_point = point - previous_centre;
  const double distance = to_point.norm();
  if (!(distance > 0)) return false;
  const double margin = 1e-4 * distance + 1e-3;
  if (distance <= margin) return false;
  *direction = to_point / distance;
  *length = static_cast<float>(distance - margin);
  return true;
}

void OccludedSegments(RTCScene rtc_scene,
                      const Eigen::Vector3d& origin,
                      const Eigen::Vector3d* directions,
                      const float* lengths,
                      const uint8_t* wanted,
                      int count,
                      RTCIntersectContext* context,
                      uint8_t* out) {
  OccludedInPackets(rtc_scene, Segments{origin, directions, lengths}, wanted, count, context, out);
}

void OccludedSegments(RTCScene rtc_scene,
                      const Eigen::Vector3d* origins,
                      const Eigen::Vector3d* directions,
                      const float* lengths,
                      const uint8_t* wanted,
                      int count,
                      RTCIntersectContext* context,
                      uint8_t* out) {
  OccludedInPackets(
      rtc_scene, OriginSegments{origins, directions, lengths}, wanted, count, context, out);
}

}  // namespace lsds::gen

// The renderer's Embree ray casts, in one place so that the benchmark's floor
// (bench/bench_generate.cc) casts exactly the rays the renderer does: a
// pixel's camera rays as one packet, their shadow rays towards the sun as
// another, and the one-ray calls they must agree with bit for bit
// (RenderSettings::packets).
#pragma once

#include <cstdint>
#include <limits>

#include <embree3/rtcore.h>
#include <Eigen/Core>

namespace lsds::gen {

// What Embree reports for one ray: the closest triangle and where on it.
struct EmbreeHit {
  unsigned geom = RTC_INVALID_GEOMETRY_ID;
  unsigned prim = 0;
  float u = 0, v = 0, tfar = std::numeric_limits<float>::infinity();
};

// The most lanes of one packet (rtcIntersect8, rtcOccluded8); a pixel's
// samples go in packets of up to this many.
constexpr int kPacket = 8;

// `count` <= kPacket rays from one origin (a pixel's camera rays, the most
// coherent rays there are) traced together with rtcIntersect4/8. Each lane is
// the same float ray TraceOne would trace.
void TracePacket(RTCScene rtc_scene,
                 const Eigen::Vector3d& origin,
                 const Eigen::Vector3d* directions,
                 int count,
                 RTCIntersectContext* context,
                 EmbreeHit* out);
EmbreeHit TraceOne(RTCScene rtc_scene,
                   const Eigen::Vector3d& origin,
                   const Eigen::Vector3d& direction,
                   RTCIntersectContext* context);

// `count` <= kPacket rays in one direction (a pixel's shadow rays, from points
// a pixel apart) tested together with rtcOccluded4/8; out[i] = whether ray i
// is blocked. Rays whose wanted[i] is 0 are not traced (out[i] = 0). Each
// traced lane is the float ray Occluded would trace.
void OccludedPacket(RTCScene rtc_scene,
                    const Eigen::Vector3d* origins,
                    const Eigen::Vector3d& direction,
                    const uint8_t* wanted,
                    int count,
                    RTCIntersectContext* context,
                    uint8_t* out);
bool Occluded(RTCScene rtc_scene,
              const Eigen::Vector3d& origin,
              const Eigen::Vector3d& direction,
              RTCIntersectContext* context);

}  // namespace lsds::gen

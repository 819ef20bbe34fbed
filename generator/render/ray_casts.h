// The renderer's Embree ray casts, in one place so that the benchmark's floor
// (bench/bench_generate.cc) casts exactly the rays the renderer does: the
// camera rays of a block of pixels in packets, their shadow rays towards the
// sun in packets, and the one-ray calls they must agree with bit for bit
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

// A context for coherent rays: the camera rays of a block of neighbouring
// pixels, their shadow rays towards the sun. Embree then traverses a packet's
// rays together (RTC_INTERSECT_CONTEXT_FLAG_COHERENT), about twice as fast on
// such rays, with the same hits lane for lane.
void InitCoherentContext(RTCIntersectContext* context);

// The most lanes of one packet (rtcIntersect16, rtcOccluded16): the camera
// rays of a 2x2 block of pixels at 4 samples per pixel.
constexpr int kPacket = 16;

// Pixels per side of the blocks whose rays are cast together. Blocks are
// aligned to the image, so a block is always the same pixels (and its packets
// the same rays) whatever the tiles.
constexpr int kBlock = 2;

// The pixels of block (block_row, block_col) of a width x height image, row
// by row: x[i], y[i] for i < the returned count (kBlock * kBlock, fewer in the
// image's last block column and row).
int BlockPixels(int block_row, int block_col, int width, int height, int* x, int* y);

// `count` rays from one origin (the camera rays of a block of pixels, the
// most coherent rays there are), traced kPacket at a time with
// rtcIntersect4/8/16. Each lane is the same float ray TraceOne would trace.
void TraceRays(RTCScene rtc_scene,
               const Eigen::Vector3d& origin,
               const Eigen::Vector3d* directions,
               int count,
               RTCIntersectContext* context,
               EmbreeHit* out);
EmbreeHit TraceOne(RTCScene rtc_scene,
                   const Eigen::Vector3d& origin,
                   const Eigen::Vector3d& direction,
                   RTCIntersectContext* context);

// `count` rays in one direction (the shadow rays of a block of pixels, from
// points a pixel apart), tested kPacket at a time with rtcOccluded4/8/16;
// out[i] = whether ray i is blocked. Rays whose wanted[i] is 0 are not traced
// (out[i] = 0). Each traced lane is the float ray Occluded would trace.
void OccludedRays(RTCScene rtc_scene,
                  const Eigen::Vector3d* origins,
                  const Eigen::Vector3d& direction,
                  const uint8_t* wanted,
                  int count,
                  RTCIntersectContext* context,
                  uint8_t* out);
// One ray, blocked within `length` of its origin (unbounded by default).
bool Occluded(RTCScene rtc_scene,
              const Eigen::Vector3d& origin,
              const Eigen::Vector3d& direction,
              RTCIntersectContext* context,
              float length = std::numeric_limits<float>::infinity());

// The ray that tells whether `point` (in the previous world) was hidden from
// the previous camera centre by another surface, in which case the pixel was
// disoccluded and has no motion: from the centre towards the point, stopping
// short of the surface itself (a relative and an absolute margin cover the
// float precision of the Embree hit). False when there is nothing to test.
bool DisocclusionRay(const Eigen::Vector3d& previous_centre,
                     const Eigen::Vector3d& point,
                     Eigen::Vector3d* direction,
                     float* length);

// `count` rays from one origin (the disocclusion rays of a block of pixels:
// from the previous camera centre towards the points it saw), ray i along
// unit directions[i] for lengths[i]; tested kPacket at a time, out[i] =
// whether ray i is blocked. Rays whose wanted[i] is 0 are not traced (out[i]
// = 0). Each traced lane is the float ray Occluded(origin, directions[i],
// context, lengths[i]) would trace.
void OccludedSegments(RTCScene rtc_scene,
                      const Eigen::Vector3d& origin,
                      const Eigen::Vector3d* directions,
                      const float* lengths,
                      const uint8_t* wanted,
                      int count,
                      RTCIntersectContext* context,
                      uint8_t* out);
// The same from an origin per ray (the sky-light rays of a block of pixels,
// each from its own pixel's surface).
void OccludedSegments(RTCScene rtc_scene,
                      const Eigen::Vector3d* origins,
                      const Eigen::Vector3d* directions,
                      const float* lengths,
                      const uint8_t* wanted,
                      int count,
                      RTCIntersectContext* context,
                      uint8_t* out);

}  // namespace lsds::gen

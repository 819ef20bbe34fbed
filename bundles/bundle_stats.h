// Mixed-pixel statistics of pixel bundles (the deep `bundle` layer,
// docs/format.md): how many pixels hold more than one surface, which classes
// share pixels, how pure they are, how far apart their depths and normals lie,
// and which averaged depths would fly. docs/bundles.md explains each figure.
//
// One BundleStats holds the figures of one frame or of many merged together;
// its size depends on the number of classes, objects and bins, never on the
// number of frames.
#pragma once

#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "libs/exr/deep_image.h"

namespace lsds::bundle {

struct StatsOptions {
  // An averaged depth d flies when every sample depth z_i is farther from it
  // than max(flying_absolute, flying_relative * d): it lies in empty space
  // between the surfaces. The same threshold marks depth discontinuities inside
  // a pixel for the edge mask.
  double flying_absolute = 0.05;  // world length units
  double flying_relative = 0.01;  // share of the averaged depth
  // Lower edges of the distance bands (world units, ascending, first 0); the
  // last band is open.
  std::vector<double> distance_bands = {0, 5, 10, 20, 50, 100, 200, 500};
  // Lower edges of the object size bins (pixels of an object in a frame,
  // ascending, first 1).
  std::vector<int64_t> size_bins = {1, 16, 64, 256, 1024, 4096, 16384, 65536};
  int purity_bins = 10;  // equal bins over [0, 1]; purity 1 falls into the last
};

// Upper edges of the fixed histograms (the last bin is open).
const std::vector<double>& DepthSpreadEdges();   // world units
const std::vector<double>& NormalSpreadEdges();  // degrees

struct MixCounter {
  uint64_t pixels = 0;
  uint64_t mixed = 0;  // of those, pixels with more than one instance id
};

struct ObjectCounter {
  uint32_t class_id = 0;
  uint64_t frames = 0;  // frames in which it has at least one sample
  uint64_t pixels = 0;  // pixels holding at least one of its samples
  uint64_t mixed = 0;
};

struct SizeBin {
  uint64_t objects = 0;  // (object, frame) pairs whose size falls in the bin
  uint64_t pixels = 0;
  uint64_t mixed = 0;
  double share_sum = 0;  // sum over those pairs of mixed / pixels
};

struct BundleStats {
  explicit BundleStats(const StatsOptions& options = {});

  int64_t frames = 0;
  uint64_t pixels = 0;        // pixels with at least one sample
  uint64_t empty_pixels = 0;  // pixels with no sample
  uint64_t samples = 0;
  uint64_t mixed_pixels = 0;        // more than one instance id
  uint64_t class_mixed_pixels = 0;  // more than one class id

  std::map<uint32_t, MixCounter> per_class;  // pixels holding at least one sample of the class
  std::vector<MixCounter> by_distance;       // by the pixel's nearest depth; one per band
  MixCounter sky_only;                       // pixels without a finite depth
  // (a, b) -> samples of class a in pixels that also hold class b; (a, a) ->
  // samples of class a in pixels holding no other class.
  std::map<std::pair<uint32_t, uint32_t>, uint64_t> class_mixing;

  std::vector<uint64_t> purity_histogram;
  double purity_sum = 0;
  double entropy_sum = 0;  // bits, instance ids
  double entropy_sum_mixed = 0;

  uint64_t depth_pixels = 0;  // pixels with at least two finite depths
  double depth_spread_sum = 0;
  double depth_spread_sum_mixed = 0;
  uint64_t depth_pixels_mixed = 0;
  double depth_spread_max = 0;
  std::vector<uint64_t> depth_spread_histogram;
  uint64_t flying_pixels = 0;

  uint64_t normal_pixels = 0;  // pixels with at least two non-zero normals
  uint64_t normal_pixels_mixed = 0;
  double normal_spread_sum = 0;  // degrees
  double normal_spread_sum_mixed = 0;
  double normal_spread_max = 0;
  std::vector<uint64_t> normal_spread_histogram;

  std::map<uint32_t, ObjectCounter> objects;  // instance id > 0
  std::vector<SizeBin> by_object_size;

  void Merge(const BundleStats& other);
};

// Per-pixel results, filled on request to write derived layers and pictures.
struct PixelMaps {
  std::vector<uint32_t> majority_instance;
  std::vector<uint32_t> majority_class;
  std::vector<float> purity;
  std::vector<uint8_t> mixed;
  std::vector<uint8_t> edge;  // mixed, or depths farther apart than the flying threshold
  // Soft coverage: per pixel, one entry per distinct instance id, by coverage
  // descending.
  std::vector<uint32_t> coverage_counts;
  std::vector<uint32_t> coverage_instance;
  std::vector<uint32_t> coverage_class;
  std::vector<float> coverage;
};

// Channels read from a bundle layer; the normals are optional.
const std::vector<std::string>& BundleChannels();

// The figures of one frame. `bundle` must hold UINT channels instanceid and
// classid and a FLOAT channel Z; NX, NY, NZ are used when present. Throws
// lsds::Error otherwise.
BundleStats AnalyzeFrame(const exr::DeepImage& bundle,
                         const StatsOptions& options,
                         PixelMaps* maps = nullptr);

}  // namespace lsds::bundle

// Stratified, jittered sub-pixel samples (docs/format.md, "Pixel bundles"). A
// format rule, not only a generator detail: the compact bundle layout stores no
// positions, readers derive them here from (seed, frame, pixel, spp, jitter).
// `spp` must be a square n * n: the pixel is cut into n x n cells and each cell
// gets one sample jittered by `jitter` (1: anywhere in the cell, 0: its
// centre), except that the sample nearest the pixel centre is moved exactly
// onto it and stored first: the single-value layers are that sample's values.
// Positions depend only on (seed, frame, pixel, sample): any frame subset,
// shard or thread count gives the same samples.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace lsds {

struct SamplerSettings {
  int spp = 4;
  double jitter = 1.0;
  uint64_t seed = 0;
};

// Throws lsds::Error unless spp is a square in [1, 256] and jitter in [0, 1].
void CheckSamplerSettings(const SamplerSettings& settings);

// The rule for the pixels of one frame, with what they share computed once
// (the frame's seed, the cell grid, each sample's hash of its index): a
// renderer or a bundle codec derives a million pixels' positions per frame.
class FrameSampler {
 public:
  // `settings` must pass CheckSamplerSettings.
  FrameSampler(const SamplerSettings& settings, int64_t frame);

  int spp() const { return static_cast<int>(sample_hashes_.size()); }

  // Writes the spp sample positions of pixel (x, y) in pixel-edge image
  // coordinates, the pixel centre (x + 0.5, y + 0.5) first, the others in
  // cell order.
  void PixelSamples(int x, int y, Eigen::Vector2d* out) const;

 private:
  int per_axis_ = 1;  // n: the pixel's n x n cells
  double jitter_ = 1.0;
  uint64_t frame_seed_ = 0;
  std::vector<uint64_t> sample_hashes_;  // per sample k, SplitMix64(k)
};

// FrameSampler(settings, frame).PixelSamples(x, y, out), for a single pixel.
void PixelSamples(
    const SamplerSettings& settings, int64_t frame, int x, int y, Eigen::Vector2d* out);

}  // namespace lsds

// The two on-disk layouts of the pixel bundle (docs/format.md "Pixel
// bundles") and the one reader for both.
//
// full:    every sample of every pixel, channels instanceid, classid (UINT), Z,
//          NX, NY, NZ, SX, SY (FLOAT), as written up to 0.1.
// compact: only what cannot be derived. Sample positions follow the sampling
//          rule (libs/collection/sample_positions.h) and are not stored; classid
//          is a per-frame function of instanceid, stored once as a header
//          table; a pixel whose samples are all identical (same instance, the
//          same depth and normal bits) stores one sample that stands for all.
//          Lossless: the reader yields exactly the full layout's samples.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "libs/collection/sample_positions.h"
#include "libs/exr/deep_image.h"
#include "libs/exr/exr_types.h"

namespace lsds {

enum class BundleLayout { kFull, kCompact };
const char* BundleLayoutName(BundleLayout layout);  // "full" | "compact"
bool ParseBundleLayout(const std::string& name, BundleLayout* layout);

// The channels of a full bundle, in order: what every reader yields.
const std::vector<exr::ChannelSpec>& FullBundleChannels();

// How the bundle of one frame was sampled: what a compact file needs to derive
// the sample positions.
struct BundleSampling {
  SamplerSettings sampler;
  int64_t frame = 0;
};

// Writes `full` (the full layout's channels, `sampler.spp` samples in every
// pixel) in `layout`. The compact encoder checks every claim it relies on:
// positions it cannot re-derive bit for bit, or class ids that are not a
// function of instance ids, are kept as channels, so the result is always
// lossless. Without `sampling` (or with other sample counts) it writes the full
// layout.
void WriteBundleExr(const std::filesystem::path& path,
                    const exr::DeepImage& full,
                    BundleLayout layout,
                    const std::optional<BundleSampling>& sampling,
                    const exr::WriteOptions& options);

// Reads the named channels (all of the full layout when empty) of a bundle in
// either layout: the same samples, in the same order, whichever was written.
// Other deep files read as they are. Throws lsds::Error naming the file.
exr::DeepImage ReadBundleExr(const std::filesystem::path& path,
                             const std::vector<std::string>& channels = {},
                             const exr::ReadLimits& limits = {});

// The channels a reader gets from a file with header `info` (for a compact
// bundle: the stored ones plus the derived ones), sorted by name as EXR lists
// them. Validators compare this against the layer table.
std::vector<exr::ChannelSpec> ReadableChannels(const exr::ExrInfo& info);

// The header attribute naming the layout ("compact"; absent in full files).
inline constexpr const char* kBundleLayoutAttribute = "lsdsBundleLayout";

}  // namespace lsds

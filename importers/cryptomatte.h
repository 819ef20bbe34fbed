// Cryptomatte ids (specification: github.com/Psyop/Cryptomatte,
// specification/cryptomatte_specification.pdf): names are hashed with
// MurmurHash3_x86_32 (seed 0), the hash is stored bit for bit in a 32-bit
// float channel after one exponent bit is flipped where the exponent would be
// 0 or 255 (no denormals, infinities or NaNs), and the header carries, per
// layer `cryptomatte/<key>/{name,hash,conversion,manifest}` with the manifest
// a JSON object {name: "8 hex digits of the hash"}. Pixel (id, coverage) pairs
// are in channels <name>00.R/G, <name>00.B/A, <name>01.R/G, ..., rank 0 (the
// largest coverage) first.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace lsds::import {

uint32_t MurmurHash3_32(std::string_view text, uint32_t seed = 0);

// The float a hash is stored as, and the bits of that float (which are what a
// pixel holds).
float CryptomatteFloatFromHash(uint32_t hash);
uint32_t CryptomatteBitsFromHash(uint32_t hash);

struct CryptomatteLayer {
  std::string key;   // the 7 hex digits of the attribute names
  std::string name;  // e.g. "CryptoActor"; channels are <name>00.R, ...
  // Pixel bits (CryptomatteBitsFromHash) -> the name in the manifest.
  std::unordered_map<uint32_t, std::string> names_by_bits;
};

// Every layer declared in the header `attributes` (name -> string value) of
// `file`. Throws lsds::Error naming the file and attribute for an unknown hash
// or conversion, a missing or malformed manifest (a sidecar manif_file is not
// supported).
std::vector<CryptomatteLayer> ParseCryptomatteLayers(
    const std::map<std::string, std::string>& attributes, const std::string& file);

// The rank-0 (id, coverage) channels of layer `name` among `channels`, in
// any writer's spelling: <name>00.R / .G (the specification, Arnold, V-Ray,
// Unreal), <name>00.red / .green (Nuke's), <name>00.r / .g (Blender's);
// none when the file has no such pair.
struct CryptomatteRankChannels {
  std::string id, coverage;
};
std::optional<CryptomatteRankChannels> FindRank0Channels(const std::vector<std::string>& channels,
                                                         const std::string& name);

// "cryptomatte/<key>/<field>" for layer `name`: key = first 7 hex digits of
// MurmurHash3_32(name), as writers name them.
std::string CryptomatteAttribute(const std::string& name, const std::string& field);

// The manifest of `names`: {"name": "hex8", ...}, sorted by name.
std::string CryptomatteManifest(const std::vector<std::string>& names);

}  // namespace lsds::import

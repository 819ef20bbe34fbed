#include "importers/cryptomatte.h"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <utility>

#include <nlohmann/json.hpp>

#include "libs/util/error.h"

namespace lsds::import {

namespace {
uint32_t Rotl(uint32_t x, int r) { return (x << r) | (x >> (32 - r)); }

std::string Hex8(uint32_t value) {
  char text[9];
  std::snprintf(text, sizeof text, "%08x", value);
  return text;
}
}  // namespace

uint32_t MurmurHash3_32(std::string_view text, uint32_t seed) {
  const auto* data = reinterpret_cast<const uint8_t*>(text.data());
  const size_t length = text.size();
  const uint32_t c1 = 0xcc9e2d51, c2 = 0x1b873593;
  uint32_t h = seed;
  const size_t blocks = length / 4;
  for (size_t i = 0; i < blocks; ++i) {
    uint32_t k = static_cast<uint32_t>(data[4 * i]) | static_cast<uint32_t>(data[4 * i + 1]) << 8 |
                 static_cast<uint32_t>(data[4 * i + 2]) << 16 |
                 static_cast<uint32_t>(data[4 * i + 3]) << 24;
    k *= c1;
    k = Rotl(k, 15);
    k *= c2;
    h ^= k;
    h = Rotl(h, 13);
    h = h * 5 + 0xe6546b64;
  }
  const uint8_t* tail = data + 4 * blocks;
  uint32_t k = 0;
  switch (length & 3) {
    case 3:
      k ^= static_cast<uint32_t>(tail[2]) << 16;
      [[fallthrough]];
    case 2:
      k ^= static_cast<uint32_t>(tail[1]) << 8;
      [[fallthrough]];
    case 1:
      k ^= tail[0];
      k *= c1;
      k = Rotl(k, 15);
      k *= c2;
      h ^= k;
  }
  h ^= static_cast<uint32_t>(length);
  h ^= h >> 16;
  h *= 0x85ebca6b;
  h ^= h >> 13;
  h *= 0xc2b2ae35;
  h ^= h >> 16;
  return h;
}

uint32_t CryptomatteBitsFromHash(uint32_t hash) {
  const uint32_t exponent = (hash >> 23) & 0xff;
  // The specification avoids denormals, infinities and NaNs by flipping the
  // lowest exponent bit.
  if (exponent == 0 || exponent == 0xff) hash ^= 1u << 23;
  return hash;
}

float CryptomatteFloatFromHash(uint32_t hash) {
  const uint32_t bits = CryptomatteBitsFromHash(hash);
  float value;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}

std::string CryptomatteAttribute(const std::string& name, const std::string& field) {
  return "cryptomatte/" + Hex8(MurmurHash3_32(name)).substr(0, 7) + "/" + field;
}

std::string CryptomatteManifest(const std::vector<std::string>& names) {
  nlohmann::json manifest = nlohmann::json::object();
  for (const std::string& name : names) manifest[name] = Hex8(MurmurHash3_32(name));
  return manifest.dump();
}

std::vector<CryptomatteLayer> ParseCryptomatteLayers(
    const std::map<std::string, std::string>& attributes, const std::string& file) {
  // Group "cryptomatte/<key>/<field>" by key.
  std::map<std::string, std::map<std::string, std::string>> by_key;
  const std::string prefix = "cryptomatte/";
  for (const auto& [name, value] : attributes) {
    if (name.rfind(prefix, 0) != 0) continue;
    const size_t slash = name.find('/', prefix.size());
    if (slash == std::string::npos) continue;
    by_key[name.substr(prefix.size(), slash - prefix.size())][name.substr(slash + 1)] = value;
  }
  std::vector<CryptomatteLayer> layers;
  for (const auto& [key, fields] : by_key) {
    const std::string where = prefix + key + "/";
    auto field = [&, &fields = fields](const std::string& f) -> const std::string& {
      const auto it = fields.find(f);
      if (it == fields.end())
        throw Error("cryptomatte layer without header attribute '" + where + f + "'",
                    Location(file));
      return it->second;
    };
    CryptomatteLayer layer;
    layer.key = key;
    layer.name = field("name");
    if (fields.count("hash") && field("hash") != "MurmurHash3_32")
      throw Error("attribute '" + where + "hash' is '" + field("hash") +
                      "'; only MurmurHash3_32 is defined by the "
                      "Cryptomatte specification",
                  Location(file));
    if (fields.count("conversion") && field("conversion") != "uint32_to_float32")
      throw Error("attribute '" + where + "conversion' is '" + field("conversion") +
                      "'; expected uint32_to_float32",
                  Location(file));
    if (!fields.count("manifest"))
      throw Error("cryptomatte layer '" + layer.name + "' has no '" + where +
                      "manifest' attribute (a sidecar manif_file is not "
                      "supported): its ids cannot be named",
                  Location(file));
    nlohmann::json manifest;
    try {
      manifest = nlohmann::json::parse(field("manifest"));
    } catch (const nlohmann::json::exception& e) {
      throw Error("attribute '" + where + "manifest' is not JSON: " + e.what(), Location(file));
    }
    if (!manifest.is_object())
      throw Error("attribute '" + where + "manifest' is not a JSON object", Location(file));
    for (const auto& [object, hex] : manifest.items()) {
      uint32_t hash = 0;
      if (!hex.is_string() || hex.get<std::string>().size() != 8 ||
          std::sscanf(hex.get<std::string>().c_str(), "%8x", &hash) != 1)
        throw Error(
            "manifest entry '" + object + "' in '" + where + "manifest' is not 8 hex digits",
            Location(file));
      layer.names_by_bits[CryptomatteBitsFromHash(hash)] = object;
    }
    layers.push_back(std::move(layer));
  }
  return layers;
}

std::optional<CryptomatteRankChannels> FindRank0Channels(const std::vector<std::string>& channels,
                                                         const std::string& name) {
  const auto has = [&](const std::string& channel) {
    return std::find(channels.begin(), channels.end(), channel) != channels.end();
  };
  for (const auto& [id, coverage] :
       {std::pair<const char*, const char*>{"R", "G"}, {"red", "green"}, {"r", "g"}}) {
    const std::string id_channel = name + "00." + id;
    const std::string coverage_channel = name + "00." + coverage;
    if (has(id_channel) && has(coverage_channel))
      return CryptomatteRankChannels{id_channel, coverage_channel};
  }
  return std::nullopt;
}

}  // namespace lsds::import

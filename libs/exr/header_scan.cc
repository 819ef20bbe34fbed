// OpenEXR allocates what a header declares before it reads it: an attribute of
// a declared 2 GB in a 500-byte file, a data window of 2^31 lines (the line
// offset table, the line buffers) are allocated in the InputFile constructor,
// before CheckLimits can look at the header (found by fuzz/flat_exr_fuzzer
// and fuzz/deep_exr_fuzzer: seconds and gigabytes per malformed file). This
// scan reads the header's attribute table itself, which costs a few hundred
// bytes of reading, and refuses such files first.
#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>

#include "libs/exr/exr_internal.h"

namespace lsds::exr::internal {

namespace {

constexpr uint32_t kMagic = 20000630;  // 0x762f3101
constexpr uint32_t kLongNames = 0x400;
constexpr uint32_t kMultiPart = 0x1000;
constexpr int kMaxName = 255;  // OpenEXR's limit with long names

class HeaderScanner {
 public:
  HeaderScanner(const std::filesystem::path& path, const ReadLimits& limits)
      : path_(path), limits_(limits), in_(path, std::ios::binary) {
    std::error_code ec;
    size_ = static_cast<int64_t>(std::filesystem::file_size(path, ec));
    if (ec || !in_) Fail("cannot open: " + ec.message());
  }

  void Scan() {
    if (ReadU32() != kMagic) return;  // not an EXR: OpenEXR says so in its words
    const uint32_t flags = ReadU32();
    const int max_name = (flags & kLongNames) ? kMaxName : 31;
    do {
      if (!ScanHeader(max_name)) break;
    } while (flags & kMultiPart);
  }

 private:
  [[noreturn]] void Fail(const std::string& what) const {
    throw Error("malformed EXR header: " + what, Location(path_.string()));
  }

  uint32_t ReadU32() {
    unsigned char b[4];
    if (!in_.read(reinterpret_cast<char*>(b), 4)) Fail("truncated at byte " + std::to_string(pos_));
    pos_ += 4;
    return uint32_t{b[0]} | uint32_t{b[1]} << 8 | uint32_t{b[2]} << 16 | uint32_t{b[3]} << 24;
  }

  std::string ReadName(int max_name) {
    std::string name;
    for (char c; in_.get(c);) {
      ++pos_;
      if (c == '\0') return name;
      if (static_cast<int>(name.size()) == max_name) {
        Fail("a name longer than " + std::to_string(max_name) + " bytes at byte " +
             std::to_string(pos_ - 1 - max_name));
      }
      name += c;
    }
    Fail("truncated at byte " + std::to_string(pos_));
  }

  // One header (one part); false at the empty header that ends a multi-part
  // file's list.
  bool ScanHeader(int max_name) {
    for (int attributes = 0;; ++attributes) {
      const int64_t start = pos_;
      const std::string name = ReadName(max_name);
      if (name.empty()) return attributes > 0;
      const std::string type = ReadName(max_name);
      const int64_t size = static_cast<int32_t>(ReadU32());
      if (size < 0 || size > size_ - pos_) {
        Fail("attribute '" + name + "' (" + type + ") at byte " + std::to_string(start) +
             " declares " + std::to_string(size) + " bytes, but the file ends " +
             std::to_string(size_ - pos_) + " bytes later");
      }
      // OpenEXR reads a known type by the type, not by the declared size:
      // follow it the same way, or the attribute table diverges from its.
      const auto fixed = FixedSize(type);
      if (name == "dataWindow" && type == "box2i") {
        CheckWindow();
      } else if (name == "chunkCount" && type == "int") {
        // Every chunk has an 8-byte offset in the file.
        const int64_t chunks = static_cast<int32_t>(ReadU32());
        if (chunks < 0 || chunks > size_ / 8) {
          Fail("chunkCount " + std::to_string(chunks) + " does not fit in a file of " +
               std::to_string(size_) + " bytes");
        }
      } else if (type == "chlist") {
        ScanChannelList(max_name);
      } else if (type == "preview") {
        // Unsigned, as OpenEXR reads them; compared without a product that
        // could overflow.
        const uint64_t width = ReadU32(), height = ReadU32();
        const uint64_t room = static_cast<uint64_t>(size_ - pos_) / 4;
        if (width != 0 && height > room / width) {
          Fail("preview image of " + std::to_string(width) + "x" + std::to_string(height) +
               " at byte " + std::to_string(start) + " does not fit in the file");
        }
        Skip(static_cast<int64_t>(width * height * 4));
      } else if (fixed > 0) {
        if (fixed > size_ - pos_) Fail("truncated at byte " + std::to_string(pos_));
        Skip(fixed);
      } else {
        Skip(size);  // strings, vectors and types OpenEXR does not know: `size` bytes
      }
    }
  }

  // The bytes OpenEXR reads for a fixed-size attribute type, 0 for the others.
  static int64_t FixedSize(const std::string& type) {
    static const std::pair<const char*, int64_t> kSizes[] = {
        {"box2i", 16},      {"box2f", 16},   {"chromaticities", 32},
        {"compression", 1}, {"double", 8},   {"envmap", 1},
        {"float", 4},       {"int", 4},      {"keycode", 28},
        {"lineOrder", 1},   {"m33f", 36},    {"m33d", 72},
        {"m44f", 64},       {"m44d", 128},   {"rational", 8},
        {"tiledesc", 9},    {"timecode", 8}, {"v2i", 8},
        {"v2f", 8},         {"v2d", 16},     {"v3i", 12},
        {"v3f", 12},        {"v3d", 24},     {"deepImageState", 1}};
    for (const auto& [name, bytes] : kSizes) {
      if (type == name) return bytes;
    }
    return 0;
  }

  // A channel list is read up to its empty name: name, then 16 bytes each.
  void ScanChannelList(int max_name) {
    for (int channels = 0;; ++channels) {
      if (ReadName(max_name).empty()) return;
      if (channels >= limits_.max_channels) {
        Fail("more than " + std::to_string(limits_.max_channels) + " channels");
      }
      if (16 > size_ - pos_) Fail("truncated at byte " + std::to_string(pos_));
      Skip(16);
    }
  }

  void Skip(int64_t bytes) {
    in_.seekg(bytes, std::ios::cur);
    pos_ += bytes;
  }

  // The reader's size limits, before OpenEXR sizes its offset table and line
  // buffers by the window; and no more lines than the file has offset-table
  // entries for (8 bytes each, at most 256 lines a chunk, DWAB's).
  void CheckWindow() {
    int64_t v[4];
    for (int64_t& x : v) x = static_cast<int32_t>(ReadU32());
    const int64_t width = v[2] - v[0] + 1, height = v[3] - v[1] + 1;
    if (width <= 0 || height <= 0) return;  // CheckLimits names it
    if (width > limits_.max_width || height > limits_.max_height ||
        width * height > limits_.max_pixels || height > size_ / 8 * 256) {
      Fail("data window of " + std::to_string(width) + "x" + std::to_string(height) +
           " pixels exceeds the reader's size limits (or what a file of " + std::to_string(size_) +
           " bytes can hold)");
    }
  }

  const std::filesystem::path& path_;
  const ReadLimits& limits_;
  std::ifstream in_;
  int64_t size_ = 0;
  int64_t pos_ = 0;
};

}  // namespace

void ScanHeader(const std::filesystem::path& path, const ReadLimits& limits) {
  HeaderScanner(path, limits).Scan();
}

}  // namespace lsds::exr::internal

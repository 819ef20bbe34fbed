// NumPy's .npy files (format versions 1-3, little-endian, C order): plain
// arrays (`<f4`, `<u4`, ...) and structured ones (Replicator's bounding box
// records: named fields, some with a sub-shape such as ('transform', '<f4',
// (4, 4))). The header's Python literal is parsed here; the payload is kept as
// bytes and read by field.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace lsds {

struct NpyField {
  std::string name;   // empty for a plain array
  char kind = 'f';    // 'f' float, 'u' unsigned, 'i' signed, 'b' bool
  int size = 4;       // bytes per element
  int64_t count = 1;  // elements per record (product of the sub-shape)
  size_t offset = 0;  // in the record
};

struct NpyArray {
  std::vector<int64_t> shape;
  std::vector<NpyField> fields;  // one unnamed field for a plain array
  size_t record_size = 0;        // bytes per element of `shape`
  std::string data;

  int64_t size() const;  // product of shape
  // The field named `name`; throws lsds::Error naming `file` when absent.
  const NpyField& Field(const std::string& name, const std::string& file) const;
  // Element `element` of `field` in record `record`, as a double.
  double Get(int64_t record, const NpyField& field, int64_t element = 0) const;
};

// Throws lsds::Error naming the file for anything but a little-endian,
// C-order array of bool, integer or float fields.
NpyArray ReadNpy(const std::filesystem::path& path);

// Writes `array` as a version 1.0 .npy file, as numpy.save does (the header
// padded with spaces to a multiple of 64 bytes). `descr` is the header's
// dtype literal, e.g. "'<f4'" or "[('semanticId', '<u4'), ...]".
void WriteNpy(const std::filesystem::path& path,
              const std::string& descr,
              const std::vector<int64_t>& shape,
              const std::string& data);

}  // namespace lsds

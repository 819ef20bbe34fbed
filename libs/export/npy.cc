#include "libs/export/npy.h"

#include <fstream>

#include "libs/util/error.h"

namespace lsds::layer_export {

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__,
              "the .npy writer stores the host's bytes as little-endian");

std::string NpyHeader(const std::string& descr,
                      const std::vector<int64_t>& shape) {
  std::string dict = "{'descr': '" + descr + "', 'fortran_order': False, " +
                     "'shape': (";
  for (size_t i = 0; i < shape.size(); ++i) {
    dict += std::to_string(shape[i]);
    if (shape.size() == 1 || i + 1 < shape.size()) dict += ",";
    if (i + 1 < shape.size()) dict += " ";
  }
  dict += "), }";
  // magic (6) + version (2) + header length (2) + dict + padding + '\n'.
  const size_t unpadded = 10 + dict.size() + 1;
  dict.append((64 - unpadded % 64) % 64, ' ');
  dict += '\n';
  std::string header("\x93NUMPY\x01\x00", 8);
  header += static_cast<char>(dict.size() & 0xff);
  header += static_cast<char>((dict.size() >> 8) & 0xff);
  return header + dict;
}

void WriteNpy(const std::filesystem::path& path,
              const std::string& descr,
              const std::vector<int64_t>& shape,
              const void* data,
              size_t bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  const std::string header = NpyHeader(descr, shape);
  out.write(header.data(), static_cast<std::streamsize>(header.size()));
  out.write(static_cast<const char*>(data), static_cast<std::streamsize>(bytes));
  out.close();
  if (!out) throw Error("cannot write the file", Location(path.string()));
}

}  // namespace lsds::layer_export

#include "libs/exr/exr_chunks.h"

#include <openexr.h>

#include <algorithm>
#include <string>

#include "libs/util/error.h"

namespace lsds::exr {

namespace {

// OpenEXR's core library prints its errors on stderr by default; lsds says
// what went wrong itself, naming the file.
void Quiet(exr_const_context_t, exr_result_t, const char*) {}

std::string CoreMessage(exr_result_t code) { return exr_get_default_error_message(code); }

}  // namespace

void CheckChunksWithinFile(const std::filesystem::path& path, uint64_t file_size) {
  const Location where(path.string());
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  init.error_handler_fn = &Quiet;
  // Reconstruction would scan a damaged file for chunks and hide the damage:
  // a bad chunk table entry is an error here.
  init.flags = EXR_CONTEXT_FLAG_SILENT_HEADER_PARSE | EXR_CONTEXT_FLAG_DISABLE_CHUNK_RECONSTRUCTION;
  exr_context_t context = nullptr;
  struct Finish {
    exr_context_t* context;
    ~Finish() { exr_finish(context); }
  } finish{&context};
  exr_result_t rv = exr_start_read(&context, path.c_str(), &init);
  if (rv != EXR_ERR_SUCCESS) throw Error("cannot read the EXR header: " + CoreMessage(rv), where);
  exr_storage_t storage = EXR_STORAGE_LAST_TYPE;
  exr_attr_box2i_t window{};
  int32_t lines = 0;
  if (exr_get_storage(context, 0, &storage) != EXR_ERR_SUCCESS ||
      exr_get_data_window(context, 0, &window) != EXR_ERR_SUCCESS ||
      exr_get_scanlines_per_chunk(context, 0, &lines) != EXR_ERR_SUCCESS || lines < 1)
    throw Error("cannot read the EXR header's data window and compression", where);
  if (storage != EXR_STORAGE_SCANLINE && storage != EXR_STORAGE_DEEP_SCANLINE)
    throw Error("tiled EXR files are not lsds layers", where);
  const bool deep = storage == EXR_STORAGE_DEEP_SCANLINE;
  for (int64_t y = window.min.y; y <= window.max.y; y += lines) {
    const std::string chunk = "the chunk of lines " + std::to_string(y) + " to " +
                              std::to_string(std::min<int64_t>(y + lines - 1, window.max.y));
    exr_chunk_info_t info{};
    rv = exr_read_scanline_chunk_info(context, 0, static_cast<int>(y), &info);
    if (rv != EXR_ERR_SUCCESS)
      throw Error("truncated or damaged: " + chunk + " cannot be found in the file's " +
                      std::to_string(file_size) + " bytes (" + CoreMessage(rv) + ")",
                  where);
    // Sums of values read from the file: compared without overflow.
    auto beyond = [file_size](uint64_t offset, uint64_t size) {
      return offset > file_size || size > file_size - offset;
    };
    if (beyond(info.data_offset, info.packed_size) ||
        (deep && beyond(info.sample_count_data_offset, info.sample_count_table_size))) {
      throw Error("truncated: " + chunk + " ends past the end of the file (" +
                      std::to_string(file_size) + " bytes)",
                  where);
    }
  }
}

}  // namespace lsds::exr

// Streaming a JSON file whose top level is an object holding one large array
// (collection.json's "frames", metadata.json's "frames"): the elements are
// handed out one at a time, so memory does not grow with the number of
// elements.
#pragma once

#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "libs/util/error.h"

namespace lsds {

// Parses `path`. Every member except `array_key` goes into `*header` (when not
// null), with `array_key` set to an empty array; each element of `array_key` is
// passed to `on_element` with its index (when set) and then freed. Returns the
// number of elements. Throws lsds::Error with the file, line and column on a
// syntax error, and when the top level is not an object.
size_t StreamJsonArrayMember(
    const std::filesystem::path& path,
    const std::string& array_key,
    nlohmann::json* header,
    const std::function<void(nlohmann::json&& element, size_t index)>& on_element);

// What a streamed element is handed to: the member name of its array ("" for
// a root array), the element, its index in that array.
using JsonElementHandler =
    std::function<void(const std::string& array_key, nlohmann::json&& element, size_t index)>;

// The same for several large arrays of the root object (a COCO dataset's
// "images" and "annotations"), or, with no `array_keys`, for a root that is
// itself a list (a COCO results file; `header` is then unused, and a root that
// is not a list is an error at "/"). Returns the number of elements streamed.
size_t StreamJsonArrays(const std::filesystem::path& path,
                        const std::vector<std::string>& array_keys,
                        nlohmann::json* header,
                        const JsonElementHandler& on_element);

// Writes such a file: the header members first (pretty), then the array one
// element per line. Atomic: nothing appears under `path` until Commit().
class JsonArrayWriter {
 public:
  JsonArrayWriter(const std::filesystem::path& path,
                  const nlohmann::json& header,
                  const std::string& array_key);
  ~JsonArrayWriter();
  void Append(const nlohmann::json& element);
  size_t count() const { return count_; }
  void Commit();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;  // owned even when the constructor throws
  size_t count_ = 0;
};

}  // namespace lsds

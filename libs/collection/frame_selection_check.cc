#include "libs/collection/frame_selection_check.h"

#include <algorithm>

#include "libs/collection/collection_reader.h"

namespace lsds {

std::vector<int64_t> CollectionFrameIndices(const std::filesystem::path& root) {
  const CollectionReader reader(root);
  std::vector<int64_t> indices;
  indices.reserve(reader.frames_in_file());
  reader.ForEachFrameJson([&](const nlohmann::json& frame, const std::string&) {
    const auto it = frame.find("index");
    if (it != frame.end() && it->is_number_integer()) indices.push_back(it->get<int64_t>());
  });
  // Indices are unique and increasing (docs/format.md); sorting keeps the
  // check meaningful on a collection that breaks that rule (validate names it).
  std::sort(indices.begin(), indices.end());
  return indices;
}

FrameRange SelectCollectionFrames(const std::string& text, const std::filesystem::path& root) {
  if (text.empty()) return {};
  FrameSelection selection = ParseFrameSelection(text);
  CheckFrameSelection(selection, CollectionFrameIndices(root), "the collection " + root.string());
  return selection;
}

}  // namespace lsds

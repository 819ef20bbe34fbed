#include "evaluate/truth_tables.h"

#include <algorithm>
#include <mutex>
#include <set>
#include <stdexcept>

namespace lsds::evaluate {

namespace {

// Sorts by `key`, keeping of equal keys the one added last.
template <typename T, typename Key>
void SortKeepingLast(std::vector<T>* items, Key key) {
  std::stable_sort(
      items->begin(), items->end(), [&](const T& a, const T& b) { return key(a) < key(b); });
  std::vector<T> kept;
  kept.reserve(items->size());
  for (size_t i = 0; i < items->size(); ++i)
    if (i + 1 == items->size() || key((*items)[i + 1]) != key((*items)[i]))
      kept.push_back(std::move((*items)[i]));
  kept.shrink_to_fit();
  *items = std::move(kept);
}

}  // namespace

void ImageTable::Add(
    int64_t id, std::string_view file_name, int64_t frame, int64_t height, int64_t width) {
  ImageEntry image;
  image.id = id;
  image.frame = frame;
  image.height = static_cast<int32_t>(height);
  image.width = static_cast<int32_t>(width);
  image.name_begin = static_cast<uint32_t>(names_.size());
  image.name_size = static_cast<uint32_t>(file_name.size());
  names_.append(file_name);
  images_.push_back(image);
}

void ImageTable::Seal() {
  SortKeepingLast(&images_, [](const ImageEntry& e) { return e.id; });
  names_.shrink_to_fit();
  name_order_.resize(images_.size());
  for (size_t i = 0; i < images_.size(); ++i) name_order_[i] = static_cast<uint32_t>(i);
  std::stable_sort(name_order_.begin(), name_order_.end(), [&](uint32_t a, uint32_t b) {
    return FileName(images_[a]) < FileName(images_[b]);
  });
}

const ImageEntry* ImageTable::Find(int64_t id) const {
  const auto it = std::lower_bound(
      images_.begin(), images_.end(), id, [](const ImageEntry& e, int64_t v) { return e.id < v; });
  return it != images_.end() && it->id == id ? &*it : nullptr;
}

const ImageEntry& ImageTable::At(int64_t id) const {
  const ImageEntry* image = Find(id);
  if (image == nullptr) throw std::out_of_range("no image " + std::to_string(id));
  return *image;
}

const ImageEntry* ImageTable::FindFileName(std::string_view file_name) const {
  // Of two images with one name, the last in id order (as a map keyed by name
  // filled in id order keeps it).
  const auto it = std::upper_bound(
      name_order_.begin(), name_order_.end(), file_name, [&](std::string_view v, uint32_t i) {
        return v < FileName(images_[i]);
      });
  if (it == name_order_.begin() || FileName(images_[*(it - 1)]) != file_name) return nullptr;
  return &images_[*(it - 1)];
}

const std::string* InternLabel(std::string_view label) {
  static std::mutex mutex;
  static std::set<std::string, std::less<>> labels;
  const std::lock_guard<std::mutex> lock(mutex);
  auto it = labels.find(label);
  if (it == labels.end()) it = labels.emplace(label).first;
  return &*it;
}

void FrameTable::Seal() {
  SortKeepingLast(&frames_, [](const FrameFacts& f) { return f.index; });
}

FrameFacts* FrameTable::Find(int64_t index) {
  const auto it =
      std::lower_bound(frames_.begin(), frames_.end(), index, [](const FrameFacts& f, int64_t v) {
        return f.index < v;
      });
  return it != frames_.end() && it->index == index ? &*it : nullptr;
}

const FrameFacts* FrameTable::Find(int64_t index) const {
  return const_cast<FrameTable*>(this)->Find(index);
}

}  // namespace lsds::evaluate

#include "evaluate/detections_by_image.h"

#include <algorithm>
#include <cstring>
#include <string>

namespace lsds::evaluate {

namespace {

uint64_t BytesOf(const DetectionBox& d) {
  return sizeof(DetectionBox) + d.mask.counts.capacity() * sizeof(uint32_t) +
         d.quad.capacity() * sizeof(double);
}

template <typename T>
void Put(std::string* out, const T& value) {
  out->append(reinterpret_cast<const char*>(&value), sizeof(T));
}

// One entry as the run stores it: the fixed fields, then the mask's counts and
// the polygon's corners, each after its length.
void Serialize(const DetectionBox& d, std::string* out) {
  Put(out, d.image_id);
  Put(out, d.category_id);
  Put(out, d.bbox);
  Put(out, d.score);
  const uint8_t has_area = d.area.has_value() ? 1 : 0;
  Put(out, has_area);
  Put(out, d.area.value_or(0.0));
  Put(out, d.mask.height);
  Put(out, d.mask.width);
  Put(out, static_cast<uint64_t>(d.mask.counts.size()));
  out->append(reinterpret_cast<const char*>(d.mask.counts.data()),
              d.mask.counts.size() * sizeof(uint32_t));
  Put(out, static_cast<uint64_t>(d.quad.size()));
  out->append(reinterpret_cast<const char*>(d.quad.data()), d.quad.size() * sizeof(double));
}

DetectionBox Deserialize(SpillReader* in) {
  DetectionBox d;
  d.image_id = in->Read<int64_t>();
  d.category_id = in->Read<int64_t>();
  d.bbox = in->Read<BoxXywh>();
  d.score = in->Read<double>();
  const auto has_area = in->Read<uint8_t>();
  const auto area = in->Read<double>();
  if (has_area) d.area = area;
  d.mask.height = in->Read<int64_t>();
  d.mask.width = in->Read<int64_t>();
  d.mask.counts.resize(in->Read<uint64_t>());
  in->Read(d.mask.counts.data(), d.mask.counts.size() * sizeof(uint32_t));
  d.quad.resize(in->Read<uint64_t>());
  in->Read(d.quad.data(), d.quad.size() * sizeof(double));
  return d;
}

void SortByImage(std::vector<DetectionBox>* detections) {
  std::stable_sort(
      detections->begin(), detections->end(), [](const DetectionBox& a, const DetectionBox& b) {
        return a.image_id < b.image_id;
      });
}

}  // namespace

DetectionsByImage::DetectionsByImage(uint64_t memory_bytes) : memory_bytes_(memory_bytes) {}

DetectionsByImage::~DetectionsByImage() = default;

void DetectionsByImage::Add(DetectionBox detection) {
  held_bytes_ += BytesOf(detection);
  held_.push_back(std::move(detection));
  ++count_;
  // The vector's spare capacity counts too: it is memory held.
  if (held_bytes_ + (held_.capacity() - held_.size()) * sizeof(DetectionBox) > memory_bytes_)
    Spill();
}

// One run: the held entries sorted by image, stably (file order within an
// image), written in one go.
void DetectionsByImage::Spill() {
  if (held_.empty()) return;
  if (!file_) file_ = std::make_unique<SpillFile>();
  SortByImage(&held_);
  const uint64_t offset = file_->size();
  std::string bytes;
  for (const DetectionBox& d : held_) {
    Serialize(d, &bytes);
    if (bytes.size() >= (1u << 20)) {
      file_->Append(bytes.data(), bytes.size());
      bytes.clear();
    }
  }
  file_->Append(bytes.data(), bytes.size());
  run_extents_.emplace_back(offset, held_.size());
  std::vector<DetectionBox>().swap(held_);
  held_bytes_ = 0;
}

void DetectionsByImage::Advance(Run* run) {
  run->has_head = run->left > 0;
  if (!run->has_head) return;
  --run->left;
  run->head = Deserialize(run->reader.get());
}

void DetectionsByImage::StartReading() {
  reading_ = true;
  SortByImage(&held_);
  for (size_t i = 0; i < run_extents_.size(); ++i) {
    const uint64_t end = i + 1 < run_extents_.size() ? run_extents_[i + 1].first : file_->size();
    Run run;
    run.reader = std::make_unique<SpillReader>(
        *file_, run_extents_[i].first, end, ReaderBufferBytes(memory_bytes_, run_extents_.size()));
    run.left = run_extents_[i].second;
    Advance(&run);
    runs_.push_back(std::move(run));
  }
}

// The runs in the order they were written, then the held entries (the last
// read): an image's entries come out in file order.
std::vector<DetectionBox> DetectionsByImage::Take(int64_t image_id) {
  if (!reading_) StartReading();
  std::vector<DetectionBox> out;
  for (Run& run : runs_) {
    while (run.has_head && run.head.image_id <= image_id) {
      if (run.head.image_id == image_id) out.push_back(std::move(run.head));
      Advance(&run);
    }
  }
  while (held_at_ < held_.size() && held_[held_at_].image_id <= image_id) {
    if (held_[held_at_].image_id == image_id) out.push_back(std::move(held_[held_at_]));
    ++held_at_;
  }
  return out;
}

}  // namespace lsds::evaluate

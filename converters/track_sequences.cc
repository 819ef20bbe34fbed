#include "converters/track_sequences.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <system_error>

#include "converters/format_util.h"
#include "libs/util/error.h"

namespace lsds::convert {

namespace fs = std::filesystem;

std::vector<TrackObject> TrackObjects(const FrameContext& frame, const ClassMap& classes) {
  std::map<const ObjectTruth*, const KeptObject*> kept;
  for (const KeptObject& object : frame.objects) kept[object.truth] = &object;
  std::vector<TrackObject> out;
  for (const ObjectTruth& object : frame.frame->objects) {
    if (const auto it = kept.find(&object); it != kept.end()) {
      out.push_back({&object, it->second->class_index, it->second->box, true});
      continue;
    }
    // Not kept: an ignore row when only a quality filter dropped it (it is
    // visible and its class is an output class).
    if (!object.bbox || object.visible_pixels <= 0) continue;
    const std::optional<int> index = classes.Map(object.class_id);
    if (!index) continue;
    const Box2d box = object.bbox->ClippedTo(frame.width, frame.height);
    if (box.empty()) continue;
    out.push_back({&object, *index, box, false});
  }
  return out;
}

void CountIgnored(const std::vector<TrackObject>& objects,
                  const ClassMap& classes,
                  const char* reason,
                  LossReport* loss) {
  for (const TrackObject& object : objects) {
    if (!object.considered) loss->Add(reason, classes.classes()[object.class_index].name);
  }
}

int TrackSequence::TrackId(uint32_t instance_id) {
  return ids.emplace(instance_id, static_cast<int>(ids.size()) + 1).first->second;
}

double TrackSequence::FrameRate() const {
  std::vector<double> steps;
  for (size_t i = 1; i < times.size(); ++i) steps.push_back(times[i] - times[i - 1]);
  if (steps.empty()) return 1;
  std::nth_element(steps.begin(), steps.begin() + steps.size() / 2, steps.end());
  const double step = steps[steps.size() / 2];
  return step > 0 ? 1 / step : 1;
}

namespace {

std::string FileName(const std::string& text) {
  std::string out;
  for (char c : text) out += std::isalnum(static_cast<unsigned char>(c)) || c == '-' ? c : '_';
  return out;
}

}  // namespace

TrackSequence& TrackSequences::Add(const FrameContext& frame) {
  const Frame& f = *frame.frame;
  const Key key{frame.split, f.sequence, f.shot.value_or(-1), f.rig_camera.value_or("")};
  auto it = index_.find(key);
  if (it == index_.end()) {
    // "<sequence>[-shot<first frame>][-<camera>]"; a number is appended when
    // two keys make the same file name.
    std::string name = FileName(f.sequence.empty() ? "seq" : f.sequence);
    if (f.shot) name += "-shot" + std::to_string(*f.shot);
    if (f.rig_camera) name += "-" + FileName(*f.rig_camera);
    std::string unique = name;
    for (int k = 2; names_used_.count({frame.split, unique}) != 0; ++k)
      unique = name + "-" + std::to_string(k);
    names_used_.insert({frame.split, unique});
    name = unique;
    TrackSequence sequence;
    sequence.name = name;
    sequence.width = frame.width;
    sequence.height = frame.height;
    it = index_.emplace(key, sequences_.size()).first;
    sequences_.emplace_back(frame.split, std::move(sequence));
  }
  TrackSequence& sequence = sequences_[it->second].second;
  sequence.frame_indices.push_back(f.index);
  sequence.times.push_back(f.time);
  return sequence;
}

std::vector<const TrackSequence*> TrackSequences::OfSplit(const std::string& split) const {
  std::vector<const TrackSequence*> out;
  for (const auto& [s, sequence] : sequences_)
    if (s == split) out.push_back(&sequence);
  return out;
}

void LinkImage(const fs::path& image, const fs::path& link) {
  fs::create_directories(link.parent_path());
  std::error_code error;
  fs::create_hard_link(image, link, error);
  if (!error) return;
  fs::copy_file(image, link, fs::copy_options::overwrite_existing, error);
  if (error)
    throw Error("cannot link or copy the image: " + error.message(), Location(link.string()));
}

std::string TrimmedFixed(double value, int decimals) {
  std::string text = Format("%.*f", decimals, value);
  if (text.find('.') != std::string::npos) {
    while (text.back() == '0') text.pop_back();
    if (text.back() == '.') text.pop_back();
  }
  if (text == "-0") text = "0";
  return text;
}

}  // namespace lsds::convert

// MOT17 layout, one sequence per split, sequence, shot and rig camera:
//   mot/LSDS-<split>/<SEQ>/gt/gt.txt, seqinfo.ini, frames.txt, img1/000001.png
//   mot/seqmaps/LSDS-<split>.txt
// which is TrackEval's default layout for --BENCHMARK LSDS --SPLIT_TO_EVAL
// <split> (GT_FOLDER/BENCHMARK-SPLIT/SEQ/gt/gt.txt and
// GT_FOLDER/seqmaps/BENCHMARK-SPLIT.txt, mot_challenge_2d_box.py:36,50,153).
#include "converters/mot/mot_converter.h"

#include <algorithm>
#include <cctype>
#include <cmath>

#include "converters/format_util.h"
#include "converters/track_sequences.h"
#include "libs/util/atomic_file.h"

namespace lsds::convert {

namespace {

constexpr const char* kBenchmark = "LSDS";
constexpr const char* kIgnored =
    "mot: written with conf 0 (ignored by TrackEval): dropped by a filter";
constexpr const char* kNoMot17Id =
    "mot: not written: the class has no MOT17 id (--mot-classes mot17)";

std::string SetFolder(const std::string& split) { return std::string(kBenchmark) + "-" + split; }

class MotConverter : public Converter {
 public:
  std::string name() const override { return "mot"; }
  bool NeedsMasks() const override { return false; }

  void Begin(const ConvertSetup& setup) override {
    setup_ = setup;
    for (const OutputClass& c : setup.classes->classes()) {
      if (setup.options->mot_classes == "mot17") {
        mot_class_.push_back(Mot17ClassId(c.name).value_or(-1));
      } else {
        mot_class_.push_back(static_cast<int>(mot_class_.size()) + 1);
      }
    }
    for (const SplitPart& split : setup.splits)
      std::filesystem::create_directories(setup.root / "mot" / SetFolder(split.name));
  }

  std::unique_ptr<FramePiece> EncodeFrame(const FrameContext& frame,
                                          LossReport* loss) const override {
    const std::vector<TrackObject> objects = TrackObjects(frame, *setup_.classes);
    for (const TrackObject& object : objects) {
      const std::string& class_name = setup_.classes->classes()[object.class_index].name;
      if (mot_class_[object.class_index] < 0) {
        loss->Add(kNoMot17Id, class_name);
      } else if (!object.considered) {
        loss->Add(kIgnored, class_name);
      }
    }
    return nullptr;  // the rows need the sequence's frame numbers: AddFrame
  }

  void AddFrame(const FrameContext& frame, std::unique_ptr<FramePiece>) override {
    TrackSequence& sequence = sequences_.Add(frame);
    const int64_t number = sequence.frames();  // 1-based
    for (const TrackObject& object : TrackObjects(frame, *setup_.classes)) {
      const int mot_class = mot_class_[object.class_index];
      if (mot_class < 0) continue;
      // MOT17's boxes are the full extent of the object (amodal): the
      // projected 3D box's bounds, clipped to the image in the truth.
      Box2d box = object.box;
      if (setup_.options->mot_box == "projected" && object.truth->bbox_projected &&
          !object.truth->bbox_projected->empty()) {
        box = object.truth->bbox_projected->ClippedTo(frame.width, frame.height);
      }
      const double visibility =
          std::clamp(object.truth->visibility * object.truth->in_frame, 0.0, 1.0);
      // 1-based pixel coordinates: pixel-edge x0 = 0 is MOT's bb_left = 1.
      sequence.rows += std::to_string(number) + "," +
                       std::to_string(sequence.TrackId(object.truth->instance_id)) + "," +
                       TrimmedFixed(box.x0 + 1, 2) + "," + TrimmedFixed(box.y0 + 1, 2) + "," +
                       TrimmedFixed(box.width(), 2) + "," + TrimmedFixed(box.height(), 2) + "," +
                       (object.considered ? "1" : "0") + "," + std::to_string(mot_class) + "," +
                       TrimmedFixed(visibility, 5) + "\n";
    }
    if (setup_.options->images != "none") {
      LinkImage(setup_.root / "images" / frame.split / frame.image_name,
                SequenceFolder(frame.split, sequence) / "img1" /
                    (Format("%06lld", static_cast<long long>(number)) +
                     setup_.options->ImageExtension()));
    }
  }

  void Finish() override {
    for (const SplitPart& split : setup_.splits) {
      std::string seqmap = "name\n";  // TrackEval skips the first line (:162)
      for (const TrackSequence* sequence : sequences_.OfSplit(split.name)) {
        seqmap += sequence->name + "\n";
        const std::filesystem::path folder = SequenceFolder(split.name, *sequence);
        std::filesystem::create_directories(folder / "gt");
        WriteFileAtomic(folder / "gt" / "gt.txt", sequence->rows);
        WriteFileAtomic(folder / "seqinfo.ini", SeqInfo(*sequence));
        std::string frames = "frame,collection_frame\n";
        for (int64_t k = 0; k < sequence->frames(); ++k) {
          frames += std::to_string(k + 1) + "," + std::to_string(sequence->frame_indices[k]) + "\n";
        }
        WriteFileAtomic(folder / "frames.txt", frames);
        std::string ids = "id,instance_id\n";
        for (const auto& [instance, id] : sequence->ids)
          ids += std::to_string(id) + "," + std::to_string(instance) + "\n";
        WriteFileAtomic(folder / "gt" / "instance_ids.txt", ids);
      }
      const std::filesystem::path seqmaps = setup_.root / "mot" / "seqmaps";
      std::filesystem::create_directories(seqmaps);
      WriteFileAtomic(seqmaps / (SetFolder(split.name) + ".txt"), seqmap);
    }
  }

 private:
  std::filesystem::path SequenceFolder(const std::string& split,
                                       const TrackSequence& sequence) const {
    return setup_.root / "mot" / SetFolder(split) / sequence.name;
  }

  std::string SeqInfo(const TrackSequence& sequence) const {
    const double rate = sequence.FrameRate();
    // An integer rate where the times give one (trackers read it as an int).
    const std::string rate_text = std::abs(rate - std::round(rate)) < 1e-3
                                      ? std::to_string(std::lround(rate))
                                      : TrimmedFixed(rate, 3);
    return "[Sequence]\nname=" + sequence.name + "\nimDir=img1\nframeRate=" + rate_text +
           "\nseqLength=" + std::to_string(sequence.frames()) +
           "\nimWidth=" + std::to_string(sequence.width) +
           "\nimHeight=" + std::to_string(sequence.height) +
           "\nimExt=" + setup_.options->ImageExtension() + "\n";
  }

  ConvertSetup setup_;
  std::vector<int> mot_class_;  // per output class: the MOT class id, -1: not written
  TrackSequences sequences_;
};

}  // namespace

std::optional<int> Mot17ClassId(const std::string& name) {
  static const std::pair<const char*, int> kClasses[] = {
      {"pedestrian", 1},
      {"person_on_vehicle", 2},
      {"car", 3},
      {"bicycle", 4},
      {"motorbike", 5},
      {"non_mot_vehicle", 6},
      {"static_person", 7},
      {"distractor", 8},
      {"occluder", 9},
      {"occluder_on_ground", 10},
      {"occluder_full", 11},
      {"reflection", 12},
      {"crowd", 13},
      // lsds's built-in walking figure is MOT17's pedestrian.
      {"person", 1}};
  std::string key;
  for (char c : name)
    key +=
        c == ' ' || c == '-' ? '_' : static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  for (const auto& [n, id] : kClasses)
    if (key == n) return id;
  return std::nullopt;
}

std::unique_ptr<Converter> MakeMotConverter() { return std::make_unique<MotConverter>(); }

}  // namespace lsds::convert

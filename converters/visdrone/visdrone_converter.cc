// VisDrone DET: visdrone/<split>/{images/<stem>.png, annotations/<stem>.txt}.
// VisDrone VID: visdrone-vid/<split>/{sequences/<SEQ>/0000001.png,
// annotations/<SEQ>.txt, frames/<SEQ>.txt}, one sequence per split, sequence,
// shot and rig camera. Both write classes.txt, the category map.
#include "converters/visdrone/visdrone_converter.h"

#include "converters/format_util.h"
#include "converters/track_sequences.h"
#include "converters/visdrone/visdrone_common.h"
#include "libs/util/atomic_file.h"

namespace lsds::convert {

namespace {

class VisDroneConverter : public Converter {
 public:
  std::string name() const override { return "visdrone"; }
  bool NeedsMasks() const override { return false; }

  void Begin(const ConvertSetup& setup) override {
    setup_ = setup;
    categories_ = visdrone::Categories(*setup.classes);
    for (const SplitPart& split : setup.splits) {
      const std::filesystem::path folder = setup.root / "visdrone" / split.name;
      std::filesystem::create_directories(folder / "annotations");
      // Made here: EncodeFrame runs for several frames at once.
      if (setup.options->images != "none") std::filesystem::create_directories(folder / "images");
    }
    WriteFileAtomic(setup.root / "visdrone" / "classes.txt",
                    visdrone::CategoryMapText(*setup.classes));
  }

  // Each frame's file is written here, in parallel (one file per frame).
  std::unique_ptr<FramePiece> EncodeFrame(const FrameContext& frame,
                                          LossReport* loss) const override {
    std::string text;
    for (const TrackObject& object : TrackObjects(frame, *setup_.classes)) {
      text += visdrone::Columns(object,
                                categories_[object.class_index],
                                setup_.classes->classes()[object.class_index].name,
                                name(),
                                loss) +
              "\n";
    }
    const std::filesystem::path folder = setup_.root / "visdrone" / frame.split;
    WriteFileAtomic(folder / "annotations" / (frame.stem + ".txt"), text);
    if (setup_.options->images != "none") {
      LinkImage(setup_.root / "images" / frame.split / frame.image_name,
                folder / "images" / frame.image_name);
    }
    return nullptr;
  }

  void AddFrame(const FrameContext&, std::unique_ptr<FramePiece>) override {}
  void Finish() override {}

 private:
  ConvertSetup setup_;
  std::vector<int> categories_;
};

class VisDroneVidConverter : public Converter {
 public:
  std::string name() const override { return "visdrone-vid"; }
  bool NeedsMasks() const override { return false; }

  void Begin(const ConvertSetup& setup) override {
    setup_ = setup;
    categories_ = visdrone::Categories(*setup.classes);
    for (const SplitPart& split : setup.splits)
      std::filesystem::create_directories(setup.root / "visdrone-vid" / split.name / "annotations");
    WriteFileAtomic(setup.root / "visdrone-vid" / "classes.txt",
                    visdrone::CategoryMapText(*setup.classes));
  }

  // The columns after frame_index and target_id, which need the sequence:
  // AddFrame.
  struct Piece : FramePiece {
    std::vector<std::pair<uint32_t, std::string>> rows;  // (instance id, columns)
  };

  std::unique_ptr<FramePiece> EncodeFrame(const FrameContext& frame,
                                          LossReport* loss) const override {
    auto piece = std::make_unique<Piece>();
    for (const TrackObject& object : TrackObjects(frame, *setup_.classes)) {
      piece->rows.emplace_back(object.truth->instance_id,
                               visdrone::Columns(object,
                                                 categories_[object.class_index],
                                                 setup_.classes->classes()[object.class_index].name,
                                                 name(),
                                                 loss));
    }
    return piece;
  }

  void AddFrame(const FrameContext& frame, std::unique_ptr<FramePiece> piece) override {
    TrackSequence& sequence = sequences_.Add(frame);
    const int64_t number = sequence.frames();  // VisDrone-VID's frame_index is 1-based
    for (const auto& [instance, columns] : static_cast<Piece&>(*piece).rows) {
      sequence.rows += std::to_string(number) + "," + std::to_string(sequence.TrackId(instance)) +
                       "," + columns + "\n";
    }
    if (setup_.options->images != "none") {
      LinkImage(setup_.root / "images" / frame.split / frame.image_name,
                setup_.root / "visdrone-vid" / frame.split / "sequences" / sequence.name /
                    (Format("%07lld", static_cast<long long>(number)) +
                     setup_.options->ImageExtension()));
    }
  }

  void Finish() override {
    for (const SplitPart& split : setup_.splits) {
      const std::filesystem::path folder = setup_.root / "visdrone-vid" / split.name;
      for (const TrackSequence* sequence : sequences_.OfSplit(split.name)) {
        WriteFileAtomic(folder / "annotations" / (sequence->name + ".txt"), sequence->rows);
        std::string frames = "frame_index,collection_frame\n";
        for (int64_t k = 0; k < sequence->frames(); ++k) {
          frames += std::to_string(k + 1) + "," + std::to_string(sequence->frame_indices[k]) + "\n";
        }
        std::filesystem::create_directories(folder / "frames");
        WriteFileAtomic(folder / "frames" / (sequence->name + ".txt"), frames);
      }
    }
  }

 private:
  ConvertSetup setup_;
  std::vector<int> categories_;
  TrackSequences sequences_;
};

}  // namespace

std::unique_ptr<Converter> MakeVisDroneConverter() { return std::make_unique<VisDroneConverter>(); }
std::unique_ptr<Converter> MakeVisDroneVidConverter() {
  return std::make_unique<VisDroneVidConverter>();
}

}  // namespace lsds::convert

// CVAT for video 1.1: one <track> per instance (per sequence) across the frames
// of a split.
#include <fstream>
#include <map>

#include "converters/cvat/cvat_converter.h"
#include "converters/cvat/cvat_xml.h"
#include "converters/format_util.h"
#include "libs/util/strings.h"

namespace lsds::convert {

namespace {

struct VideoPiece : FramePiece {};

class CvatVideoConverter : public Converter {
 public:
  std::string name() const override { return "cvat-video"; }
  bool NeedsMasks() const override { return false; }

  void Begin(const ConvertSetup& setup) override {
    setup_ = setup;
    for (const SplitPart& split : setup.splits) splits_[split.name];
  }

  std::unique_ptr<FramePiece> EncodeFrame(const FrameContext&, LossReport*) const override {
    return nullptr;  // nothing heavy: the boxes are recorded in AddFrame
  }

  void AddFrame(const FrameContext& frame, std::unique_ptr<FramePiece>) override {
    Split& s = splits_.at(frame.split);
    const int64_t number = s.frames++;
    if (s.frames == 1) {
      s.width = frame.width;
      s.height = frame.height;
    }
    for (const KeptObject& object : frame.objects) {
      const std::pair<std::string, uint32_t> key{frame.frame->sequence, object.truth->instance_id};
      auto it = s.track_index.find(key);
      if (it == s.track_index.end()) {
        it = s.track_index.emplace(key, s.tracks.size()).first;
        s.tracks.push_back({object.class_index, {}});
      }
      // Compact records: the XML is written at the end, when every track is
      // complete.
      s.tracks[it->second].boxes.push_back(
          {number, object.box, object.truth->visibility < setup_.options->occluded_below});
    }
  }

  void Finish() override {
    const std::vector<OutputClass>& classes = setup_.classes->classes();
    for (auto& [name, s] : splits_) {
      const std::filesystem::path path =
          setup_.root / "annotations" / ("cvat_video_" + name + ".xml");
      std::unique_ptr<AtomicFile> file = OpenForWrite(path);
      std::ostream& out = file->stream();
      out << "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n<annotations>\n  "
             "<version>1.1</version>\n"
          << "  <meta>\n    <task>\n      <name>" << XmlEscape(name) << "</name>\n"
          << "      <size>" << s.frames << "</size>\n      <mode>interpolation</mode>\n"
          << "      <overlap>0</overlap>\n      <start_frame>0</start_frame>\n"
          << "      <stop_frame>" << std::max<int64_t>(0, s.frames - 1) << "</stop_frame>\n"
          << cvat::LabelsXml(*setup_.classes, "      ") << "      <original_size>\n"
          << "        <width>" << s.width << "</width>\n        <height>" << s.height
          << "</height>\n      </original_size>\n    </task>\n  </meta>\n";
      for (size_t t = 0; t < s.tracks.size(); ++t) {
        const Track& track = s.tracks[t];
        out << "  <track id=\"" << t << "\" label=\"" << XmlEscape(classes[track.class_index].name)
            << "\" source=\"manual\">\n";
        auto write = [&](int64_t frame, const Box2d& box, bool outside, bool occluded) {
          out << "    <box frame=\"" << frame << "\" keyframe=\"1\" outside=\"" << outside
              << "\" occluded=\"" << occluded << "\" " << cvat::BoxCorners(box)
              << " z_order=\"0\">\n    </box>\n";
        };
        for (size_t k = 0; k < track.boxes.size(); ++k) {
          const Record& r = track.boxes[k];
          write(r.frame, r.box, false, r.occluded);
          const bool last = k + 1 == track.boxes.size();
          const int64_t next = last ? s.frames : track.boxes[k + 1].frame;
          // The object leaves the view (or is filtered out) after this frame:
          // CVAT's "outside" keyframe, so that interpolation does not carry the
          // box on.
          if (next > r.frame + 1) write(r.frame + 1, r.box, true, r.occluded);
        }
        out << "  </track>\n";
      }
      out << "</annotations>\n";
      file->Commit();
    }
  }

 private:
  struct Record {
    int64_t frame;
    Box2d box;
    bool occluded;
  };
  struct Track {
    int class_index;
    std::vector<Record> boxes;
  };
  struct Split {
    int64_t frames = 0;
    int width = 0, height = 0;
    std::map<std::pair<std::string, uint32_t>, size_t> track_index;
    std::vector<Track> tracks;
  };
  ConvertSetup setup_;
  std::map<std::string, Split> splits_;
};

}  // namespace

std::unique_ptr<Converter> MakeCvatVideoConverter() {
  return std::make_unique<CvatVideoConverter>();
}

}  // namespace lsds::convert

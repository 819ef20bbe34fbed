#include "converters/cvat/cvat_converter.h"
#include "libs/util/strings.h"

#include <fstream>
#include <map>

#include "converters/cvat/cvat_xml.h"
#include "converters/format_util.h"
#include "libs/masks/cvat_rle.h"

namespace lsds::convert {

namespace {

struct CvatPiece : FramePiece {
  std::string shapes;  // the <box> and <mask> elements of one <image>
};

class CvatImagesConverter : public Converter {
 public:
  std::string name() const override { return "cvat"; }
  bool NeedsMasks() const override { return true; }

  void Begin(const ConvertSetup& setup) override {
    setup_ = setup;
    for (const SplitPart& split : setup.splits) {
      Split& s = splits_[split.name];
      s.part_path = setup.root / "annotations" / (".cvat_" + split.name + ".part");
      s.part = OpenForWrite(s.part_path);
    }
  }

  std::unique_ptr<FramePiece> EncodeFrame(const FrameContext& frame, LossReport*) const override {
    auto piece = std::make_unique<CvatPiece>();
    const std::vector<OutputClass>& classes = setup_.classes->classes();
    for (const KeptObject& object : frame.objects) {
      const std::string label = XmlEscape(classes[object.class_index].name);
      const bool occluded = object.truth->visibility < setup_.options->occluded_below;
      const std::string common =
          "label=\"" + label + "\" source=\"manual\" occluded=\"" + (occluded ? "1" : "0") + "\"";
      piece->shapes += "    <box " + common + " " + cvat::BoxCorners(object.box) +
                       " z_order=\"0\">\n    </box>\n";
      const masks::BoxMask& mask = *object.mask;
      piece->shapes += "    <mask " + common + " rle=\"" +
                       masks::CvatRleToString(masks::CvatRleCounts(mask)) + "\" left=\"" +
                       std::to_string(mask.left) + "\" top=\"" + std::to_string(mask.top) +
                       "\" width=\"" + std::to_string(mask.width()) + "\" height=\"" +
                       std::to_string(mask.height()) + "\" z_order=\"0\">\n    </mask>\n";
    }
    return piece;
  }

  void AddFrame(const FrameContext& frame, std::unique_ptr<FramePiece> base) override {
    auto* piece = static_cast<CvatPiece*>(base.get());
    Split& s = splits_.at(frame.split);
    s.part->stream() << "  <image id=\"" << s.count++ << "\" name=\"" << XmlEscape(frame.image_name)
                     << "\" width=\"" << frame.width << "\" height=\"" << frame.height << "\">\n"
                     << piece->shapes << "  </image>\n";
  }

  void Finish() override {
    for (auto& [name, s] : splits_) {
      s.part->Commit();
      const std::filesystem::path path = setup_.root / "annotations" / ("cvat_" + name + ".xml");
      std::unique_ptr<AtomicFile> file = OpenForWrite(path);
      std::ostream& out = file->stream();
      out << "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n<annotations>\n  "
             "<version>1.1</version>\n"
          << "  <meta>\n    <task>\n      <name>" << XmlEscape(name) << "</name>\n"
          << "      <size>" << s.count << "</size>\n      <mode>annotation</mode>\n"
          << "      <overlap>0</overlap>\n"
          << cvat::LabelsXml(*setup_.classes, "      ") << "    </task>\n  </meta>\n";
      AppendAndRemove(out, s.part_path);
      out << "</annotations>\n";
      file->Commit();
    }
  }

 private:
  struct Split {
    std::filesystem::path part_path;
    std::unique_ptr<AtomicFile> part;
    int64_t count = 0;
  };
  ConvertSetup setup_;
  std::map<std::string, Split> splits_;
};

}  // namespace

std::unique_ptr<Converter> MakeCvatImagesConverter() {
  return std::make_unique<CvatImagesConverter>();
}

}  // namespace lsds::convert

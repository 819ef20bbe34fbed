#include "converters/dota/dota_converter.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <map>

#include "converters/check/dota_layout.h"
#include "converters/format_util.h"
#include "libs/collection/collection_reader.h"
#include "libs/util/atomic_file.h"
#include "libs/util/error.h"

namespace lsds::convert {

namespace {

// The corners as written (2 decimals) and read back, so that the size rules
// see what MMRotate will see.
std::array<Eigen::Vector2d, 4> WrittenCorners(const std::string& coordinates) {
  std::array<Eigen::Vector2d, 4> corners;
  const char* p = coordinates.c_str();
  for (Eigen::Vector2d& c : corners) {
    char* end = nullptr;
    c.x() = std::strtod(p, &end);
    c.y() = std::strtod(end, &end);
    p = end;
  }
  return corners;
}

class DotaConverter : public Converter {
 public:
  std::string name() const override { return "dota"; }
  bool NeedsMasks() const override { return false; }
  bool NeedsOrientedBoxes() const override { return true; }

  void Begin(const ConvertSetup& setup) override {
    setup_ = setup;
    for (const SplitPart& split : setup.splits) {
      std::filesystem::create_directories(setup.root / "labelTxt" / split.name);
    }
    // Two output classes that read the same in DOTA would merge silently.
    std::map<std::string, std::string> seen;
    for (const OutputClass& c : setup.classes->classes()) {
      const std::string dota = DotaClassName(c.name);
      names_.push_back(dota);
      const auto [it, fresh] = seen.emplace(dota, c.name);
      if (!fresh) {
        throw Error("dota: classes '" + it->second + "' and '" + c.name + "' are both written '" +
                        dota + "'; rename one with --classes",
                    Location("--to"));
      }
    }
    if (setup.options->dota_header) {
      // The ground sample distance of each frame, from the truth metadata
      // (format 1.1 `gsd_m`); a few bytes per frame.
      const std::filesystem::path metadata = setup.options->collection / kMetadataFile;
      if (std::filesystem::exists(metadata)) {
        MetadataReader(metadata).ForEachFrame([&](const MetadataFrame& f) {
          if (f.gsd_m) gsd_m_[f.index] = *f.gsd_m;
        });
      }
    }
  }

  std::unique_ptr<FramePiece> EncodeFrame(const FrameContext& frame,
                                          LossReport* loss) const override {
    const ConvertOptions& options = *setup_.options;
    std::string text;
    if (options.dota_header) {
      // DOTA's own header lines. MMRotate parses every line as an object
      // (mmrotate/datasets/dota.py:99-100 in 0.x, :92-93 in 1.x) and stops
      // on them, hence off by default.
      const auto gsd = gsd_m_.find(frame.frame->index);
      text += "imagesource:lsds\n";
      text += gsd == gsd_m_.end() ? std::string("gsd:null\n") : Format("gsd:%.9g\n", gsd->second);
    }
    int written = 0;
    const std::vector<OutputClass>& classes = setup_.classes->classes();
    for (const KeptObject& object : frame.objects) {
      const std::string& name = classes[object.class_index].name;
      const std::optional<DotaLabel> label = DotaLabelOf(object, options);
      if (!label) {
        loss->Add(loss::kDotaUnderMinSize, name);
        continue;
      }
      if (label->difficult) loss->Add(loss::kDotaDifficult, name);
      text +=
          label->corners_text + names_[object.class_index] + (label->difficult ? " 1\n" : " 0\n");
      ++written;
    }
    if (written == 0) loss->Add(loss::kDotaEmptyImages, loss::kImages);
    // Every image gets a label file, empty without objects: DOTA's own
    // devkit and MMRotate's test mode list images by their label files.
    std::unique_ptr<AtomicFile> out =
        OpenForWrite(setup_.root / "labelTxt" / frame.split / (frame.stem + ".txt"));
    out->stream() << text;
    out->Commit();
    return nullptr;
  }

  void AddFrame(const FrameContext&, std::unique_ptr<FramePiece>) override {}
  // The names to set as `classes` in MMRotate's dataset config, in order
  // (check-export reads them as that configuration).
  void Finish() override {
    std::string text;
    for (const std::string& name : names_) text += name + "\n";
    WriteFileAtomic(setup_.root / check::kDotaClassesFile, text);
  }

 private:
  ConvertSetup setup_;
  std::vector<std::string> names_;  // by output class index
  std::map<int64_t, double> gsd_m_;
};

}  // namespace

std::optional<DotaLabel> DotaLabelOf(const KeptObject& object, const ConvertOptions& options) {
  DotaLabel label;
  for (const Eigen::Vector2d& c : object.oriented->corners)
    label.corners_text += Format("%.2f %.2f ", c.x(), c.y());
  label.corners = WrittenCorners(label.corners_text);
  const double side_a = (label.corners[1] - label.corners[0]).norm();
  const double side_b = (label.corners[2] - label.corners[1]).norm();
  // MMRotate drops a box whose minimum-area rectangle has a side under
  // 2 px (mmrotate/core/bbox/transforms.py:347-348, poly2obb_np_oc; the
  // le90 and le135 versions likewise).
  if (std::min(side_a, side_b) < options.dota_min_size) return std::nullopt;
  label.difficult = object.truth->visibility < options.dota_difficult_below ||
                    std::max(side_a, side_b) < options.dota_difficult_size;
  return label;
}

std::string DotaClassName(const std::string& name) {
  std::string out;
  for (const char c : name) {
    const auto u = static_cast<unsigned char>(c);
    out += std::isspace(u) ? '-' : static_cast<char>(std::tolower(u));
  }
  return out;
}

std::unique_ptr<Converter> MakeDotaConverter() { return std::make_unique<DotaConverter>(); }

}  // namespace lsds::convert

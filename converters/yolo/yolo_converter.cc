#include "converters/yolo/yolo_converter.h"

#include <algorithm>
#include <array>
#include <cstdlib>
#include <fstream>
#include <set>

#include "converters/format_util.h"
#include "converters/yolo/yolo_segment.h"
#include "libs/util/atomic_file.h"
#include "libs/util/strings.h"

namespace lsds::convert {

namespace {

double Clip01(double v, int* clipped) {
  if (v < 0 || v > 1) {
    ++*clipped;
    return std::clamp(v, 0.0, 1.0);
  }
  return v;
}

// YAML double-quoted scalar.
std::string Quote(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

// Ultralytics' duplicate-row key of an OBB line: the class and the xywh of
// the corners' bounds, as float32 (ultralytics/data/utils.py:206-209 turns
// the corners into segments2boxes, :228-229 drops repeated rows).
std::array<float, 5> UltralyticsRow(const std::string& line) {
  std::array<float, 9> v{};
  const char* p = line.c_str();
  for (float& value : v) {
    char* end = nullptr;
    value = std::strtof(p, &end);
    p = end;
  }
  float x0 = v[1], x1 = v[1], y0 = v[2], y1 = v[2];
  for (int i = 1; i < 4; ++i) {
    x0 = std::min(x0, v[1 + 2 * i]), x1 = std::max(x1, v[1 + 2 * i]);
    y0 = std::min(y0, v[2 + 2 * i]), y1 = std::max(y1, v[2 + 2 * i]);
  }
  return {v[0], (x0 + x1) / 2, (y0 + y1) / 2, x1 - x0, y1 - y0};
}

class YoloConverter : public Converter {
 public:
  explicit YoloConverter(YoloTask task) : task_(task) {}
  std::string name() const override {
    switch (task_) {
      case YoloTask::kDetect:
        return "yolo";
      case YoloTask::kSegment:
        return "yolo-seg";
      case YoloTask::kOriented:
        return "yolo-obb";
    }
    return "yolo";
  }
  bool NeedsMasks() const override { return task_ == YoloTask::kSegment; }
  bool NeedsOrientedBoxes() const override { return task_ == YoloTask::kOriented; }

  void Begin(const ConvertSetup& setup) override {
    setup_ = setup;
    for (const SplitPart& split : setup.splits) {
      std::filesystem::create_directories(setup.root / "labels" / split.name);
    }
  }

  std::unique_ptr<FramePiece> EncodeFrame(const FrameContext& frame,
                                          LossReport* loss) const override {
    std::string text;
    const std::vector<OutputClass>& classes = setup_.classes->classes();
    std::set<std::array<float, 5>> rows;  // yolo-obb: Ultralytics' duplicate keys
    for (const KeptObject& object : frame.objects) {
      const std::string& name = classes[object.class_index].name;
      int clipped = 0;
      if (task_ == YoloTask::kDetect) {
        text += YoloBoxLine(object.class_index, object.box, frame.width, frame.height, &clipped);
      } else if (task_ == YoloTask::kOriented) {
        bool obb_clipped = false;
        const std::string line = YoloObbLine(
            object.class_index, *object.oriented, frame.width, frame.height, &obb_clipped);
        if (obb_clipped) loss->Add(loss::kObbClipped, name);
        if (!rows.insert(UltralyticsRow(line)).second) loss->Add(loss::kObbDuplicate, name);
        text += line;
      } else {
        text += YoloSegmentLine(object.class_index, name, *object.mask, loss, &clipped);
      }
      if (clipped > 0) loss->Add(loss::kBoxClipped, name);
    }
    // Every image gets a label file, empty when it has no objects (Ultralytics
    // then counts it as a background image instead of a missing label).
    std::unique_ptr<AtomicFile> out =
        OpenForWrite(setup_.root / "labels" / frame.split / (frame.stem + ".txt"));
    out->stream() << text;
    out->Commit();
    return nullptr;
  }

  void AddFrame(const FrameContext&, std::unique_ptr<FramePiece>) override {}

  void Finish() override {
    auto has = [&](const std::string& name) {
      return std::any_of(setup_.splits.begin(), setup_.splits.end(), [&](const SplitPart& s) {
        return s.name == name;
      });
    };
    std::string yaml =
        "# Ultralytics YOLO dataset written by lsds convert "
        "(docs/convert.md)\n";
    // No `path:`: Ultralytics then takes the folder of this file as the
    // dataset root, so the dataset can be moved or copied. (A relative `path:`,
    // even ".", is resolved against Ultralytics' datasets_dir instead.)
    yaml +=
        "# dataset root: the folder of this file (no path key, see "
        "docs/convert.md)\n";
    // Ultralytics needs train and val: a missing one points at the first split
    // (see docs).
    const std::string first = setup_.splits.front().name;
    yaml += "train: images/" + (has("train") ? std::string("train") : first) + "\n";
    yaml += "val: images/" + (has("val") ? std::string("val") : first) + "\n";
    if (has("test")) yaml += "test: images/test\n";
    yaml += "names:\n";
    const std::vector<OutputClass>& classes = setup_.classes->classes();
    for (size_t i = 0; i < classes.size(); ++i) {
      // The mapping back to the collection's class table, as a comment
      // (Ultralytics reads only the names).
      std::vector<std::string> ids;
      for (uint32_t id : classes[i].source_ids) ids.push_back(std::to_string(id));
      yaml += "  " + std::to_string(i) + ": " + Quote(classes[i].name) + "  # lsds class id " +
              Join(ids, ", ") + "\n";
    }
    WriteFileAtomic(setup_.root / "data.yaml", yaml);
  }

 private:
  YoloTask task_;
  ConvertSetup setup_;
};

}  // namespace

std::string YoloBoxLine(int class_index, const Box2d& box, int width, int height, int* clipped) {
  const double xc = Clip01((box.x0 + box.x1) / 2 / width, clipped);
  const double yc = Clip01((box.y0 + box.y1) / 2 / height, clipped);
  const double w = Clip01(box.width() / width, clipped);
  const double h = Clip01(box.height() / height, clipped);
  return std::to_string(class_index) + Format(" %.6f %.6f %.6f %.6f\n", xc, yc, w, h);
}

std::string YoloObbLine(
    int class_index, const OrientedBox2d& box, int width, int height, bool* clipped) {
  const Box2d image{0, 0, double(width), double(height)};
  const std::optional<OrientedBox2d> inside = ClippedTo(box, image);
  // Nothing of a visible box lies outside the image but its own corners:
  // with no area inside, the box is kept as it is and only clamped.
  const OrientedBox2d& written = inside ? *inside : box;
  int clamped = 0;
  std::string line = std::to_string(class_index);
  for (const Eigen::Vector2d& c : written.corners) {
    line += Format(" %.6f %.6f", Clip01(c.x() / width, &clamped), Clip01(c.y() / height, &clamped));
  }
  *clipped = !inside || clamped > 0 || inside->corners != box.corners;
  return line + "\n";
}

std::unique_ptr<Converter> MakeYoloConverter(YoloTask task) {
  return std::make_unique<YoloConverter>(task);
}

}  // namespace lsds::convert

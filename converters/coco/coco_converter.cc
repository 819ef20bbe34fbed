#include "converters/coco/coco_converter.h"

#include <fstream>
#include <map>

#include <nlohmann/json.hpp>

#include "converters/format_util.h"
#include "libs/collection/json_io.h"
#include "libs/masks/coco_rle.h"
#include "libs/masks/contours.h"

namespace lsds::convert {

namespace {

using nlohmann::json;

struct CocoPiece : FramePiece {
  std::string image;                     // the images[] entry
  std::vector<std::string> annotations;  // each without its id: "{" + id is prepended serially
};

json BoxJson(const Box2d& box) { return json::array({box.x0, box.y0, box.width(), box.height()}); }

class CocoConverter : public Converter {
 public:
  std::string name() const override { return "coco"; }
  bool NeedsMasks() const override { return true; }

  void Begin(const ConvertSetup& setup) override {
    setup_ = setup;
    polygons_ = setup.options->segmentation == "polygon";
    for (const SplitPart& split : setup.splits) {
      Split& s = splits_[split.name];
      s.images_path = setup.root / "annotations" / (".images_" + split.name + ".part");
      s.annotations_path = setup.root / "annotations" / (".annotations_" + split.name + ".part");
      s.images = OpenForWrite(s.images_path);
      s.annotations = OpenForWrite(s.annotations_path);
    }
  }

  std::unique_ptr<FramePiece> EncodeFrame(const FrameContext& frame,
                                          LossReport* loss) const override {
    auto piece = std::make_unique<CocoPiece>();
    const int64_t image_id = frame.image_index + 1;
    json image = {{"id", image_id},
                  {"file_name", frame.image_name},
                  {"width", frame.width},
                  {"height", frame.height},
                  {"lsds",
                   {{"frame", frame.frame->index},
                    {"time", frame.frame->time},
                    {"sequence", frame.frame->sequence}}}};
    piece->image = image.dump();
    const std::vector<OutputClass>& classes = setup_.classes->classes();
    for (const KeptObject& object : frame.objects) {
      const ObjectTruth& truth = *object.truth;
      json a;
      a["image_id"] = image_id;
      a["category_id"] = object.class_index + 1;
      a["bbox"] = BoxJson(object.box);
      a["area"] = object.mask->pixel_count;
      a["iscrowd"] = 0;
      if (polygons_) {
        const masks::MaskPolygons polygons = masks::ExtractPolygons(*object.mask);
        const std::string& name = classes[object.class_index].name;
        if (polygons.pieces.size() > 1) loss->Add(loss::kPiecesSplit, name);
        if (polygons.holes > 0) loss->Add(loss::kHolesFilled, name);
        loss->Add(loss::kPolygonMaskPixels, name, object.mask->pixel_count);
        loss->Add(loss::kPolygonHolePixels, name, polygons.hole_pixels);
        json segmentation = json::array();
        for (const masks::Polygon& polygon : polygons.pieces) {
          json flat = json::array();
          for (const cv::Point2d& p : polygon) {
            flat.push_back(p.x);
            flat.push_back(p.y);
          }
          segmentation.push_back(std::move(flat));
        }
        a["segmentation"] = std::move(segmentation);
      } else {
        a["segmentation"] = {
            {"size", {frame.height, frame.width}},
            {"counts", masks::CocoRleToString(masks::CocoRleCounts(*object.mask))}};
      }
      a["lsds"] = {
          {"instance_id", truth.instance_id},
          {"class_id", truth.class_id},
          {"name", truth.name},
          {"visible_pixels", truth.visible_pixels},
          {"visibility", truth.visibility},
          {"in_frame", truth.in_frame},
          {"bbox_projected", truth.bbox_projected ? BoxJson(*truth.bbox_projected) : json()}};
      if (truth.obb)
        a["lsds"]["obb"] = {{"center", Vector3ToJson(truth.obb->center)},
                            {"half_extents", Vector3ToJson(truth.obb->half_extents)},
                            {"world_from_box", Matrix3ToJson(truth.obb->world_from_box)}};
      std::string text = a.dump();
      piece->annotations.push_back(text.substr(1));  // without the leading "{"
    }
    return piece;
  }

  void AddFrame(const FrameContext& frame, std::unique_ptr<FramePiece> base) override {
    auto* piece = static_cast<CocoPiece*>(base.get());
    Split& s = splits_.at(frame.split);
    s.images->stream() << (s.image_count++ ? ",\n" : "") << piece->image;
    for (const std::string& annotation : piece->annotations) {
      s.annotations->stream() << (s.annotation_count++ ? ",\n" : "")
                              << "{\"id\":" << next_annotation_id_++ << "," << annotation;
    }
  }

  void Finish() override {
    json categories = json::array();
    const std::vector<OutputClass>& classes = setup_.classes->classes();
    for (size_t i = 0; i < classes.size(); ++i) {
      categories.push_back({{"id", i + 1},
                            {"name", classes[i].name},
                            {"supercategory", ""},
                            {"lsds", {{"class_ids", classes[i].source_ids}}}});
    }
    const json info = {{"description", "written by lsds convert (docs/convert.md)"},
                       {"lsds_format_version", setup_.header->format_version},
                       {"bbox", "pixel-edge [x, y, width, height]"},
                       {"segmentation", polygons_ ? "polygons" : "compressed RLE"}};
    for (auto& [name, s] : splits_) {
      s.images->Commit();
      s.annotations->Commit();
      const std::filesystem::path path =
          setup_.root / "annotations" / ("instances_" + name + ".json");
      std::unique_ptr<AtomicFile> file = OpenForWrite(path);
      std::ostream& out = file->stream();
      out << "{\"info\":" << info.dump() << ",\n\"licenses\":[],\n\"images\":[\n";
      AppendAndRemove(out, s.images_path);
      out << "\n],\n\"annotations\":[\n";
      AppendAndRemove(out, s.annotations_path);
      out << "\n],\n\"categories\":" << categories.dump() << "}\n";
      file->Commit();
    }
  }

 private:
  struct Split {
    std::filesystem::path images_path, annotations_path;
    std::unique_ptr<AtomicFile> images, annotations;
    int64_t image_count = 0, annotation_count = 0;
  };
  ConvertSetup setup_;
  bool polygons_ = false;
  std::map<std::string, Split> splits_;
  int64_t next_annotation_id_ = 1;
};

}  // namespace

std::unique_ptr<Converter> MakeCocoConverter() { return std::make_unique<CocoConverter>(); }

}  // namespace lsds::convert

#include "evaluate/yolo_results.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <sstream>
#include <string>

#include <opencv2/core.hpp>

#include "converters/yolo/yolo_segment.h"
#include "evaluate/text_number.h"
#include "libs/masks/coco_rle.h"
#include "libs/util/error.h"
#include "libs/util/input_file.h"
#include "libs/util/strings.h"

namespace lsds::evaluate {

namespace fs = std::filesystem;

namespace {

struct YoloLine {
  int64_t class_index = 0;
  std::vector<double> coordinates;  // normalised
  double confidence = 0;
};

struct YoloImage {
  int64_t image_id = 0;
  std::string stem;
  EvaluationTruth::ImageSize size;
};

// The `.txt` files of `folder`, each matched to an image of the truth by stem.
std::vector<std::pair<fs::path, YoloImage>> PredictionFiles(const fs::path& folder,
                                                            const EvaluationTruth& truth) {
  if (!fs::is_directory(folder))
    throw Error(
        "--format yolo reads a folder of <image>.txt files (Ultralytics' labels/ of "
        "predict save_txt=True)",
        Location(folder.string()));
  std::map<std::string, int64_t> by_stem;
  for (const ImageEntry& image : truth.images.images())
    by_stem[fs::path(truth.images.FileName(image)).stem().string()] = image.id;
  std::vector<std::pair<fs::path, YoloImage>> files;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder)) {
    if (entry.path().extension() != ".txt") continue;
    const std::string stem = entry.path().stem().string();
    const auto it = by_stem.find(stem);
    if (it == by_stem.end())
      throw Error("'" + stem +
                      "' is not an image of the ground truth (the name lsds convert gives the "
                      "image, without extension: 000007)",
                  Location(entry.path().string()));
    files.emplace_back(entry.path(), YoloImage{it->second, stem, truth.SizeOf(it->second)});
  }
  if (files.empty()) throw Error("no <image>.txt file in the folder", Location(folder.string()));
  std::sort(
      files.begin(), files.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  return files;
}

constexpr size_t kPolygon = 0;  // ForEachYoloLine's `coordinates` of a polygon line

// A polygon line (Results.save_txt of a segment model: `class x1 y1 ... xn yn
// conf`, the track id after it only from `yolo track`) has an even number of
// fields: the class, pairs, the confidence. An odd number is a line without
// the confidence or with a track id, which cannot be told apart.
size_t PolygonCoordinates(size_t fields, const Location& at) {
  if (fields % 2 != 0)
    throw Error("expected 'class x1 y1 ... xn yn conf' (an even number of fields), got " +
                    std::to_string(fields) +
                    ": without save_conf=True the confidence is missing (AP needs it), and track "
                    "ids (yolo track) are not read",
                at);
  if (fields < 8)
    throw Error("a polygon needs at least 3 points: got " + std::to_string((fields - 2) / 2), at);
  return fields - 2;
}

// Every line of `file` with `coordinates` numbers after the class (kPolygon:
// any number of x y pairs, at least 3).
template <typename Each>
void ForEachYoloLine(const fs::path& file, size_t fixed_coordinates, Each each) {
  std::istringstream in(ReadTextFile(file));
  std::string text;
  for (int number = 1; std::getline(in, text); ++number) {
    std::istringstream words(text);
    std::vector<std::string> tokens;
    for (std::string token; words >> token;) tokens.push_back(token);
    if (tokens.empty()) continue;
    const Location at = Location::Text(file.string(), number, 0);
    const size_t coordinates =
        fixed_coordinates == kPolygon ? PolygonCoordinates(tokens.size(), at) : fixed_coordinates;
    if (tokens.size() == coordinates + 1)
      throw Error("no confidence: Ultralytics writes it with save_conf=True, and AP needs it", at);
    if (tokens.size() != coordinates + 2 && tokens.size() != coordinates + 3)
      throw Error("expected 'class " +
                      std::string(coordinates == 4 ? "cx cy w h" : "x1 y1 x2 y2 x3 y3 x4 y4") +
                      " conf [track id]', got " + std::to_string(tokens.size()) + " fields",
                  at);
    YoloLine line;
    const double class_value = FiniteNumber(tokens[0], at);
    if (class_value < 0 || class_value != std::floor(class_value))
      throw Error("the class is not an index >= 0: '" + tokens[0] + "'", at);
    line.class_index = static_cast<int64_t>(class_value);
    for (size_t i = 0; i < coordinates; ++i)
      line.coordinates.push_back(FiniteNumber(tokens[1 + i], at));
    line.confidence = FiniteNumber(tokens[1 + coordinates], at);
    each(line, at);
  }
}

// Class c as COCO category c + 1 (as lsds convert --to yolo and --to coco
// number them).
int64_t CategoryOfClass(const YoloLine& line, const EvaluationTruth& truth, const Location& at) {
  const int64_t category = line.class_index + 1;
  if (std::find(truth.coco.category_ids.begin(), truth.coco.category_ids.end(), category) ==
      truth.coco.category_ids.end())
    throw Error("class " + std::to_string(line.class_index) +
                    " is not a class of the ground truth (YOLO class c is COCO category c + 1)",
                at);
  return category;
}

}  // namespace

std::vector<DetectionBox> ReadYoloDetections(const fs::path& folder, const EvaluationTruth& truth) {
  std::vector<DetectionBox> detections;
  for (const auto& entry : PredictionFiles(folder, truth)) {
    const fs::path& file = entry.first;
    const YoloImage& image = entry.second;  // a variable, not a binding: lambdas capture it
    ForEachYoloLine(file, 4, [&](const YoloLine& line, const Location& at) {
      DetectionBox d;
      d.image_id = image.image_id;
      d.category_id = CategoryOfClass(line, truth, at);
      const double w = static_cast<double>(image.size.width);
      const double h = static_cast<double>(image.size.height);
      // xywhn: centre and size over the image's width and height.
      d.bbox.w = line.coordinates[2] * w;
      d.bbox.h = line.coordinates[3] * h;
      d.bbox.x = line.coordinates[0] * w - d.bbox.w / 2;
      d.bbox.y = line.coordinates[1] * h - d.bbox.h / 2;
      if (d.bbox.w < 0 || d.bbox.h < 0) throw Error("negative width or height", at);
      d.score = line.confidence;
      detections.push_back(d);
    });
  }
  return detections;
}

std::vector<DetectionBox> ReadYoloSegmentDetections(const fs::path& folder,
                                                    const EvaluationTruth& truth) {
  std::vector<DetectionBox> detections;
  for (const auto& entry : PredictionFiles(folder, truth)) {
    const fs::path& file = entry.first;
    const YoloImage& image = entry.second;  // a variable, not a binding: lambdas capture it
    ForEachYoloLine(file, kPolygon, [&](const YoloLine& line, const Location& at) {
      DetectionBox d;
      d.image_id = image.image_id;
      d.category_id = CategoryOfClass(line, truth, at);
      d.score = line.confidence;
      // The mask as Ultralytics reads the same line as a label (polygon2mask),
      // as COCO's RLE; the area and box as COCO.loadRes gives a result without
      // a bbox (coco.py:341-347): the mask's.
      const int width = static_cast<int>(image.size.width);
      const int height = static_cast<int>(image.size.height);
      for (size_t i = 0; i < line.coordinates.size(); ++i) {
        // polygon2mask casts each pixel position to int32.
        const double pixels = line.coordinates[i] * (i % 2 == 0 ? width : height);
        if (std::abs(pixels) > masks::kMaxPolygonCoordinate)
          throw Error("coordinate " + std::to_string(i + 1) + " lies " + FormatNumber(pixels, 3) +
                          " pixels away, far outside the image",
                      at);
      }
      const std::vector<float> xy(line.coordinates.begin(), line.coordinates.end());
      masks::BoxMask mask;
      mask.mask = convert::UltralyticsPolygonMask(xy, width, height, cv::Rect(0, 0, width, height));
      mask.pixel_count = cv::countNonZero(mask.mask);
      mask.image_width = width;
      mask.image_height = height;
      d.mask = {image.size.height, image.size.width, masks::CocoRleCounts(mask)};
      d.area = static_cast<double>(mask.pixel_count);
      const std::array<double, 4> box = masks::CocoRleBox(d.mask);
      d.bbox = {box[0], box[1], box[2], box[3]};
      detections.push_back(std::move(d));
    });
  }
  return detections;
}

std::vector<DotaDetection> ReadYoloObbDetections(const fs::path& folder,
                                                 const EvaluationTruth& truth,
                                                 const std::vector<std::string>& class_names) {
  std::vector<DotaDetection> detections;
  for (const auto& entry : PredictionFiles(folder, truth)) {
    const fs::path& file = entry.first;
    const YoloImage& image = entry.second;  // a variable, not a binding: lambdas capture it
    ForEachYoloLine(file, 8, [&](const YoloLine& line, const Location& at) {
      if (line.class_index >= static_cast<int64_t>(class_names.size()))
        throw Error("class " + std::to_string(line.class_index) + " is not a class of the ground " +
                        "truth (" + std::to_string(class_names.size()) + " classes)",
                    at);
      DotaDetection d;
      d.image = image.stem;
      d.class_name = class_names[static_cast<size_t>(line.class_index)];
      d.score = line.confidence;
      // xyxyxyxyn: corners over the image's width and height.
      for (size_t i = 0; i < 8; ++i)
        d.quad[i] = line.coordinates[i] *
                    static_cast<double>(i % 2 == 0 ? image.size.width : image.size.height);
      detections.push_back(std::move(d));
    });
  }
  return detections;
}

}  // namespace lsds::evaluate

#include "evaluate/yolo_results.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <sstream>
#include <string>

#include "evaluate/text_number.h"
#include "libs/util/error.h"
#include "libs/util/input_file.h"

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
  for (const auto& [name, id] : truth.image_by_file_name)
    by_stem[fs::path(name).stem().string()] = id;
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
    files.emplace_back(entry.path(), YoloImage{it->second, stem, truth.image_size.at(it->second)});
  }
  if (files.empty()) throw Error("no <image>.txt file in the folder", Location(folder.string()));
  std::sort(
      files.begin(), files.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  return files;
}

// Every line of `file` with `coordinates` numbers after the class.
template <typename Each>
void ForEachYoloLine(const fs::path& file, size_t coordinates, Each each) {
  std::istringstream in(ReadTextFile(file));
  std::string text;
  for (int number = 1; std::getline(in, text); ++number) {
    std::istringstream words(text);
    std::vector<std::string> tokens;
    for (std::string token; words >> token;) tokens.push_back(token);
    if (tokens.empty()) continue;
    const Location at = Location::Text(file.string(), number, 0);
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

}  // namespace

std::vector<DetectionBox> ReadYoloDetections(const fs::path& folder, const EvaluationTruth& truth) {
  std::vector<DetectionBox> detections;
  for (const auto& entry : PredictionFiles(folder, truth)) {
    const fs::path& file = entry.first;
    const YoloImage& image = entry.second;  // a variable, not a binding: lambdas capture it
    ForEachYoloLine(file, 4, [&](const YoloLine& line, const Location& at) {
      DetectionBox d;
      d.image_id = image.image_id;
      d.category_id = line.class_index + 1;
      if (std::find(truth.coco.category_ids.begin(),
                    truth.coco.category_ids.end(),
                    d.category_id) == truth.coco.category_ids.end())
        throw Error("class " + std::to_string(line.class_index) +
                        " is not a class of the ground truth (YOLO class c is COCO category c + 1)",
                    at);
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

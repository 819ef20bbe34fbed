#include "evaluate/mot_results.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <optional>
#include <sstream>

#include "converters/mot/mot_converter.h"
#include "evaluate/assignment.h"
#include "evaluate/conditions.h"
#include "evaluate/text_number.h"
#include "libs/util/error.h"
#include "libs/util/input_file.h"

namespace lsds::evaluate {

namespace fs = std::filesystem;

namespace {

// TrackEval's reader takes commas, or spaces when a line has none.
std::vector<std::string> Fields(const std::string& line) {
  std::string text = line;
  if (text.find(',') != std::string::npos) std::replace(text.begin(), text.end(), ',', ' ');
  std::istringstream words(text);
  std::vector<std::string> fields;
  for (std::string word; words >> word;) fields.push_back(word);
  return fields;
}

// TrackEval's MOT17 class ids of its distractor classes
// (mot_challenge_2d_box.py:76-78, :325-328; non_mot_vehicle only for MOT20).
const std::set<int> kDistractorIds = {2, 7, 8, 12};

// The category of each MOT class id lsds convert --to mot writes.
std::map<int64_t, int64_t> CategoryOfMotClass(const EvaluationTruth& truth,
                                              const std::string& mot_classes) {
  std::map<int64_t, int64_t> category_of;
  for (size_t k = 0; k < truth.coco.category_ids.size(); ++k) {
    const int64_t category = truth.coco.category_ids[k];
    if (mot_classes != "mot17") {
      category_of[category] = category;  // order: the output index + 1, as COCO's
      continue;
    }
    const std::optional<int> id = convert::Mot17ClassId(truth.category_names[k]);
    if (!id) continue;  // not written to gt.txt
    const auto [it, fresh] = category_of.emplace(*id, category);
    if (!fresh)
      throw Error("--mot-classes mot17: classes '" + *CategoryName(truth, it->second) + "' and '" +
                  truth.category_names[k] + "' are both MOT17 class " + std::to_string(*id) +
                  ", so tracker rows cannot tell them apart");
  }
  return category_of;
}

// A row's category: its class, the 8th field when it has one, else 1
// (astype(int) of the float: cut toward zero; :249-253).
int64_t RowCategory(const std::vector<std::string>& fields,
                    const std::map<int64_t, int64_t>& category_of,
                    const EvaluationTruth& truth,
                    const Location& at) {
  const double value = fields.size() >= 8 ? FiniteNumber(fields[7], at) : 1.0;
  if (std::abs(value) > 1e9)
    throw Error("the class (8th field) is not a class id: " + fields[7], at);
  const auto mot_class = static_cast<int64_t>(std::trunc(value));
  if (const auto it = category_of.find(mot_class); it != category_of.end()) return it->second;
  if (truth.coco.category_ids.size() == 1 && mot_class <= 1) return truth.coco.category_ids.front();
  if (fields.size() < 8)
    throw Error("no class (8th field), and the ground truth has " +
                    std::to_string(truth.coco.category_ids.size()) +
                    " categories: write the class id lsds convert --to mot writes in gt.txt",
                at);
  throw Error("class " + std::to_string(mot_class) +
                  " (8th field) is not a class of the ground truth (lsds convert --to mot's class "
                  "ids; --mot-classes as the export was made)",
              at);
}

// _calculate_box_ious (trackeval/datasets/_base_dataset.py:248-286) of two
// [x, y, w, h] boxes: 0 where either area or the union is at most eps.
double TrackEvalIou(const BoxXywh& a, const BoxXywh& b) {
  constexpr double kEps = std::numeric_limits<double>::epsilon();
  const double w = std::max(std::min(a.x + a.w, b.x + b.w) - std::max(a.x, b.x), 0.0);
  const double h = std::max(std::min(a.y + a.h, b.y + b.h) - std::max(a.y, b.y), 0.0);
  double intersection = w * h;
  const double area_a = a.w * a.h, area_b = b.w * b.h;
  double union_area = area_a + area_b - intersection;
  if (area_a <= kEps || area_b <= kEps || union_area <= kEps) intersection = 0;
  if (union_area <= kEps) union_area = 1;
  return intersection / union_area;
}

// The rows (of every class) TrackEval's assignment matches to an object of a
// distractor category in their image (mot_challenge_2d_box.py:373-382:
// similarities under .5 - eps set to 0, linear_sum_assignment of their
// negatives, pairs above eps kept), left out.
void DropDistractorMatches(const EvaluationTruth& truth,
                           const std::set<int64_t>& distractors,
                           std::vector<DetectionBox>* detections) {
  if (distractors.empty()) return;
  constexpr double kEps = std::numeric_limits<double>::epsilon();
  std::map<int64_t, std::vector<size_t>> rows_of_image;
  for (size_t d = 0; d < detections->size(); ++d)
    rows_of_image[(*detections)[d].image_id].push_back(d);
  std::vector<char> drop(detections->size(), 0);
  truth.ForEachImage([&](TruthImage&& image) {
    const auto rows = rows_of_image.find(image.image_id);
    if (rows == rows_of_image.end()) return;
    const bool any = std::any_of(image.boxes.begin(), image.boxes.end(), [&](const auto& g) {
      return distractors.count(g.category_id) > 0;
    });
    if (!any) return;
    const size_t G = image.boxes.size(), D = rows->second.size();
    std::vector<double> cost(G * D, 0);
    for (size_t g = 0; g < G; ++g)
      for (size_t d = 0; d < D; ++d) {
        const double iou = TrackEvalIou(image.boxes[g].bbox, (*detections)[rows->second[d]].bbox);
        cost[g * D + d] = iou < 0.5 - kEps ? 0 : -iou;
      }
    const std::vector<int> match = MinCostAssignment(cost, G, D);
    for (size_t g = 0; g < G; ++g) {
      if (match[g] < 0 || -cost[g * D + static_cast<size_t>(match[g])] <= kEps) continue;
      if (distractors.count(image.boxes[g].category_id))
        drop[rows->second[static_cast<size_t>(match[g])]] = 1;
    }
  });
  size_t kept = 0;
  for (size_t d = 0; d < detections->size(); ++d)
    if (!drop[d]) (*detections)[kept++] = (*detections)[d];
  detections->resize(kept);
}

}  // namespace

std::set<int64_t> MotDistractorCategories(const EvaluationTruth& truth,
                                          const std::string& mot_classes) {
  std::set<int64_t> out;
  if (mot_classes != "mot17") return out;
  for (size_t k = 0; k < truth.coco.category_ids.size(); ++k) {
    const std::optional<int> id = convert::Mot17ClassId(truth.category_names[k]);
    if (id && kDistractorIds.count(*id)) out.insert(truth.coco.category_ids[k]);
  }
  return out;
}

std::vector<DetectionBox> ReadMotDetections(const fs::path& folder,
                                            const EvaluationTruth& truth,
                                            const MotSequences& sequences,
                                            const std::string& mot_classes) {
  if (!fs::is_directory(folder))
    throw Error("--format mot reads a folder of <SEQ>.txt tracker files (TrackEval's data/)",
                Location(folder.string()));
  const std::map<int64_t, int64_t> category_of = CategoryOfMotClass(truth, mot_classes);
  std::map<int64_t, int64_t> image_of_frame;
  for (const ImageEntry& image : truth.images.images())
    image_of_frame.emplace(image.frame, image.id);
  std::vector<fs::path> files;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder))
    if (entry.path().extension() == ".txt") files.push_back(entry.path());
  if (files.empty()) throw Error("no <SEQ>.txt file in the folder", Location(folder.string()));
  std::sort(files.begin(), files.end());
  std::vector<DetectionBox> detections;
  for (const fs::path& file : files) {
    const auto sequence = sequences.find(file.stem().string());
    if (sequence == sequences.end())
      throw Error("'" + file.stem().string() +
                      "' is not a sequence of lsds convert --to mot (its seqmaps list them)",
                  Location(file.string()));
    std::istringstream in(ReadTextFile(file));
    int number = 0;
    for (std::string line; std::getline(in, line);) {
      const Location at = Location::Text(file.string(), ++number, 0);
      const std::vector<std::string> fields = Fields(line);
      if (fields.empty()) continue;
      if (fields.size() < 7)
        throw Error("expected 'frame,id,bb_left,bb_top,bb_width,bb_height,conf[,class,...]', got " +
                        std::to_string(fields.size()) + " fields",
                    at);
      const double frame_number = FiniteNumber(fields[0], at);
      const std::vector<int64_t>& frames = sequence->second;
      if (frame_number < 1 || frame_number > static_cast<double>(frames.size()) ||
          frame_number != std::floor(frame_number))
        throw Error("frame " + fields[0] + " is not a frame of the sequence (1.." +
                        std::to_string(frames.size()) + ")",
                    at);
      const auto image = image_of_frame.find(frames[static_cast<size_t>(frame_number) - 1]);
      if (image == image_of_frame.end())
        throw Error("frame " + fields[0] + " has no image in the ground truth", at);
      DetectionBox d;
      d.image_id = image->second;
      d.category_id = RowCategory(fields, category_of, truth, at);
      // MOT's boxes are 1-based: bb_left 1 is the first pixel column.
      d.bbox = {FiniteNumber(fields[2], at) - 1,
                FiniteNumber(fields[3], at) - 1,
                FiniteNumber(fields[4], at),
                FiniteNumber(fields[5], at)};
      if (d.bbox.w < 0 || d.bbox.h < 0) throw Error("negative width or height", at);
      d.score = FiniteNumber(fields[6], at);
      detections.push_back(d);
    }
  }
  DropDistractorMatches(truth, MotDistractorCategories(truth, mot_classes), &detections);
  return detections;
}

}  // namespace lsds::evaluate

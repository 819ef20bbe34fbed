#include "evaluate/predictions.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>

#include "evaluate/segmentation.h"
#include "libs/collection/json_stream.h"
#include "libs/util/error.h"
#include "libs/util/input_file.h"
#include "libs/util/json_errors.h"
#include "libs/util/limits.h"

namespace lsds::evaluate {

using nlohmann::json;

namespace {

// The spellings Python's json.dump gives non-finite floats. They are not
// JSON; each one outside a string is quoted, so that the entry holding it is
// reported at its JSON pointer rather than as a syntax error.
const char* const kNonFinite[] = {"-Infinity", "Infinity", "NaN"};

std::string QuoteNonFiniteTokens(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  bool in_string = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      out += c;
      if (c == '\\' && i + 1 < text.size()) {
        out += text[++i];
      } else if (c == '"') {
        in_string = false;
      }
      continue;
    }
    if (c == '"') in_string = true;
    bool quoted = false;
    for (const char* token : kNonFinite) {
      const size_t n = std::strlen(token);
      if (text.compare(i, n, token) == 0) {
        out += '"' + std::string(token) + '"';
        i += n - 1;
        quoted = true;
        break;
      }
    }
    if (!quoted) out += c;
  }
  return out;
}

class EntryReader {
 public:
  EntryReader(const std::string& file, const EvaluationTruth& truth) : file_(file), truth_(truth) {
    for (int64_t id : truth.coco.image_ids) images_.push_back(id);
    std::sort(images_.begin(), images_.end());
    for (int64_t id : truth.coco.category_ids) categories_.push_back(id);
    std::sort(categories_.begin(), categories_.end());
  }

  DetectionBox Read(const json& entry, const std::string& at) const {
    if (!entry.is_object())
      Fail(at,
           truth_.coco.iou_type == IouType::kMask
               ? "expected an object {image_id, category_id, segmentation, score}"
               : "expected an object {image_id, category_id, bbox, score}");
    DetectionBox d;
    d.image_id = Image(entry, at);
    d.category_id = Id(entry, at, "category_id");
    if (!std::binary_search(categories_.begin(), categories_.end(), d.category_id))
      Fail(at + "/category_id",
           "category " + std::to_string(d.category_id) + " is not a category of the ground truth");
    if (truth_.coco.iou_type == IouType::kMask) {
      const EvaluationTruth::ImageSize size = truth_.SizeOf(d.image_id);
      d.mask = ReadSegmentation(
          *Member(entry, at, "segmentation"), size.height, size.width, file_, at + "/segmentation");
    }
    if (NeedsBox(entry)) {
      d.bbox = Box(*Member(entry, at, "bbox"), at + "/bbox");
    } else {
      const std::array<double, 4> box = masks::CocoRleBox(d.mask);
      d.bbox = {box[0], box[1], box[2], box[3]};
    }
    // COCO.loadRes for a mask result file whose first entry has no box: every
    // area is the mask's, a missing box the mask's (coco.py:341-347).
    if (truth_.coco.iou_type == IouType::kMask && !boxes_given_)
      d.area = static_cast<double>(masks::CocoRleArea(d.mask.counts));
    d.score = Number(*Member(entry, at, "score"), at + "/score");
    return d;
  }

  // COCO.loadRes takes the boxes' branch when the first entry has a non-empty
  // bbox (coco.py:332-340): then every entry needs one, and its area is w * h.
  void SetBoxesGiven(const json& first) {
    const auto bbox = first.is_object() ? first.find("bbox") : first.end();
    boxes_given_ = bbox != first.end() && !(bbox->is_array() && bbox->empty());
  }

  [[noreturn]] void Fail(const std::string& at, const std::string& what) const {
    throw Error(what, Location(file_, at));
  }

 private:
  bool NeedsBox(const json& entry) const {
    if (truth_.coco.iou_type == IouType::kBox || boxes_given_) return true;
    const auto bbox = entry.find("bbox");
    return bbox != entry.end() && !(bbox->is_array() && bbox->empty());
  }

  BoxXywh Box(const json& bbox, const std::string& at) const {
    if (!bbox.is_array() || bbox.size() != 4)
      Fail(at, "expected [x, y, width, height], got " + bbox.dump());
    BoxXywh box;
    double* values[] = {&box.x, &box.y, &box.w, &box.h};
    for (size_t i = 0; i < 4; ++i) {
      *values[i] = Number(bbox[i], at + "/" + std::to_string(i));
      if (i >= 2 && *values[i] < 0)
        Fail(at + "/" + std::to_string(i),
             std::string(i == 2 ? "width" : "height") + " is negative: " + bbox[i].dump());
    }
    return box;
  }

  const json* Member(const json& entry, const std::string& at, const char* key) const {
    const auto it = entry.find(key);
    if (it == entry.end()) Fail(at, std::string("missing '") + key + "'");
    return &*it;
  }

  double Number(const json& value, const std::string& at) const {
    if (value.is_string()) {
      for (const char* token : kNonFinite)
        if (value.get<std::string>() == token)
          Fail(at, std::string(token) + " is not a finite number");
    }
    if (!value.is_number()) Fail(at, "expected a number, got " + value.dump());
    const double number = value.get<double>();
    if (!std::isfinite(number)) Fail(at, "not a finite number: " + value.dump());
    return number;
  }

  int64_t Id(const json& entry, const std::string& at, const char* key) const {
    const json* value = Member(entry, at, key);
    return AtPointer(file_, at + "/" + key, [&] { return JsonInteger<int64_t>(*value, key); });
  }

  // image_id, or file_name as `lsds convert` names the image.
  int64_t Image(const json& entry, const std::string& at) const {
    if (!entry.contains("image_id") && entry.contains("file_name")) {
      const json& name = entry["file_name"];
      const ImageEntry* image = name.is_string()
                                    ? truth_.images.FindFileName(name.get_ref<const std::string&>())
                                    : nullptr;
      if (image == nullptr)
        Fail(at + "/file_name", "image " + name.dump() + " is not an image of the ground truth");
      return image->id;
    }
    const int64_t id = Id(entry, at, "image_id");
    if (!std::binary_search(images_.begin(), images_.end(), id))
      Fail(at + "/image_id",
           "image " + std::to_string(id) +
               " is not an image of the ground truth (ids are frame index + 1, as lsds convert "
               "--to coco assigns them)");
    return id;
  }

  std::string file_;
  const EvaluationTruth& truth_;
  std::vector<int64_t> images_, categories_;
  bool boxes_given_ = true;
};

}  // namespace

std::vector<DetectionBox> ParseCocoPredictions(const std::string& text,
                                               const std::string& file,
                                               const EvaluationTruth& truth) {
  if (text.find_first_not_of(" \t\r\n") == std::string::npos)
    throw Error("the predictions file is empty (expected a JSON list, [] for none)",
                Location(file));
  CheckJsonNesting(text, file);
  json document;
  try {
    document = ParseJsonText(text, file);
  } catch (const Error&) {
    // NaN / Infinity tokens: parsed quoted, then reported at their entry; any
    // other syntax error at its own line and column.
    const std::string quoted = QuoteNonFiniteTokens(text);
    if (quoted == text) throw;
    try {
      document = ParseJsonText(quoted, file);
    } catch (const Error&) {
      ParseJsonText(text, file);  // throws the error of the text as given
      throw;
    }
  }
  if (!document.is_array())
    throw Error("expected a JSON list of detections (a COCO results file), got a " +
                    std::string(document.type_name()),
                Location(file, "/"));
  EntryReader reader(file, truth);
  if (!document.empty()) reader.SetBoxesGiven(document[0]);
  std::vector<DetectionBox> detections;
  detections.reserve(document.size());
  for (size_t i = 0; i < document.size(); ++i)
    detections.push_back(reader.Read(document[i], "/" + std::to_string(i)));
  return detections;
}

void ReadCocoPredictions(const std::filesystem::path& file,
                         const EvaluationTruth& truth,
                         const std::function<void(DetectionBox&&)>& on_detection) {
  // The entries one at a time as they are parsed (no document of the whole
  // list is built); a file that does not parse as a list is read again whole
  // by ParseCocoPredictions, which says what is wrong with it (an empty file,
  // NaN or Infinity at their entry, a syntax error at its line and column).
  EntryReader reader(file.string(), truth);
  bool entry_failed = false;
  try {
    StreamJsonArrays(file, {}, nullptr, [&](const std::string&, json&& entry, size_t index) {
      try {
        if (index == 0) reader.SetBoxesGiven(entry);
        on_detection(reader.Read(entry, "/" + std::to_string(index)));
      } catch (...) {
        entry_failed = true;
        throw;
      }
    });
  } catch (const Error&) {
    if (entry_failed) throw;
    // Entries were handed out already: the whole-file parse only names the
    // fault; should it find none, the streaming parser's error stands.
    ParseCocoPredictions(ReadTextFile(file), file.string(), truth);
    throw;
  }
}

std::vector<DetectionBox> ReadCocoPredictions(const std::filesystem::path& file,
                                              const EvaluationTruth& truth) {
  std::vector<DetectionBox> detections;
  ReadCocoPredictions(
      file, truth, [&detections](DetectionBox&& d) { detections.push_back(std::move(d)); });
  detections.shrink_to_fit();
  return detections;
}

}  // namespace lsds::evaluate

// pycocotools' COCO index and COCOeval (PythonAPI/pycocotools/coco.py,
// cocoeval.py and _mask.pyx at 8c9bcc3): what a ground-truth file needs so
// that every annotation is indexed and evaluated.
#include <map>
#include <set>
#include <system_error>

#include <nlohmann/json.hpp>

#include "converters/check/consumer.h"
#include "converters/check/text_input.h"
#include "libs/util/strings.h"

namespace lsds::check {

namespace fs = std::filesystem;
using nlohmann::json;

const std::vector<Rule>& PycocotoolsRules() {
  static const std::vector<Rule> rules = {
      {"pycocotools.document",
       Severity::kRejected,
       "PythonAPI/pycocotools/coco.py:84-85 (8c9bcc3)",
       "the file must be a JSON object"},
      {"pycocotools.required-key",
       Severity::kRejected,
       "PythonAPI/pycocotools/coco.py:96-110; cocoeval.py:251, 261 (8c9bcc3)",
       "annotations need id, image_id, category_id, area and iscrowd; images and categories "
       "need id (KeyError otherwise)"},
      {"pycocotools.duplicate-image-id",
       Severity::kDroppedImage,
       "PythonAPI/pycocotools/coco.py:101-102 (8c9bcc3)",
       "a second image with the same id replaces the first in the index"},
      {"pycocotools.duplicate-annotation-id",
       Severity::kDroppedBox,
       "PythonAPI/pycocotools/coco.py:96-98 (8c9bcc3)",
       "a second annotation with the same id replaces the first in the index"},
      {"pycocotools.unknown-category",
       Severity::kDroppedBox,
       "PythonAPI/pycocotools/cocoeval.py:81; coco.py:149 (8c9bcc3)",
       "an annotation whose category_id no category has is never evaluated"},
      {"pycocotools.unknown-image",
       Severity::kDroppedBox,
       "PythonAPI/pycocotools/cocoeval.py:80; coco.py:145, 418 (8c9bcc3)",
       "an annotation whose image_id no image has is never evaluated (segm: KeyError)"},
      {"pycocotools.bbox",
       Severity::kRejected,
       "PythonAPI/pycocotools/_mask.pyx:179-184 (8c9bcc3)",
       "bbox must be a list of 4 numbers"},
      {"pycocotools.polygon",
       Severity::kRejected,
       "PythonAPI/pycocotools/_mask.pyx:288-307 (8c9bcc3)",
       "each polygon needs at least 6 coordinates, an even number (4 are read as a box, fewer "
       "raise); an empty list raises"},
      {"pycocotools.rle-size",
       Severity::kRejected,
       "PythonAPI/pycocotools/coco.py:418-431; _mask.pyx:283 (8c9bcc3)",
       "an RLE needs counts and size, and size must be the image's [height, width]"},
      {"pycocotools.image-size",
       Severity::kRejected,
       "PythonAPI/pycocotools/coco.py:418-419 (8c9bcc3)",
       "an image with annotations needs width and height (segmentation evaluation)"},
  };
  return rules;
}

namespace {

// The 1-based line on which each element of the top-level arrays "images",
// "annotations" and "categories" starts: nlohmann keeps no positions, and a
// finding must say where the element is.
std::map<std::string, std::vector<int64_t>> ElementLines(const std::string& text) {
  std::map<std::string, std::vector<int64_t>> lines;
  int depth = 0;
  int64_t line = 1;
  std::string last_key, current, array;  // the key being read, the last key at depth 1
  bool in_string = false, escaped = false, expect_element = false;
  for (char c : text) {
    if (c == '\n') ++line;
    if (in_string) {
      if (escaped)
        escaped = false;
      else if (c == '\\')
        escaped = true;
      else if (c == '"')
        in_string = false;
      else if (depth == 1)
        current += c;
      continue;
    }
    if (c == ' ' || c == '\t' || c == '\r' || c == '\n') continue;
    if (expect_element && c != ']') {
      lines[array].push_back(line);
      expect_element = false;
    }
    switch (c) {
      case '"':
        in_string = true;
        if (depth == 1) current.clear();
        break;
      case ':':
        if (depth == 1) last_key = current;
        break;
      case '{':
      case '[':
        ++depth;
        if (c == '[' && depth == 2 &&
            (last_key == "images" || last_key == "annotations" || last_key == "categories")) {
          array = last_key;
          expect_element = true;
        }
        break;
      case '}':
      case ']':
        if (depth == 2) array.clear();
        --depth;
        expect_element = false;
        break;
      case ',':
        if (depth == 2 && !array.empty()) expect_element = true;
        break;
      default:
        break;
    }
  }
  return lines;
}

int64_t LineOf(const std::map<std::string, std::vector<int64_t>>& lines,
               const std::string& array,
               size_t index) {
  const auto it = lines.find(array);
  return it != lines.end() && index < it->second.size() ? it->second[index] : 0;
}

std::string IdText(const json& value) { return value.dump(); }

void CheckSegmentation(const json& segmentation,
                       const json* image,
                       const fs::path& file,
                       int64_t line,
                       FindingSink* sink) {
  if (segmentation.is_array()) {
    if (segmentation.empty()) {
      sink->Add("pycocotools.polygon", file, line, "empty segmentation list: frPyObjects raises");
      return;
    }
    for (size_t p = 0; p < segmentation.size(); ++p) {
      const json& polygon = segmentation[p];
      if (!polygon.is_array()) {
        sink->Add(
            "pycocotools.polygon", file, line, "polygon " + std::to_string(p) + " is not a list");
        continue;
      }
      if (polygon.size() < 6 || polygon.size() % 2 != 0) {
        sink->Add("pycocotools.polygon",
                  file,
                  line,
                  "polygon " + std::to_string(p) + " has " + std::to_string(polygon.size()) +
                      " coordinates (an even number >= 6 needed)");
      }
    }
    return;
  }
  if (!segmentation.is_object() || !segmentation.contains("counts") ||
      !segmentation.contains("size")) {
    sink->Add("pycocotools.rle-size", file, line, "segmentation is neither polygons nor an RLE");
    return;
  }
  const json& size = segmentation["size"];
  if (image == nullptr || !image->contains("height") || !image->contains("width")) return;
  if (!size.is_array() || size.size() != 2 || size[0] != (*image)["height"] ||
      size[1] != (*image)["width"]) {
    sink->Add("pycocotools.rle-size",
              file,
              line,
              "RLE size " + size.dump() + " is not the image's [height, width] [" +
                  (*image)["height"].dump() + ", " + (*image)["width"].dump() + "]");
  }
}

// The array `key` of the document, or an empty one.
const json& ArrayOf(const json& document, const char* key) {
  static const json empty = json::array();
  return document.contains(key) && document[key].is_array() ? document[key] : empty;
}

// One COCO file's check against the index pycocotools builds (COCO.createIndex):
// images and categories indexed first, then each annotation checked.
class CocoFileCheck {
 public:
  CocoFileCheck(const fs::path& file,
                const std::string& text,
                const json& document,
                FindingSink* sink)
      : file_(file),
        sink_(sink),
        lines_(ElementLines(text)),
        images_(ArrayOf(document, "images")),
        annotations_(ArrayOf(document, "annotations")),
        categories_(ArrayOf(document, "categories")) {}

  void Run() {
    IndexImages();
    IndexCategories();
    for (size_t i = 0; i < annotations_.size(); ++i) CheckAnnotation(i);
    CheckAnnotatedImageSizes();
  }

 private:
  void IndexImages();
  void IndexCategories();
  void CheckAnnotation(size_t i);
  void CheckAnnotationId(const json& a, size_t i, int64_t line);
  const json* FindImage(const json& a, int64_t line);
  void CheckAnnotatedImageSizes();

  const fs::path& file_;
  FindingSink* sink_;
  const std::map<std::string, std::vector<int64_t>> lines_;
  const json& images_;
  const json& annotations_;
  const json& categories_;
  std::map<std::string, size_t> image_index_;  // id (as JSON text) -> index
  std::set<std::string> category_ids_;
  std::map<std::string, size_t> annotation_index_;
  std::set<std::string> images_with_annotations_;
};

void CocoFileCheck::IndexImages() {
  for (size_t i = 0; i < images_.size(); ++i) {
    const int64_t line = LineOf(lines_, "images", i);
    if (!images_[i].is_object() || !images_[i].contains("id")) {
      sink_->Add(
          "pycocotools.required-key", file_, line, "image " + std::to_string(i) + " has no id");
      continue;
    }
    const std::string id = IdText(images_[i]["id"]);
    const auto [it, inserted] = image_index_.emplace(id, i);
    if (!inserted) {
      sink_->Add("pycocotools.duplicate-image-id",
                 file_,
                 line,
                 "image id " + id + " already on line " +
                     std::to_string(LineOf(lines_, "images", it->second)) +
                     ": one of them is lost");
      it->second = i;  // the later one stays in the index
    }
  }
}

void CocoFileCheck::IndexCategories() {
  for (size_t i = 0; i < categories_.size(); ++i) {
    if (!categories_[i].is_object() || !categories_[i].contains("id")) {
      sink_->Add("pycocotools.required-key",
                 file_,
                 LineOf(lines_, "categories", i),
                 "category " + std::to_string(i) + " has no id");
      continue;
    }
    category_ids_.insert(IdText(categories_[i]["id"]));
  }
}

void CocoFileCheck::CheckAnnotationId(const json& a, size_t i, int64_t line) {
  if (!a.contains("id")) return;
  const std::string id = IdText(a["id"]);
  const auto [it, inserted] = annotation_index_.emplace(id, i);
  if (!inserted) {
    sink_->Add("pycocotools.duplicate-annotation-id",
               file_,
               line,
               "annotation id " + id + " already on line " +
                   std::to_string(LineOf(lines_, "annotations", it->second)) +
                   ": one of them is lost");
  }
}

// The annotation's image, or null (without image_id, or an unknown one).
const json* CocoFileCheck::FindImage(const json& a, int64_t line) {
  if (!a.contains("image_id")) return nullptr;
  const auto found = image_index_.find(IdText(a["image_id"]));
  if (found == image_index_.end()) {
    sink_->Add("pycocotools.unknown-image",
               file_,
               line,
               "image_id " + IdText(a["image_id"]) + " is not an image: never evaluated");
    return nullptr;
  }
  images_with_annotations_.insert(found->first);
  return &images_[found->second];
}

void CocoFileCheck::CheckAnnotation(size_t i) {
  const json& a = annotations_[i];
  const int64_t line = LineOf(lines_, "annotations", i);
  if (!a.is_object()) {
    sink_->Add("pycocotools.required-key",
               file_,
               line,
               "annotation " + std::to_string(i) + " is not an object");
    return;
  }
  std::vector<std::string> missing;
  for (const char* key : {"id", "image_id", "category_id", "area", "iscrowd"}) {
    if (!a.contains(key)) missing.emplace_back(key);
  }
  if (!missing.empty()) {
    sink_->Add("pycocotools.required-key",
               file_,
               line,
               "annotation " + std::to_string(i) + " has no " + Join(missing, ", "));
  }
  CheckAnnotationId(a, i, line);
  if (a.contains("category_id") && category_ids_.count(IdText(a["category_id"])) == 0) {
    sink_->Add("pycocotools.unknown-category",
               file_,
               line,
               "category_id " + IdText(a["category_id"]) + " is not a category: never evaluated");
  }
  const json* image = FindImage(a, line);
  if (a.contains("bbox")) {
    const json& bbox = a["bbox"];
    bool ok = bbox.is_array() && bbox.size() == 4;
    for (size_t k = 0; ok && k < 4; ++k) ok = bbox[k].is_number();
    if (!ok)
      sink_->Add("pycocotools.bbox", file_, line, "bbox " + bbox.dump() + " is not 4 numbers");
  }
  if (a.contains("segmentation")) CheckSegmentation(a["segmentation"], image, file_, line, sink_);
}

void CocoFileCheck::CheckAnnotatedImageSizes() {
  for (const auto& [id, index] : image_index_) {
    if (images_with_annotations_.count(id) == 0) continue;
    const json& image = images_[index];
    if (!image.contains("width") || !image.contains("height")) {
      sink_->Add("pycocotools.image-size",
                 file_,
                 LineOf(lines_, "images", index),
                 "image " + id + " has annotations but no width or height");
    }
  }
}

void CheckCocoFile(const fs::path& file, FindingSink* sink) {
  std::string text;
  ReadBytes(file, &text);
  sink->CountFile();
  const json document = json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (document.is_discarded() || !document.is_object()) {
    sink->Add("pycocotools.document",
              file,
              0,
              document.is_discarded() ? "not valid JSON" : "not a JSON object");
    return;
  }
  CocoFileCheck(file, text, document, sink).Run();
}

}  // namespace

void CheckPycocotools(const std::string& /*format*/,
                      const fs::path& dir,
                      const CheckOptions& /*options*/,
                      FindingSink* sink) {
  std::vector<fs::path> files;
  for (const fs::path& file : ListFiles(dir / "annotations")) {
    if (LowerExtension(file) == "json" && file.filename().string().rfind('.', 0) != 0)
      files.push_back(file);
  }
  if (files.empty()) {
    sink->Add("pycocotools.document", dir / "annotations", 0, "no annotations/*.json file");
    return;
  }
  for (const fs::path& file : files) CheckCocoFile(file, sink);
}

}  // namespace lsds::check

#include "converters/visdrone/visdrone_common.h"

#include <algorithm>
#include <cctype>
#include <cmath>

#include "converters/format_util.h"

namespace lsds::convert::visdrone {

namespace {

// VisDrone2019 (DET and VID readme, "object_category").
constexpr const char* kNames[] = {"ignored-regions",
                                  "pedestrian",
                                  "people",
                                  "bicycle",
                                  "car",
                                  "van",
                                  "truck",
                                  "tricycle",
                                  "awning-tricycle",
                                  "bus",
                                  "motor",
                                  "others"};
constexpr int kOthers = 11;

long Percent(double ratio) { return std::lround(100 * std::clamp(ratio, 0.0, 1.0)); }

}  // namespace

int CategoryOf(const std::string& class_name) {
  std::string key;
  for (char c : class_name)
    key +=
        c == '_' || c == ' ' ? '-' : static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  for (int k = 1; k < kOthers; ++k)
    if (key == kNames[k]) return k;
  // lsds's built-in walking figure is VisDrone's pedestrian ("people" are
  // sitting or lying).
  if (key == "person") return 1;
  return kOthers;
}

const char* CategoryName(int category) { return kNames[category]; }

std::vector<int> Categories(const ClassMap& classes) {
  std::vector<int> out;
  for (const OutputClass& c : classes.classes()) out.push_back(CategoryOf(c.name));
  return out;
}

std::string CategoryMapText(const ClassMap& classes) {
  std::string text = "class,category,category_name\n";
  for (const OutputClass& c : classes.classes()) {
    const int category = CategoryOf(c.name);
    text += c.name + "," + std::to_string(category) + "," + CategoryName(category) + "\n";
  }
  return text;
}

int TruncationLevel(double in_frame) { return Percent(1 - in_frame) == 0 ? 0 : 1; }

int OcclusionLevel(double visibility) {
  const long occluded = Percent(1 - visibility);
  return occluded == 0 ? 0 : occluded <= 50 ? 1 : 2;
}

std::string Columns(const TrackObject& object,
                    int category,
                    const std::string& class_name,
                    const std::string& format,
                    LossReport* loss) {
  if (loss != nullptr) {
    if (!object.considered) {
      loss->Add(format + ": written with score 0 (ignored): dropped by a filter", class_name);
    }
    if (category == kOthers)
      loss->Add(format + ": category 11 (others): no VisDrone name", class_name);
    if (Percent(1 - object.truth->in_frame) > 50) {
      loss->Add(format + ": truncated by more than 50 %, written as truncation 1", class_name);
    }
  }
  // The visible box lies on pixel edges: its integers are exact.
  const Box2d& b = object.box;
  const long x0 = std::lround(b.x0), y0 = std::lround(b.y0);
  return Format("%ld,%ld,%ld,%ld,%d,%d,%d,%d",
                x0,
                y0,
                std::lround(b.x1) - x0,
                std::lround(b.y1) - y0,
                object.considered ? 1 : 0,
                category,
                TruncationLevel(object.truth->in_frame),
                OcclusionLevel(object.truth->visibility));
}

}  // namespace lsds::convert::visdrone

#include "evaluate/conditions.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>
#include <set>

#include "libs/util/strings.h"

namespace lsds::evaluate {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr int kDataBins = 5;  // equal-width bins over the recorded range

using Number = std::optional<double>;
using Label = std::optional<std::string>;

// One condition: numeric (fixed edges, or kDataBins equal-width bins over the
// values when `edges` is empty) or categorical (`label`), of an object or a
// frame.
struct Definition {
  const char* name;
  const char* description;
  Level level;
  std::vector<double> edges;
  std::function<Number(const EvaluationTruth&, size_t object)> object_number;
  std::function<Label(const EvaluationTruth&, size_t object)> object_label;
  std::function<Number(const FrameFacts&)> frame_number;
  std::function<Label(const FrameFacts&)> frame_label;
  std::vector<std::string> order;  // categorical: labels in this order first
};

std::string FogLabel(const FrameFacts& f) {
  if (!f.fog_visibility_m) return "clear";
  const double v = *f.fog_visibility_m;
  if (v < 100) return "visibility < 100 m";
  if (v < 300) return "visibility 100-300 m";
  if (v < 1000) return "visibility 300-1000 m";
  if (v < 3000) return "visibility 1000-3000 m";
  return "visibility >= 3000 m";
}

using ObjectNumber = std::function<Number(const EvaluationTruth&, size_t object)>;
using ObjectLabel = std::function<Label(const EvaluationTruth&, size_t object)>;
using FrameNumber = std::function<Number(const FrameFacts&)>;
using FrameLabel = std::function<Label(const FrameFacts&)>;

Definition Object(const char* name,
                  const char* description,
                  std::vector<double> edges,
                  ObjectNumber number) {
  Definition d{
      name, description, Level::kObject, std::move(edges), std::move(number), {}, {}, {}, {}};
  return d;
}

Definition Object(const char* name,
                  const char* description,
                  ObjectLabel label,
                  std::vector<std::string> order = {}) {
  return {name, description, Level::kObject, {}, {}, std::move(label), {}, {}, std::move(order)};
}

Definition Frame(const char* name,
                 const char* description,
                 std::vector<double> edges,
                 FrameNumber number) {
  return {name, description, Level::kFrame, std::move(edges), {}, {}, std::move(number), {}, {}};
}

Definition Frame(const char* name,
                 const char* description,
                 FrameLabel label,
                 std::vector<std::string> order = {}) {
  return {name, description, Level::kFrame, {}, {}, {}, {}, std::move(label), std::move(order)};
}

const std::vector<Definition>& Definitions() {
  static const std::vector<Definition> definitions = {
      Object("size_px",
             "larger side of the box, pixels",
             {0, 8, 16, 32, 64, 128, 256, kInf},
             [](const EvaluationTruth& t, size_t i) -> Number { return t.objects[i].size_px; }),
      Object("visibility",
             "visible share of the object (1 - occlusion)",
             {0, 0.25, 0.5, 0.75, 1},
             [](const EvaluationTruth& t, size_t i) -> Number { return t.objects[i].visibility; }),
      Object("in_frame",
             "whole in the image, or truncated by its border",
             ObjectLabel([](const EvaluationTruth& t, size_t i) -> Label {
               return t.objects[i].in_frame < 1 ? "truncated" : "whole";
             }),
             {"truncated", "whole"}),
      Object("class",
             "the COCO category",
             ObjectLabel([](const EvaluationTruth& t, size_t i) -> Label {
               const int64_t id = t.coco.ground_truth[i].category_id;
               for (size_t k = 0; k < t.coco.category_ids.size(); ++k)
                 if (t.coco.category_ids[k] == id) return t.category_names[k];
               return std::nullopt;
             })),
      Object("distance_m",
             "camera centre to the object's OBB centre, metres",
             {},
             [](const EvaluationTruth& t, size_t i) -> Number { return t.objects[i].distance_m; }),
      Frame("gsd_m",
            "ground sample distance at the image centre, metres per pixel",
            {},
            [](const FrameFacts& f) { return f.gsd_m; }),
      Frame("altitude_agl_m",
            "camera height above the terrain under it, metres",
            {},
            [](const FrameFacts& f) { return f.altitude_agl_m; }),
      Frame("off_nadir_deg",
            "optical axis from straight down, degrees",
            {0, 10, 20, 30, 45, 60, 90},
            [](const FrameFacts& f) { return f.off_nadir_deg; }),
      Frame("sun_elevation_deg",
            "sun above the horizon, degrees",
            {-90, 0, 15, 30, 45, 60, 90},
            [](const FrameFacts& f) { return f.sun_elevation_deg; }),
      Frame("fog",
            "meteorological visibility through the atmosphere",
            FrameLabel([](const FrameFacts& f) -> Label {
              if (!f.atmosphere_recorded) return std::nullopt;
              return FogLabel(f);
            }),
            {"visibility < 100 m",
             "visibility 100-300 m",
             "visibility 300-1000 m",
             "visibility 1000-3000 m",
             "visibility >= 3000 m",
             "clear"}),
      Frame("clouds", "cloud type of the sky", FrameLabel([](const FrameFacts& f) {
              return f.clouds;
            })),
      Frame("terrain_material", "the terrain's material", FrameLabel([](const FrameFacts& f) {
              return f.terrain_material;
            })),
  };
  return definitions;
}

std::string EdgeText(double value) { return std::isinf(value) ? "inf" : FormatNumber(value, 3); }

// Numeric bins: [e0, e1), [e1, e2), ..., [e(n-1), en]; values outside go to
// the first or last bin.
struct NumericBins {
  std::vector<double> edges;

  static NumericBins Make(std::vector<double> edges, const std::vector<Number>& values) {
    if (edges.empty()) {
      double lo = kInf, hi = -kInf;
      for (const Number& v : values)
        if (v) lo = std::min(lo, *v), hi = std::max(hi, *v);
      if (lo > hi) return {};
      edges = {lo};
      for (int b = 1; b <= (hi > lo ? kDataBins : 1); ++b)
        edges.push_back(hi > lo ? lo + (hi - lo) * b / kDataBins : hi);
    }
    return {std::move(edges)};
  }
  int Count() const { return edges.empty() ? 0 : static_cast<int>(edges.size()) - 1; }
  int Of(double v) const {
    const int b =
        static_cast<int>(std::upper_bound(edges.begin(), edges.end(), v) - edges.begin()) - 1;
    return std::clamp(b, 0, Count() - 1);
  }
  std::vector<std::string> Labels() const {
    std::vector<std::string> labels;
    for (int b = 0; b < Count(); ++b) {
      const bool last = b == Count() - 1 && !std::isinf(edges[b + 1]);
      labels.push_back("[" + EdgeText(edges[b]) + ", " + EdgeText(edges[b + 1]) +
                       (last ? "]" : ")"));
    }
    return labels;
  }
};

// The values of a definition for every item: the objects, or the images.
struct Values {
  std::vector<Number> numbers;
  std::vector<Label> labels;
};

Values ObjectValues(const Definition& d, const EvaluationTruth& truth) {
  Values v;
  for (size_t i = 0; i < truth.objects.size(); ++i) {
    if (d.object_number) v.numbers.push_back(d.object_number(truth, i));
    if (d.object_label) v.labels.push_back(d.object_label(truth, i));
  }
  return v;
}

Values ImageValues(const Definition& d, const EvaluationTruth& truth) {
  Values v;
  for (int64_t image : truth.coco.image_ids) {
    const auto frame = truth.frames.find(truth.frame_of_image.at(image));
    const FrameFacts facts = frame == truth.frames.end() ? FrameFacts{} : frame->second;
    if (d.frame_number) v.numbers.push_back(d.frame_number(facts));
    if (d.frame_label) v.labels.push_back(d.frame_label(facts));
  }
  return v;
}

// Bin indices of the items (-1: not recorded) and the bin labels.
std::vector<int> Bin(const Definition& d,
                     const Values& values,
                     std::vector<std::string>* labels,
                     NumericBins* numeric) {
  std::vector<int> bins;
  if (d.object_number || d.frame_number) {
    *numeric = NumericBins::Make(d.edges, values.numbers);
    *labels = numeric->Labels();
    for (const Number& v : values.numbers) bins.push_back(v ? numeric->Of(*v) : -1);
    return bins;
  }
  std::set<std::string> seen;
  for (const Label& l : values.labels)
    if (l) seen.insert(*l);
  for (const std::string& l : d.order) {  // listed even when empty: coverage shows the hole
    seen.erase(l);
    labels->push_back(l);
  }
  labels->insert(labels->end(), seen.begin(), seen.end());
  for (const Label& l : values.labels) {
    const auto it = l ? std::find(labels->begin(), labels->end(), *l) : labels->end();
    bins.push_back(it == labels->end() ? -1 : static_cast<int>(it - labels->begin()));
  }
  return bins;
}

}  // namespace

const std::vector<std::string>& ConditionNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (const Definition& d : Definitions()) n.emplace_back(d.name);
    return n;
  }();
  return names;
}

std::vector<ConditionBins> BinConditions(const EvaluationTruth& truth,
                                         const std::vector<DetectionBox>& detections) {
  std::vector<ConditionBins> out;
  for (const Definition& d : Definitions()) {
    ConditionBins c;
    c.name = d.name;
    c.description = d.description;
    c.level = d.level;
    NumericBins numeric;
    if (d.level == Level::kObject) {
      c.object_bin = Bin(d, ObjectValues(d, truth), &c.bins, &numeric);
      c.edges = numeric.edges;
      if (std::none_of(c.object_bin.begin(), c.object_bin.end(), [](int b) { return b >= 0; }))
        continue;
      if (c.name == "size_px") {
        for (const DetectionBox& box : detections)
          c.detection_bin.push_back(numeric.Of(std::max(box.bbox.w, box.bbox.h)));
      }
    } else {
      const std::vector<int> per_image = Bin(d, ImageValues(d, truth), &c.bins, &numeric);
      c.edges = numeric.edges;
      for (size_t i = 0; i < per_image.size(); ++i)
        if (per_image[i] >= 0) c.image_bin[truth.coco.image_ids[i]] = per_image[i];
      if (c.image_bin.empty()) continue;
      for (const GroundTruthBox& g : truth.coco.ground_truth) {
        const auto it = c.image_bin.find(g.image_id);
        c.object_bin.push_back(it == c.image_bin.end() ? -1 : it->second);
      }
    }
    out.push_back(std::move(c));
  }
  return out;
}

}  // namespace lsds::evaluate

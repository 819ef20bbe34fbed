#include "evaluate/conditions.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>
#include <set>

#include "libs/collection/requirement_summary.h"
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
  std::function<Number(const ObjectView&)> object_number;
  std::function<Label(const ObjectView&)> object_label;
  std::function<Number(const FrameFacts&)> frame_number;
  std::function<Label(const FrameFacts&)> frame_label;
  std::vector<std::string> order;  // categorical: labels in this order first
};

std::string FogLabel(const FrameFacts& f) {
  if (std::isnan(f.fog_visibility_m)) return "clear";
  const double v = f.fog_visibility_m;
  if (v < 100) return "visibility < 100 m";
  if (v < 300) return "visibility 100-300 m";
  if (v < 1000) return "visibility 300-1000 m";
  if (v < 3000) return "visibility 1000-3000 m";
  return "visibility >= 3000 m";
}

Label Interned(const std::string* label) {
  if (label == nullptr) return std::nullopt;
  return *label;
}

using ObjectNumber = std::function<Number(const ObjectView&)>;
using ObjectLabel = std::function<Label(const ObjectView&)>;
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
             [](const ObjectView& o) -> Number { return o.facts.size_px; }),
      Object("visibility",
             "visible share of the object (1 - occlusion)",
             {0, 0.25, 0.5, 0.75, 1},
             [](const ObjectView& o) -> Number { return o.facts.visibility; }),
      Object("in_frame",
             "whole in the image, or truncated by its border",
             ObjectLabel([](const ObjectView& o) -> Label {
               return o.facts.in_frame < 1 ? "truncated" : "whole";
             }),
             {"truncated", "whole"}),
      Object("class", "the COCO category", ObjectLabel([](const ObjectView& o) -> Label {
               if (o.category == nullptr) return std::nullopt;
               return *o.category;
             })),
      Object("distance_m",
             "camera centre to the object's OBB centre, metres",
             {},
             [](const ObjectView& o) -> Number { return o.facts.distance_m; }),
      Frame("gsd_m",
            "ground sample distance at the image centre, metres per pixel",
            {},
            [](const FrameFacts& f) { return Recorded(f.gsd_m); }),
      Frame("altitude_agl_m",
            "camera height above the terrain under it, metres",
            {},
            [](const FrameFacts& f) { return Recorded(f.altitude_agl_m); }),
      Frame("off_nadir_deg",
            "optical axis from straight down, degrees",
            {0, 10, 20, 30, 45, 60, 90},
            [](const FrameFacts& f) { return Recorded(f.off_nadir_deg); }),
      Frame("sun_elevation_deg",
            "sun above the horizon, degrees",
            {-90, 0, 15, 30, 45, 60, 90},
            [](const FrameFacts& f) { return Recorded(f.sun_elevation_deg); }),
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
              return Interned(f.clouds);
            })),
      Frame("terrain_material", "the terrain's material", FrameLabel([](const FrameFacts& f) {
              return Interned(f.terrain_material);
            })),
  };
  return definitions;
}

std::string EdgeText(double value) { return std::isinf(value) ? "inf" : FormatNumber(value, 3); }

// Numeric bins: [e0, e1), [e1, e2), ..., [e(n-1), en]; values outside go to
// the first or last bin.
struct NumericBins {
  std::vector<double> edges;

  // Fixed `edges`, or kDataBins equal-width bins over [lo, hi] (none when no
  // value was seen: lo > hi).
  static NumericBins Make(std::vector<double> edges, double lo, double hi) {
    if (edges.empty()) {
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

// What one pass over the items of a definition saw: the range of its numbers,
// the set of its labels.
struct Seen {
  double lo = kInf, hi = -kInf;
  std::set<std::string> labels;

  void Add(const Definition& d, const Number& number, const Label& label) {
    if (d.object_number || d.frame_number) {
      if (number) lo = std::min(lo, *number), hi = std::max(hi, *number);
    } else if (label) {
      labels.insert(*label);
    }
  }
};

// The bins of a definition from what was seen: numeric edges and labels, or
// the categorical labels (those of `order` first, listed even when empty:
// coverage shows the hole).
void MakeBins(const Definition& d, const Seen& seen, ConditionBins* c) {
  if (d.object_number || d.frame_number) {
    const NumericBins numeric = NumericBins::Make(d.edges, seen.lo, seen.hi);
    c->edges = numeric.edges;
    c->bins = numeric.Labels();
    return;
  }
  std::set<std::string> rest = seen.labels;
  for (const std::string& l : d.order) {
    rest.erase(l);
    c->bins.push_back(l);
  }
  c->bins.insert(c->bins.end(), rest.begin(), rest.end());
}

int BinOf(const ConditionBins& c, const Number& number, const Label& label) {
  if (!c.edges.empty()) return number ? NumericBins{c.edges}.Of(*number) : -1;
  if (!label) return -1;
  const auto it = std::find(c.bins.begin(), c.bins.end(), *label);
  return it == c.bins.end() ? -1 : static_cast<int>(it - c.bins.begin());
}

bool IsNumeric(const Definition& d) { return d.object_number || d.frame_number; }

const FrameFacts& FactsOfImage(const EvaluationTruth& truth, int64_t image) {
  static const FrameFacts none;
  const ImageEntry* entry = truth.images.Find(image);
  if (entry == nullptr) return none;
  const FrameFacts* frame = truth.frames.Find(entry->frame);
  return frame == nullptr ? none : *frame;
}

// A quota as a frame condition: every bin listed (coverage shows an empty one).
ConditionBins QuotaCondition(const nlohmann::json& quotas, size_t q) {
  const nlohmann::json& quota = quotas[q];
  ConditionBins c;
  c.name = "quota:" + quota.at("name").get<std::string>();
  const std::string target = quota.value("target", "");
  c.description = "LCAP quota: " + quota.at("quantity").get<std::string>() + " of " +
                  (target.empty() ? std::string("the frame") : target) + ", " +
                  QuotaBinsText(quota) + ", the frame's achieved value";
  c.level = Level::kFrame;
  c.quota = static_cast<int>(q);
  if (quota.contains("classes")) {
    c.bins = quota.at("classes").get<std::vector<std::string>>();
  } else {
    c.edges = quota.at("bins").get<std::vector<double>>();
    c.bins = NumericBins{c.edges}.Labels();
  }
  if (quota.contains("planned")) c.planned = quota.at("planned").get<std::vector<int64_t>>();
  return c;
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

const std::string* CategoryName(const EvaluationTruth& truth, int64_t category_id) {
  for (size_t k = 0; k < truth.coco.category_ids.size() && k < truth.category_names.size(); ++k)
    if (truth.coco.category_ids[k] == category_id) return &truth.category_names[k];
  return nullptr;
}

int ObjectBin(const ConditionBins& c, const ObjectView& object) {
  const Definition& d = Definitions()[c.definition];
  return BinOf(c,
               d.object_number ? d.object_number(object) : Number(),
               d.object_label ? d.object_label(object) : Label());
}

int FrameBin(const ConditionBins& c, const FrameFacts& facts) {
  if (c.quota >= 0)
    return static_cast<size_t>(c.quota) < facts.quota_bins.size() ? facts.quota_bins[c.quota] : -1;
  const Definition& d = Definitions()[c.definition];
  return BinOf(c,
               d.frame_number ? d.frame_number(facts) : Number(),
               d.frame_label ? d.frame_label(facts) : Label());
}

int ImageBin(const ConditionBins& c, const EvaluationTruth& truth, int64_t image) {
  return FrameBin(c, FactsOfImage(truth, image));
}

int DetectionBin(const ConditionBins& c, const DetectionBox& detection) {
  if (!c.bins_detections) return -1;
  return NumericBins{c.edges}.Of(std::max(detection.bbox.w, detection.bbox.h));
}

std::vector<ConditionBins> BinConditions(const EvaluationTruth& truth) {
  const std::vector<Definition>& definitions = Definitions();
  std::vector<Seen> seen(definitions.size());
  // Frame conditions over the images, object conditions over every annotation
  // (one pass over the truth, streamed or not).
  for (size_t i = 0; i < definitions.size(); ++i) {
    const Definition& d = definitions[i];
    if (d.level != Level::kFrame) continue;
    for (int64_t image : truth.coco.image_ids) {
      const FrameFacts& facts = FactsOfImage(truth, image);
      seen[i].Add(d,
                  d.frame_number ? d.frame_number(facts) : Number(),
                  d.frame_label ? d.frame_label(facts) : Label());
    }
  }
  truth.ForEachImage([&](TruthImage&& image) {
    for (size_t o = 0; o < image.boxes.size(); ++o) {
      const ObjectView view{image.objects[o], CategoryName(truth, image.boxes[o].category_id)};
      for (size_t i = 0; i < definitions.size(); ++i) {
        const Definition& d = definitions[i];
        if (d.level != Level::kObject) continue;
        seen[i].Add(d,
                    d.object_number ? d.object_number(view) : Number(),
                    d.object_label ? d.object_label(view) : Label());
      }
    }
  });
  std::vector<ConditionBins> out;
  for (size_t i = 0; i < definitions.size(); ++i) {
    const Definition& d = definitions[i];
    ConditionBins c;
    c.name = d.name;
    c.description = d.description;
    c.level = d.level;
    c.definition = i;
    c.bins_detections = c.name == "size_px";
    MakeBins(d, seen[i], &c);
    // A condition nothing records is left out.
    const bool recorded = IsNumeric(d) ? seen[i].lo <= seen[i].hi : !seen[i].labels.empty();
    if (recorded) out.push_back(std::move(c));
  }
  for (size_t q = 0; q < truth.quotas.size(); ++q) out.push_back(QuotaCondition(truth.quotas, q));
  return out;
}

}  // namespace lsds::evaluate

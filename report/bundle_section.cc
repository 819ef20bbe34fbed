#include "report/bundle_section.h"

#include <cmath>
#include <cstdio>

#include "libs/util/error.h"
#include "libs/util/strings.h"
#include "report/html_text.h"
#include "report/svg_plot.h"

namespace lsds::report {

namespace {

std::string Percent(double share) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.2f %%", 100.0 * share);
  return buffer;
}

std::string ClassName(const CollectionHeader& header, uint32_t id) {
  const ClassInfo* c = header.FindClass(id);
  return c ? c->name : "class " + std::to_string(id);
}

[[noreturn]] void Fail(const std::string& file,
                       const std::string& pointer,
                       const std::string& what) {
  throw Error(what, Location(file, pointer));
}

// The format, and what the section shows besides the summary: typed here, so
// that the writer meets no value of another type.
void CheckHead(const nlohmann::json& stats, const std::string& file) {
  if (!stats.is_object() || !stats.contains("format") || stats["format"] != "lsds-bundle-stats") {
    Fail(file,
         "/format",
         "not an lsds bundles statistics file (format "
         "lsds-bundle-stats; write one with lsds bundles -o)");
  }
  if (stats.contains("bundle_layer") && !stats["bundle_layer"].is_string()) {
    Fail(file, "/bundle_layer", "not a string");
  }
  if (stats.contains("frame_range")) {
    const nlohmann::json& range = stats["frame_range"];
    for (const char* key : {"first", "end"}) {
      if (!range.is_object() || !range.contains(key) || !range[key].is_number_integer()) {
        Fail(file, std::string("/frame_range/") + key, "missing or not an integer");
      }
    }
  }
}

// /summary/class_mixing: class ids and a square table of sample counts.
void CheckClassMixing(const nlohmann::json& s, const std::string& file) {
  if (!s.contains("class_mixing") || !s["class_mixing"].is_object() ||
      !s["class_mixing"].contains("classes") || !s["class_mixing"]["classes"].is_array() ||
      !s["class_mixing"].contains("samples") || !s["class_mixing"]["samples"].is_array()) {
    Fail(file, "/summary/class_mixing", "missing or not {classes, samples}");
  }
  const size_t n = s["class_mixing"]["classes"].size();
  const nlohmann::json& samples = s["class_mixing"]["samples"];
  if (samples.size() != n) {
    Fail(file, "/summary/class_mixing/samples", "not one row per class");
  }
  for (size_t i = 0; i < n; ++i) {
    if (!s["class_mixing"]["classes"][i].is_number_unsigned()) {
      Fail(file, "/summary/class_mixing/classes/" + std::to_string(i), "not a class id");
    }
    if (!samples[i].is_array() || samples[i].size() != n) {
      Fail(file, "/summary/class_mixing/samples/" + std::to_string(i), "not one count per class");
    }
    for (const nlohmann::json& v : samples[i]) {
      if (!v.is_number_unsigned())
        Fail(file, "/summary/class_mixing/samples/" + std::to_string(i), "not a sample count");
    }
  }
}

// One bin of /summary/by_object_size.
void CheckSizeBin(const nlohmann::json& b, size_t i, const std::string& file) {
  const std::string at = "/summary/by_object_size/" + std::to_string(i);
  for (const char* key : {"min_pixels", "mixed_fraction"}) {
    if (!b.is_object() || !b.contains(key) || !b[key].is_number()) {
      Fail(file, at + "/" + key, "missing or not a number");
    }
  }
  // Counts: integers (a float beyond int64 would not convert).
  for (const char* key : {"objects", "pixels", "mixed_pixels"}) {
    if (!b.contains(key) || !b[key].is_number_integer()) {
      Fail(file, at + "/" + key, "missing or not an integer");
    }
  }
  if (b.contains("max_pixels") && !b["max_pixels"].is_number() && !b["max_pixels"].is_null()) {
    Fail(file, at + "/max_pixels", "not a number");
  }
}

}  // namespace

void CheckBundleStats(const nlohmann::json& stats, const std::string& file) {
  CheckHead(stats, file);
  if (!stats.contains("summary") || !stats["summary"].is_object()) {
    Fail(file, "/summary", "missing");
  }
  const nlohmann::json& s = stats["summary"];
  CheckClassMixing(s, file);
  if (!s.contains("by_object_size") || !s["by_object_size"].is_array()) {
    Fail(file, "/summary/by_object_size", "missing or not an array");
  }
  for (size_t i = 0; i < s["by_object_size"].size(); ++i)
    CheckSizeBin(s["by_object_size"][i], i, file);
}

Html BundleStatsSection(const nlohmann::json& stats, const CollectionHeader& header) {
  const nlohmann::json& s = stats["summary"];
  Html out;
  out << "<section id=\"bundles\"><h2>Mixed pixels (pixel bundles)</h2>"
      << "<p class=\"help\">From <code>lsds bundles</code> over layer '"
      << stats.value("bundle_layer", std::string("bundle")) << "', frame positions ["
      << stats.value("frame_range", nlohmann::json::object()).value("first", int64_t{0}) << ", "
      << stats.value("frame_range", nlohmann::json::object()).value("end", int64_t{0}) << ")"
      << " (docs/bundles.md).";
  if (s.contains("class_mixed_fraction") && s["class_mixed_fraction"].is_number())
    out << " Pixels holding more than one class: "
        << Percent(s["class_mixed_fraction"].get<double>()) << ".";
  out << "</p><div class=\"plots\"><div class=\"plot\"><h3>Class mixing "
         "(samples)</h3><table class=\"mixing\"><tr><th>class \\ shares "
         "pixels with</th>";
  const nlohmann::json& classes = s["class_mixing"]["classes"];
  const nlohmann::json& samples = s["class_mixing"]["samples"];
  for (const nlohmann::json& c : classes) {
    out << "<th>" << ClassName(header, c.get<uint32_t>()) << "</th>";
  }
  out << "</tr>";
  for (size_t a = 0; a < classes.size(); ++a) {
    double row = 0;
    for (const nlohmann::json& v : samples[a]) row += v.get<double>();
    out << "<tr><th>" << ClassName(header, classes[a].get<uint32_t>()) << "</th>";
    for (size_t b = 0; b < classes.size(); ++b) {
      const uint64_t v = samples[a][b].get<uint64_t>();
      const double share = row > 0 ? v / row : 0;
      // Off-diagonal cells shade red by their share of the row (heat =
      // mixing); the diagonal is the pure part.
      const int shade =
          static_cast<int>(std::lround(255 - (a == b ? 0.0 : std::min(1.0, share * 20.0)) * 160));
      out << "<td style=\"background:rgb(255," << shade << "," << shade << ")\" title=\""
          << Percent(share) << " of the row\">" << v << "<br><small>" << Percent(share)
          << "</small></td>";
    }
    out << "</tr>";
  }
  out << "</table><p class=\"note\">rows: the class of a sample; columns: "
         "the class it shares its pixel with; diagonal: samples in pixels "
         "with no other class</p></div>";
  out << "<div class=\"plot\"><h3>Mixed pixels by object size</h3><table "
         "class=\"sizes\"><tr><th>object size (px)</th><th>objects</th>"
         "<th>pixels</th><th>mixed</th><th>mixed share</th></tr>";
  for (const nlohmann::json& b : s["by_object_size"]) {
    const double share = b["mixed_fraction"].get<double>();
    const nlohmann::json max = b.value("max_pixels", nlohmann::json());
    out << "<tr><td>" << FormatAxisNumber(b["min_pixels"].get<double>());
    if (max.is_number()) {
      out << " &ndash; " << FormatAxisNumber(max.get<double>());
    } else {
      out << " and up";
    }
    out << "</td><td>" << b["objects"].get<int64_t>() << "</td><td>" << b["pixels"].get<int64_t>()
        << "</td><td>" << b["mixed_pixels"].get<int64_t>() << "</td><td><span class=\"meter\" "
        << "style=\"width:" << std::lround(std::min(1.0, share) * 120) << "px\"></span> "
        << Percent(share) << "</td></tr>";
  }
  out << "</table><p class=\"note\">objects: (object, frame) pairs whose "
         "pixel count falls in the band; mixed share: their mixed pixels / "
         "their pixels</p></div></div></section>";
  return out;
}

}  // namespace lsds::report

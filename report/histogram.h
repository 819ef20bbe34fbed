// Fixed-bin histograms for the report's distributions. Bins are fixed before
// the frames are streamed, so memory does not grow with the collection and the
// counts are exact (no sampling, no value list).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace lsds::report {

struct Histogram {
  std::string id;       // stable key, e.g. "visibility" (tests, HTML anchors)
  std::string title;    // "Visibility"
  std::string x_label;  // "visible / unoccluded pixels"
  std::string unit;     // "m", "px", "deg", "" for ratios and counts
  std::string counted;  // what one count is: "visible objects", "frames"
  // Numeric: bin i holds values in [edges[i], edges[i + 1]); the last bin also
  // holds edges.back(). Categorical histograms leave `edges` empty and name
  // their bins in `labels`.
  std::vector<double> edges;
  std::vector<std::string> labels;
  std::vector<int64_t> counts;
  int64_t below = 0;    // values < edges.front()
  int64_t above = 0;    // values > edges.back()
  int64_t invalid = 0;  // NaN or not measurable (sky at the image centre, ...)
  // Bins whose upper edge is at or below this are drawn as a warning (e.g.
  // boxes under 8 px); NaN: none.
  double warn_below = 0.0 / 0.0;

  bool categorical() const { return edges.empty(); }
  size_t bins() const { return counts.size(); }
  int64_t total() const;  // in-range counts + below + above (not invalid)
  void Add(double value);
  void AddCategory(size_t bin);  // categorical only
};

Histogram MakeNumeric(std::string id,
                      std::string title,
                      std::string x_label,
                      std::string unit,
                      std::string counted,
                      std::vector<double> edges);
Histogram MakeCategorical(std::string id,
                          std::string title,
                          std::string x_label,
                          std::string counted,
                          std::vector<std::string> labels);

// Equal bins: first, first + step, ..., last.
std::vector<double> LinearEdges(double first, double last, double step);
// 1-2-5 steps from `first` to `last` (both powers of ten): 0.1, 0.2, 0.5, 1,
// ...
std::vector<double> OneTwoFiveEdges(double first, double last);
// Powers of `base` from `first` up to `last` inclusive.
std::vector<double> GeometricEdges(double first, double last, double base);

}  // namespace lsds::report

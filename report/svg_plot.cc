#include "report/svg_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "libs/util/strings.h"

namespace lsds::report {

namespace {

struct Bar {
  std::string label;    // under the bar (categorical) or empty
  std::string tooltip;  // "[1, 2) m: 5"
  int64_t count = 0;
  bool warn = false;
};

// A 1-2-5 step giving about `ticks` ticks up to `max`.
double NiceStep(double max, int ticks) {
  if (max <= 0) return 1;
  const double raw = max / ticks;
  const double p = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0, 10.0}) {
    if (m * p >= raw) return std::max(1.0, m * p);
  }
  return std::max(1.0, 10 * p);
}

// The bins shown of a numeric histogram: those from the first to the last
// non-empty one, at least 5 where the histogram has them.
void ShownBins(const Histogram& h, size_t* first_bin, size_t* last_bin) {
  size_t first = h.bins(), last = 0;
  for (size_t i = 0; i < h.bins(); ++i) {
    if (h.counts[i] > 0) first = std::min(first, i), last = std::max(last, i);
  }
  if (first > last) first = 0, last = std::min<size_t>(h.bins() - 1, 4);
  // Show at least a few bins so that one full bin still reads as a range.
  while (last - first < 4 && (first > 0 || last + 1 < h.bins())) {
    if (last + 1 < h.bins()) ++last;
    if (last - first < 4 && first > 0) --first;
  }
  *first_bin = first;
  *last_bin = last;
}

// A numeric histogram's bars: below the first edge, the shown bins, above the
// last edge; with the labels of the edges (one more than the bars).
std::vector<Bar> NumericBars(const Histogram& h, std::vector<std::string>* edge_labels) {
  const std::string unit = h.unit.empty() ? "" : " " + h.unit;
  std::vector<Bar> bars;
  size_t first = 0, last = 0;
  ShownBins(h, &first, &last);
  if (h.below > 0) {
    bars.push_back(
        {"<",
         "< " + FormatAxisNumber(h.edges.front()) + unit + ": " + std::to_string(h.below),
         h.below,
         true});
    edge_labels->push_back("");
  }
  for (size_t i = first; i <= last; ++i) {
    const bool closed = i + 1 == h.bins();
    bars.push_back({"",
                    "[" + FormatAxisNumber(h.edges[i]) + ", " + FormatAxisNumber(h.edges[i + 1]) +
                        (closed ? "]" : ")") + unit + ": " + std::to_string(h.counts[i]),
                    h.counts[i],
                    !std::isnan(h.warn_below) && h.edges[i + 1] <= h.warn_below});
    edge_labels->push_back(FormatAxisNumber(h.edges[i]));
  }
  edge_labels->push_back(FormatAxisNumber(h.edges[last + 1]));
  if (h.above > 0) {
    bars.push_back({">",
                    "> " + FormatAxisNumber(h.edges.back()) + unit + ": " + std::to_string(h.above),
                    h.above,
                    true});
    edge_labels->push_back("");
  }
  return bars;
}

// The plot's place in the SVG, in pixels.
struct PlotArea {
  static constexpr int left = 52, right = 24, top = 10, bottom = 48;
  double plot_w = 0, plot_h = 0, bar_w = 0;
};

// Count axis with grid lines.
void DrawCountAxis(
    const PlotArea& p, double step, double top_value, const std::string& counted, Html* s) {
  const int left = PlotArea::left, top = PlotArea::top;
  for (double v = 0; v <= top_value + 1e-9; v += step) {
    const double y = top + p.plot_h * (1 - v / top_value);
    *s << "<line x1=\"" << left << "\" x2=\"" << left + p.plot_w << "\" y1=\"" << y << "\" y2=\""
       << y << "\" class=\"grid\"/>";
    *s << "<text x=\"" << left - 4 << "\" y=\"" << y + 3 << "\" text-anchor=\"end\">"
       << FormatAxisNumber(v) << "</text>";
  }
  *s << "<text transform=\"translate(12," << top + p.plot_h / 2
     << ") rotate(-90)\" text-anchor=\"middle\">" << counted << "</text>";
}

void DrawBars(const PlotArea& p, const std::vector<Bar>& bars, double top_value, Html* s) {
  const int left = PlotArea::left, top = PlotArea::top;
  for (size_t i = 0; i < bars.size(); ++i) {
    const Bar& b = bars[i];
    const double bh = p.plot_h * b.count / top_value;
    const double x = left + i * p.bar_w;
    *s << "<rect class=\"" << (b.warn ? Html::Markup("bar warn") : Html::Markup("bar")) << "\" x=\""
       << x + 1 << "\" y=\"" << top + p.plot_h - bh << "\" width=\"" << std::max(1.0, p.bar_w - 2)
       << "\" height=\"" << bh << "\"><title>" << b.tooltip << "</title></rect>";
    if (!b.label.empty()) {
      *s << "<text x=\"" << x + p.bar_w / 2 << "\" y=\"" << top + p.plot_h + 13
         << "\" text-anchor=\"middle\">" << b.label << "</text>";
    }
  }
}

// Numeric: edge values at the bar boundaries, thinned to fit.
void DrawEdgeLabels(const PlotArea& p, const std::vector<std::string>& edge_labels, Html* s) {
  const int left = PlotArea::left, top = PlotArea::top;
  if (edge_labels.empty()) return;
  const size_t every = std::max<size_t>(1, (edge_labels.size() + 7) / 8);
  for (size_t i = 0; i < edge_labels.size(); i += every) {
    if (edge_labels[i].empty()) continue;
    *s << "<text x=\"" << left + i * p.bar_w << "\" y=\"" << top + p.plot_h + 13
       << "\" text-anchor=\"middle\">" << edge_labels[i] << "</text>";
  }
}

}  // namespace

Html HistogramSvg(const Histogram& h, int width, int height) {
  std::vector<Bar> bars;
  std::vector<std::string> edge_labels;  // numeric: one more than the bars
  if (h.categorical()) {
    for (size_t i = 0; i < h.bins(); ++i) {
      bars.push_back(
          {h.labels[i], h.labels[i] + ": " + std::to_string(h.counts[i]), h.counts[i], false});
    }
  } else {
    bars = NumericBars(h, &edge_labels);
  }
  int64_t max_count = 0;
  for (const Bar& b : bars) max_count = std::max(max_count, b.count);
  const double step = NiceStep(static_cast<double>(max_count), 4);
  const double top_value = std::max(step, std::ceil(max_count / step) * step);

  const int left = PlotArea::left, top = PlotArea::top;
  PlotArea p;
  p.plot_w = width - PlotArea::left - PlotArea::right;
  p.plot_h = height - PlotArea::top - PlotArea::bottom;
  p.bar_w = p.plot_w / std::max<size_t>(1, bars.size());
  Html s;
  s << "<svg class=\"hist\" xmlns=\"http://www.w3.org/2000/svg\" width=\"" << width
    << "\" height=\"" << height << "\" viewBox=\"0 0 " << width << " " << height << "\" data-id=\""
    << h.id << "\">";
  DrawCountAxis(p, step, top_value, h.counted, &s);
  DrawBars(p, bars, top_value, &s);
  DrawEdgeLabels(p, edge_labels, &s);
  s << "<line x1=\"" << left << "\" x2=\"" << left + p.plot_w << "\" y1=\"" << top + p.plot_h
    << "\" y2=\"" << top + p.plot_h << "\" class=\"axis\"/>";
  s << "<line x1=\"" << left << "\" x2=\"" << left << "\" y1=\"" << top << "\" y2=\""
    << top + p.plot_h << "\" class=\"axis\"/>";
  s << "<text x=\"" << left + p.plot_w / 2 << "\" y=\"" << height - 8
    << "\" text-anchor=\"middle\">" << h.x_label;
  if (!h.unit.empty()) s << " (" << h.unit << ")";
  s << "</text>";
  s << "</svg>";
  return s;
}

}  // namespace lsds::report

#include "report/histogram.h"

#include <algorithm>
#include <cmath>

namespace lsds::report {

int64_t Histogram::total() const {
  int64_t sum = below + above;
  for (int64_t c : counts) sum += c;
  return sum;
}

void Histogram::Add(double value) {
  if (std::isnan(value)) {
    ++invalid;
    return;
  }
  if (value < edges.front()) {
    ++below;
    return;
  }
  if (value > edges.back()) {
    ++above;
    return;
  }
  // First edge greater than the value; the closing edge belongs to the last
  // bin.
  const auto it = std::upper_bound(edges.begin(), edges.end(), value);
  const size_t bin =
      std::min<size_t>(static_cast<size_t>(it - edges.begin()) - 1, counts.size() - 1);
  ++counts[bin];
}

void Histogram::AddCategory(size_t bin) { ++counts.at(bin); }

Histogram MakeNumeric(std::string id,
                      std::string title,
                      std::string x_label,
                      std::string unit,
                      std::string counted,
                      std::vector<double> edges) {
  Histogram h;
  h.id = std::move(id);
  h.title = std::move(title);
  h.x_label = std::move(x_label);
  h.unit = std::move(unit);
  h.counted = std::move(counted);
  h.edges = std::move(edges);
  h.counts.assign(h.edges.size() - 1, 0);
  return h;
}

Histogram MakeCategorical(std::string id,
                          std::string title,
                          std::string x_label,
                          std::string counted,
                          std::vector<std::string> labels) {
  Histogram h;
  h.id = std::move(id);
  h.title = std::move(title);
  h.x_label = std::move(x_label);
  h.counted = std::move(counted);
  h.labels = std::move(labels);
  h.counts.assign(h.labels.size(), 0);
  return h;
}

std::vector<double> LinearEdges(double first, double last, double step) {
  std::vector<double> edges;
  const int n = static_cast<int>(std::lround((last - first) / step));
  for (int i = 0; i <= n; ++i) edges.push_back(first + i * step);
  return edges;
}

std::vector<double> OneTwoFiveEdges(double first, double last) {
  // Integer exponents, so that the edges print as round numbers.
  const int e0 = static_cast<int>(std::lround(std::log10(first)));
  const int e1 = static_cast<int>(std::lround(std::log10(last)));
  std::vector<double> edges;
  for (int e = e0; e <= e1; ++e) {
    for (double m : {1.0, 2.0, 5.0}) {
      if (e == e1 && m > 1) break;
      edges.push_back(m * std::pow(10.0, e));
    }
  }
  return edges;
}

std::vector<double> GeometricEdges(double first, double last, double base) {
  std::vector<double> edges;
  for (double v = first; v <= last * 1.0001; v *= base) edges.push_back(v);
  return edges;
}

}  // namespace lsds::report

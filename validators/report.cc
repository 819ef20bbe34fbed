#include "validators/report.h"

#include <algorithm>
#include <cmath>

namespace lsds::validate {

double Statistic::rms() const {
  return count == 0 ? 0.0 : std::sqrt(sum_squares / count);
}

void Report::AddLocked(Finding finding) {
  CheckResult& result = results_[finding.check_id];
  ++result.counts[static_cast<int>(finding.severity)];
  auto frame_of = [](const Finding& f) {
    return f.location.frame.value_or(-1);
  };
  auto& examples = result.examples;
  if (examples.size() >= max_examples_ &&
      frame_of(finding) >= frame_of(examples.back()))
    return;
  const auto at = std::upper_bound(examples.begin(),
                                   examples.end(),
                                   finding,
                                   [&](const Finding& a, const Finding& b) {
                                     return frame_of(a) < frame_of(b);
                                   });
  examples.insert(at, std::move(finding));
  if (examples.size() > max_examples_) examples.pop_back();
}

void Report::Add(Finding finding) {
  std::lock_guard<std::mutex> lock(*mutex_);
  AddLocked(std::move(finding));
}

void Report::AddAll(std::vector<Finding>* findings) {
  if (findings->empty()) return;
  std::lock_guard<std::mutex> lock(*mutex_);
  for (Finding& finding : *findings) AddLocked(std::move(finding));
  findings->clear();
}

void Report::AddStatistic(const std::string& name, double value) {
  Statistic s;
  s.max = std::abs(value);
  s.sum_squares = value * value;
  s.count = 1;
  MergeStatistic(name, s);
}

void Report::MergeStatistic(const std::string& name,
                            const Statistic& statistic) {
  if (statistic.count == 0) return;
  std::lock_guard<std::mutex> lock(*mutex_);
  Statistic& s = statistics_[name];
  s.max = std::max(s.max, statistic.max);
  s.sum_squares += statistic.sum_squares;
  s.count += statistic.count;
}

int64_t Report::Count(Severity severity) const {
  std::lock_guard<std::mutex> lock(*mutex_);
  int64_t n = 0;
  for (const auto& [id, result] : results_)
    n += result.counts[static_cast<int>(severity)];
  return n;
}

bool Report::Fails(Severity fail_on) const {
  for (int s = static_cast<int>(fail_on);
       s <= static_cast<int>(Severity::kError);
       ++s) {
    if (Count(static_cast<Severity>(s)) > 0) return true;
  }
  return false;
}

std::vector<Finding> Report::Examples(const std::string& check_id) const {
  std::lock_guard<std::mutex> lock(*mutex_);
  const auto it = results_.find(check_id);
  return it == results_.end() ? std::vector<Finding>{} : it->second.examples;
}

int64_t Report::CountOf(const std::string& check_id) const {
  std::lock_guard<std::mutex> lock(*mutex_);
  const auto it = results_.find(check_id);
  return it == results_.end() ? 0 : it->second.total();
}

}  // namespace lsds::validate

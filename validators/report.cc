#include "validators/report.h"

#include <algorithm>
#include <cmath>

namespace lsds::validate {

double Statistic::rms() const { return count == 0 ? 0.0 : std::sqrt(sum_squares / count); }

void Report::AddLocked(Finding finding) {
  CheckResult& result = results_[finding.check_id];
  ++result.counts[static_cast<int>(finding.severity)];
  auto frame_of = [](const Finding& f) { return f.location.frame.value_or(-1); };
  auto& examples = result.examples;
  if (examples.size() >= max_examples_ && frame_of(finding) >= frame_of(examples.back())) return;
  const auto at = std::upper_bound(
      examples.begin(), examples.end(), finding, [&](const Finding& a, const Finding& b) {
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

void Report::MergeStatistic(const std::string& name, const Statistic& statistic) {
  if (statistic.count == 0) return;
  std::lock_guard<std::mutex> lock(*mutex_);
  Statistic& s = statistics_[name];
  s.max = std::max(s.max, statistic.max);
  s.sum_squares += statistic.sum_squares;
  s.count += statistic.count;
}

void Report::AddCheckSeconds(const std::string& id, double seconds) {
  std::lock_guard<std::mutex> lock(*mutex_);
  check_seconds_[id] += seconds;
}

void Report::MergeFrom(const Report& other) {
  std::lock_guard<std::mutex> lock(*mutex_);
  for (const auto& [id, result] : other.results_) {
    CheckResult& mine = results_[id];
    // Examples first through AddLocked (which counts each), then the counts
    // the other report did not keep as examples.
    const std::array<int64_t, 3> before = mine.counts;
    for (const Finding& finding : result.examples) AddLocked(finding);
    for (int s = 0; s < 3; ++s) mine.counts[s] = before[s] + result.counts[s];
  }
  for (const auto& [name, s] : other.statistics_) {
    if (s.count == 0) continue;
    Statistic& mine = statistics_[name];
    mine.max = std::max(mine.max, s.max);
    mine.sum_squares += s.sum_squares;
    mine.count += s.count;
  }
  for (const auto& [id, seconds] : other.check_seconds_) check_seconds_[id] += seconds;
  frames += other.frames;
  files_decoded += other.files_decoded;
  bytes_decoded += other.bytes_decoded;
  seconds += other.seconds;
}

void Report::Restore(const std::string& id,
                     const std::array<int64_t, 3>& counts,
                     std::vector<Finding> examples) {
  std::lock_guard<std::mutex> lock(*mutex_);
  CheckResult& result = results_[id];
  result.counts = counts;
  result.examples = std::move(examples);
}

CheckTimer::CheckTimer(CheckSeconds* sink, std::vector<std::string> ids)
    : sink_(sink), ids_(std::move(ids)), start_(std::chrono::steady_clock::now()) {}

CheckTimer::~CheckTimer() {
  if (ids_.empty()) return;
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count() /
      static_cast<double>(ids_.size());
  for (const std::string& id : ids_) (*sink_)[id] += seconds;
}

int64_t Report::Count(Severity severity) const {
  std::lock_guard<std::mutex> lock(*mutex_);
  int64_t n = 0;
  for (const auto& [id, result] : results_) n += result.counts[static_cast<int>(severity)];
  return n;
}

bool Report::Fails(Severity fail_on) const {
  for (int s = static_cast<int>(fail_on); s <= static_cast<int>(Severity::kError); ++s) {
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

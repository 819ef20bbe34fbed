// The outcome of a validation run. Memory is bounded: per check it keeps counts
// and the first `max_examples` findings (earliest frames first), never every
// finding.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "validators/checks.h"
#include "validators/finding.h"

namespace lsds::validate {

struct CheckResult {
  std::array<int64_t, 3> counts{};  // by Severity
  std::vector<Finding> examples;    // the first ones, sorted by frame
  int64_t total() const { return counts[0] + counts[1] + counts[2]; }
};

// A number measured over the run (e.g. the world-position vs depth error): max,
// RMS, count.
struct Statistic {
  double max = 0;
  double sum_squares = 0;
  int64_t count = 0;
  double rms() const;
};

class Report {
 public:
  explicit Report(size_t max_examples = 20) : max_examples_(max_examples) {}

  void Add(Finding finding);                    // thread-safe
  void AddAll(std::vector<Finding>* findings);  // thread-safe; empties `findings`
  // Thread-safe: folds `value` (or a pre-aggregated statistic) into the
  // statistic `name`.
  void AddStatistic(const std::string& name, double value);
  void MergeStatistic(const std::string& name, const Statistic& statistic);
  // Thread-safe: charges `seconds` of work to the check `id` (JUnit testcase
  // time; see docs/validate.md for how shared work is charged).
  void AddCheckSeconds(const std::string& id, double seconds);
  // Thread-safe: adds another report's counts, examples (keeping the first
  // `max_examples` by frame), statistics, check times and frame/file tallies.
  // Used to join the partial reports of `validate --shard`.
  void MergeFrom(const Report& other);
  // Sets one check's result as a partial report recorded it (counts of all
  // findings, the examples it kept).
  void Restore(const std::string& id,
               const std::array<int64_t, 3>& counts,
               std::vector<Finding> examples);

  std::string collection;           // the folder validated
  std::vector<std::string> checks;  // the selected check ids, registry order
  int64_t frames = 0;               // frames examined
  int64_t files_decoded = 0;
  int64_t bytes_decoded = 0;  // size on disk of the EXR files decoded
  double seconds = 0;

  const std::map<std::string, CheckResult>& results() const { return results_; }
  const std::map<std::string, Statistic>& statistics() const { return statistics_; }
  const std::map<std::string, double>& check_seconds() const { return check_seconds_; }
  size_t max_examples() const { return max_examples_; }
  int64_t Count(Severity severity) const;
  // True when some finding is at or above `fail_on`.
  bool Fails(Severity fail_on) const;
  // Every finding of `check_id` kept as an example (tests use this).
  std::vector<Finding> Examples(const std::string& check_id) const;
  int64_t CountOf(const std::string& check_id) const;

 private:
  void AddLocked(Finding finding);

  size_t max_examples_;
  std::unique_ptr<std::mutex> mutex_ = std::make_unique<std::mutex>();  // movable Report
  std::map<std::string, CheckResult> results_;
  std::map<std::string, Statistic> statistics_;
  std::map<std::string, double> check_seconds_;
};

// Seconds per check id of one thread or frame. A map, not a list of blocks:
// its size is bounded by the number of checks, so the streaming state of
// `validate` does not grow with the frames (docs/reliability.md, "Scale").
using CheckSeconds = std::map<std::string, double>;

// Charges the wall time of a block of one thread to one or more checks (split
// evenly when a block serves several, e.g. the camera solve). Adds to `sink`,
// merged into the report later, so no lock is taken per block.
class CheckTimer {
 public:
  CheckTimer(CheckSeconds* sink, std::vector<std::string> ids);
  ~CheckTimer();
  CheckTimer(const CheckTimer&) = delete;
  CheckTimer& operator=(const CheckTimer&) = delete;

 private:
  CheckSeconds* sink_;
  std::vector<std::string> ids_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace lsds::validate

#include "evaluate/accumulation.h"

#include <algorithm>
#include <limits>
#include <queue>

namespace lsds::evaluate {

namespace {

using Record = AccumulationBuilder::Record;

constexpr int kT = kIouThresholdCount;
constexpr int kR = kRecallThresholdCount;
constexpr int kM = static_cast<int>(kMaxDetections.size());

constexpr uint32_t kRankBits = 7;  // ranks 0..99
constexpr uint32_t kRankMask = (1u << kRankBits) - 1;
static_assert(kMaxDetections.back() <= (1 << kRankBits), "a rank fits its bits");
static_assert(kRankBits + 2 * kT <= 32, "the flags fit 32 bits");
static_assert(sizeof(Record) == 16, "a record is 16 bytes, on disk as in memory");

bool TruePositive(uint32_t bits, int t) { return (bits >> (kRankBits + t)) & 1u; }
bool FalsePositive(uint32_t bits, int t) { return (bits >> (kRankBits + kT + t)) & 1u; }

// accumulate's order (cocoeval.py:362-371): np.argsort(-dtScores,
// kind='mergesort') over each image's detections (by rank) concatenated in
// image order. The key is unique within a selection and category, so any sort
// gives the stable sort's order.
bool Before(const Record& a, const Record& b) {
  if (a.score != b.score) return a.score > b.score;
  if (a.image != b.image) return a.image < b.image;
  return (a.bits & kRankMask) < (b.bits & kRankMask);
}

// The records of category `k` held by `parts`, sorted.
std::vector<Record> SortedRecords(const std::vector<const AccumulationBuilder*>& parts, size_t k) {
  std::vector<Record> all;
  size_t n = 0;
  for (const AccumulationBuilder* part : parts) n += part->records(k).size();
  all.reserve(n);
  for (const AccumulationBuilder* part : parts)
    all.insert(all.end(), part->records(k).begin(), part->records(k).end());
  std::sort(all.begin(), all.end(), Before);
  return all;
}

// A k-way merge of sorted sources (runs on the scratch file and the records
// in memory), handing the records out in accumulate's order.
class RecordMerge {
 public:
  RecordMerge(std::vector<SpillReader> runs, std::vector<uint64_t> counts, std::vector<Record> held)
      : runs_(std::move(runs)), left_(std::move(counts)), held_(std::move(held)) {
    for (size_t i = 0; i < runs_.size(); ++i) Pull(i);
    if (!held_.empty()) heads_.push({held_[0], kHeld});
  }
  bool Next(Record* out) {
    if (heads_.empty()) return false;
    const Head head = heads_.top();
    heads_.pop();
    *out = head.record;
    if (head.source == kHeld) {
      if (++held_at_ < held_.size()) heads_.push({held_[held_at_], kHeld});
    } else {
      Pull(head.source);
    }
    return true;
  }

 private:
  static constexpr size_t kHeld = std::numeric_limits<size_t>::max();
  struct Head {
    Record record;
    size_t source;
  };
  struct After {
    bool operator()(const Head& a, const Head& b) const { return Before(b.record, a.record); }
  };
  void Pull(size_t i) {
    if (left_[i] == 0) return;
    --left_[i];
    heads_.push({runs_[i].Read<Record>(), i});
  }

  std::vector<SpillReader> runs_;
  std::vector<uint64_t> left_;
  std::vector<Record> held_;
  size_t held_at_ = 0;
  std::priority_queue<Head, std::vector<Head>, After> heads_;
};

}  // namespace

AccumulationBuilder::AccumulationBuilder(size_t categories)
    : records_(categories),
      counted_(categories, 0),
      top_score_(categories, -std::numeric_limits<double>::infinity()) {}

void AccumulationBuilder::Add(const EvaluationCell& cell,
                              const CellResult& result,
                              uint32_t image_index) {
  counted_[cell.category] += result.ground_truth_counted;
  const size_t D = result.scores.size();
  // scores are sorted: the first is the cell's highest (cocoeval.py:406 reads
  // it at recall 0 whether it counts or not).
  if (D > 0) top_score_[cell.category] = std::max(top_score_[cell.category], result.scores[0]);
  for (size_t d = 0; d < D; ++d) {
    uint32_t flags = 0;
    for (int t = 0; t < kT; ++t) {
      const size_t at = t * D + d;
      if (result.ignored[at]) continue;  // dtIg: neither (cocoeval.py:375-376)
      flags |= 1u << (result.matched[at] ? t : kT + t);
    }
    if (flags == 0) continue;
    records_[cell.category].push_back(
        Record{result.scores[d], image_index, static_cast<uint32_t>(d) | flags << kRankBits});
    ++held_;
  }
}

PrecisionPass::PrecisionPass(int64_t ground_truth_counted)
    : npig_(static_cast<double>(ground_truth_counted)), curves_(static_cast<size_t>(kM) * kT) {}

void PrecisionPass::Add(const Record& record) {
  const uint32_t rank = record.bits & kRankMask;
  const auto& thresholds = RecallThresholds();
  for (int m = 0; m < kM; ++m) {
    if (rank >= static_cast<uint32_t>(kMaxDetections[m])) continue;  // [0:maxDet] (:362, :369)
    for (int t = 0; t < kT; ++t) {
      Curve& c = curves_[m * kT + t];
      c.tp += TruePositive(record.bits, t) ? 1 : 0;  // the cumulative sums (:375-379)
      c.fp += FalsePositive(record.bits, t) ? 1 : 0;
      const double rc = c.tp / npig_;                                                   // :384
      const double pr = c.tp / (c.fp + c.tp + std::numeric_limits<double>::epsilon());  // :385
      // searchsorted(rc, recThrs, side='left') (:402): threshold r is reached
      // first where rc >= recThrs[r].
      while (c.reached < kR && thresholds[c.reached] <= rc) c.score[c.reached++] = record.score;
      c.best[c.reached - 1] = std::max(c.best[c.reached - 1], pr);  // recThrs[0] = 0: reached >= 1
    }
  }
}

void PrecisionPass::Finish(size_t k, double top_score, Accumulation* a) const {
  const size_t K = a->categories;
  const bool any = top_score > -std::numeric_limits<double>::infinity();
  for (int m = 0; m < kM; ++m) {
    for (int t = 0; t < kT; ++t) {
      const Curve& c = curves_[m * kT + t];
      a->recall[(static_cast<size_t>(t) * K + k) * kM + m] = c.tp / npig_;  // rc[-1], 0 if nd = 0
      double envelope = 0;  // a threshold no detection reaches keeps q's 0 (:386, :403-408)
      for (int r = kR - 1; r >= 0; --r) {
        envelope = std::max(envelope, c.best[r]);
        const size_t at = ((static_cast<size_t>(t) * kR + r) * K + k) * kM + m;
        a->precision[at] = envelope;
        // dtScoresSorted[0] at recall 0: the highest score, counted or not.
        a->scores[at] = r == 0 ? (any ? top_score : 0) : c.score[r];
      }
      if (t == 0 && m == kM - 1) {
        a->matched_50 += static_cast<int64_t>(c.tp);
        a->false_positives_50 += static_cast<int64_t>(c.fp);
      }
    }
  }
}

// accumulate (cocoeval.py:353-410) per category: the records of every part
// and run merged in accumulate's order, streamed through PrecisionPass.
Accumulation AccumulationBuilder::Finish(const std::vector<const AccumulationBuilder*>& parts,
                                         const AccumulationRuns* runs,
                                         size_t selection) {
  const size_t K = parts.empty() ? 0 : parts.front()->records_.size();
  Accumulation a;
  a.categories = K;
  a.precision.assign(static_cast<size_t>(kT) * kR * K * kM, -1.0);
  a.scores.assign(a.precision.size(), -1.0);
  a.recall.assign(static_cast<size_t>(kT) * K * kM, -1.0);
  for (const AccumulationBuilder* part : parts) a.images += part->images_;
  const size_t run_count = runs ? runs->runs() : 0;
  for (size_t k = 0; k < K; ++k) {
    int64_t npig = 0;
    double top_score = -std::numeric_limits<double>::infinity();
    for (const AccumulationBuilder* part : parts) {
      npig += part->counted_[k];
      top_score = std::max(top_score, part->top_score_[k]);
    }
    a.ground_truth += npig;
    if (npig == 0) continue;  // :372-374
    std::vector<SpillReader> readers;
    std::vector<uint64_t> counts;
    for (size_t r = 0; r < run_count; ++r) {
      const AccumulationRuns::Segment& s = runs->segments_[r][selection * K + k];
      readers.emplace_back(*runs->file_,
                           s.offset,
                           s.offset + s.count * sizeof(Record),
                           ReaderBufferBytes(runs->memory_bytes_, run_count));
      counts.push_back(s.count);
    }
    RecordMerge merge(std::move(readers), std::move(counts), SortedRecords(parts, k));
    PrecisionPass pass(npig);
    Record record{};
    while (merge.Next(&record)) pass.Add(record);
    pass.Finish(k, top_score, &a);
  }
  return a;
}

AccumulationRuns::AccumulationRuns(size_t selections, size_t categories, uint64_t memory_bytes)
    : selections_(selections), categories_(categories), memory_bytes_(memory_bytes) {}

AccumulationRuns::~AccumulationRuns() = default;

void AccumulationRuns::Spill(const std::vector<std::vector<AccumulationBuilder*>>& parts) {
  if (!file_) file_ = std::make_unique<SpillFile>();
  std::vector<Segment> segments(selections_ * categories_);
  for (size_t s = 0; s < selections_; ++s) {
    const std::vector<const AccumulationBuilder*> builders(parts[s].begin(), parts[s].end());
    for (size_t k = 0; k < categories_; ++k) {
      const std::vector<Record> sorted = SortedRecords(builders, k);
      Segment& segment = segments[s * categories_ + k];
      segment.count = sorted.size();
      segment.offset = file_->size();
      if (!sorted.empty()) file_->Append(sorted.data(), sorted.size() * sizeof(Record));
      records_ += sorted.size();
      for (AccumulationBuilder* builder : parts[s]) std::deque<Record>().swap(builder->records_[k]);
    }
    for (AccumulationBuilder* builder : parts[s]) builder->held_ = 0;
  }
  segments_.push_back(std::move(segments));
}

}  // namespace lsds::evaluate

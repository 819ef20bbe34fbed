// Benchmark of `lsds evaluate` (docs/evaluate.md) on a large synthetic prediction set: N images of
// 15 ground-truth boxes in 3 classes, each found with probability 0.9 (its box moved by 5 %, a
// random score) plus 10 random false positives per image. The ground truth is written as the
// COCO dataset `lsds convert --to coco` writes (with its `lsds` extras: visibility, in_frame, the
// object's 3D box centre), the predictions as a COCO results file, both straight to disk, and
// `lsds evaluate` reads them as it reads a collection's: the ground truth image by image from
// the dataset file (StreamCocoGroundTruth), the results file entry by entry (ReadCocoPredictions).
//
// Printed per size: the floor, parsing the results file with nlohmann's SAX parser and nothing
// else (what any evaluator of the file does); read_s, reading and checking every entry into the
// detections grouped by image (DetectionsByImage, spilled past its share of the budget);
// truth_s, the dataset's image and category tables; coco_s, COCOeval's 12 numbers (the results
// read again); report_s, the whole report (the 12 numbers plus every stratum of every condition);
// the ratio (read + truth + report) / floor; the process's CPU seconds (user + sys, all threads);
// its peak resident memory (getrusage ru_maxrss, so run one size per process to see each size's
// own peak), that peak per image; the runs written to the scratch file (detections, records)
// and the records the accumulations kept (16 bytes each).
//
// --memory-budget is lsds evaluate's: the detections and the records each held in memory up to
// 1/32 of it (docs/evaluate.md, "Memory"). --report-only skips the coco_s pass.
// --write DIR keeps the files (DIR/gt_N.json, DIR/dt_N.json) for a peer: pycocotools' COCOeval on
// the same data (bench/README.md, "lsds evaluate"; bench/peers/coco_eval_files.py); without it
// they go to a scratch folder. With it the 12 numbers are printed to 17 digits, and the CPU
// seconds of loading (the truth's tables and the results file) and of the 12 numbers alone.
//
//   bench_evaluate [--images 2000,10000] [--memory-budget 8G] [--report-only] [--write DIR]
#include <stdlib.h>
#include <sys/resource.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "bench/null_sax.h"
#include "bench/stopwatch.h"
#include "evaluate/evaluate_run.h"
#include "evaluate/predictions.h"
#include "evaluate/strata.h"
#include "libs/util/limits.h"

namespace {

namespace fs = std::filesystem;
using namespace lsds::evaluate;
using lsds::bench::Clock;
using lsds::bench::Seconds;
using nlohmann::json;

// The peak resident set of this process so far, MiB (Linux reports KiB).
double PeakRssMib() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;
}

// The CPU seconds of this process so far, user + sys, every thread.
double CpuSeconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  const auto seconds = [](const timeval& t) {
    return static_cast<double>(t.tv_sec) + static_cast<double>(t.tv_usec) * 1e-6;
  };
  return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

// The results file read into detections grouped by image, as lsds evaluate reads it.
std::unique_ptr<DetectionsByImage> ReadDetections(const fs::path& file,
                                                  const EvaluationTruth& truth,
                                                  uint64_t budget) {
  auto detections = std::make_unique<DetectionsByImage>(SpillShare(budget));
  ReadCocoPredictions(file, truth, [&](DetectionBox&& d) { detections->Add(std::move(d)); });
  return detections;
}

// Writes DIR/gt_N.json and DIR/dt_N.json one entry at a time; returns the frames' facts.
FrameTable WriteData(int64_t images, const fs::path& folder) {
  std::mt19937_64 rng(44);
  std::uniform_real_distribution<double> u(0, 1);
  const std::string n = std::to_string(images);
  std::ofstream gt(folder / ("gt_" + n + ".json")), dt(folder / ("dt_" + n + ".json"));
  std::string annotations;  // one image's, written after the images list
  std::ofstream annotation_part(folder / ("gt_" + n + ".annotations"));
  FrameTable frames;
  gt << "{\"images\":[\n";
  dt << "[";
  int64_t id = 1, detections = 0;
  for (int64_t image = 1; image <= images; ++image) {
    gt << (image > 1 ? ",\n" : "")
       << json{{"id", image},
               {"file_name", std::to_string(image) + ".png"},
               {"width", 1000},
               {"height", 800},
               {"lsds", {{"frame", image - 1}}}}
              .dump();
    FrameFacts facts;
    facts.index = image - 1;
    facts.off_nadir_deg = 40 * u(rng);
    facts.altitude_agl_m = 30 + 90 * u(rng);
    facts.camera_in_world = {0, 0, 0};
    frames.Add(std::move(facts));
    for (int k = 0; k < 25; ++k) {
      const double w = 4 + 120 * u(rng) * u(rng), h = w * (0.5 + u(rng));
      const double x = 900 * u(rng), y = 700 * u(rng);
      const int64_t category = 1 + static_cast<int64_t>(3 * u(rng));
      if (k < 15) {
        const double visibility = u(rng);
        const double in_frame = u(rng) < 0.9 ? 1 : 0.5;
        const double distance = 20 + 100 * u(rng);
        annotation_part << (id > 1 ? ",\n" : "")
                        << json{{"id", id},
                                {"image_id", image},
                                {"category_id", category},
                                {"bbox", {x, y, w, h}},
                                {"area", w * h * 0.8},
                                {"iscrowd", 0},
                                {"lsds",
                                 {{"instance_id", k + 1},
                                  {"name", "T#" + std::to_string(k)},
                                  {"visibility", visibility},
                                  {"in_frame", in_frame},
                                  {"obb", {{"center", {distance, 0, 0}}}}}}}
                               .dump();
        ++id;
        if (u(rng) > 0.9) continue;
      }
      const double jitter = k < 15 ? 0.05 : 0;
      dt << (detections++ ? ",\n" : "")
         << json{{"image_id", image},
                 {"category_id", category},
                 {"bbox",
                  {x + jitter * w * (u(rng) - 0.5),
                   y + jitter * h * (u(rng) - 0.5),
                   w * (1 + jitter * (u(rng) - 0.5)),
                   h}},
                 {"score", u(rng)}}
                .dump();
    }
  }
  annotation_part.close();
  gt << "\n],\n\"annotations\":[\n"
     << std::ifstream(folder / ("gt_" + n + ".annotations")).rdbuf() << "\n],\n"
     << "\"categories\":[{\"id\":1,\"name\":\"car\"},{\"id\":2,\"name\":\"truck\"},"
        "{\"id\":3,\"name\":\"person\"}]}\n";
  fs::remove(folder / ("gt_" + n + ".annotations"));
  dt << "]\n";
  frames.Seal();
  return frames;
}

// nlohmann's SAX parser over the file, building nothing: the floor of reading it.
void ParseOnly(const fs::path& file) {
  lsds::bench::NullSax sax;
  std::ifstream in(file, std::ios::binary);
  json::sax_parse(in, &sax);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"lsds evaluate: COCO metrics and strata of a large synthetic prediction set"};
  std::vector<int64_t> sizes = {2000, 10000};
  app.add_option("--images", sizes, "image counts")->delimiter(',');
  std::string write, budget_text;
  app.add_option("--write", write, "keep the data as COCO files in this folder");
  app.add_option("--memory-budget", budget_text, "lsds evaluate's --memory-budget (default 8G)");
  bool report_only = false;
  app.add_flag("--report-only", report_only, "skip the pass of the 12 numbers alone");
  CLI11_PARSE(app, argc, argv);
  if (!budget_text.empty()) lsds::SetMemoryBudget(budget_text);
  const uint64_t budget = lsds::MemoryBudgetBytes();
  fs::path folder = write;
  if (write.empty()) {
    std::string pattern = (fs::temp_directory_path() / "bench-evaluate-XXXXXX").string();
    if (mkdtemp(pattern.data()) == nullptr) return 2;
    folder = pattern;
  }
  std::printf("%8s %10s %8s %8s %8s %8s %9s %9s %7s %8s %9s %8s %6s %6s %10s\n",
              "images",
              "dets",
              "floor_s",
              "read_s",
              "truth_s",
              "coco_s",
              "report_s",
              "total_s",
              "ratio",
              "cpu_s",
              "peak_mib",
              "kib/img",
              "d_runs",
              "r_runs",
              "kept");
  for (const int64_t images : sizes) {
    FrameTable frames = WriteData(images, folder);
    const std::string n = std::to_string(images);
    const fs::path gt = folder / ("gt_" + n + ".json"), dt = folder / ("dt_" + n + ".json");
    auto t = Clock::now();
    ParseOnly(dt);
    const double floor = Seconds(t);
    t = Clock::now();
    const double cpu_before_load = CpuSeconds();
    EvaluationTruth truth = StreamCocoGroundTruth(gt, false);
    truth.frames = std::move(frames);
    const double truth_s = Seconds(t);
    t = Clock::now();
    std::unique_ptr<DetectionsByImage> detections = ReadDetections(dt, truth, budget);
    const double read = Seconds(t);
    const double load_cpu = CpuSeconds() - cpu_before_load;  // truth tables and results file
    const int64_t entries = detections->size();
    const size_t detection_runs = detections->runs();
    double coco_s = 0, coco_cpu = 0;
    std::optional<CocoStats> coco_stats;
    if (!report_only) {
      t = Clock::now();
      const double cpu_before = CpuSeconds();
      coco_stats = EvaluateImages(truth, {}, detections.get(), 30, SpillShare(budget)).stats;
      coco_s = Seconds(t);
      coco_cpu = CpuSeconds() - cpu_before;
      detections = ReadDetections(dt, truth, budget);  // taken image by image: read again
    }
    t = Clock::now();
    const std::vector<ConditionBins> conditions = BinConditions(truth);
    const ImageMetrics whole =
        EvaluateImages(truth, conditions, detections.get(), 30, SpillShare(budget));
    const double report = Seconds(t);
    detections.reset();
    if (!coco_stats) coco_stats = whole.stats;
    if (!write.empty()) {  // for comparison with the peer's stats
      std::printf("stats %lld:", static_cast<long long>(images));
      for (const double v : *coco_stats) std::printf(" %.17g", v);
      std::printf("\ncpu %lld: load_cpu_s %.2f coco_cpu_s %.2f\n",
                  static_cast<long long>(images),
                  load_cpu,
                  coco_cpu);
    }
    const double peak = PeakRssMib();
    const double total = read + truth_s + report;
    std::printf(
        "%8lld %10lld %8.3f %8.3f %8.3f %8.3f %9.3f %9.3f %7.1f %8.1f %9.1f %8.2f %6zu %6zu %10zu  "
        " "
        "(AP %.3f, %zu conditions)\n",
        static_cast<long long>(images),
        static_cast<long long>(entries),
        floor,
        read,
        truth_s,
        coco_s,
        report,
        total,
        total / floor,
        CpuSeconds(),
        peak,
        peak * 1024.0 / static_cast<double>(images),
        detection_runs,
        whole.spilled_runs,
        whole.kept_detections,
        (*coco_stats)[0],
        whole.strata.size());
    std::fflush(stdout);
  }
  if (write.empty()) fs::remove_all(folder);
  return 0;
}

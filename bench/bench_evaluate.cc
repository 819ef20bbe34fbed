// Benchmark of `lsds evaluate` (docs/evaluate.md) on a large synthetic prediction set: N images of
// 15 ground-truth boxes in 3 classes, each found with probability 0.9 (its box moved by 5 %, a
// random score) plus 10 random false positives per image. Prints the time to read the
// predictions (ParseCocoPredictions), to compute COCOeval's 12 numbers (CocoEvaluator: IoUs,
// evaluateImg, accumulate for the four area ranges) and the whole report (the 12 numbers plus
// every stratum of every condition), against the floor: parsing the same JSON text with
// nlohmann alone, which any evaluator of the file does.
//
// --write DIR also writes DIR/gt_N.json (a COCO dataset) and DIR/dt_N.json (the results) for a
// peer: pycocotools' COCOeval on the same data (bench/README.md, "lsds evaluate").
//
// The last columns are the process's peak resident memory so far (getrusage ru_maxrss) and that
// peak per image: run one size per process to see each size's own peak.
//
//   bench_evaluate [--images 2000,10000] [--write DIR]
#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "bench/stopwatch.h"
#include "evaluate/evaluate_run.h"
#include "evaluate/predictions.h"

namespace {

using namespace lsds::evaluate;
using lsds::bench::Clock;
using lsds::bench::Seconds;

// The peak resident set of this process so far, MiB (Linux reports KiB).
double PeakRssMib() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;
}

// The ground truth and the predictions' JSON text for `images` images.
EvaluationTruth Truth(int64_t images, std::mt19937_64* rng, std::string* predictions) {
  EvaluationTruth truth;
  truth.coco.category_ids = {1, 2, 3};
  truth.category_names = {"car", "truck", "person"};
  std::uniform_real_distribution<double> u(0, 1);
  nlohmann::json list = nlohmann::json::array();
  int64_t id = 1;
  for (int64_t image = 1; image <= images; ++image) {
    truth.coco.image_ids.push_back(image);
    truth.frame_of_image[image] = image - 1;
    FrameFacts facts;
    facts.off_nadir_deg = 40 * u(*rng);
    facts.altitude_agl_m = 30 + 90 * u(*rng);
    truth.frames[image - 1] = facts;
    for (int k = 0; k < 25; ++k) {
      const double w = 4 + 120 * u(*rng) * u(*rng), h = w * (0.5 + u(*rng));
      const BoxXywh box{900 * u(*rng), 700 * u(*rng), w, h};
      const int64_t category = 1 + static_cast<int64_t>(3 * u(*rng));
      if (k < 15) {
        GroundTruthBox g;
        g.id = id++;
        g.image_id = image;
        g.category_id = category;
        g.bbox = box;
        g.area = w * h * 0.8;
        truth.coco.ground_truth.push_back(g);
        ObjectFacts object;
        object.frame = image - 1;
        object.visibility = u(*rng);
        object.in_frame = u(*rng) < 0.9 ? 1 : 0.5;
        object.size_px = std::max(w, h);
        object.distance_m = 20 + 100 * u(*rng);
        truth.objects.push_back(object);
        if (u(*rng) > 0.9) continue;
      }
      const double jitter = k < 15 ? 0.05 : 0;
      list.push_back({{"image_id", image},
                      {"category_id", category},
                      {"bbox",
                       {box.x + jitter * w * (u(*rng) - 0.5),
                        box.y + jitter * h * (u(*rng) - 0.5),
                        w * (1 + jitter * (u(*rng) - 0.5)),
                        h}},
                      {"score", u(*rng)}});
    }
  }
  *predictions = list.dump();
  return truth;
}

// The ground truth as a COCO dataset, for pycocotools.
void WriteCoco(const EvaluationTruth& truth,
               const std::string& predictions,
               const std::string& folder,
               int64_t images) {
  nlohmann::json gt = {{"images", nlohmann::json::array()},
                       {"annotations", nlohmann::json::array()},
                       {"categories", nlohmann::json::array()}};
  for (int64_t id : truth.coco.image_ids) gt["images"].push_back({{"id", id}});
  for (int64_t id : truth.coco.category_ids) gt["categories"].push_back({{"id", id}});
  for (const GroundTruthBox& g : truth.coco.ground_truth) {
    gt["annotations"].push_back({{"id", g.id},
                                 {"image_id", g.image_id},
                                 {"category_id", g.category_id},
                                 {"bbox", {g.bbox.x, g.bbox.y, g.bbox.w, g.bbox.h}},
                                 {"area", g.area},
                                 {"iscrowd", 0}});
  }
  const std::string n = std::to_string(images);
  std::ofstream(folder + "/gt_" + n + ".json") << gt.dump();
  std::ofstream(folder + "/dt_" + n + ".json") << predictions;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"lsds evaluate: COCO metrics and strata of a large synthetic prediction set"};
  std::vector<int64_t> sizes = {2000, 10000};
  app.add_option("--images", sizes, "image counts")->delimiter(',');
  std::string write;
  app.add_option("--write", write, "also write the data as COCO files into this folder");
  CLI11_PARSE(app, argc, argv);
  std::printf("%8s %10s %9s %9s %9s %9s %9s %7s %9s %9s\n",
              "images",
              "dets",
              "floor_s",
              "read_s",
              "coco_s",
              "report_s",
              "total_s",
              "ratio",
              "peak_mib",
              "kib/img");
  for (const int64_t images : sizes) {
    std::mt19937_64 rng(44);
    std::string text;
    const EvaluationTruth truth = Truth(images, &rng, &text);
    if (!write.empty()) WriteCoco(truth, text, write, images);
    auto t = Clock::now();
    size_t entries = 0;
    {  // the floor's document is freed before the evaluation's memory is measured
      const nlohmann::json parsed = nlohmann::json::parse(text);
      entries = parsed.size();
    }
    const double floor = Seconds(t);
    t = Clock::now();
    std::vector<DetectionBox> detections = ParseCocoPredictions(text, "bench.json", truth);
    const double read = Seconds(t);
    t = Clock::now();
    CocoData data = truth.coco;
    data.detections = detections;
    const CocoStats stats = CocoEvaluator(std::move(data)).Stats();
    const double coco = Seconds(t);
    t = Clock::now();
    const EvaluationReport report = Evaluate(truth, std::move(detections), 30);
    const double whole = Seconds(t);
    if (!write.empty()) {  // for comparison with the peer's stats
      std::printf("stats %lld:", static_cast<long long>(images));
      for (const double v : stats) std::printf(" %.17g", v);
      std::printf("\n");
    }
    const double peak = PeakRssMib();
    std::printf(
        "%8lld %10zu %9.3f %9.3f %9.3f %9.3f %9.3f %7.1f %9.1f %9.2f   (AP %.3f, %zu "
        "conditions)\n",
        static_cast<long long>(images),
        entries,
        floor,
        read,
        coco,
        whole,
        read + whole,
        (read + whole) / floor,
        peak,
        peak * 1024.0 / static_cast<double>(images),
        stats[0],
        report.strata.size());
  }
  return 0;
}

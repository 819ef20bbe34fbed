// Benchmark of collection size (bench/README.md): `lsds info`, `lsds validate` and
// `lsds convert` on a synthetic collection.json of 10^4, 10^5 and 10^6 small
// frames, each a child process: frames/s and its peak memory (getrusage maxrss
// of the child, wait4). Time must grow linearly with the frames and memory
// must not grow with them (the collection is streamed).
//
// The collection: `lsds synth` writes one 4x4 frame with its layers; its entry
// is repeated N times with indices 0..N-1, every entry naming the same layer
// files (the page cache serves them: what is measured is the per-frame work
// of the command, not the disk). metadata.json repeats its frame likewise.
//
// The floors: simdjson's On-Demand API visiting every value of the same
// collection.json (the whole file in memory; the fastest reading of the
// bytes), and beside it one streaming parse with nlohmann's SAX parser and no
// handler work. The ratio is the command's CPU time over the simdjson floor
// ("ratio"), and over nlohmann's ("ratio nl"). validate's own floor, printed
// under its row: the simdjson floors of the JSON files it reads
// (collection.json, metadata.json) and the layer decodes it must do (none
// for --checks schema,structure; every layer of every frame for all).
//
//   bench_scale [--sizes 10000,100000] (the issue-sized run: --sizes 10000,100000,1000000)
//               [--commands info,validate,convert]
//               [--validate-checks schema,structure] [--work DIR] [--keep]
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include <simdjson.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "bench/child_process.h"
#include "bench/null_sax.h"
#include "libs/collection/collection_reader.h"
#include "libs/collection/frame_text_reader.h"
#include "tests/build_paths.h"

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using lsds::bench::ChildRun;
using lsds::bench::RunChild;
using nlohmann::json;

namespace {

// CPU seconds, like the commands' figures.
double ParseFloor(const fs::path& file) {
  const std::clock_t start = std::clock();
  std::ifstream in(file, std::ios::binary);
  lsds::bench::NullSax sax;
  json::sax_parse(in, &sax);
  return static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC;
}

// CPU seconds of simdjson reading every value of the file (loading it
// included).
double SimdjsonFloor(const fs::path& file) {
  const std::clock_t start = std::clock();
  simdjson::padded_string text;
  if (simdjson::padded_string::load(file.string()).get(text) != simdjson::SUCCESS) return -1;
  lsds::FrameTextReader reader;
  if (!reader.IsWellFormed(std::string_view(text.data(), text.size()))) return -1;
  return static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC;
}

// validate's floor: the layer decodes it must do, nothing checked. The files
// `lsds validate --checks all` decodes (validators/frame_checks.cc,
// LoadLayers: each frame's flat layers but the derived ones, the first file
// of each semantic, and its bundle), decoded by the same readers one after
// the other, frames read by CollectionReader (its time not counted: the JSON
// floors count the reading). CPU seconds and the number of files.
struct DecodeFloor {
  double cpu_seconds = 0;
  int64_t files = 0;
};
DecodeFloor LayerDecodeFloor(const fs::path& collection) {
  DecodeFloor floor;
  const lsds::CollectionReader reader(collection);
  reader.ForEachFrame([&](const lsds::Frame& frame) {
    const std::clock_t start = std::clock();
    std::set<std::string> semantics;
    for (const lsds::LayerInfo& layer : reader.header().layers) {
      if (frame.files.count(layer.name) == 0 || layer.semantic == "derived") continue;
      if (layer.deep && layer.semantic != "bundle") continue;
      if (!semantics.insert(layer.semantic).second) continue;
      std::vector<std::string> channels;
      for (const lsds::LayerChannel& channel : layer.channels) channels.push_back(channel.name);
      if (layer.deep) {
        reader.ReadDeepLayer(frame, layer.name, channels);
      } else {
        reader.ReadFlatLayer(frame, layer.name, channels);
      }
      ++floor.files;
    }
    floor.cpu_seconds += static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC;
  });
  return floor;
}

// The files `lsds validate` decoded, from its JSON report.
int64_t FilesDecoded(const fs::path& report) {
  std::ifstream in(report);
  const json j = json::parse(in, nullptr, /*allow_exceptions=*/false);
  return j.is_object() && j.contains("files_decoded") ? j["files_decoded"].get<int64_t>() : -1;
}

// collection.json and metadata.json of `frames` copies of the template's
// frame 0, written as a stream (a million frames never sit in memory).
void WriteScaled(const fs::path& template_dir, const fs::path& out, int64_t frames) {
  json collection = json::parse(std::ifstream(template_dir / "collection.json"));
  json frame = collection["frames"][0];
  collection.erase("frames");
  collection["frame_count"] = frames;
  json metadata = json::parse(std::ifstream(template_dir / "metadata.json"));
  json meta_frame = metadata["frames"][0];
  metadata.erase("frames");
  metadata["frame_count"] = frames;

  auto write = [&](const fs::path& path, json header, json& entry) {
    std::string head = header.dump();
    head.pop_back();  // the closing brace: "frames" follows
    std::ofstream file(path, std::ios::binary);
    file << head << ",\"frames\":[\n";
    for (int64_t i = 0; i < frames; ++i) {
      entry["index"] = i;
      if (entry.contains("time")) entry["time"] = 0.1 * static_cast<double>(i);
      file << (i ? ",\n" : "") << entry.dump();
    }
    file << "\n]}\n";
  };
  fs::create_directories(out);
  for (const auto& entry : fs::directory_iterator(template_dir)) {
    if (entry.is_directory() && !fs::exists(out / entry.path().filename())) {
      fs::create_directory_symlink(fs::absolute(entry.path()), out / entry.path().filename());
    }
  }
  write(out / "collection.json", collection, frame);
  write(out / "metadata.json", metadata, meta_frame);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"lsds info/validate/convert on 10^4..10^6 small frames: frames/s and peak memory"};
  std::vector<int64_t> sizes = {10000, 100000};  // make bench; the issue adds 1000000
  std::vector<std::string> commands = {"info", "validate", "convert"};
  std::string validate_checks = "all";
  std::string work = (fs::temp_directory_path() / "lsds_bench_scale").string();
  std::string lsds = ::lsds::testing::BinaryDir() + "/tools/lsds";
  bool keep = false;
  app.add_option("--sizes", sizes, "frame counts")->delimiter(',');
  app.add_option("--commands", commands, "info, validate, convert")->delimiter(',');
  app.add_option("--validate-checks", validate_checks, "lsds validate --checks (default all)");
  app.add_option("--work", work, "scratch folder (removed unless --keep)");
  app.add_option("--lsds", lsds, "the lsds binary");
  app.add_flag("--keep", keep, "keep the scratch folder");
  CLI11_PARSE(app, argc, argv);

  fs::remove_all(work);
  fs::create_directories(work);
  const fs::path templ = fs::path(work) / "template";
  if (RunChild({lsds, "synth", templ.string(), "--count", "1", "--size", "4x4"}).exit_code != 0) {
    std::fprintf(stderr, "lsds synth failed\n");
    return 1;
  }
  // CPU seconds too: on a shared machine the wall time says more about the
  // other processes than about lsds.
  std::printf("%-9s %9s %9s %9s %11s %10s %9s %7s %9s %8s %6s\n",
              "command",
              "frames",
              "wall s",
              "cpu s",
              "frames/s",
              "peak MiB",
              "floor s",
              "ratio",
              "floor nl",
              "ratio nl",
              "exit");
  for (int64_t n : sizes) {
    const fs::path collection = fs::path(work) / ("C" + std::to_string(n));
    WriteScaled(templ, collection, n);
    const double floor = SimdjsonFloor(collection / "collection.json");
    const double floor_nlohmann = ParseFloor(collection / "collection.json");
    for (const std::string& command : commands) {
      std::vector<std::string> args = {lsds, command, collection.string()};
      const fs::path report = fs::path(work) / "validate.json";
      if (command == "validate") {
        fs::remove(report);
        args.insert(args.end(),
                    {"--checks", validate_checks, "--format", "json", "-o", report.string()});
      } else if (command == "convert") {
        fs::remove_all(fs::path(work) / "out");
        args.insert(args.end(),
                    {"--to", "coco", "--images", "none", "-o", (fs::path(work) / "out").string()});
      }
      const ChildRun run = RunChild(args);
      if (command == "validate") {
        // Its floor: the JSON files it reads (collection.json, metadata.json)
        // and the layer decodes it must do.
        const int64_t decoded = FilesDecoded(report);
        const DecodeFloor decodes = decoded > 0 ? LayerDecodeFloor(collection) : DecodeFloor{};
        const double validate_floor =
            floor + SimdjsonFloor(collection / "metadata.json") + decodes.cpu_seconds;
        std::printf(
            "validate floor: JSON %.3f + metadata %.3f + %lld layer decodes %.3f = %.3f "
            "CPU s (validate decoded %lld files); validate / floor %.2f\n",
            floor,
            validate_floor - floor - decodes.cpu_seconds,
            static_cast<long long>(decodes.files),
            decodes.cpu_seconds,
            validate_floor,
            static_cast<long long>(decoded),
            run.cpu_seconds / validate_floor);
      }
      // frames/s and the ratio to the floor by CPU time (both sides single
      // threaded where the command is).
      std::printf("%-9s %9lld %9.2f %9.2f %11.0f %10.1f %9.3f %7.1f %9.3f %8.1f %6d\n",
                  command.c_str(),
                  static_cast<long long>(n),
                  run.seconds,
                  run.cpu_seconds,
                  n / run.cpu_seconds,
                  run.peak_mib,
                  floor,
                  run.cpu_seconds / floor,
                  floor_nlohmann,
                  run.cpu_seconds / floor_nlohmann,
                  run.exit_code);
      std::fflush(stdout);
    }
    if (!keep) fs::remove_all(collection);
  }
  if (!keep) fs::remove_all(work);
  return 0;
}

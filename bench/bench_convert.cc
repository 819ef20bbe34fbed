// bench_convert: frames/s of `lsds convert` per format next to the floor
// (decoding the EXR layers the conversion needs + encoding the output images,
// with the same parallelism), the ratio, and the peak memory for a quarter of
// the frames and for all of them (flat = memory does not grow with frames).
//
//   bench_convert                           small default run (make bench)
//   bench_convert --frames 200 --size 1024  the issue's size
//   [--distinct K] [--formats yolo,coco,...] [--images png|jpg|none]
//
// The collection is K distinct analytic frames (synth) repeated under N
// frame indices (each a real file of its own), so that setting up N large
// frames stays cheap.
#include <sys/resource.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include <tbb/parallel_for.h>
#include <CLI/CLI.hpp>

#include "converters/convert.h"
#include "converters/registry.h"
#include "libs/collection/collection_reader.h"
#include "libs/collection/collection_writer.h"
#include "libs/exr/flat_image.h"
#include "libs/imaging/srgb_image.h"
#include "libs/util/strings.h"
#include "synth/synthetic_collection.h"

namespace fs = std::filesystem;
using namespace lsds;

namespace {

double Seconds(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

long PeakRssMb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024;
}

void BuildCollection(const fs::path& root, int frames, int size, int distinct) {
  synth::Spec spec = synth::DefaultSpec();
  spec.width = spec.height = size;
  spec.layers = {"rgb", "classid", "instanceid"};
  spec.cam_from_world.clear();
  for (int k = 0; k < distinct; ++k) {
    spec.cam_from_world.push_back(
        synth::NadirCamFromWorld({-3.0 + k * 6.0 / distinct, 0.5 * k, 20.0}));
  }
  // More targets than the default three: a grid of boxes and crates.
  for (int i = 0; i < 12; ++i) {
    synth::Box box;
    box.class_id = 2 + i % 2;
    box.instance_id = 10 + i;
    box.name = "grid#" + std::to_string(i);
    box.center = {-8.0 + 4.0 * (i % 5), -6.0 + 4.0 * (i / 5), 0.6};
    box.half_extents = {0.8, 0.5, 0.6};
    box.yaw_deg = 15.0 * i;
    spec.boxes.push_back(box);
  }
  const fs::path seed = root / "seed";
  synth::WriteCollection(seed, spec);
  const CollectionReader reader(seed);
  std::vector<Frame> seeds;
  reader.ForEachFrame([&](const Frame& f) { seeds.push_back(f); });

  const fs::path out = root / "collection";
  CollectionHeader header = reader.header();
  header.frame_count = frames;
  header.metadata.clear();
  for (const LayerInfo& layer : header.layers) fs::create_directories(out / layer.name);
  CollectionWriter writer(out, header);
  for (int i = 0; i < frames; ++i) {
    Frame frame = seeds[i % distinct];
    frame.index = i;
    frame.time = 0.1 * i;
    frame.sequence = "S" + std::to_string(i / 20);
    for (auto& [layer, file] : frame.files) {
      const std::string name = layer + "/" + FrameStem(i) + ".exr";
      fs::copy_file(seed / file, out / name, fs::copy_options::overwrite_existing);
      file = name;
    }
    writer.Append(frame);
  }
  writer.Commit();
}

// The floor: read the layers a conversion needs and write its images, nothing
// else, in parallel batches like the converter.
double Floor(const fs::path& collection,
             const std::string& images,
             bool masks,
             size_t batch_size,
             const fs::path& out) {
  const CollectionReader reader(collection);
  fs::create_directories(out);
  imaging::DisplayOptions display;
  const auto start = std::chrono::steady_clock::now();
  std::vector<Frame> batch;
  auto flush = [&] {
    tbb::parallel_for(size_t{0}, batch.size(), [&](size_t i) {
      if (images != "none") {
        const exr::FlatImage rgb =
            exr::ReadFlatExr(reader.LayerPath(batch[i], "rgb"), {"R", "G", "B"});
        imaging::WriteImage(out / (FrameStem(batch[i].index) + (images == "jpg" ? ".jpg" : ".png")),
                            imaging::ToSrgb8(rgb, display),
                            display);
      }
      if (masks) exr::ReadFlatExr(reader.LayerPath(batch[i], "instanceid"), {"id"});
    });
    batch.clear();
  };
  reader.ForEachFrame([&](const Frame& f) {
    batch.push_back(f);
    if (batch.size() == batch_size) flush();
  });
  flush();
  const double seconds = Seconds(start);
  fs::remove_all(out);
  return seconds;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("frames/s of lsds convert per format, next to its floor", "bench_convert");
  int frames = 40, size = 256, distinct = 4;
  std::string formats =
                  "yolo,yolo-seg,yolo-obb,dota,coco,cvat,cvat-video,mot,visdrone,visdrone-vid",
              images = "png", work;
  std::string child;  // internal: run one conversion and print "seconds peak_mb"
  int64_t child_frames = 0;
  app.add_option("--frames", frames, "frames in the collection")->capture_default_str();
  app.add_option("--size", size, "image width = height in pixels")->capture_default_str();
  app.add_option("--distinct", distinct, "distinct rendered frames, repeated")
      ->capture_default_str();
  app.add_option("--formats", formats, "formats to measure")->capture_default_str();
  app.add_option("--images", images, "png, jpg or none")->capture_default_str();
  app.add_option("--work", work, "work folder (default: a temporary one, removed)");
  app.add_option("--child", child)->group("");
  app.add_option("--child-frames", child_frames)->group("");
  CLI11_PARSE(app, argc, argv);

  if (!child.empty()) {
    convert::ConvertOptions options;
    options.collection = fs::path(work) / "collection";
    options.output = fs::path(work) / ("out_" + child);
    options.formats = Split(child, '+');
    options.images = images;
    options.progress = false;
    options.force = true;
    options.frames.end = child_frames;
    const auto start = std::chrono::steady_clock::now();
    const convert::ConvertResult result = convert::Convert(options);
    std::printf(
        "%.6f %ld %lld\n", Seconds(start), PeakRssMb(), static_cast<long long>(result.frames));
    fs::remove_all(options.output);
    return 0;
  }

  const bool own_work = work.empty();
  if (own_work)
    work =
        (fs::temp_directory_path() / ("lsds_convert_bench_" + std::to_string(getpid()))).string();
  fs::remove_all(work);
  fs::create_directories(work);
  auto start = std::chrono::steady_clock::now();
  BuildCollection(work, frames, size, distinct);
  std::printf(
      "collection: %d frames of %dx%d (%d distinct), built in %.1f s; images "
      "%s; %d threads\n",
      frames,
      size,
      size,
      distinct,
      Seconds(start),
      images.c_str(),
      tbb::this_task_arena::max_concurrency());

  const fs::path collection = fs::path(work) / "collection";
  const double floor_images = Floor(collection, images, false, 64, fs::path(work) / "floor");
  const double floor_masks = Floor(collection, images, true, 64, fs::path(work) / "floor");
  std::printf("floor (decode rgb + encode images):              %8.2f frames/s\n",
              frames / floor_images);
  std::printf("floor (decode rgb + instanceid + encode images): %8.2f frames/s\n\n",
              frames / floor_masks);
  std::printf("%-12s %10s %10s %8s %14s %14s\n",
              "format",
              "frames/s",
              "floor f/s",
              "ratio",
              "peak MB (1/4)",
              "peak MB (all)");

  auto run_child = [&](const std::string& format, int64_t n, double* seconds, long* mb) {
    const std::string command = std::string(argv[0]) + " --work " + work + " --images " + images +
                                " --child " + format + " --child-frames " + std::to_string(n);
    FILE* pipe = popen(command.c_str(), "r");
    long long done = 0;
    if (pipe == nullptr || std::fscanf(pipe, "%lf %ld %lld", seconds, mb, &done) != 3) {
      std::fprintf(stderr, "bench_convert: child run failed: %s\n", command.c_str());
      std::exit(2);
    }
    pclose(pipe);
  };
  // Oriented boxes are read from the truth (format 1.2) or measured on the
  // instanceid layer, whose decoding then belongs to the floor.
  bool truth_has_oriented = true;
  CollectionReader(collection).ForEachFrame([&](const Frame& frame) {
    for (const ObjectTruth& object : frame.objects)
      if (object.bbox && !object.bbox_oriented) truth_has_oriented = false;
  });
  for (const std::string& format : Split(formats, ',')) {
    const std::unique_ptr<convert::Converter> converter = convert::MakeConverter(format);
    const bool masks =
        converter->NeedsMasks() || (converter->NeedsOrientedBoxes() && !truth_has_oriented);
    const double floor_seconds = masks ? floor_masks : floor_images;
    double seconds = 0, quarter_seconds = 0;
    long mb = 0, quarter_mb = 0;
    run_child(format, frames / 4, &quarter_seconds, &quarter_mb);
    run_child(format, frames, &seconds, &mb);
    std::printf("%-12s %10.2f %10.2f %8.2f %14ld %14ld\n",
                format.c_str(),
                frames / seconds,
                frames / floor_seconds,
                seconds / floor_seconds,
                quarter_mb,
                mb);
  }
  if (own_work) fs::remove_all(work);
  return 0;
}

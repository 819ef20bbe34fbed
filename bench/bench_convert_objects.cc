// bench_convert_objects: `lsds convert` of ONE frame holding N objects, for N
// growing tenfold, with the time per object and the ratio of each run to the
// previous one (10 = linear in the object count) and to the floor (parsing
// collection.json and decoding the instanceid layer, which every conversion
// must do).
//
//   bench_convert_objects                      N = 10^3 .. 10^5 (make bench)
//   bench_convert_objects --max 1000000        up to the issue's 10^6
//   [--formats yolo,coco,cvat]
//
// Each object is one pixel of a square image (id k+1 at pixel k), so the
// image grows with N too: the floor grows with it and the ratio to the floor
// shows what the conversion adds per object.
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include <CLI/CLI.hpp>

#include "converters/convert.h"
#include "libs/collection/collection_reader.h"
#include "libs/collection/collection_writer.h"
#include "libs/exr/flat_image.h"
#include "libs/util/strings.h"
#include "synth/synthetic_collection.h"

namespace fs = std::filesystem;
using namespace lsds;

namespace {

double Seconds(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// One frame, `count` one-pixel objects of class 2.
fs::path BuildCollection(const fs::path& work, int64_t count) {
  const int side = static_cast<int>(std::ceil(std::sqrt(double(count))));
  synth::Spec spec = synth::DefaultSpec();
  spec.width = spec.height = side;
  spec.layers = {"rgb", "instanceid"};
  spec.cam_from_world.resize(1);
  const fs::path seed = work / ("seed_" + std::to_string(count));
  synth::WriteCollection(seed, spec);
  const CollectionReader reader(seed);
  Frame frame;
  reader.ForEachFrame([&](const Frame& f) {
    if (f.index == 0) frame = f;
  });
  exr::FlatImage ids(side, side);
  auto& id = ids.AddChannel("id", exr::PixelType::kUint).uints;
  frame.objects.clear();
  frame.objects.reserve(count);
  for (int64_t k = 0; k < count; ++k) {
    ObjectTruth object;
    object.instance_id = static_cast<uint32_t>(k + 1);
    object.class_id = 2;
    object.name = "o#" + std::to_string(k);
    const double x = double(k % side), y = double(k / side);
    object.bbox = Box2d{x, y, x + 1, y + 1};
    object.bbox_projected = object.bbox;
    object.visible_pixels = 1;
    object.visibility = 1;
    object.in_frame = 1;
    object.obb.emplace();
    object.obb->center = {x, y, 0};
    object.obb->half_extents = {0.5, 0.5, 0.5};
    id[k] = object.instance_id;
    frame.objects.push_back(std::move(object));
  }
  exr::WriteFlatExr(seed / frame.files.at("instanceid"), ids);
  CollectionHeader header = reader.header();
  header.frame_count = 1;
  header.metadata.clear();
  fs::remove(seed / kMetadataFile);
  CollectionWriter writer(seed, header);
  writer.Append(frame);
  writer.Commit();
  return seed;
}

double Floor(const fs::path& collection) {
  const auto start = std::chrono::steady_clock::now();
  const CollectionReader reader(collection);
  reader.ForEachFrame(
      [&](const Frame& frame) { reader.ReadFlatLayer(frame, "instanceid", {"id"}); });
  return Seconds(start);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("lsds convert of one frame with N objects", "bench_convert_objects");
  int64_t min_count = 1000, max_count = 100000;
  std::string formats = "yolo,coco,cvat";
  app.add_option("--min", min_count, "smallest N")->capture_default_str();
  app.add_option("--max", max_count, "largest N")->capture_default_str();
  app.add_option("--formats", formats, "formats")->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  const fs::path work =
      fs::temp_directory_path() / ("lsds_convert_objects_" + std::to_string(::getpid()));
  fs::remove_all(work);
  fs::create_directories(work);
  std::printf("%10s %10s %12s %12s %14s %10s\n",
              "objects",
              "floor s",
              "convert s",
              "us/object",
              "vs previous",
              "vs floor");
  double previous = 0;
  for (int64_t count = min_count; count <= max_count; count *= 10) {
    const fs::path collection = BuildCollection(work, count);
    const double floor = Floor(collection);
    convert::ConvertOptions options;
    options.collection = collection;
    options.output = work / ("out_" + std::to_string(count));
    options.formats = Split(formats, ',');
    options.images = "none";
    options.progress = false;
    const auto start = std::chrono::steady_clock::now();
    convert::Convert(options);
    const double seconds = Seconds(start);
    std::printf("%10lld %10.3f %12.3f %12.2f %14s %10.1f\n",
                static_cast<long long>(count),
                floor,
                seconds,
                1e6 * seconds / double(count),
                previous > 0 ? FormatNumber(seconds / previous, 3).c_str() : "-",
                seconds / floor);
    previous = seconds;
    fs::remove_all(collection);
    fs::remove_all(options.output);
  }
  fs::remove_all(work);
  std::printf("linear in the object count: 'vs previous' stays near 10\n");
  return 0;
}

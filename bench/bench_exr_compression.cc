// Per-layer EXR compression benchmark (docs/generator.md, "Storage"): renders frame 1 of the demo
// scene (its motion measured against frame 0) and encodes each layer with every
// lossless compression OpenEXR allows for it (flat: none, rle, zips, zip, piz;
// deep: none, rle, zips), printing the bytes, the encode and decode time
// (median of 3), with OpenEXR's thread pool off and on. The bundle is measured
// in the compact and residual layouts (libs/collection/bundle_layout.h), the
// worldposition and motion layers in the float and residual ones
// (libs/collection/worldposition_layout.h, motion_layout.h), with a histogram
// of the worldposition residuals' magnitude (how close the depth's prediction
// is to the renderer's value). docs/generator.md "Storage" keeps the table and
// the choice.
//
//   bench_exr_compression [--size 1024] [--spp 4] [--threads T] [--zip-level L]
#include <ImfThreading.h>
#include <OpenEXR/ImfCompression.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "generator/demo_plan.h"
#include "generator/generate.h"
#include "generator/render/embree_scene.h"
#include "generator/render/integrator.h"
#include "generator/render/sky.h"
#include "libs/collection/bundle_layout.h"
#include "libs/collection/motion_layout.h"
#include "libs/collection/worldposition_layout.h"
#include "libs/exr/flat_image.h"
#include "libs/util/thread_limit.h"

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using namespace lsds;
using namespace lsds::gen;

namespace {

double Since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

// Residual magnitudes (|dX| as a signed 32-bit difference of float bits) in
// bins 0, 1, 2-3, 4-15, 16-255, >= 256 ulps, over all three channels.
void PrintResidualHistogram(const exr::FlatImage& truth, const WorldPositionPrediction& input) {
  const exr::FlatImage predicted = PredictWorldPosition(input);
  const char* names[] = {"0", "1", "2-3", "4-15", "16-255", ">=256"};
  int64_t bins[6] = {0, 0, 0, 0, 0, 0};
  int64_t total = 0;
  for (const char* axis : {"X", "Y", "Z"}) {
    const std::vector<float>& t = truth.Get(axis).floats;
    const std::vector<float>& p = predicted.Get(axis).floats;
    for (size_t k = 0; k < t.size(); ++k) {
      uint32_t a, b;
      std::memcpy(&a, &t[k], 4);
      std::memcpy(&b, &p[k], 4);
      const int64_t d = std::llabs(static_cast<int64_t>(static_cast<int32_t>(a - b)));
      const int bin = d == 0 ? 0 : d == 1 ? 1 : d < 4 ? 2 : d < 16 ? 3 : d < 256 ? 4 : 5;
      ++bins[bin];
      ++total;
    }
  }
  std::printf("worldposition residual |d| in ulps (X, Y, Z together, %lld values):",
              static_cast<long long>(total));
  for (int i = 0; i < 6; ++i) std::printf(" %s: %.2f%%", names[i], 100.0 * bins[i] / total);
  std::printf("\n");
}

template <typename Fn>
double Median3(Fn fn) {
  std::vector<double> t;
  for (int i = 0; i < 3; ++i) {
    const Clock::time_point start = Clock::now();
    fn();
    t.push_back(Since(start));
  }
  std::sort(t.begin(), t.end());
  return t[1];
}

}  // namespace

int main(int argc, char** argv) {
  int size = 1024, spp = 4, threads = 0, zip_level = 1;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i];
    const int value = std::atoi(argv[i + 1]);
    if (flag == "--size") {
      size = value;
    } else if (flag == "--spp") {
      spp = value;
    } else if (flag == "--threads") {
      threads = value;
    } else if (flag == "--zip-level") {
      zip_level = value;
    } else {
      std::fprintf(
          stderr,
          "usage: bench_exr_compression [--size N] [--spp S] [--threads T] [--zip-level L]\n");
      return 2;
    }
  }
  const int pool = threads > 0 ? threads : static_cast<int>(std::thread::hardware_concurrency());
  const ThreadLimit control(threads);
  Imf::setDefaultZipCompressionLevel(zip_level);

  // Frame 1 of the demo, its motion measured against frame 0 (a shot's first
  // frame has no motion: all NaN).
  DemoOptions demo;
  demo.frames = 2;
  demo.width = demo.height = size;
  const Plan plan = MakeDemoPlan(demo);
  EmbreeDevice device;
  const SceneAssets assets = BuildSceneAssets(plan);
  const Sky sky(plan);
  const PlannedFrame& before = plan.frames.at(0);
  const PlannedFrame& frame = plan.frames.at(1);
  const WorldState world_before = WorldAt(plan, before);
  const RenderScene scene_before(device, plan, assets, world_before);
  const RenderScene scene(device, plan, assets, WorldAt(plan, frame));
  RenderSettings settings;
  settings.sampler = {spp, 1.0, plan.seed};
  const Film film =
      RenderFrame(scene, sky, frame, {&before, &world_before, &scene_before}, settings);
  CameraTruth previous_camera;
  previous_camera.intrinsics = before.camera;
  SetCamFromWorld(before.cam_from_world, &previous_camera);
  GenerateOptions options;
  const CollectionHeader header = MakeHeader(plan, options);
  // The residual layout's prediction inputs, as the generator passes them.
  WorldPositionPrediction prediction;
  prediction.depth = film.flat.at("depth").Get("Z").floats;
  prediction.width = prediction.height = size;
  prediction.depth_kind = options.depth_kind;
  prediction.camera.intrinsics = frame.camera;
  SetCamFromWorld(frame.cam_from_world, &prediction.camera);
  // The residual bundle's view, as the generator's collection builder passes it.
  const BundleSampling sampling{settings.sampler,
                                frame.index,
                                BundleView{prediction.camera.intrinsics,
                                           prediction.camera.cam_from_world_rotation,
                                           options.depth_kind}};

  const fs::path dir = fs::temp_directory_path() / "lsds_bench_exr_compression";
  fs::create_directories(dir);
  std::printf("EXR compression per layer: demo frame %dx%d, spp %d, zip level %d\n",
              size,
              size,
              spp,
              zip_level);
  std::printf("encode/decode: median of 3, s; pool = OpenEXR's thread pool with %d threads\n",
              pool);
  std::printf("%-14s %-5s %10s %9s %10s %11s %10s %11s\n",
              "layer",
              "codec",
              "MB",
              "ratio",
              "encode s",
              "encode pool",
              "decode s",
              "decode pool");
  std::vector<LayerInfo> layers;
  for (const LayerInfo& layer : header.layers) {
    layers.push_back(layer);
    if (layer.deep) {
      layers.back().layout = BundleLayout::kCompact;
      layers.push_back(layer);
      layers.back().layout = BundleLayout::kResidual;
      continue;
    }
    if (layer.semantic != "worldposition" && layer.semantic != "motion") continue;
    layers.back().flat_layout = FlatLayout::kFloat;
    layers.back().compression = StandardLayer(layer.semantic).compression;
    layers.push_back(layer);
    layers.back().flat_layout = FlatLayout::kResidual;
  }
  for (const LayerInfo& layer : layers) {
    const bool residual = (!layer.deep && layer.flat_layout == FlatLayout::kResidual) ||
                          (layer.deep && layer.layout == BundleLayout::kResidual);
    const std::string label = residual ? layer.name + "/res" : layer.name;
    std::vector<exr::Compression> codecs = {
        exr::Compression::kNone, exr::Compression::kRle, exr::Compression::kZips};
    if (!layer.deep) {  // OpenEXR's deep files allow only the three above
      codecs.push_back(exr::Compression::kZip);
      codecs.push_back(exr::Compression::kPiz);
    }
    double raw = 0;
    for (exr::Compression codec : codecs) {
      exr::WriteOptions write;
      write.compression = codec;
      const fs::path path = dir / (layer.name + ".exr");
      auto encode = [&] {
        if (layer.deep) {
          WriteBundleExr(path, film.bundle, layer.layout, sampling, write);
        } else if (layer.semantic == "worldposition") {
          WriteWorldPositionExr(
              path, film.flat.at(layer.semantic), layer.flat_layout, &prediction, "depth", write);
        } else if (layer.semantic == "motion") {
          WriteMotionExr(path,
                         film.flat.at(layer.semantic),
                         layer.flat_layout,
                         &prediction,
                         previous_camera,
                         "depth",
                         write);
        } else {
          exr::WriteFlatExr(path, film.flat.at(layer.semantic), write);
        }
      };
      auto decode = [&] {
        if (layer.deep) {
          ReadBundleExr(path);
        } else if (layer.semantic == "worldposition") {  // decoding includes the prediction
          ReadWorldPositionExr(path, {}, [&](const std::string&) { return prediction; });
        } else if (layer.semantic == "motion") {
          ReadMotionExr(path, {}, [&](const std::string&) { return prediction; });
        } else {
          exr::ReadFlatExr(path);
        }
      };
      Imf::setGlobalThreadCount(0);
      const double encode_serial = Median3(encode);
      const double decode_serial = Median3(decode);
      Imf::setGlobalThreadCount(pool);
      const double encode_pool = Median3(encode);
      const double decode_pool = Median3(decode);
      const double bytes = static_cast<double>(fs::file_size(path));
      if (codec == exr::Compression::kNone) raw = bytes;
      std::printf(
          "%-14s %-5s %10.2f %9.2f %10.3f %11.3f %10.3f %11.3f%s\n",
          label.c_str(),
          exr::CompressionName(codec),
          bytes / 1e6,
          raw / bytes,
          encode_serial,
          encode_pool,
          decode_serial,
          decode_pool,
          codec == layer.compression &&
                  (layer.semantic != "worldposition" ||
                   layer.flat_layout == options.layouts.worldposition) &&
                  (layer.semantic != "motion" || layer.flat_layout == options.layouts.motion) &&
                  (!layer.deep || layer.layout == options.layouts.bundle)
              ? "  <- chosen"
              : "");
    }
  }
  PrintResidualHistogram(film.flat.at("worldposition"), prediction);
  fs::remove_all(dir);
  return 0;
}

// bench_bundles: frames/s of `lsds bundles` (statistics, optionally derived
// layers) on a generated collection of deep bundles, next to the floor: reading
// and decoding the same bundle channels with the same frame batching. Prints
// both and their ratio (the issue aims at <= 1.3x).
//
//   bench_bundles [--frames 10] [--width 512] [--height 512] [--layout compact|full]
//                 [--samples-per-axis 2] [--discs 400] [--dir PATH] [--keep]
//                 [--with-layers] [--repeats N] [--picture PNG]
// Issue-sized run: --frames 100 --width 1024 --height 1024 (4 samples/pixel).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>

#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <CLI/CLI.hpp>

#include "bundles/bundle_run.h"
#include "bundles/bundle_stats.h"
#include "libs/collection/bundle_layout.h"
#include "libs/collection/collection_reader.h"
#include "libs/collection/collection_writer.h"
#include "libs/exr/deep_image.h"
#include "libs/util/strings.h"

namespace fs = std::filesystem;
using namespace lsds;

namespace {

struct Disc {
  double cx, cy, r, z;
  uint32_t instance, cls;
};

// A tilted ground (instance 1000, class 1) under discs that bulge towards the
// camera: many sizes, so that small objects and edges are plentiful. n x n
// stratified samples placed by the sampling rule (docs/format.md "Pixel
// bundles"), sample 0 at the centre, so that a compact bundle derives them.
exr::DeepImage MakeFrame(int width,
                         int height,
                         const SamplerSettings& sampler,
                         int64_t frame,
                         int discs,
                         uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uni(0, 1);
  std::vector<Disc> scene;
  for (int i = 0; i < discs; ++i) {
    const double r = 1.0 + std::pow(uni(rng), 3) * width / 12.0;  // mostly small
    scene.push_back({uni(rng) * width,
                     uni(rng) * height,
                     r,
                     5 + 14 * uni(rng),
                     static_cast<uint32_t>(i + 1),
                     static_cast<uint32_t>(2 + i % 4)});
  }
  std::sort(scene.begin(), scene.end(), [](const Disc& a, const Disc& b) { return a.z > b.z; });
  const int spp = sampler.spp;
  std::vector<Eigen::Vector2d> positions(spp);
  std::vector<float> sx(spp), sy(spp);
  sx[0] = sy[0] = 0.5f;
  exr::DeepImage image(
      width, height, std::vector<uint32_t>(static_cast<size_t>(width) * height, spp));
  auto& inst = image.AddChannel("instanceid", exr::PixelType::kUint).uints;
  auto& cls = image.AddChannel("classid", exr::PixelType::kUint).uints;
  auto& zs = image.AddChannel("Z", exr::PixelType::kFloat).floats;
  auto& nx = image.AddChannel("NX", exr::PixelType::kFloat).floats;
  auto& ny = image.AddChannel("NY", exr::PixelType::kFloat).floats;
  auto& nz = image.AddChannel("NZ", exr::PixelType::kFloat).floats;
  auto& px = image.AddChannel("SX", exr::PixelType::kFloat).floats;
  auto& py = image.AddChannel("SY", exr::PixelType::kFloat).floats;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const uint64_t first = image.FirstSample(x, y);
      PixelSamples(sampler, frame, x, y, positions.data());
      for (int s = 0; s < spp; ++s) {
        sx[s] = static_cast<float>(positions[s].x() - x);  // as the generator stores them
        sy[s] = static_cast<float>(positions[s].y() - y);
        inst[first + s] = 1000;
        cls[first + s] = 1;
        zs[first + s] = static_cast<float>(20.0 + 0.01 * (y + sy[s]));
        nz[first + s] = 1;
        px[first + s] = sx[s];
        py[first + s] = sy[s];
      }
    }
  }
  for (const Disc& d : scene) {  // far to near: nearer discs overwrite
    const int x0 = std::max(0, static_cast<int>(d.cx - d.r)),
              x1 = std::min(width - 1, static_cast<int>(d.cx + d.r));
    const int y0 = std::max(0, static_cast<int>(d.cy - d.r)),
              y1 = std::min(height - 1, static_cast<int>(d.cy + d.r));
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        const uint64_t first = image.FirstSample(x, y);
        for (int s = 0; s < spp; ++s) {
          const double dx = (x + px[first + s] - d.cx) / d.r, dy = (y + py[first + s] - d.cy) / d.r;
          const double q = dx * dx + dy * dy;
          if (q >= 1) continue;
          const double h = std::sqrt(1 - q);
          inst[first + s] = d.instance;
          cls[first + s] = d.cls;
          zs[first + s] = static_cast<float>(d.z - 0.05 * d.r * h);
          nx[first + s] = static_cast<float>(dx);
          ny[first + s] = static_cast<float>(dy);
          nz[first + s] = static_cast<float>(h);
        }
      }
    }
  }
  return image;
}

void Generate(const fs::path& root,
              int frames,
              int width,
              int height,
              int n,
              int discs,
              BundleLayout layout) {
  fs::create_directories(root / "bundle");
  const SamplerSettings sampler{n * n, 1.0, 1234};
  CollectionHeader header;
  header.provenance.generator = "bench_bundles";
  header.classes = {{1, "ground"}, {2, "a"}, {3, "b"}, {4, "c"}, {5, "d"}};
  header.layers = {StandardLayer("bundle")};
  header.layers[0].layout = layout;
  header.frame_count = frames;
  exr::WriteOptions write;
  write.compression = exr::Compression::kZips;
  // The residual layout's view: a camera looking straight down, as a survey
  // drone's (the synthetic depths are not its exact renders; the layout is
  // lossless whatever the prediction).
  BundleView view;
  view.intrinsics = PinholeCamera::FromHorizontalFov(width, height, 60);
  tbb::parallel_for(0, frames, [&](int i) {
    WriteBundleExr(root / "bundle" / (FrameStem(i) + ".exr"),
                   MakeFrame(width, height, sampler, i, discs, 1234 + i),
                   layout,
                   BundleSampling{sampler, i, view},
                   write);
  });
  CollectionWriter writer(root, header);
  for (int i = 0; i < frames; ++i) {
    Frame frame;
    frame.index = i;
    frame.time = 0.1 * i;
    frame.sequence = "S1";
    frame.camera.intrinsics = PinholeCamera::FromHorizontalFov(width, height, 60);
    frame.files["bundle"] = "bundle/" + FrameStem(i) + ".exr";
    writer.Append(frame);
  }
  writer.Commit();
}

double Seconds(const std::chrono::steady_clock::time_point& start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The floor: the same frame stream, batching and channels, decoding only.
double Floor(const fs::path& root, size_t batch_size) {
  const CollectionReader reader(root);
  const auto start = std::chrono::steady_clock::now();
  std::vector<Frame> batch;
  std::atomic<uint64_t> samples{0};
  auto flush = [&] {
    tbb::parallel_for(size_t{0}, batch.size(), [&](size_t i) {
      const exr::DeepImage image =
          ReadBundleExr(reader.LayerPath(batch[i], "bundle"), bundle::BundleChannels());
      samples += image.total_samples();
    });
    batch.clear();
  };
  reader.ForEachFrame([&](const Frame& frame) {
    batch.push_back(frame);
    if (batch.size() == batch_size) flush();
  });
  flush();
  return Seconds(start);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app(
      "Benchmark of lsds bundles against the floor (reading and decoding the "
      "deep bundles).");
  int frames = 10, width = 512, height = 512, n = 2, discs = 400, repeats = 1;
  std::string dir, picture;
  bool keep = false, with_layers = false;
  app.add_option("--frames", frames, "frames")->check(CLI::PositiveNumber);
  app.add_option("--width", width)->check(CLI::PositiveNumber);
  app.add_option("--height", height)->check(CLI::PositiveNumber);
  app.add_option("--samples-per-axis", n, "n: n*n samples per pixel")->check(CLI::PositiveNumber);
  app.add_option("--discs", discs, "objects per frame");
  app.add_option("--dir", dir, "where to generate the collection (default: a temporary folder)");
  app.add_option("--repeats", repeats, "timed passes of each (the best is kept)")
      ->check(CLI::PositiveNumber);
  app.add_flag("--keep", keep, "keep the generated collection");
  app.add_flag(
      "--with-layers", with_layers, "also time --write-layers majority,purity,coverage,edge");
  app.add_option("--picture", picture, "write the mixed-pixel map of frame 0 (PNG)");
  std::string layout_name = "residual";
  app.add_option(
         "--layout", layout_name, "bundle layout written: residual (default), compact or full")
      ->check(CLI::IsMember({"residual", "compact", "full"}));
  CLI11_PARSE(app, argc, argv);
  BundleLayout layout = BundleLayout::kResidual;
  ParseBundleLayout(layout_name, &layout);

  const fs::path root =
      dir.empty() ? fs::temp_directory_path() / "lsds_bundles_bench" : fs::path(dir);
  fs::remove_all(root);
  const fs::path stats = root.parent_path() / (root.filename().string() + "_stats.json");
  auto start = std::chrono::steady_clock::now();
  Generate(root, frames, width, height, n, discs, layout);
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  uint64_t bytes = 0;
  for (const auto& e : fs::directory_iterator(root / "bundle")) bytes += fs::file_size(e.path());
  std::printf(
      "generated %d frames %dx%d, %d samples per pixel, %s layout, %.2f MB/frame in %.1f s (%s)\n",
      frames,
      width,
      height,
      n * n,
      layout_name.c_str(),
      bytes / 1e6 / frames,
      Seconds(start),
      root.c_str());

  const size_t batch = static_cast<size_t>(std::max(1, tbb::info::default_concurrency()));
  Floor(root,
        batch);  // warm the page cache so that both passes read from memory
  double floor_s = 1e30, stats_s = 1e30, layers_s = 1e30;
  bundle::RunResult result;
  for (int r = 0; r < repeats; ++r) {
    floor_s = std::min(floor_s, Floor(root, batch));
    bundle::RunOptions options;
    // Outside the collection: an output may not lie inside an input.
    options.output = stats;
    options.force = true;
    if (r == 0 && !picture.empty()) options.mixed_map = picture;
    start = std::chrono::steady_clock::now();
    result = bundle::RunBundles(root, options);
    stats_s = std::min(stats_s, Seconds(start));
    if (with_layers) {
      options.write_layers = {"majority", "purity", "coverage", "edge"};
      options.mixed_map.clear();
      start = std::chrono::steady_clock::now();
      bundle::RunBundles(root, options);
      layers_s = std::min(layers_s, Seconds(start));
    }
  }
  std::printf("threads %d, batch %zu\n", tbb::info::default_concurrency(), batch);
  std::printf("mixed pixels %.3f%%, flying %.3f%%\n",
              100.0 * result.total.mixed_pixels / result.total.pixels,
              100.0 * result.total.flying_pixels / result.total.pixels);
  std::printf("floor (read + decode)   %8.2f frames/s  (%.2f s)\n", frames / floor_s, floor_s);
  std::printf("lsds bundles (stats)    %8.2f frames/s  (%.2f s)  ratio %.2fx\n",
              frames / stats_s,
              stats_s,
              stats_s / floor_s);
  if (with_layers) {
    std::printf("lsds bundles (+layers)  %8.2f frames/s  (%.2f s)  ratio %.2fx\n",
                frames / layers_s,
                layers_s,
                layers_s / floor_s);
  }
  if (!keep) fs::remove_all(root);
  fs::remove(stats);
  return 0;
}

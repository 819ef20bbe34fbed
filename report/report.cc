#include "report/report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <tbb/parallel_for.h>

#include "libs/util/atomic_file.h"
#include "libs/util/error.h"
#include "libs/util/progress.h"
#include "report/bundle_section.h"
#include "report/draw.h"
#include "report/evaluation_section.h"
#include "report/frame_sampler.h"
#include "report/frame_views.h"
#include "report/html.h"
#include "report/page_style.h"
#include "report/svg_plot.h"
#include "report/validation_section.h"

namespace lsds::report {

namespace {

namespace fs = std::filesystem;

// Without --frames every frame is shown, also one whose index is invalid
// (negative: lsds validate names it), so the page still shows it.
bool Selected(const FrameRange& frames, int64_t index) {
  return frames.all() || frames.Contains(index);
}

FrameCamera CameraOf(const CollectionReader& reader, const Frame& frame) {
  const CollectionHeader& header = reader.header();
  const LayerInfo* depth = header.FindLayerBySemantic("depth");
  if (HasFile(frame, depth) && !depth->deep) {
    try {
      const exr::FlatImage z = reader.ReadFlatLayer(frame, depth->name, {"Z"});
      return ComputeFrameCamera(header, frame, &z, depth->depth_kind);
    } catch (const Error&) {
      // An unreadable depth file: the camera figures that need it are unknown
      // (validate names the file); the pose still gives height and angle.
      FrameCamera camera = ComputeFrameCamera(header, frame, nullptr, {});
      camera.altitude_m = camera.distance_m = camera.gsd_m = 0.0 / 0.0;
      return camera;
    }
  }
  return ComputeFrameCamera(header, frame, nullptr, {});
}

}  // namespace

ReportData CollectReportData(const CollectionReader& reader,
                             const ReportOptions& options,
                             const std::set<int64_t>& always) {
  const CollectionHeader& header = reader.header();
  ReportData data;
  data.distributions = MakeDistributions(header);
  FrameSampler<SampledFrame> sampler(options.sample, always);
  Progress progress("report", static_cast<int64_t>(reader.frames_in_file()));
  // Frames in batches: the depth files of a batch decode in parallel, the
  // figures fold in in collection order.
  std::vector<Frame> batch;
  auto flush = [&] {
    std::vector<FrameCamera> cameras(batch.size());
    tbb::parallel_for(
        size_t{0}, batch.size(), [&](size_t i) { cameras[i] = CameraOf(reader, batch[i]); });
    for (size_t i = 0; i < batch.size(); ++i) {
      AddFrame(header, batch[i], cameras[i], &data.distributions);
      sampler.Offer(batch[i].index, SampledFrame{batch[i], cameras[i]});
    }
    progress.Add(static_cast<int64_t>(batch.size()));
    batch.clear();
  };
  reader.ForEachFrame([&](const Frame& frame) {
    if (!Selected(options.frames, frame.index)) {
      progress.Add();
      return;
    }
    batch.push_back(frame);
    if (batch.size() >= 32) flush();
  });
  flush();
  data.samples = sampler.Take();
  // Metadata error: the first perturbed variant, streamed the same way.
  for (const MetadataVariant& variant : header.metadata) {
    if (!variant.perturbed) continue;
    const MetadataReader metadata(reader.root() / variant.file);
    metadata.ForEachFrame([&](const MetadataFrame& frame) {
      if (!Selected(options.frames, frame.index)) return;
      AddMetadataError(frame, &data.distributions);
    });
    data.distributions.metadata_variant = variant.file;
    break;
  }
  return data;
}

namespace {

// The frames shown with every layer: spread evenly over the sample.
std::set<size_t> LayerSamples(size_t sample_count, size_t layer_frames) {
  std::set<size_t> layer_samples;
  const size_t k = std::min(layer_frames, sample_count);
  for (size_t i = 0; i < k; ++i) layer_samples.insert((2 * i + 1) * sample_count / (2 * k));
  return layer_samples;
}

// The sampled frames' cards, and the layer strips of those in `layer_samples`, drawn in
// parallel; their problems in frame order, whatever order the threads finished in.
struct SampleViews {
  std::vector<Html> cards, strips;
};

SampleViews DrawSamples(const CollectionReader& reader,
                        const ReportData& data,
                        const ReportOptions& options,
                        const std::set<size_t>& layer_samples,
                        std::vector<std::string>* problems) {
  const size_t n = data.samples.size();
  SampleViews views{std::vector<Html>(n), std::vector<Html>(n)};
  std::vector<std::vector<std::string>> sample_problems(n);
  tbb::parallel_for(size_t{0}, n, [&](size_t i) {
    const bool layers = layer_samples.count(i) > 0;
    views.cards[i] = FrameCard(reader, data.samples[i], layers, options, &sample_problems[i]);
    if (layers) views.strips[i] = LayerStrip(reader, data.samples[i], options, &sample_problems[i]);
  });
  for (std::vector<std::string>& p : sample_problems) {
    problems->insert(problems->end(), p.begin(), p.end());
  }
  return views;
}

// The page's head and its header: the collection in one line, then the sections' links.
Html PageHeader(const CollectionReader& reader,
                const ReportData& data,
                const ReportOptions& options,
                bool has_layers) {
  const CollectionHeader& header = reader.header();
  const Distributions& d = data.distributions;
  const std::string name = fs::absolute(reader.root()).lexically_normal().filename().string();
  Html s;
  s << "<!DOCTYPE html><html lang=\"en\"><head><meta charset=\"utf-8\">"
    << "<title>lsds report: " << name << "</title><style>" << PageStyle() << "</style></head><body>"
    << "<script>window.onerror=function(m){document.body.setAttribute("
       "'data-js-error',String(m));};</script>"
    << "<header><h1>lsds report: " << name << "</h1><p>" << d.frames << " frames";
  if (reader.frames_in_file() != static_cast<size_t>(d.frames)) {
    s << " selected of " << reader.frames_in_file();
  }
  s << " &middot; " << data.samples.size() << " on the contact sheet &middot; " << d.objects
    << " objects listed, " << d.visible_objects << " visible &middot; " << header.classes.size()
    << " classes &middot; " << header.layers.size() << " layers &middot; world "
    << header.conventions.world.name << ", " << header.conventions.world.length_unit
    << " &middot; format " << header.format_version << " &middot; " << header.provenance.generator
    << " " << header.provenance.generator_version
    << "</p><nav><a href=\"#sheet\">contact sheet</a> ";
  if (has_layers) s << "<a href=\"#layers\">layers</a> ";
  s << "<a href=\"#distributions\">distributions</a>";
  if (options.validation) s << " <a href=\"#validation\">validation</a>";
  if (!options.bundle_stats.is_null()) s << " <a href=\"#bundles\">mixed pixels</a>";
  if (!options.evaluation.is_null()) s << " <a href=\"#evaluation\">evaluation</a>";
  s << "</nav></header>";
  return s;
}

// The frame cards, with a class filter.
Html ContactSheet(const CollectionHeader& header, const std::vector<Html>& cards) {
  Html s;
  s << "<section id=\"sheet\"><h2>Contact sheet</h2><p class=\"help\">Tight "
       "boxes in the class colour, mask outlines in the instance colour. Click "
       "a frame for its objects (and layers when tagged).</p><div "
       "class=\"filter\">show classes: ";
  for (const ClassInfo& c : header.classes) {
    const cv::Vec3b col = ClassColor(c.id);
    char swatch[16];
    std::snprintf(swatch, sizeof(swatch), "#%02x%02x%02x", col[2], col[1], col[0]);
    s << "<label><input type=\"checkbox\" checked data-class=\"c" << c.id
      << "\"><span class=\"swatch\" style=\"background:" << std::string(swatch) << "\"></span>"
      << c.name << "</label>";
  }
  s << "<label><input type=\"checkbox\" checked data-class=\"\">frames with no "
       "visible object</label></div><div class=\"sheet\">";
  for (const Html& card : cards) s << card;
  s << "</div></section>";
  return s;
}

Html LayersSection(size_t frame_count, const std::vector<Html>& strips) {
  Html s;
  s << "<section id=\"layers\"><h2>Layers</h2><p class=\"help\">Every layer "
       "of "
    << frame_count
    << " frames side by side. Ids: one colour per id, black background. "
       "Depth: "
       "turbo colour map from near (blue) to far (red), sky dark grey. "
       "Motion: "
       "hue is the direction (wheel), saturation the speed, white no motion, "
       "checkered grey no valid motion.</p>";
  for (const Html& strip : strips) s << strip;
  s << "</section>";
  return s;
}

// One histogram's plot, with notes on its variant and the values it could not bin.
Html HistogramPlot(const Histogram& h, const std::string& metadata_variant) {
  Html s;
  s << "<div class=\"plot\" id=\"dist-" << h.id << "\"><h3>" << h.title << "</h3>"
    << HistogramSvg(h);
  if (h.id.rfind("metadata-", 0) == 0) {
    s << "<p class=\"note\">variant " << metadata_variant << "</p>";
  }
  if (h.invalid > 0) {
    s << "<p class=\"note\">" << h.invalid << " " << h.counted << " without a value";
    if (h.id == "class") {
      s << " (class id not in the class table)";
    } else if (h.id == "altitude" || h.id == "gsd") {
      s << " (sky at the image centre)";
    }
    s << "</p>";
  }
  s << "</div>";
  return s;
}

Html DistributionsSection(const Distributions& d) {
  Html s;
  s << "<section id=\"distributions\"><h2>Distributions</h2><p "
       "class=\"help\">Counts over all "
    << d.frames
    << " selected frames (not only the contact sheet). Red bars: boxes under 8 "
       "px, or values outside the bins. Hover a bar for its range and "
       "count.</p><div class=\"plots\">";
  for (const Histogram& h : d.histograms) {
    if (h.total() == 0) continue;  // e.g. no sun elevation in the scene state
    s << HistogramPlot(h, d.metadata_variant);
  }
  s << "</div></section>";
  return s;
}

}  // namespace

// Every string of the page that is not a literal comes from an input (the folder name,
// collection.json, metadata.json, the validation report, the bundle statistics, the
// evaluation) and is escaped by Html.
std::string RenderReportHtml(const CollectionReader& reader,
                             const ReportData& data,
                             const ReportOptions& options,
                             std::vector<std::string>* problems) {
  const CollectionHeader& header = reader.header();
  const std::set<size_t> layer_samples = LayerSamples(data.samples.size(), options.layer_frames);
  const SampleViews views = DrawSamples(reader, data, options, layer_samples, problems);
  std::set<int64_t> on_sheet;
  for (const SampledFrame& s : data.samples) on_sheet.insert(s.frame.index);

  Html s = PageHeader(reader, data, options, !layer_samples.empty());
  if (options.validation) s << ValidationSection(*options.validation, on_sheet);
  s << ContactSheet(header, views.cards);
  if (!layer_samples.empty()) s << LayersSection(layer_samples.size(), views.strips);
  s << DistributionsSection(data.distributions);
  if (!options.bundle_stats.is_null()) {
    s << BundleStatsSection(options.bundle_stats, header);
  }
  if (!options.evaluation.is_null()) s << EvaluationSection(options.evaluation);
  s << "<div id=\"overlay\" hidden><div class=\"panel\"><button "
       "id=\"close\">close</button><div id=\"overlay-body\"></div></div></div>";
  s << "<footer>Written by lsds report. How to read this page: docs/report.md."
       "</footer><script>"
    << PageScript() << "</script></body></html>\n";
  return s.str();
}

ReportResult WriteReport(const ReportOptions& options) {
  CheckCollectionFolder(options.collection);
  if (options.output.empty()) throw Error("no output file", Location("-o"));
  // The page must not land inside the collection: inputs stay untouched.
  const fs::path root = fs::weakly_canonical(options.collection);
  const fs::path out = fs::weakly_canonical(options.output);
  const auto mismatch = std::mismatch(root.begin(), root.end(), out.begin(), out.end());
  if (mismatch.first == root.end()) {
    throw Error("the output lies inside the input collection " + options.collection.string(),
                Location(options.output.string()));
  }
  if (fs::is_directory(options.output)) {
    throw Error("is a folder; expected an .html file path", Location(options.output.string()));
  }
  RefuseToOverwrite(options.output, options.force, "report");
  const CollectionReader reader(options.collection);
  const ReportData data = CollectReportData(
      reader,
      options,
      options.validation ? FramesWithFindings(*options.validation, 12) : std::set<int64_t>());
  ReportResult result;
  const std::string html = RenderReportHtml(reader, data, options, &result.unshown);
  WriteFileAtomic(options.output, html);
  result.frames = data.distributions.frames;
  result.sampled = data.samples.size();
  result.bytes = html.size();
  return result;
}

}  // namespace lsds::report

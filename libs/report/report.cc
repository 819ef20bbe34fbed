#include "libs/report/report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include <tbb/parallel_for.h>
#include <opencv2/imgproc.hpp>

#include "libs/bundle/bundle_stats.h"
#include "libs/bundle/mixed_map.h"
#include "libs/exr/deep_image.h"
#include "libs/report/bundle_section.h"
#include "libs/report/draw.h"
#include "libs/report/frame_sampler.h"
#include "libs/report/html.h"
#include "libs/report/layer_images.h"
#include "libs/report/page_style.h"
#include "libs/report/svg_plot.h"
#include "libs/util/atomic_file.h"
#include "libs/util/error.h"
#include "libs/util/progress.h"

namespace lsds::report {

namespace {

namespace fs = std::filesystem;

std::string Fixed(double value, int digits) {
  if (!std::isfinite(value)) return "n/a";
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.*f", digits, value);
  return buffer;
}

// "12.3 m", or "n/a" when there is no value.
std::string WithUnit(double value, int digits, const std::string& unit) {
  return std::isfinite(value) ? Fixed(value, digits) + unit : "n/a";
}

bool HasFile(const Frame& frame, const LayerInfo* layer) {
  return layer != nullptr && frame.files.count(layer->name) > 0;
}

FrameCamera CameraOf(const CollectionReader& reader, const Frame& frame) {
  const CollectionHeader& header = reader.header();
  const LayerInfo* depth = header.FindLayerBySemantic("depth");
  if (HasFile(frame, depth) && !depth->deep) {
    try {
      const exr::FlatImage z =
          exr::ReadFlatExr(reader.LayerPath(frame, depth->name), {"Z"});
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

cv::Mat Resized(const cv::Mat& image, int width, bool smooth) {
  if (image.cols <= width) return image;
  const int height = std::max(
      1,
      static_cast<int>(std::lround(double(image.rows) * width / image.cols)));
  cv::Mat out;
  cv::resize(image,
             out,
             cv::Size(width, height),
             0,
             0,
             smooth ? cv::INTER_AREA : cv::INTER_NEAREST);
  return out;
}

// The frame's colour image, or a grey placeholder when it has none.
cv::Mat DisplayImage(const CollectionReader& reader,
                     const Frame& frame,
                     const ReportOptions& options) {
  const LayerInfo* rgb = reader.header().FindLayerBySemantic("rgb");
  if (HasFile(frame, rgb)) {
    return imaging::ToSrgb8(
        exr::ReadFlatExr(reader.LayerPath(frame, rgb->name), {"R", "G", "B"}),
        options.display);
  }
  return cv::Mat(std::max(1, frame.camera.intrinsics.height),
                 std::max(1, frame.camera.intrinsics.width),
                 CV_8UC3,
                 cv::Scalar(80, 80, 80));
}

std::string ClassList(const CollectionHeader& header, const Frame& frame) {
  std::set<std::string> names;
  for (const ObjectTruth& object : frame.objects) {
    if (object.visible_pixels <= 0) continue;
    const ClassInfo* c = header.FindClass(object.class_id);
    names.insert(c ? c->name : "class-" + std::to_string(object.class_id));
  }
  std::string out;
  for (const std::string& name : names) {
    out += (out.empty() ? "" : " ") + name;
  }
  return out;
}

std::string SceneLine(const Frame& frame) {
  const nlohmann::json& scene = frame.scene;
  if (!scene.is_object()) return "";
  std::string out;
  if (scene.contains("sun") && scene["sun"].is_object()) {
    const nlohmann::json& sun = scene["sun"];
    if (sun.value("elevation_deg", nlohmann::json()).is_number()) {
      out += "sun " + Fixed(sun["elevation_deg"].get<double>(), 0) + "&deg; up";
      if (sun.value("azimuth_deg", nlohmann::json()).is_number()) {
        out += ", az " + Fixed(sun["azimuth_deg"].get<double>(), 0) + "&deg;";
      }
    }
  }
  if (scene.contains("atmosphere") && scene["atmosphere"].is_object() &&
      scene["atmosphere"].value("visibility_m", nlohmann::json()).is_number()) {
    out += (out.empty() ? "" : " &middot; ") + std::string("visibility ") +
           Fixed(scene["atmosphere"]["visibility_m"].get<double>(), 0) + " m";
  }
  if (scene.contains("sky") && scene["sky"].is_object() &&
      scene["sky"].value("cloud_type", nlohmann::json()).is_string()) {
    out += (out.empty() ? "" : " &middot; ") +
           HtmlEscape(scene["sky"]["cloud_type"].get<std::string>());
  }
  return out;
}

std::string ObjectsTable(const CollectionHeader& header,
                         const SampledFrame& sample) {
  std::ostringstream s;
  s << "<table class=\"objects\"><tr><th>instance</th><th>class</th>"
       "<th>name</th><th>box (px)</th><th>visible px</th><th>visibility</th>"
       "<th>in frame</th><th>distance (m)</th></tr>";
  for (const ObjectTruth& o : sample.frame.objects) {
    const ClassInfo* c = header.FindClass(o.class_id);
    s << "<tr><td>" << o.instance_id << "</td><td>"
      << HtmlEscape(c ? c->name : std::to_string(o.class_id)) << "</td><td>"
      << HtmlEscape(o.name) << "</td><td>";
    if (o.bbox) {
      s << Fixed(o.bbox->x0, 0) << ", " << Fixed(o.bbox->y0, 0) << " &ndash; "
        << Fixed(o.bbox->x1, 0) << ", " << Fixed(o.bbox->y1, 0);
    } else {
      s << "&ndash;";
    }
    s << "</td><td>" << o.visible_pixels << "</td><td>"
      << Fixed(o.visibility, 2) << "</td><td>" << Fixed(o.in_frame, 2)
      << "</td><td>" << Fixed(ObjectDistanceM(header, sample.camera, o), 1)
      << "</td></tr>";
  }
  s << "</table>";
  return s.str();
}

std::string Figure(const std::string& uri,
                   const cv::Size& size,
                   const std::string& caption) {
  std::ostringstream s;
  s << "<figure><img src=\"" << uri << "\" width=\"" << size.width
    << "\" height=\"" << size.height << "\" alt=\"\"><figcaption>" << caption
    << "</figcaption></figure>";
  return s.str();
}

std::string Failed(const std::string& layer, const std::string& message) {
  return "<figure class=\"failed\"><div>cannot show " + HtmlEscape(layer) +
         ": " + HtmlEscape(message) + "</div><figcaption>" + HtmlEscape(layer) +
         "</figcaption></figure>";
}

// Every displayable layer of one frame, side by side.
std::string LayerStrip(const CollectionReader& reader,
                       const SampledFrame& sample,
                       const ReportOptions& options) {
  const CollectionHeader& header = reader.header();
  const Frame& frame = sample.frame;
  const std::string unit = header.conventions.world.length_unit;
  std::ostringstream s;
  s << "<section class=\"layers\" id=\"layers-" << frame.index
    << "\"><h3>frame " << frame.index << "</h3><div class=\"strip\">";
  for (const LayerInfo& layer : header.layers) {
    if (!HasFile(frame, &layer)) continue;
    const std::string& sem = layer.semantic;
    const std::string title = HtmlEscape(layer.name);
    try {
      const fs::path path = reader.LayerPath(frame, layer.name);
      if (sem == "rgb") {
        const cv::Mat image = Resized(
            DisplayImage(reader, frame, options), options.layer_width, true);
        s << Figure(ImageDataUri(image, true), image.size(), title);
      } else if (sem == "classid" || sem == "instanceid") {
        const cv::Mat image =
            Resized(ColorizeIds(exr::ReadFlatExr(path, {"id"})),
                    options.layer_width,
                    false);
        s << Figure(ImageDataUri(image, false),
                    image.size(),
                    title + " (a stable colour per id)");
      } else if (sem == "depth" && !layer.deep) {
        double lo = 0, hi = 0;
        const cv::Mat image =
            Resized(ColorizeDepth(exr::ReadFlatExr(path, {"Z"}), &lo, &hi),
                    options.layer_width,
                    true);
        const cv::Mat bar = DepthScaleBar(image.cols, 10);
        s << Figure(
            ImageDataUri(image, false),
            image.size(),
            title + " (" +
                (layer.depth_kind ? DepthKindName(*layer.depth_kind) : "") +
                ")<img class=\"bar\" src=\"" + ImageDataUri(bar, false) +
                "\" width=\"" + std::to_string(bar.cols) +
                "\" height=\"10\" alt=\"\"><span class=\"range\"><span>" +
                FormatNumber(lo) + " " + HtmlEscape(unit) + "</span><span>" +
                FormatNumber(hi) + " " + HtmlEscape(unit) + "</span></span>");
      } else if (sem == "normal") {
        const cv::Mat image =
            Resized(ColorizeNormals(exr::ReadFlatExr(path, {"X", "Y", "Z"})),
                    options.layer_width,
                    false);
        s << Figure(ImageDataUri(image, false),
                    image.size(),
                    title + " (world RGB = (n + 1) / 2)");
      } else if (sem == "shadow") {
        const cv::Mat image =
            Resized(ColorizeShadow(exr::ReadFlatExr(path, {"Y"})),
                    options.layer_width,
                    true);
        s << Figure(ImageDataUri(image, false),
                    image.size(),
                    title + " (black: full shadow)");
      } else if (sem == "motion") {
        double max_px = 0;
        int64_t invalid = 0;
        const exr::FlatImage motion = exr::ReadFlatExr(path, {"X", "Y"});
        const cv::Mat image = Resized(ColorizeMotion(motion, &max_px, &invalid),
                                      options.layer_width,
                                      false);
        const double share =
            100.0 * invalid / std::max<size_t>(1, motion.pixel_count());
        s << Figure(ImageDataUri(image, false),
                    image.size(),
                    title + "<img class=\"wheel\" src=\"" +
                        ImageDataUri(FlowWheel(40), false) +
                        "\" width=\"40\" height=\"40\" alt=\"\"> max " +
                        Fixed(max_px, 1) + " px; invalid (checkered) " +
                        Fixed(share, 1) + " %");
      } else if (sem == "bundle" && layer.deep) {
        const exr::DeepImage deep = exr::ReadDeepExr(path);
        bundle::PixelMaps maps;
        const bundle::BundleStats stats =
            bundle::AnalyzeFrame(deep, bundle::StatsOptions(), &maps);
        std::vector<uint8_t> bgr =
            bundle::MixedMapBgr(maps, deep.width(), deep.height());
        const cv::Mat full(deep.height(), deep.width(), CV_8UC3, bgr.data());
        const cv::Mat image = Resized(full, options.layer_width, false);
        const double share =
            100.0 * stats.mixed_pixels / std::max<uint64_t>(1, stats.pixels);
        s << Figure(ImageDataUri(image, false),
                    image.size(),
                    title + " mixed pixels " + Fixed(share, 2) +
                        " % (yellow &rarr; red &rarr; magenta: less pure)");
      }
    } catch (const Error& e) {
      s << Failed(layer.name, e.what());
    } catch (const cv::Exception& e) {
      s << Failed(layer.name, e.what());
    }
  }
  s << "</div></section>";
  return s.str();
}

std::string Card(const CollectionReader& reader,
                 const SampledFrame& sample,
                 bool has_layers,
                 const ReportOptions& options) {
  const CollectionHeader& header = reader.header();
  const Frame& frame = sample.frame;
  std::ostringstream s;
  s << "<figure class=\"card\" id=\"frame-" << frame.index << "\" data-frame=\""
    << frame.index << "\" data-classes=\""
    << HtmlEscape(ClassList(header, frame)) << "\">";
  try {
    cv::Mat image = DisplayImage(reader, frame, options);
    const double scale = image.cols > options.thumb_width
                             ? double(options.thumb_width) / image.cols
                             : 1.0;
    image = Resized(image, options.thumb_width, true);
    std::optional<exr::FlatImage> ids;
    const LayerInfo* instance = header.FindLayerBySemantic("instanceid");
    if (HasFile(frame, instance)) {
      ids = exr::ReadFlatExr(reader.LayerPath(frame, instance->name), {"id"});
    }
    AnnotateOptions annotate;
    annotate.scale = scale;
    DrawAnnotations(&image, header, frame, ids ? &*ids : nullptr, annotate);
    s << "<img src=\"" << ImageDataUri(image, true) << "\" width=\""
      << image.cols << "\" height=\"" << image.rows << "\" alt=\"frame "
      << frame.index << "\">";
  } catch (const Error& e) {
    s << "<div class=\"failed\">" << HtmlEscape(e.what()) << "</div>";
  }
  int visible = 0;
  for (const ObjectTruth& o : frame.objects) visible += o.visible_pixels > 0;
  const FrameCamera& c = sample.camera;
  s << "<figcaption><b>frame " << frame.index << "</b> t "
    << Fixed(frame.time, 2) << " s"
    << (frame.sequence.empty() ? "" : " &middot; " + HtmlEscape(frame.sequence))
    << (has_layers ? " <span class=\"tag\">layers</span>" : "") << "<br>alt "
    << WithUnit(c.altitude_m, 1, " m") << " &middot; off-nadir "
    << WithUnit(c.off_nadir_deg, 1, "&deg;") << " &middot; GSD "
    << WithUnit(c.gsd_m * 100, 2, " cm/px") << "<br>" << visible
    << " visible of " << frame.objects.size() << " objects";
  const std::string scene = SceneLine(frame);
  if (!scene.empty()) s << "<br>" << scene;
  s << "</figcaption><div class=\"detail\" hidden>"
    << ObjectsTable(header, sample) << "</div></figure>";
  return s.str();
}

std::string ValidationSection(const nlohmann::json& v,
                              const std::set<int64_t>& on_sheet) {
  std::ostringstream s;
  const std::string verdict = v.value("verdict", "");
  s << "<section id=\"validation\"><h2>Validation</h2><p class=\"verdict "
    << HtmlEscape(verdict) << "\">" << HtmlEscape(verdict) << " (fail on "
    << HtmlEscape(v.value("fail_on", "")) << "): ";
  if (v.contains("counts") && v["counts"].is_object()) {
    s << v["counts"].value("error", 0) << " errors, "
      << v["counts"].value("warning", 0) << " warnings, "
      << v["counts"].value("info", 0) << " notes";
  }
  s << " over " << v.value("frames", 0) << " frames</p>";
  s << "<table class=\"findings\"><tr><th>check</th><th>severity</th>"
       "<th>count</th><th>where</th><th>what</th></tr>";
  bool any = false;
  if (v.contains("checks") && v["checks"].is_array()) {
    for (const nlohmann::json& check : v["checks"]) {
      const int64_t count = check.value("count", int64_t{0});
      if (count == 0) continue;
      any = true;
      const nlohmann::json findings =
          check.value("findings", nlohmann::json::array());
      s << "<tr class=\"" << HtmlEscape(check.value("severity", ""))
        << "\"><td>" << HtmlEscape(check.value("id", "")) << "</td><td>"
        << HtmlEscape(check.value("severity", "")) << "</td><td>" << count
        << "</td><td colspan=\"2\">"
        << (findings.size() < size_t(count)
                ? "the first " + std::to_string(findings.size()) + " listed"
                : "")
        << "</td></tr>";
      for (const nlohmann::json& f : findings) {
        const nlohmann::json location =
            f.value("location", nlohmann::json::object());
        std::string where = HtmlEscape(location.value("file", ""));
        if (location.contains("json_pointer")) {
          where +=
              "#" + HtmlEscape(location["json_pointer"].get<std::string>());
        }
        if (location.contains("frame") &&
            location["frame"].is_number_integer()) {
          const int64_t frame = location["frame"].get<int64_t>();
          const std::string label = "frame " + std::to_string(frame);
          where += " " + (on_sheet.count(frame)
                              ? "<a href=\"#frame-" + std::to_string(frame) +
                                    "\" data-goto=\"" + std::to_string(frame) +
                                    "\">" + label + "</a>"
                              : label);
        }
        if (location.contains("pixel") && location["pixel"].is_array() &&
            location["pixel"].size() == 2) {
          where += " pixel (" + location["pixel"][0].dump() + ", " +
                   location["pixel"][1].dump() + ")";
        }
        s << "<tr class=\"finding\"><td></td><td>"
          << HtmlEscape(f.value("severity", "")) << "</td><td></td><td>"
          << where << "</td><td>"
          << HtmlEscape((f.contains("object")
                             ? f["object"].get<std::string>() + ": "
                             : std::string()) +
                        f.value("message", ""))
          << "</td></tr>";
      }
    }
  }
  if (!any) s << "<tr><td colspan=\"5\">no findings</td></tr>";
  s << "</table></section>";
  return s.str();
}

}  // namespace

std::set<int64_t> FramesWithFindings(const nlohmann::json& validation,
                                     size_t max) {
  std::set<int64_t> frames;
  if (!validation.is_object() || !validation.contains("checks") ||
      !validation["checks"].is_array()) {
    return frames;
  }
  for (const nlohmann::json& check : validation["checks"]) {
    if (!check.is_object() || !check.contains("findings")) continue;
    for (const nlohmann::json& f : check["findings"]) {
      if (frames.size() >= max) return frames;
      if (f.is_object() && f.contains("location") &&
          f["location"].is_object() && f["location"].contains("frame") &&
          f["location"]["frame"].is_number_integer()) {
        frames.insert(f["location"]["frame"].get<int64_t>());
      }
    }
  }
  return frames;
}

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
    tbb::parallel_for(size_t{0}, batch.size(), [&](size_t i) {
      cameras[i] = CameraOf(reader, batch[i]);
    });
    for (size_t i = 0; i < batch.size(); ++i) {
      AddFrame(header, batch[i], cameras[i], &data.distributions);
      sampler.Offer(batch[i].index, SampledFrame{batch[i], cameras[i]});
    }
    progress.Add(static_cast<int64_t>(batch.size()));
    batch.clear();
  };
  reader.ForEachFrame([&](const Frame& frame) {
    if (frame.index < options.frame_begin || frame.index >= options.frame_end) {
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
      if (frame.index < options.frame_begin || frame.index >= options.frame_end)
        return;
      AddMetadataError(frame, &data.distributions);
    });
    data.distributions.metadata_variant = variant.file;
    break;
  }
  return data;
}

std::string RenderReportHtml(const CollectionReader& reader,
                             const ReportData& data,
                             const ReportOptions& options) {
  const CollectionHeader& header = reader.header();
  const size_t n = data.samples.size();
  // The frames shown with every layer: spread evenly over the sample.
  std::set<size_t> layer_samples;
  const size_t k = std::min(options.layer_frames, n);
  for (size_t i = 0; i < k; ++i)
    layer_samples.insert((2 * i + 1) * n / (2 * k));
  std::vector<std::string> cards(n), strips(n);
  tbb::parallel_for(size_t{0}, n, [&](size_t i) {
    const bool layers = layer_samples.count(i) > 0;
    cards[i] = Card(reader, data.samples[i], layers, options);
    if (layers) strips[i] = LayerStrip(reader, data.samples[i], options);
  });
  std::set<int64_t> on_sheet;
  for (const SampledFrame& s : data.samples) on_sheet.insert(s.frame.index);

  const Distributions& d = data.distributions;
  const std::string name =
      fs::absolute(reader.root()).lexically_normal().filename().string();
  std::ostringstream s;
  s << "<!DOCTYPE html><html lang=\"en\"><head><meta charset=\"utf-8\">"
    << "<title>lsds report: " << HtmlEscape(name) << "</title><style>"
    << PageStyle() << "</style></head><body>"
    << "<script>window.onerror=function(m){document.body.setAttribute("
       "'data-js-error',String(m));};</script>"
    << "<header><h1>lsds report: " << HtmlEscape(name) << "</h1><p>" << d.frames
    << " frames";
  if (reader.frames_in_file() != static_cast<size_t>(d.frames)) {
    s << " selected of " << reader.frames_in_file();
  }
  s << " &middot; " << n << " on the contact sheet &middot; " << d.objects
    << " objects listed, " << d.visible_objects << " visible &middot; "
    << header.classes.size() << " classes &middot; " << header.layers.size()
    << " layers &middot; world " << HtmlEscape(header.conventions.world.name)
    << ", " << HtmlEscape(header.conventions.world.length_unit)
    << " &middot; format " << HtmlEscape(header.format_version) << " &middot; "
    << HtmlEscape(header.provenance.generator) << " "
    << HtmlEscape(header.provenance.generator_version) << "</p>"
    << "<nav><a href=\"#sheet\">contact sheet</a> "
    << (layer_samples.empty() ? "" : "<a href=\"#layers\">layers</a> ")
    << "<a href=\"#distributions\">distributions</a>"
    << (options.validation.is_object()
            ? " <a href=\"#validation\">validation</a>"
            : "")
    << (options.bundle_stats.is_null()
            ? ""
            : " <a href=\"#bundles\">mixed pixels</a>")
    << "</nav></header>";

  if (options.validation.is_object()) {
    s << ValidationSection(options.validation, on_sheet);
  }

  s << "<section id=\"sheet\"><h2>Contact sheet</h2><p class=\"help\">Tight "
       "boxes in the class colour, mask outlines in the instance colour. Click "
       "a frame for its objects (and layers when tagged).</p><div "
       "class=\"filter\">show classes: ";
  for (const ClassInfo& c : header.classes) {
    const cv::Vec3b col = ClassColor(c.id);
    char swatch[16];
    std::snprintf(
        swatch, sizeof(swatch), "#%02x%02x%02x", col[2], col[1], col[0]);
    s << "<label><input type=\"checkbox\" checked data-class=\""
      << HtmlEscape(c.name)
      << "\"><span class=\"swatch\" style=\"background:" << swatch
      << "\"></span>" << HtmlEscape(c.name) << "</label>";
  }
  s << "<label><input type=\"checkbox\" checked data-class=\"\">frames with no "
       "visible object</label></div><div class=\"sheet\">";
  for (const std::string& card : cards) s << card;
  s << "</div></section>";

  if (!layer_samples.empty()) {
    s << "<section id=\"layers\"><h2>Layers</h2><p class=\"help\">Every layer "
         "of "
      << layer_samples.size()
      << " frames side by side. Ids: one colour per id, black background. "
         "Depth: "
         "turbo colour map from near (blue) to far (red), sky dark grey. "
         "Motion: "
         "hue is the direction (wheel), saturation the speed, white no motion, "
         "checkered grey no valid motion.</p>";
    for (const std::string& strip : strips) s << strip;
    s << "</section>";
  }

  s << "<section id=\"distributions\"><h2>Distributions</h2><p "
       "class=\"help\">Counts over all "
    << d.frames
    << " selected frames (not only the contact sheet). Red bars: boxes under 8 "
       "px, or values outside the bins. Hover a bar for its range and "
       "count.</p><div class=\"plots\">";
  for (const Histogram& h : d.histograms) {
    if (h.total() == 0) continue;  // e.g. no sun elevation in the scene state
    s << "<div class=\"plot\" id=\"dist-" << HtmlEscape(h.id) << "\"><h3>"
      << HtmlEscape(h.title) << "</h3>" << HistogramSvg(h);
    if (h.id.rfind("metadata-", 0) == 0) {
      s << "<p class=\"note\">variant " << HtmlEscape(d.metadata_variant)
        << "</p>";
    }
    if (h.invalid > 0) {
      s << "<p class=\"note\">" << h.invalid << " " << HtmlEscape(h.counted)
        << " without a value"
        << (h.id == "class" ? " (class id not in the class table)"
                            : (h.id == "altitude" || h.id == "gsd"
                                   ? " (sky at the image centre)"
                                   : ""))
        << "</p>";
    }
    s << "</div>";
  }
  s << "</div></section>";
  if (!options.bundle_stats.is_null()) {
    s << BundleStatsSection(options.bundle_stats, header);
  }
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
  const auto mismatch =
      std::mismatch(root.begin(), root.end(), out.begin(), out.end());
  if (mismatch.first == root.end()) {
    throw Error("the output lies inside the input collection " +
                    options.collection.string(),
                Location(options.output.string()));
  }
  if (fs::is_directory(options.output)) {
    throw Error("is a folder; expected an .html file path",
                Location(options.output.string()));
  }
  RefuseToOverwrite(options.output, options.force, "report");
  const CollectionReader reader(options.collection);
  const ReportData data = CollectReportData(
      reader, options, FramesWithFindings(options.validation, 12));
  const std::string html = RenderReportHtml(reader, data, options);
  WriteFileAtomic(options.output, html);
  return {data.distributions.frames, data.samples.size(), html.size()};
}

}  // namespace lsds::report

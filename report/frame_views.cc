#include "report/frame_views.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <set>

#include <opencv2/imgproc.hpp>

#include "bundles/bundle_stats.h"
#include "bundles/mixed_map.h"
#include "libs/exr/deep_image.h"
#include "libs/util/error.h"
#include "libs/util/strings.h"
#include "report/draw.h"
#include "report/html.h"
#include "report/layer_images.h"
#include "report/svg_plot.h"

namespace lsds::report {

std::string Fixed(double value, int digits) {
  if (!std::isfinite(value)) return "n/a";
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.*f", digits, value);
  return buffer;
}

// "12.3 m", or "n/a" when there is no value.
namespace {

std::string WithUnit(double value, int digits, const std::string& unit) {
  return std::isfinite(value) ? Fixed(value, digits) + unit : "n/a";
}

}  // namespace

bool HasFile(const Frame& frame, const LayerInfo* layer) {
  return layer != nullptr && frame.files.count(layer->name) > 0;
}

namespace {

cv::Mat Resized(const cv::Mat& image, int width, bool smooth) {
  if (image.cols <= width) return image;
  const int height =
      std::max(1, static_cast<int>(std::lround(double(image.rows) * width / image.cols)));
  cv::Mat out;
  cv::resize(
      image, out, cv::Size(width, height), 0, 0, smooth ? cv::INTER_AREA : cv::INTER_NEAREST);
  return out;
}

// The frame's colour image, or a grey placeholder when it has none.
cv::Mat DisplayImage(const CollectionReader& reader,
                     const Frame& frame,
                     const ReportOptions& options) {
  const LayerInfo* rgb = reader.header().FindLayerBySemantic("rgb");
  if (HasFile(frame, rgb)) {
    return imaging::ToSrgb8(reader.ReadFlatLayer(frame, rgb->name, {"R", "G", "B"}),
                            options.display);
  }
  return cv::Mat(std::max(1, frame.camera.intrinsics.height),
                 std::max(1, frame.camera.intrinsics.width),
                 CV_8UC3,
                 cv::Scalar(80, 80, 80));
}

// The classes of the frame's visible objects as "c2 c3" (by id, so that any
// class name is safe in the attribute), for the contact sheet filter.
std::string ClassList(const Frame& frame) {
  std::set<uint32_t> ids;
  for (const ObjectTruth& object : frame.objects) {
    if (object.visible_pixels > 0) ids.insert(object.class_id);
  }
  std::string out;
  for (uint32_t id : ids) {
    out += (out.empty() ? "c" : " c") + std::to_string(id);
  }
  return out;
}

// The frame's scene state and exposure; numbers only where numbers are
// expected, names (exposure mode, cloud type) as escaped text.
Html SceneLine(const Frame& frame) {
  const nlohmann::json& scene = frame.scene;
  if (!scene.is_object()) return {};
  Html out;
  const auto next = [&]() -> Html& {
    if (!out.empty()) out << " &middot; ";
    return out;
  };
  if (scene.contains("sun") && scene["sun"].is_object()) {
    const nlohmann::json& sun = scene["sun"];
    if (sun.value("elevation_deg", nlohmann::json()).is_number()) {
      next() << "sun " << Fixed(sun["elevation_deg"].get<double>(), 0) << "&deg; up";
      if (sun.value("azimuth_deg", nlohmann::json()).is_number()) {
        out << ", az " << Fixed(sun["azimuth_deg"].get<double>(), 0) << "&deg;";
      }
    }
    if (sun.value("illuminance_lux", nlohmann::json()).is_number()) {
      out << ", " << Fixed(sun["illuminance_lux"].get<double>(), 0) << " lx";
    }
  }
  // The camera's exposure (docs/format.md, "Exposure").
  if (frame.exposure.is_object() && frame.exposure.value("ev100", nlohmann::json()).is_number()) {
    const nlohmann::json mode = frame.exposure.value("mode", nlohmann::json());
    next() << "EV100 " << Fixed(frame.exposure["ev100"].get<double>(), 1) << " ("
           << (mode.is_string() ? mode.get<std::string>() : std::string("?")) << ")";
  }
  if (scene.contains("atmosphere") && scene["atmosphere"].is_object() &&
      scene["atmosphere"].value("visibility_m", nlohmann::json()).is_number()) {
    next() << "visibility " << Fixed(scene["atmosphere"]["visibility_m"].get<double>(), 0) << " m";
  }
  if (scene.contains("sky") && scene["sky"].is_object() &&
      scene["sky"].value("cloud_type", nlohmann::json()).is_string()) {
    next() << scene["sky"]["cloud_type"].get<std::string>();
  }
  return out;
}

Html ObjectsTable(const CollectionHeader& header, const SampledFrame& sample) {
  Html s;
  s << "<table class=\"objects\"><tr><th>instance</th><th>class</th>"
       "<th>name</th><th>box (px)</th><th>visible px</th><th>visibility</th>"
       "<th>in frame</th><th>distance (m)</th></tr>";
  for (const ObjectTruth& o : sample.frame.objects) {
    const ClassInfo* c = header.FindClass(o.class_id);
    s << "<tr><td>" << o.instance_id << "</td><td>" << (c ? c->name : std::to_string(o.class_id))
      << "</td><td>" << o.name << "</td><td>";
    if (o.bbox) {
      s << Fixed(o.bbox->x0, 0) << ", " << Fixed(o.bbox->y0, 0) << " &ndash; "
        << Fixed(o.bbox->x1, 0) << ", " << Fixed(o.bbox->y1, 0);
    } else {
      s << "&ndash;";
    }
    s << "</td><td>" << o.visible_pixels << "</td><td>" << Fixed(o.visibility, 2) << "</td><td>"
      << Fixed(o.in_frame, 2) << "</td><td>" << Fixed(ObjectDistanceM(header, sample.camera, o), 1)
      << "</td></tr>";
  }
  s << "</table>";
  return s;
}

Html Figure(const std::string& uri, const cv::Size& size, const Html& caption) {
  Html s;
  s << "<figure><img src=\"" << uri << "\" width=\"" << size.width << "\" height=\"" << size.height
    << "\" alt=\"\"><figcaption>" << caption << "</figcaption></figure>";
  return s;
}

Html Failed(const std::string& layer, const std::string& message) {
  Html s;
  s << "<figure class=\"failed\"><div>cannot show " << layer << ": " << message
    << "</div><figcaption>" << layer << "</figcaption></figure>";
  return s;
}

// Every displayable layer of one frame, side by side.
}  // namespace

Html LayerStrip(const CollectionReader& reader,
                const SampledFrame& sample,
                const ReportOptions& options,
                std::vector<std::string>* problems) {
  const CollectionHeader& header = reader.header();
  const Frame& frame = sample.frame;
  const std::string unit = header.conventions.world.length_unit;
  Html s;
  s << "<section class=\"layers\" id=\"layers-" << frame.index << "\"><h3>frame " << frame.index
    << "</h3><div class=\"strip\">";
  for (const LayerInfo& layer : header.layers) {
    if (!HasFile(frame, &layer)) continue;
    const std::string& sem = layer.semantic;
    // The caption starts with the layer's name, as text.
    Html title = Html::Text(layer.name);
    try {
      if (sem == "rgb") {
        const cv::Mat image =
            Resized(DisplayImage(reader, frame, options), options.layer_width, true);
        s << Figure(ImageDataUri(image, true), image.size(), title);
      } else if (sem == "classid" || sem == "instanceid") {
        const cv::Mat image = Resized(ColorizeIds(reader.ReadFlatLayer(frame, layer.name, {"id"})),
                                      options.layer_width,
                                      false);
        s << Figure(ImageDataUri(image, false), image.size(), title << " (a stable colour per id)");
      } else if (sem == "depth" && !layer.deep) {
        double lo = 0, hi = 0;
        const cv::Mat image =
            Resized(ColorizeDepth(reader.ReadFlatLayer(frame, layer.name, {"Z"}), &lo, &hi),
                    options.layer_width,
                    true);
        const cv::Mat bar = DepthScaleBar(image.cols, 10);
        title << " (" << (layer.depth_kind ? DepthKindName(*layer.depth_kind) : std::string())
              << ")<img class=\"bar\" src=\"" << ImageDataUri(bar, false) << "\" width=\""
              << bar.cols << "\" height=\"10\" alt=\"\"><span class=\"range\"><span>"
              << FormatAxisNumber(lo) << " " << unit << "</span><span>" << FormatAxisNumber(hi)
              << " " << unit << "</span></span>";
        s << Figure(ImageDataUri(image, false), image.size(), title);
      } else if (sem == "normal") {
        const cv::Mat image =
            Resized(ColorizeNormals(reader.ReadFlatLayer(frame, layer.name, {"X", "Y", "Z"})),
                    options.layer_width,
                    false);
        s << Figure(
            ImageDataUri(image, false), image.size(), title << " (world RGB = (n + 1) / 2)");
      } else if (sem == "shadow") {
        const cv::Mat image =
            Resized(ColorizeShadow(reader.ReadFlatLayer(frame, layer.name, {"Y"})),
                    options.layer_width,
                    true);
        s << Figure(ImageDataUri(image, false), image.size(), title << " (black: full shadow)");
      } else if (sem == "motion") {
        double max_px = 0;
        int64_t invalid = 0;
        const exr::FlatImage motion = reader.ReadFlatLayer(frame, layer.name, {"X", "Y"});
        const cv::Mat image =
            Resized(ColorizeMotion(motion, &max_px, &invalid), options.layer_width, false);
        const double share = 100.0 * invalid / std::max<size_t>(1, motion.pixel_count());
        title << "<img class=\"wheel\" src=\"" << ImageDataUri(FlowWheel(40), false)
              << "\" width=\"40\" height=\"40\" alt=\"\"> max " << Fixed(max_px, 1)
              << " px; invalid (checkered) " << Fixed(share, 1) << " %";
        s << Figure(ImageDataUri(image, false), image.size(), title);
      } else if (sem == "bundle" && layer.deep) {
        const exr::DeepImage deep = reader.ReadDeepLayer(frame, layer.name, {});
        bundle::PixelMaps maps;
        const bundle::BundleStats stats = bundle::AnalyzeFrame(deep, bundle::StatsOptions(), &maps);
        std::vector<uint8_t> bgr = bundle::MixedMapBgr(maps, deep.width(), deep.height());
        const cv::Mat full(deep.height(), deep.width(), CV_8UC3, bgr.data());
        const cv::Mat image = Resized(full, options.layer_width, false);
        const double share = 100.0 * stats.mixed_pixels / std::max<uint64_t>(1, stats.pixels);
        title << " mixed pixels " << Fixed(share, 2)
              << " % (yellow &rarr; red &rarr; magenta: less pure)";
        s << Figure(ImageDataUri(image, false), image.size(), title);
      }
    } catch (const Error& e) {
      s << Failed(layer.name, e.what());
      problems->push_back(layer.name + " of frame " + std::to_string(frame.index) + ": " +
                          e.what());
    } catch (const cv::Exception& e) {
      s << Failed(layer.name, e.what());
      problems->push_back(layer.name + " of frame " + std::to_string(frame.index) + ": " +
                          e.what());
    }
  }
  s << "</div></section>";
  return s;
}

Html FrameCard(const CollectionReader& reader,
               const SampledFrame& sample,
               bool has_layers,
               const ReportOptions& options,
               std::vector<std::string>* problems) {
  const CollectionHeader& header = reader.header();
  const Frame& frame = sample.frame;
  Html s;
  s << "<figure class=\"card\" id=\"frame-" << frame.index << "\" data-frame=\"" << frame.index
    << "\" data-classes=\"" << ClassList(frame) << "\">";
  try {
    cv::Mat image = DisplayImage(reader, frame, options);
    const double scale =
        image.cols > options.thumb_width ? double(options.thumb_width) / image.cols : 1.0;
    image = Resized(image, options.thumb_width, true);
    std::optional<exr::FlatImage> ids;
    const LayerInfo* instance = header.FindLayerBySemantic("instanceid");
    if (HasFile(frame, instance)) {
      ids = reader.ReadFlatLayer(frame, instance->name, {"id"});
    }
    AnnotateOptions annotate;
    annotate.scale = scale;
    DrawAnnotations(&image, header, frame, ids ? &*ids : nullptr, annotate);
    s << "<img src=\"" << ImageDataUri(image, true) << "\" width=\"" << image.cols << "\" height=\""
      << image.rows << "\" alt=\"frame " << frame.index << "\">";
  } catch (const Error& e) {
    s << "<div class=\"failed\">" << e.what() << "</div>";
    problems->push_back("image of frame " + std::to_string(frame.index) + ": " + e.what());
  }
  int visible = 0;
  for (const ObjectTruth& o : frame.objects) visible += o.visible_pixels > 0;
  const FrameCamera& c = sample.camera;
  s << "<figcaption><b>frame " << frame.index << "</b> t " << Fixed(frame.time, 2) << " s";
  if (!frame.sequence.empty()) s << " &middot; " << frame.sequence;
  if (has_layers) s << " <span class=\"tag\">layers</span>";
  s << "<br>alt " << WithUnit(c.altitude_m, 1, " m") << " &middot; off-nadir "
    << WithUnit(c.off_nadir_deg, 1, "°") << " &middot; GSD " << WithUnit(c.gsd_m * 100, 2, " cm/px")
    << "<br>" << visible << " visible of " << frame.objects.size() << " objects";
  const Html scene = SceneLine(frame);
  if (!scene.empty()) s << "<br>" << scene;
  s << "</figcaption><div class=\"detail\" hidden>" << ObjectsTable(header, sample)
    << "</div></figure>";
  return s;
}

}  // namespace lsds::report

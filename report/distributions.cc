#include "report/distributions.h"

#include <algorithm>
#include <cmath>

#include "libs/util/error.h"

namespace lsds::report {

const Histogram& Distributions::Get(const std::string& id) const {
  for (const Histogram& h : histograms) {
    if (h.id == id) return h;
  }
  throw Error("report: no distribution '" + id + "'");
}

Histogram& Distributions::Get(const std::string& id) {
  return const_cast<Histogram&>(static_cast<const Distributions&>(*this).Get(id));
}

Distributions MakeDistributions(const CollectionHeader& header) {
  Distributions d;
  std::vector<std::string> names;
  for (const ClassInfo& c : header.classes) {
    d.class_bin[c.id] = names.size();
    names.push_back(c.name);
  }
  d.histograms.push_back(
      MakeCategorical("class", "Objects per class", "class", "visible objects", names));
  Histogram box = MakeNumeric("box-size",
                              "Object size",
                              "longer side of the tight box",
                              "px",
                              "visible objects",
                              GeometricEdges(1, 16384, 2));
  box.warn_below = 8;  // detectors rarely learn anything smaller
  d.histograms.push_back(box);
  d.histograms.push_back(MakeNumeric("visible-pixels",
                                     "Visible pixels",
                                     "pixels of the instance mask",
                                     "px",
                                     "visible objects",
                                     GeometricEdges(1, 1 << 26, 4)));
  d.histograms.push_back(MakeNumeric("visibility",
                                     "Visibility",
                                     "visible / unoccluded pixels",
                                     "",
                                     "listed objects",
                                     LinearEdges(0, 1, 0.1)));
  d.histograms.push_back(MakeNumeric("in-frame",
                                     "In-frame fraction",
                                     "share of the silhouette in the image",
                                     "",
                                     "listed objects",
                                     LinearEdges(0, 1, 0.1)));
  d.histograms.push_back(MakeNumeric("distance",
                                     "Object distance",
                                     "camera centre to OBB centre",
                                     "m",
                                     "visible objects",
                                     OneTwoFiveEdges(0.1, 100000)));
  d.histograms.push_back(MakeNumeric("altitude",
                                     "Altitude",
                                     "above the surface seen at the centre",
                                     "m",
                                     "frames",
                                     OneTwoFiveEdges(0.1, 100000)));
  d.histograms.push_back(MakeNumeric("off-nadir",
                                     "Off-nadir angle",
                                     "optical axis from straight down",
                                     "deg",
                                     "frames",
                                     LinearEdges(0, 180, 5)));
  d.histograms.push_back(MakeNumeric("gsd",
                                     "Ground sample distance",
                                     "at the image centre",
                                     "cm/px",
                                     "frames",
                                     OneTwoFiveEdges(0.01, 100000)));
  d.histograms.push_back(MakeNumeric("sun-elevation",
                                     "Sun elevation",
                                     "time of day: sun above the horizon",
                                     "deg",
                                     "frames",
                                     LinearEdges(-90, 90, 5)));
  d.histograms.push_back(MakeNumeric("metadata-position",
                                     "Metadata position error",
                                     "perturbed minus true camera position, length",
                                     "m",
                                     "frames",
                                     OneTwoFiveEdges(0.001, 1000)));
  d.histograms.push_back(MakeNumeric("metadata-rotation",
                                     "Metadata rotation error",
                                     "perturbed vs true attitude, angle",
                                     "deg",
                                     "frames",
                                     OneTwoFiveEdges(0.001, 100)));
  return d;
}

void AddFrame(const CollectionHeader& header,
              const Frame& frame,
              const FrameCamera& camera,
              Distributions* d) {
  ++d->frames;
  Histogram& classes = d->Get("class");
  Histogram& box = d->Get("box-size");
  Histogram& pixels = d->Get("visible-pixels");
  Histogram& visibility = d->Get("visibility");
  Histogram& in_frame = d->Get("in-frame");
  Histogram& distance = d->Get("distance");
  for (const ObjectTruth& object : frame.objects) {
    ++d->objects;
    visibility.Add(object.visibility);
    in_frame.Add(object.in_frame);
    if (object.visible_pixels <= 0) continue;
    ++d->visible_objects;
    const auto bin = d->class_bin.find(object.class_id);
    if (bin == d->class_bin.end()) {
      ++classes.invalid;  // a class id the table does not name
    } else {
      classes.AddCategory(bin->second);
    }
    box.Add(object.bbox ? std::max(object.bbox->width(), object.bbox->height()) : 0.0 / 0.0);
    pixels.Add(static_cast<double>(object.visible_pixels));
    distance.Add(ObjectDistanceM(header, camera, object));
  }
  d->Get("altitude").Add(camera.altitude_m);
  d->Get("off-nadir").Add(camera.off_nadir_deg);
  d->Get("gsd").Add(camera.gsd_m * 100.0);
  double sun = 0.0 / 0.0;
  if (frame.scene.is_object() && frame.scene.contains("sun") && frame.scene["sun"].is_object() &&
      frame.scene["sun"].contains("elevation_deg") &&
      frame.scene["sun"]["elevation_deg"].is_number()) {
    sun = frame.scene["sun"]["elevation_deg"].get<double>();
  }
  d->Get("sun-elevation").Add(sun);
}

void AddMetadataError(const MetadataFrame& frame, Distributions* d) {
  double position = 0.0 / 0.0, rotation = 0.0 / 0.0;
  const nlohmann::json& e = frame.error;
  if (e.is_object()) {
    if (e.contains("position_enu_m") && e["position_enu_m"].is_array() &&
        e["position_enu_m"].size() == 3) {
      const nlohmann::json& p = e["position_enu_m"];
      if (p[0].is_number() && p[1].is_number() && p[2].is_number()) {
        position =
            Eigen::Vector3d(p[0].get<double>(), p[1].get<double>(), p[2].get<double>()).norm();
      }
    }
    if (e.contains("rotation_deg") && e["rotation_deg"].is_number()) {
      rotation = e["rotation_deg"].get<double>();
    }
  }
  d->Get("metadata-position").Add(position);
  d->Get("metadata-rotation").Add(rotation);
}

}  // namespace lsds::report

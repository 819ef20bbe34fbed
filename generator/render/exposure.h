// The camera's exposure (docs/generator.md, "Physical light and camera"): the
// renderer computes photometric radiance (RGB whose relative luminance is in
// cd/m^2); the rgb layer holds it times the frame's exposure scale
//
//   scale = 2^compensation / (1.2 * 2^EV100),
//
// the ISO 12232 saturation-based sensitivity with q = 0.65, so that 1.0 is the
// luminance that saturates the sensor. Manual exposure takes EV100 from the
// LCAP csettings (`ev100`, or `shutter`, `f_number` and `iso`:
// EV100 = log2(N^2 / t) - log2(S / 100)); auto exposure meters the frame.
#pragma once

#include <nlohmann/json.hpp>

#include "generator/plan/plan.h"
#include "generator/render/film.h"

namespace lsds::gen {

struct FrameExposure {
  bool manual = false;
  double ev100 = 0;
  double iso = 100, shutter_s = 0, f_number = 8;
  double compensation_ev = 0;
  double scale = 1;           // rgb layer value per cd/m^2
  double metered_cd_m2 = -1;  // auto: the metered mean luminance; manual: -1
};

// The reflected-light meter calibration constant (ISO 2720, K = 12.5 cd s /
// m^2): a meter puts the mean luminance L at EV100 = log2(L * 100 / K).
constexpr double kMeterCalibration = 12.5;
// Auto exposure meters the mean luminance of the frame's pixels without its
// brightest kMeterIgnoredShare (the sun's disc, glints).
constexpr double kMeterIgnoredShare = 0.02;

double Ev100FromSettings(double f_number, double shutter_s, double iso);
double ScaleFromEv100(double ev100, double compensation_ev);

// The exposure of one frame: manual settings as planned, or metered on the
// linear rgb of `film` (auto).
FrameExposure MeterExposure(const PlannedExposure& planned, const Film& film);
// Multiplies the film's rgb by the exposure's scale (truth layers untouched).
void ApplyExposure(const FrameExposure& exposure, Film* film);
// The frame's `exposure` record (docs/format.md, "Exposure").
nlohmann::json ExposureJson(const FrameExposure& exposure);

}  // namespace lsds::gen

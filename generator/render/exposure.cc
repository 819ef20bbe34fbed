#include "generator/render/exposure.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace lsds::gen {
namespace {

constexpr double kDefaultIso = 100;
constexpr double kDefaultFNumber = 8;  // auto exposure: aperture priority at f/8
// A frame without light (all black) would meter to -infinity: the meter's
// range, about that of a real camera's.
constexpr double kMinEv100 = -10, kMaxEv100 = 24;

}  // namespace

double Ev100FromSettings(double f_number, double shutter_s, double iso) {
  return std::log2(f_number * f_number / shutter_s) - std::log2(iso / 100);
}

double ScaleFromEv100(double ev100, double compensation_ev) {
  return std::exp2(compensation_ev) / (1.2 * std::exp2(ev100));
}

FrameExposure MeterExposure(const PlannedExposure& planned, const Film& film) {
  FrameExposure e;
  e.manual = planned.Manual();
  e.iso = planned.iso.value_or(kDefaultIso);
  e.f_number = planned.f_number.value_or(kDefaultFNumber);
  e.compensation_ev = planned.compensation_ev;
  if (planned.ev100) {
    e.ev100 = *planned.ev100;
  } else if (planned.shutter_s) {
    e.ev100 = Ev100FromSettings(e.f_number, *planned.shutter_s, e.iso);
  } else {
    const exr::FlatImage& rgb = film.flat.at("rgb");
    const std::vector<float>& r = rgb.Get("R").floats;
    const std::vector<float>& g = rgb.Get("G").floats;
    const std::vector<float>& b = rgb.Get("B").floats;
    std::vector<float> luminance(r.size());
    for (size_t i = 0; i < r.size(); ++i) {
      const float y = 0.2126f * r[i] + 0.7152f * g[i] + 0.0722f * b[i];
      luminance[i] = std::isfinite(y) && y > 0 ? y : 0.f;
    }
    const size_t kept =
        luminance.size() - static_cast<size_t>(std::floor(kMeterIgnoredShare * luminance.size()));
    if (kept < luminance.size())
      std::nth_element(luminance.begin(), luminance.begin() + kept, luminance.end());
    double sum = 0;
    for (size_t i = 0; i < kept; ++i) sum += luminance[i];
    e.metered_cd_m2 = kept > 0 ? sum / kept : 0;
    e.ev100 =
        e.metered_cd_m2 > 0 ? std::log2(e.metered_cd_m2 * 100 / kMeterCalibration) : kMinEv100;
    e.ev100 = std::clamp(e.ev100, kMinEv100, kMaxEv100);
  }
  // The shutter time the EV100 means at this ISO and aperture.
  e.shutter_s = planned.shutter_s && !planned.ev100
                    ? *planned.shutter_s
                    : e.f_number * e.f_number / std::exp2(e.ev100 + std::log2(e.iso / 100));
  e.scale = ScaleFromEv100(e.ev100, e.compensation_ev);
  return e;
}

void ApplyExposure(const FrameExposure& exposure, Film* film) {
  exr::FlatImage& rgb = film->flat.at("rgb");
  const float scale = static_cast<float>(exposure.scale);
  for (const char* c : {"R", "G", "B"})
    for (float& v : rgb.Get(c).floats) v *= scale;
}

nlohmann::json ExposureJson(const FrameExposure& e) {
  nlohmann::json j = {{"mode", e.manual ? "manual" : "auto"},
                      {"ev100", e.ev100},
                      {"iso", e.iso},
                      {"shutter_s", e.shutter_s},
                      {"f_number", e.f_number},
                      {"compensation_ev", e.compensation_ev},
                      {"scale", e.scale}};
  if (!e.manual) j["metered_cd_m2"] = e.metered_cd_m2;
  return j;
}

}  // namespace lsds::gen

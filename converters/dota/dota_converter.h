// DOTA v1 oriented-box labels (`dota`, docs/convert.md): labelTxt/<split>/<frame>.txt
// beside the shared images/<split>/<frame>.png.
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <string>

#include <Eigen/Core>

#include "converters/converter.h"

namespace lsds::convert {

std::unique_ptr<Converter> MakeDotaConverter();

// The label line of a kept object (its oriented box set) as the DOTA
// converter writes it: the corners with 2 decimals and as read back, and
// whether it is marked difficult (under --dota-difficult-below visibility or
// --dota-difficult-size pixels). None when the converter leaves it out (a
// side under --dota-min-size). `lsds evaluate` chooses its oriented-box truth
// by this rule.
struct DotaLabel {
  std::string corners_text;  // "x1 y1 x2 y2 x3 y3 x4 y4 " (2 decimals)
  std::array<Eigen::Vector2d, 4> corners;
  bool difficult = false;
};
std::optional<DotaLabel> DotaLabelOf(const KeptObject& object, const ConvertOptions& options);

// A class name as DOTA writes its own ("small-vehicle"): lowercase ASCII, and
// every whitespace character (space, tab, ...) becomes '-', since the label
// line is split on whitespace.
std::string DotaClassName(const std::string& name);

}  // namespace lsds::convert

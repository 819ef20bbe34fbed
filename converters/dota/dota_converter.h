// DOTA v1 oriented-box labels (`dota`, docs/convert.md): labelTxt/<split>/<frame>.txt
// beside the shared images/<split>/<frame>.png.
#pragma once

#include <memory>
#include <string>

#include "converters/converter.h"

namespace lsds::convert {

std::unique_ptr<Converter> MakeDotaConverter();

// A class name as DOTA writes its own ("small-vehicle"): lowercase ASCII, and
// every whitespace character (space, tab, ...) becomes '-', since the label
// line is split on whitespace.
std::string DotaClassName(const std::string& name);

}  // namespace lsds::convert

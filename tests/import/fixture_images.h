// What the import fixtures share: the colour PNG simulators write, 8-bit sRGB
// of the analytic scene's linear rgb layer (libs/imaging, the same encoding
// `lsds convert` uses), with an opaque alpha for the RGBA writers.
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "libs/exr/flat_image.h"
#include "libs/imaging/srgb_image.h"

namespace lsds::testing {

inline cv::Mat SrgbPng(const exr::FlatImage& rgb, bool alpha) {
  imaging::DisplayOptions display;
  display.tonemap = imaging::ToneMap::kClamp;  // a simulator's PNG: no tone curve
  cv::Mat bgr = imaging::ToSrgb8(rgb, display);
  if (!alpha) return bgr;
  std::vector<cv::Mat> planes;
  cv::split(bgr, planes);
  planes.push_back(cv::Mat(bgr.rows, bgr.cols, CV_8UC1, cv::Scalar(255)));
  cv::Mat bgra;
  cv::merge(planes, bgra);
  return bgra;
}

}  // namespace lsds::testing

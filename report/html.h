// Small pieces of the self-contained HTML page: base64 data URIs (the markup
// and its escaping: html_text.h).
#pragma once

#include <string>

#include <opencv2/core.hpp>

#include "report/html_text.h"

namespace lsds::report {

std::string Base64(const std::string& bytes);
// "data:image/png;base64,..." (or image/jpeg for `jpeg`) of a BGR image.
std::string ImageDataUri(const cv::Mat& bgr, bool jpeg, int jpeg_quality = 90);

}  // namespace lsds::report

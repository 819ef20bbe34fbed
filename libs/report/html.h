// Small pieces of the self-contained HTML page: escaping, base64 data URIs.
#pragma once

#include <string>

#include <opencv2/core.hpp>

namespace lsds::report {

std::string Base64(const std::string& bytes);
// "data:image/png;base64,..." (or image/jpeg for `jpeg`) of a BGR image.
std::string ImageDataUri(const cv::Mat& bgr, bool jpeg, int jpeg_quality = 90);
// Text escaped for HTML content and attribute values.
std::string HtmlEscape(const std::string& text);

}  // namespace lsds::report

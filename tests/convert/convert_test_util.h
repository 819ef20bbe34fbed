// Shared pieces of the convert tests: temporary folders, synthetic collections,
// output parsing.
#pragma once

#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "converters/convert.h"
#include "libs/collection/collection_reader.h"
#include "libs/exr/flat_image.h"
#include "libs/util/strings.h"
#include "synth/synthetic_collection.h"
#include "tests/test_util.h"

namespace lsds::testing {

namespace fs = std::filesystem;

// TempDir: tests/test_util.h.

inline std::string ReadText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The instance mask of `instance_id` in `frame` of a collection, from its
// instanceid EXR.
inline cv::Mat InstanceMask(const fs::path& collection, const Frame& frame, uint32_t instance_id) {
  const fs::path path = collection / frame.files.at("instanceid");
  const exr::FlatImage ids = exr::ReadFlatExr(path, {"id"});
  cv::Mat mask = cv::Mat::zeros(ids.height(), ids.width(), CV_8U);
  const std::vector<uint32_t>& v = ids.Get("id").uints;
  for (int y = 0; y < ids.height(); ++y) {
    for (int x = 0; x < ids.width(); ++x)
      mask.at<uint8_t>(y, x) = v[ids.Index(x, y)] == instance_id;
  }
  return mask;
}

// Every frame of a collection, in order.
inline std::vector<Frame> Frames(const fs::path& collection) {
  std::vector<Frame> frames;
  CollectionReader(collection).ForEachFrame([&](const Frame& f) { frames.push_back(f); });
  return frames;
}

// Attributes of every <TAG ...> element of an XML text, in order.
inline std::vector<std::map<std::string, std::string>> XmlElements(const std::string& xml,
                                                                   const std::string& tag) {
  std::vector<std::map<std::string, std::string>> out;
  const std::regex element("<" + tag + " ([^>]*)>");
  const std::regex attribute("([a-z_]+)=\"([^\"]*)\"");
  for (auto it = std::sregex_iterator(xml.begin(), xml.end(), element);
       it != std::sregex_iterator();
       ++it) {
    std::map<std::string, std::string> attributes;
    const std::string body = (*it)[1];
    for (auto a = std::sregex_iterator(body.begin(), body.end(), attribute);
         a != std::sregex_iterator();
         ++a) {
      attributes[(*a)[1]] = (*a)[2];
    }
    out.push_back(attributes);
  }
  return out;
}

inline convert::ConvertOptions Options(const fs::path& collection,
                                       const fs::path& out,
                                       std::vector<std::string> formats) {
  convert::ConvertOptions options;
  options.collection = collection;
  options.output = out;
  options.formats = std::move(formats);
  options.progress = false;
  options.images = "none";
  return options;
}

}  // namespace lsds::testing

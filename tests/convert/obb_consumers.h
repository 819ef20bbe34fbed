// The loading rules of the oriented-box consumers, ported from their loaders
// (read, not copied; file:line of the version read named at each rule), so
// that tests can say what each consumer does with an export:
//   DOTA devkit  CAPTAIN-WHU/DOTA_devkit dota_utils.py (parse_dota_poly)
//   MMRotate     open-mmlab/mmrotate main (0.x, b030f38) mmrotate/datasets/dota.py and
//                mmrotate/core/bbox/transforms.py; 1.x (d50ab76) mmrotate/datasets/dota.py
//   Ultralytics  ultralytics/ultralytics (00bfe34) ultralytics/data/utils.py
//                verify_image_label and ultralytics/utils/ops.py segments2boxes
// docs/convert.md cites the same lines.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <opencv2/imgproc.hpp>

namespace lsds::testing {

// Python's str.split() (any run of whitespace) and str.split(' ').
inline std::vector<std::string> SplitWhitespace(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> out;
  for (std::string token; in >> token;) out.push_back(token);
  return out;
}
inline std::vector<std::string> SplitSpace(const std::string& line) {
  std::vector<std::string> out(1);
  for (const char c : line) {
    if (c == ' ') {
      out.emplace_back();
    } else {
      out.back() += c;
    }
  }
  return out;
}

// Python float(): the whole token must be a number.
inline std::optional<double> PyFloat(const std::string& token) {
  if (token.empty()) return std::nullopt;
  char* end = nullptr;
  const double v = std::strtod(token.c_str(), &end);
  if (end != token.c_str() + token.size()) return std::nullopt;
  return v;
}
// Python int() of a decimal token.
inline std::optional<long> PyInt(const std::string& token) {
  if (token.empty()) return std::nullopt;
  char* end = nullptr;
  const long v = std::strtol(token.c_str(), &end, 10);
  if (end != token.c_str() + token.size()) return std::nullopt;
  return v;
}

inline std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// --- DOTA devkit, dota_utils.py parse_dota_poly ---
struct DevkitObject {
  std::string name, difficult;
  std::array<double, 8> poly{};
};
// What the devkit reads from a labelTxt file; `error` is set where Python
// would raise.
inline std::vector<DevkitObject> DevkitParse(const std::string& text, std::string* error) {
  std::vector<DevkitObject> objects;
  for (std::string line : Lines(text)) {
    // dota_utils.py:61 line.strip().split(' '): single spaces only.
    while (!line.empty() && std::isspace(static_cast<unsigned char>(line.back()))) line.pop_back();
    const std::vector<std::string> t = SplitSpace(line);
    if (t.size() < 9) continue;  // dota_utils.py:65-66 (header lines land here)
    DevkitObject o;
    o.name = t[8];                             // :67-68
    o.difficult = t.size() == 9 ? "0" : t[9];  // :69-76
    for (int i = 0; i < 8; ++i) {              // :79-83 float() of the first eight
      const std::optional<double> v = PyFloat(t[i]);
      if (!v) {
        *error = "float('" + t[i] + "')";
        return objects;
      }
      o.poly[i] = *v;
    }
    objects.push_back(o);
  }
  return objects;
}

// --- MMRotate 0.x, DOTADataset.load_annotations ---
struct MmrotateFile {
  bool crashed = false;  // an exception escapes load_annotations
  std::string error;
  bool skipped_empty = false;  // dota.py:93-94, filter_empty_gt and a 0-byte file
  int boxes = 0;               // kept
  int dropped = 0;             // poly2obb_np returned None (side < 2): `continue`, silently
};
inline MmrotateFile MmrotateLoad(const std::string& text, const std::set<std::string>& classes) {
  MmrotateFile file;
  if (text.empty()) {  // dota.py:93 os.path.getsize(ann_file) == 0 and filter_empty_gt
    file.skipped_empty = true;
    return file;
  }
  for (const std::string& line : Lines(text)) {
    const std::vector<std::string> t = SplitWhitespace(line);  // dota.py:99 si.split()
    // dota.py:100 np.array(bbox_info[:8], dtype=np.float32): outside the try,
    // so a header line ("imagesource:...") raises out of the loader.
    std::vector<float> poly;
    for (size_t i = 0; i < std::min<size_t>(8, t.size()); ++i) {
      const std::optional<double> v = PyFloat(t[i]);
      if (!v) {
        file.crashed = true, file.error = "float32('" + t[i] + "')";
        return file;
      }
      poly.push_back(static_cast<float>(*v));
    }
    // dota.py:101-104 poly2obb_np inside try/except: continue. transforms.py:343-348:
    // cv2.minAreaRect of the 4 points (reshape((4, 2)) raises for fewer: also
    // caught), None when w < 2 or h < 2.
    if (poly.size() != 8) {
      ++file.dropped;
      continue;
    }
    std::vector<cv::Point2f> points;
    for (int i = 0; i < 4; ++i) points.emplace_back(poly[2 * i], poly[2 * i + 1]);
    const cv::RotatedRect r = cv::minAreaRect(points);
    if (r.size.width < 2 || r.size.height < 2) {
      ++file.dropped;
      continue;
    }
    if (t.size() < 10) {  // dota.py:105-106 bbox_info[8], bbox_info[9]: IndexError
      file.crashed = true, file.error = "IndexError: " + std::to_string(t.size()) + " tokens";
      return file;
    }
    if (!classes.count(t[8])) {  // dota.py:107 cls_map[cls_name]: KeyError
      file.crashed = true, file.error = "KeyError('" + t[8] + "')";
      return file;
    }
    if (!PyInt(t[9])) {  // dota.py:106 int(bbox_info[9])
      file.crashed = true, file.error = "int('" + t[9] + "')";
      return file;
    }
    ++file.boxes;
  }
  return file;
}
// dota.py:149-156 _filter_imgs (and 1.x dota.py:116-122 filter_empty_gt):
// an image is trained on only with at least one box.
inline bool MmrotateTrainsOn(const MmrotateFile& file) {
  return !file.crashed && !file.skipped_empty && file.boxes > 0;
}

// --- Ultralytics, ultralytics/data/utils.py verify_image_label ---
struct UltralyticsLabel {
  bool dropped = false;  // the whole image is ignored ("ignoring corrupt image/label")
  std::string error;
  int rows = 0;        // after duplicate removal
  int duplicates = 0;  // utils.py:228-229, removed with a warning
};
inline UltralyticsLabel UltralyticsVerify(const std::string& text, int nc) {
  UltralyticsLabel out;
  // utils.py:205 [x.split() for x in f.read().strip().splitlines() if len(x)]
  std::vector<std::vector<std::string>> lb;
  for (const std::string& line : Lines(text))
    if (!line.empty()) lb.push_back(SplitWhitespace(line));
  if (lb.empty()) return out;  // utils.py:232-234 empty label: a background image
  auto fail = [&](const std::string& e) {
    out.dropped = true, out.error = e;
    return out;
  };
  std::vector<std::array<float, 5>> rows;
  const bool segments = std::any_of(lb.begin(), lb.end(), [](const auto& x) {
    return x.size() > 6;
  });  // utils.py:206 (keypoint false for OBB)
  for (const auto& x : lb) {
    std::vector<float> v;
    for (const std::string& token : x) {  // np.array(..., dtype=np.float32)
      const std::optional<double> f = PyFloat(token);
      if (!f) return fail("float32('" + token + "')");
      v.push_back(static_cast<float>(*f));
    }
    if (segments) {
      // utils.py:207-209: reshape(-1, 2) of the coordinates, then
      // segments2boxes (ops.py): xywh of the points' min/max.
      if (v.size() < 3 || (v.size() - 1) % 2 != 0) return fail("cannot reshape to (-1, 2)");
      float x0 = v[1], x1 = v[1], y0 = v[2], y1 = v[2];
      for (size_t i = 1; i + 1 < v.size(); i += 2) {
        x0 = std::min(x0, v[i]), x1 = std::max(x1, v[i]);
        y0 = std::min(y0, v[i + 1]), y1 = std::max(y1, v[i + 1]);
      }
      rows.push_back({v[0], (x0 + x1) / 2, (y0 + y1) / 2, x1 - x0, y1 - y0});
    } else {
      // utils.py:216 labels require 5 columns
      if (v.size() != 5) return fail("labels require 5 columns");
      rows.push_back({v[0], v[1], v[2], v[3], v[4]});
    }
  }
  for (const auto& r : rows) {
    for (int i = 1; i < 5; ++i)
      if (r[i] > 1.01f) return fail("non-normalized or out of bounds coordinates");  // utils.py:219
    for (int i = 0; i < 5; ++i)
      if (r[i] < -0.01f) return fail("negative class labels or coordinate");   // utils.py:220
    if (!(r[0] < nc)) return fail("Label class exceeds dataset class count");  // utils.py:223-227
  }
  const std::set<std::array<float, 5>> unique(rows.begin(), rows.end());  // utils.py:228
  out.rows = static_cast<int>(unique.size());
  out.duplicates = static_cast<int>(rows.size() - unique.size());
  return out;
}

}  // namespace lsds::testing

#include "evaluate/segmentation.h"

#include <cmath>
#include <vector>

#include "libs/util/error.h"

namespace lsds::evaluate {

using nlohmann::json;

namespace {

[[noreturn]] void Fail(const std::string& file, const std::string& at, const std::string& what) {
  throw Error(what, Location(file, at));
}

masks::CocoRle ReadRle(const json& segmentation,
                       int64_t height,
                       int64_t width,
                       const std::string& file,
                       const std::string& at) {
  const auto size = segmentation.find("size");
  if (size == segmentation.end() || !size->is_array() || size->size() != 2 ||
      !(*size)[0].is_number_integer() || !(*size)[1].is_number_integer())
    Fail(file, at + "/size", "expected \"size\": [height, width]");
  if ((*size)[0].get<int64_t>() != height || (*size)[1].get<int64_t>() != width)
    Fail(file,
         at + "/size",
         "the mask is " + size->dump() + " but the image is [" + std::to_string(height) + "," +
             std::to_string(width) + "] ([height, width])");
  masks::CocoRle rle{height, width, {}};
  const auto counts = segmentation.find("counts");
  if (counts == segmentation.end()) Fail(file, at, "missing 'counts'");
  if (counts->is_string()) {
    if (!masks::CocoRleFromString(counts->get<std::string>(), &rle.counts))
      Fail(file, at + "/counts", "not a compressed COCO RLE string (rleFrString cannot decode it)");
  } else if (counts->is_array()) {
    for (size_t i = 0; i < counts->size(); ++i) {
      const json& run = (*counts)[i];
      if (!run.is_number_integer() || run.get<int64_t>() < 0 ||
          run.get<int64_t>() > static_cast<int64_t>(UINT32_MAX))
        Fail(file, at + "/counts/" + std::to_string(i), "expected a run length >= 0");
      rle.counts.push_back(run.get<uint32_t>());
    }
  } else {
    Fail(file, at + "/counts", "expected a compressed RLE string or a list of run lengths");
  }
  uint64_t pixels = 0;
  for (uint32_t run : rle.counts) pixels += run;
  if (pixels != static_cast<uint64_t>(height * width))
    Fail(file,
         at + "/counts",
         "the runs cover " + std::to_string(pixels) + " pixels, the image has " +
             std::to_string(height * width));
  return rle;
}

masks::CocoRle ReadPolygons(const json& segmentation,
                            int64_t height,
                            int64_t width,
                            const std::string& file,
                            const std::string& at) {
  // COCO.annToRLE: each polygon rasterised (frPoly), the parts merged.
  std::vector<masks::CocoRle> parts;
  for (size_t p = 0; p < segmentation.size(); ++p) {
    const json& polygon = segmentation[p];
    const std::string here = at + "/" + std::to_string(p);
    if (!polygon.is_array() || polygon.size() < 6 || polygon.size() % 2 != 0)
      Fail(file, here, "expected a polygon [x0, y0, x1, y1, x2, y2, ...] of three points or more");
    std::vector<double> xy;
    for (size_t i = 0; i < polygon.size(); ++i) {
      if (!polygon[i].is_number() || !std::isfinite(polygon[i].get<double>()))
        Fail(file, here + "/" + std::to_string(i), "expected a finite number");
      if (std::fabs(polygon[i].get<double>()) > masks::kMaxPolygonCoordinate)
        Fail(file,
             here + "/" + std::to_string(i),
             "a polygon coordinate beyond +-1e6 pixels (" + polygon[i].dump() +
                 "): no mask of the image has one, and rasterising it as the COCO API does "
                 "would walk its edges for minutes");
      xy.push_back(polygon[i].get<double>());
    }
    parts.push_back(masks::CocoRleFromPolygon(xy, height, width));
  }
  if (parts.empty()) Fail(file, at, "no polygon");
  return masks::CocoRleUnion(parts);
}

}  // namespace

masks::CocoRle ReadSegmentation(const json& segmentation,
                                int64_t height,
                                int64_t width,
                                const std::string& file,
                                const std::string& at) {
  if (segmentation.is_object()) return ReadRle(segmentation, height, width, file, at);
  if (segmentation.is_array()) return ReadPolygons(segmentation, height, width, file, at);
  Fail(file,
       at,
       "expected a COCO segmentation: {size, counts} (RLE) or [[x0, y0, ...], ...] (polygons)");
}

}  // namespace lsds::evaluate

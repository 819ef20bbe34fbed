#include "converters/registry.h"

#include <functional>

#include "converters/coco/coco_converter.h"
#include "converters/cvat/cvat_converter.h"
#include "converters/dota/dota_converter.h"
#include "converters/mot/mot_converter.h"
#include "converters/visdrone/visdrone_converter.h"
#include "converters/yolo/yolo_converter.h"
#include "libs/util/error.h"
#include "libs/util/strings.h"

namespace lsds::convert {

namespace {

struct Entry {
  const char* name;
  std::function<std::unique_ptr<Converter>()> make;
};

const std::vector<Entry>& Entries() {
  static const std::vector<Entry> entries = {
      {"yolo", [] { return MakeYoloConverter(YoloTask::kDetect); }},
      {"yolo-seg", [] { return MakeYoloConverter(YoloTask::kSegment); }},
      {"yolo-obb", [] { return MakeYoloConverter(YoloTask::kOriented); }},
      {"dota", [] { return MakeDotaConverter(); }},
      {"coco", [] { return MakeCocoConverter(); }},
      {"cvat", [] { return MakeCvatImagesConverter(); }},
      {"cvat-video", [] { return MakeCvatVideoConverter(); }},
      {"mot", [] { return MakeMotConverter(); }},
      {"visdrone", [] { return MakeVisDroneConverter(); }},
      {"visdrone-vid", [] { return MakeVisDroneVidConverter(); }},
  };
  return entries;
}

}  // namespace

std::vector<std::string> ConverterNames() {
  std::vector<std::string> names;
  for (const Entry& entry : Entries()) names.push_back(entry.name);
  return names;
}

std::unique_ptr<Converter> MakeConverter(const std::string& name) {
  for (const Entry& entry : Entries()) {
    if (name == entry.name) return entry.make();
  }
  throw Error("unknown format '" + name + "'" + DidYouMean(name, ConverterNames()),
              Location("--to"));
}

}  // namespace lsds::convert

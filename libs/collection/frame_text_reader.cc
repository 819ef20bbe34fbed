#include "libs/collection/frame_text_reader.h"

#include <array>
#include <climits>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>

#include <simdjson.h>

#include "libs/collection/json_array_split.h"
#include "libs/collection/schema.h"
#include "libs/util/confined_path.h"

namespace lsds {

static_assert(kElementTextPadding >= simdjson::SIMDJSON_PADDING);

namespace {

// The readers of one simdjson kernel (frame_text_reader_kernel.inc).
class FrameTextKernel {
 public:
  virtual ~FrameTextKernel() = default;
  virtual bool Read(std::string_view text, Frame* frame) = 0;
  virtual bool IsWellFormed(std::string_view text) = 0;
};

// A member whose model is JSON itself (scene, exposure, requirements,
// changes): its text parsed by nlohmann, as the DOM path holds it.
bool ReadJsonText(std::string_view text, nlohmann::json* out) {
  try {
    *out = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception&) {
    return false;
  }
  return true;
}

bool MatchesDefinition(const nlohmann::json& json, const char* definition) {
  return JsonSchema::Get("collection.schema.json", definition).Validate(json).empty();
}

// definitions/frame/properties/exposure.
bool IsExposure(const nlohmann::json& exposure) {
  if (!exposure.is_object()) return false;
  for (const char* required : {"mode", "ev100", "scale"})
    if (!exposure.contains(required)) return false;
  for (const auto& [key, value] : exposure.items()) {
    if (key == "mode") {
      if (value != "auto" && value != "manual") return false;
      continue;
    }
    if (!value.is_number()) return false;
    const double number = value.get<double>();
    if (key == "ev100" || key == "compensation_ev") continue;
    if (key == "metered_cd_m2") {
      if (number < 0) return false;
      continue;
    }
    if (key != "iso" && key != "shutter_s" && key != "f_number" && key != "scale" &&
        key != "focus_distance_m")
      return false;
    if (!(number > 0)) return false;
  }
  return true;
}

bool AllIn(std::string_view text, bool (*allowed)(char)) {
  if (text.empty()) return false;
  for (const char c : text)
    if (!allowed(c)) return false;
  return true;
}
bool IsLayerNameChar(char c) {
  return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
}
bool IsRigCameraChar(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
         c == '-';
}
bool IsReferenceChar(char c) { return IsRigCameraChar(c) || c == '.' || c == '/'; }

}  // namespace

// The readers over simdjson's builtin kernel (the one the build's flags
// allow).
namespace frame_text_builtin {
namespace od = simdjson::ondemand;
#include "libs/collection/frame_text_reader_kernel.inc"
}  // namespace frame_text_builtin

namespace {

std::unique_ptr<FrameTextKernel> MakeFastestKernel() { return frame_text_builtin::MakeKernel(); }

}  // namespace

struct FrameTextReader::Impl {
  std::unique_ptr<FrameTextKernel> kernel = MakeFastestKernel();
};

FrameTextReader::FrameTextReader() : impl_(std::make_unique<Impl>()) {}
FrameTextReader::~FrameTextReader() = default;

bool FrameTextReader::Read(std::string_view text, Frame* frame) {
  return impl_->kernel->Read(text, frame);
}

bool FrameTextReader::IsWellFormed(std::string_view text) {
  return impl_->kernel->IsWellFormed(text);
}

}  // namespace lsds

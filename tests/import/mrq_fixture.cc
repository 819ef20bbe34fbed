#include "tests/import/mrq_fixture.h"

#include <cstdio>
#include <fstream>
#include <map>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfMultiPartOutputFile.h>
#include <ImfOutputFile.h>
#include <ImfOutputPart.h>
#include <ImfPartType.h>
#include <ImfStringAttribute.h>
#include <half.h>
#include <nlohmann/json.hpp>

#include "importers/cryptomatte.h"
#include "importers/unreal_frame.h"

namespace lsds::testing {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

struct Channel {
  std::string name;
  bool half = false;
  std::vector<float> values;
};
struct Part {
  std::string name;
  std::vector<Channel> channels;
  std::map<std::string, std::string> attributes;
};

std::string Text(double value) {
  char text[64];
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}

Imf::Header MakeHeader(int w, int h, const Part& part) {
  Imf::Header header(w, h);
  header.compression() = Imf::ZIP_COMPRESSION;
  for (const Channel& c : part.channels)
    header.channels().insert(c.name, Imf::Channel(c.half ? Imf::HALF : Imf::FLOAT));
  for (const auto& [name, value] : part.attributes)
    header.insert(name, Imf::StringAttribute(value));
  return header;
}

// Slices over `halves` (kept alive by the caller) or the float values.
Imf::FrameBuffer MakeBuffer(int w,
                            const std::vector<Channel>& channels,
                            std::vector<std::vector<half>>* halves) {
  Imf::FrameBuffer buffer;
  for (const Channel& c : channels) {
    if (c.half) {
      halves->emplace_back(c.values.begin(), c.values.end());
      buffer.insert(c.name,
                    Imf::Slice(Imf::HALF,
                               reinterpret_cast<char*>(halves->back().data()),
                               sizeof(half),
                               sizeof(half) * w));
    } else {
      buffer.insert(c.name,
                    Imf::Slice(Imf::FLOAT,
                               const_cast<char*>(reinterpret_cast<const char*>(c.values.data())),
                               sizeof(float),
                               sizeof(float) * w));
    }
  }
  return buffer;
}

void WriteExr(const fs::path& path, int w, int h, const std::vector<Part>& parts, bool multipart) {
  if (multipart) {
    std::vector<Imf::Header> headers;
    for (const Part& part : parts) {
      headers.push_back(MakeHeader(w, h, part));
      headers.back().setName(part.name);
      headers.back().setType(Imf::SCANLINEIMAGE);
    }
    Imf::MultiPartOutputFile file(path.c_str(), headers.data(), static_cast<int>(headers.size()));
    for (size_t i = 0; i < parts.size(); ++i) {
      std::vector<std::vector<half>> halves;
      halves.reserve(parts[i].channels.size());
      Imf::OutputPart out(file, static_cast<int>(i));
      out.setFrameBuffer(MakeBuffer(w, parts[i].channels, &halves));
      out.writePixels(h);
    }
    return;
  }
  Part merged;
  for (const Part& part : parts) {
    merged.channels.insert(merged.channels.end(), part.channels.begin(), part.channels.end());
    merged.attributes.insert(part.attributes.begin(), part.attributes.end());
  }
  Imf::OutputFile file(path.c_str(), MakeHeader(w, h, merged));
  std::vector<std::vector<half>> halves;
  halves.reserve(merged.channels.size());
  file.setFrameBuffer(MakeBuffer(w, merged.channels, &halves));
  file.writePixels(h);
}

}  // namespace

std::string MrqActorName(uint32_t instance_id) {
  return instance_id == 1000 ? "Landscape" : "BP_Target_C_" + std::to_string(instance_id);
}

void WriteMrqFixture(const fs::path& folder,
                     const synth::Spec& spec,
                     const MrqFixtureOptions& options) {
  fs::create_directories(folder);
  // The sidecar, as the UE script of docs/import.md writes it.
  json classes = json::array();
  for (const ClassInfo& c : spec.classes) classes.push_back({{"id", c.id}, {"name", c.name}});
  json actors = json::array();
  std::vector<std::string> names = {MrqActorName(1000)};
  actors.push_back({{"name", MrqActorName(1000)}, {"instance_id", 1000}, {"class_id", 1}});
  for (const synth::Box& box : spec.boxes) {
    Eigen::Vector3d center, extent;
    import::UnrealRotator rotation;
    import::UnrealBoxOfEnuBox(box.Obb(), &center, &extent, &rotation);
    names.push_back(MrqActorName(box.instance_id));
    actors.push_back(
        {{"name", MrqActorName(box.instance_id)},
         {"object", box.name},
         {"asset", "box"},
         {"instance_id", box.instance_id},
         {"class_id", box.class_id},
         {"obb",
          {{"center", {center.x(), center.y(), center.z()}},
           {"extent", {extent.x(), extent.y(), extent.z()}},
           {"rotation",
            {{"pitch", rotation.pitch}, {"yaw", rotation.yaw}, {"roll", rotation.roll}}}}}});
  }
  std::ofstream(folder / "lsds_objects.json") << json{
      {"format", "lsds-ue-objects"},
      {"version", 1},
      {"fps", options.fps},
      {"classes", classes},
      {"actors", actors}}.dump(2);
  const std::string layer = "CryptoActor";
  std::map<uint32_t, float> id_of_instance = {{0, 0.0f}};
  for (uint32_t instance : {1000u, 1u, 2u, 3u})
    id_of_instance[instance] =
        import::CryptomatteFloatFromHash(import::MurmurHash3_32(MrqActorName(instance)));
  for (const synth::Box& box : spec.boxes)
    id_of_instance[box.instance_id] =
        import::CryptomatteFloatFromHash(import::MurmurHash3_32(MrqActorName(box.instance_id)));

  for (int k = 0; k < static_cast<int>(spec.cam_from_world.size()); ++k) {
    const synth::RenderedFrame frame = synth::RenderFrame(spec, k);
    const int w = spec.width, h = spec.height;
    const size_t n = static_cast<size_t>(w) * h;
    Part rgba{"rgba", {}, {}};
    for (const char* c : {"R", "G", "B"})
      rgba.channels.push_back({c, true, frame.flat.at("rgb").Get(c).floats});
    rgba.channels.push_back({"A", true, std::vector<float>(n, 1.0f)});
    Eigen::Vector3d location;
    import::UnrealRotator rotation;
    import::UnrealCameraOfCamFromEnu(spec.cam_from_world[k], &location, &rotation);
    rgba.attributes = {{"unreal/camera/curPos/x", Text(location.x())},
                       {"unreal/camera/curPos/y", Text(location.y())},
                       {"unreal/camera/curPos/z", Text(location.z())},
                       {"unreal/camera/curRot/pitch", Text(rotation.pitch)},
                       {"unreal/camera/curRot/yaw", Text(rotation.yaw)},
                       {"unreal/camera/curRot/roll", Text(rotation.roll)},
                       {"unreal/camera/FinalImage/fov", Text(spec.hfov_deg)}};
    Part depth{"FinalImageMovieRenderQueue_WorldDepth", {}, {}};
    std::vector<float> cm = frame.flat.at("depth").Get("Z").floats;
    for (float& v : cm) v *= 100.0f;  // m -> cm (inf stays inf: the sky)
    for (const char* c : {"R", "G", "B"})
      depth.channels.push_back(
          {"FinalImageMovieRenderQueue_WorldDepth." + std::string(c), options.half_depth, cm});
    depth.channels.push_back({"FinalImageMovieRenderQueue_WorldDepth.A",
                              options.half_depth,
                              std::vector<float>(n, 1.0f)});
    Part crypto{layer, {}, {}};
    std::vector<float> id(n), coverage(n), zero(n, 0.0f);
    const std::vector<uint32_t>& instances = frame.flat.at("instanceid").Get("id").uints;
    for (size_t p = 0; p < n; ++p) {
      id[p] = id_of_instance.at(instances[p]);
      coverage[p] = instances[p] == 0 ? 0.0f : 1.0f;  // one sample per pixel
    }
    crypto.channels = {{layer + "00.R", false, id},
                       {layer + "00.G", false, coverage},
                       {layer + "00.B", false, zero},
                       {layer + "00.A", false, zero},
                       {layer + "01.R", false, zero},
                       {layer + "01.G", false, zero},
                       {layer + "01.B", false, zero},
                       {layer + "01.A", false, zero}};
    crypto.attributes = {
        {import::CryptomatteAttribute(layer, "name"), layer},
        {import::CryptomatteAttribute(layer, "hash"), "MurmurHash3_32"},
        {import::CryptomatteAttribute(layer, "conversion"), "uint32_to_float32"},
        {import::CryptomatteAttribute(layer, "manifest"), import::CryptomatteManifest(names)}};
    char name[64];
    std::snprintf(name, sizeof name, "%s.%04d.exr", options.sequence.c_str(), k);
    WriteExr(folder / name, w, h, {rgba, depth, crypto}, options.multipart);
  }
}

}  // namespace lsds::testing

// Cryptomatte as other writers spell it, on a real file: Psyop's sample
// special_chars.exr (tests/import/data/cryptomatte, README there), written by
// Arnold with Nuke's channel names (<layer>00.red/.green/...) and no depth
// pass. The ids decode to the file's own manifest; wrapped in Movie Render
// Queue's camera attributes it imports into a valid collection without depth,
// whose instance layer holds the manifest's objects pixel for pixel; the FOV
// spans the window the flag names.
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStringAttribute.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "importers/cryptomatte.h"
#include "importers/source_exr.h"
#include "libs/collection/collection_reader.h"
#include "libs/exr/flat_image.h"
#include "tests/build_paths.h"
#include "tests/test_util.h"

namespace lsds::testing {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr double kPi = 3.14159265358979323846;

fs::path Sample() {
  return fs::path(SourceDir()) / "tests/import/data/cryptomatte/special_chars.exr";
}

// The file's manifest, read here with nlohmann only: name -> the 32 bits a
// pixel holds (the manifest's hex is the stored float's bit pattern).
std::map<uint32_t, std::string> ManifestByBits(const import::SourceExr& exr,
                                               const std::string& key) {
  const json manifest = json::parse(exr.attributes().at("cryptomatte/" + key + "/manifest"));
  std::map<uint32_t, std::string> names;
  for (const auto& [name, hex] : manifest.items())
    names[static_cast<uint32_t>(std::stoul(hex.get<std::string>(), nullptr, 16))] = name;
  return names;
}

// Every pixel's rank-0 name ("" for none), decoded from the file.
std::vector<std::string> Rank0Names(const import::SourceExr& exr,
                                    const std::string& id_channel,
                                    const std::string& coverage_channel,
                                    const std::map<uint32_t, std::string>& names) {
  const std::vector<float> ids = exr.ReadFloat(id_channel);
  const std::vector<float> coverage = exr.ReadFloat(coverage_channel);
  std::vector<std::string> out(ids.size());
  for (size_t p = 0; p < ids.size(); ++p) {
    uint32_t bits;
    std::memcpy(&bits, &ids[p], sizeof bits);
    if (bits == 0 || !(coverage[p] > 0)) continue;
    out[p] = names.at(bits);
  }
  return out;
}

TEST(CryptomatteSample, NukeChannelNamesAndTheManifestOfTheFile) {
  const import::SourceExr exr(Sample());
  const auto layers = import::ParseCryptomatteLayers(exr.attributes(), exr.file());
  ASSERT_EQ(layers.size(), 1u);
  EXPECT_EQ(layers[0].name, "special_chars");
  const auto rank0 = import::FindRank0Channels(exr.ChannelNames(), layers[0].name);
  ASSERT_TRUE(rank0.has_value());
  EXPECT_EQ(rank0->id, "special_chars00.red");
  EXPECT_EQ(rank0->coverage, "special_chars00.green");
  // Our hash of each name is the writer's (names with quotes, a slash,
  // commas, Cyrillic).
  const std::map<uint32_t, std::string> names = ManifestByBits(exr, layers[0].key);
  ASSERT_EQ(names.size(), 4u);
  for (const auto& [bits, name] : names) {
    EXPECT_EQ(import::CryptomatteBitsFromHash(import::MurmurHash3_32(name)), bits) << name;
    EXPECT_EQ(layers[0].names_by_bits.at(bits), name);
  }
  // Every pixel's rank-0 id is one of the manifest's.
  const std::vector<std::string> decoded = Rank0Names(exr, rank0->id, rank0->coverage, names);
  std::map<std::string, int> counts;
  for (const std::string& name : decoded) ++counts[name];
  EXPECT_EQ(decoded.size(), 64u * 64u);
  EXPECT_EQ(counts.size(), 5u);  // the four names and the background
  for (const auto& [name, count] : counts) std::cout << "'" << name << "': " << count << " px\n";
  // The other spellings are found as well; a missing pair is none.
  EXPECT_EQ(import::FindRank0Channels({"L00.R", "L00.G"}, "L")->id, "L00.R");
  EXPECT_EQ(import::FindRank0Channels({"V.L00.r", "V.L00.g"}, "V.L")->coverage, "V.L00.g");
  EXPECT_FALSE(import::FindRank0Channels({"L00.red"}, "L").has_value());
}

struct Window {
  int x0, y0, x1, y1;
};

// The sample's pixels in window `data` (of its 64 x 64 frame) under a display
// window `display`, with the header attributes Movie Render Queue writes
// (unreal/camera/..., MoviePipelineImagePassBase.cpp) added: a stand-in for
// an MRQ frame with Cryptomatte and without depth.
void WriteAsMrqFrame(const fs::path& out, const Window& data, const Window& display, double fov) {
  Imf::InputFile in(Sample().c_str());
  const Imath::Box2i source_window = in.header().dataWindow();
  const int w = source_window.max.x - source_window.min.x + 1;
  const int h = source_window.max.y - source_window.min.y + 1;
  std::map<std::string, std::vector<float>> pixels;
  Imf::FrameBuffer read;
  for (auto c = in.header().channels().begin(); c != in.header().channels().end(); ++c) {
    std::vector<float>& values = pixels[c.name()];
    values.resize(static_cast<size_t>(w) * h);
    read.insert(
        c.name(),
        Imf::Slice(
            Imf::FLOAT, reinterpret_cast<char*>(values.data()), sizeof(float), sizeof(float) * w));
  }
  in.setFrameBuffer(read);
  in.readPixels(source_window.min.y, source_window.max.y);

  Imf::Header header(Imath::Box2i({display.x0, display.y0}, {display.x1, display.y1}),
                     Imath::Box2i({data.x0, data.y0}, {data.x1, data.y1}));
  for (auto a = in.header().begin(); a != in.header().end(); ++a)
    if (std::string(a.name()).rfind("cryptomatte/", 0) == 0) header.insert(a.name(), a.attribute());
  const std::map<std::string, std::string> camera = {
      {"unreal/camera/curPos/x", "100"},
      {"unreal/camera/curPos/y", "-250"},
      {"unreal/camera/curPos/z", "1200"},
      {"unreal/camera/curRot/pitch", "-90"},
      {"unreal/camera/curRot/yaw", "0"},
      {"unreal/camera/curRot/roll", "0"},
      {"unreal/camera/FinalImage/fov", std::to_string(fov)}};
  for (const auto& [name, value] : camera) header.insert(name, Imf::StringAttribute(value));
  const int out_w = data.x1 - data.x0 + 1;
  Imf::FrameBuffer write;
  std::map<std::string, std::vector<float>> cropped;
  for (const auto& [name, values] : pixels) {
    header.channels().insert(name, Imf::Channel(Imf::FLOAT));
    std::vector<float>& crop = cropped[name];
    for (int y = data.y0; y <= data.y1; ++y)
      for (int x = data.x0; x <= data.x1; ++x)
        crop.push_back(values[static_cast<size_t>(y) * w + x]);
    char* base = reinterpret_cast<char*>(crop.data()) -
                 (static_cast<ptrdiff_t>(data.y0) * out_w + data.x0) * sizeof(float);
    write.insert(name, Imf::Slice(Imf::FLOAT, base, sizeof(float), sizeof(float) * out_w));
  }
  Imf::OutputFile file(out.c_str(), header);
  file.setFrameBuffer(write);
  file.writePixels(data.y1 - data.y0 + 1);
}

// The sidecar: every manifest name an actor (instance 1..4, one class).
void WriteSidecar(const fs::path& folder, const std::map<uint32_t, std::string>& names) {
  json actors = json::array();
  uint32_t id = 1;
  for (const auto& [bits, name] : names)
    actors.push_back({{"name", name}, {"instance_id", id++}, {"class_id", 1}});
  std::ofstream(folder / "lsds_objects.json") << json{
      {"format", "lsds-ue-objects"},
      {"version", 1},
      {"fps", 24},
      {"classes", {{{"id", 1}, {"name", "thing"}}}},
      {"actors", actors}}.dump(2);
}

TEST(CryptomatteSample, AnMrqFrameWithoutDepthImportsItsIdsAndNoDepthLayer) {
  TempDir dir;
  const fs::path source = dir / "Shot";
  fs::create_directories(source);
  WriteAsMrqFrame(source / "Shot.0000.exr", {0, 0, 63, 63}, {0, 0, 63, 63}, 60);
  const import::SourceExr sample(Sample());
  const auto layers = import::ParseCryptomatteLayers(sample.attributes(), sample.file());
  const std::map<uint32_t, std::string> names = ManifestByBits(sample, layers[0].key);
  WriteSidecar(source, names);
  const fs::path out = dir / "collection";
  const CommandResult imported =
      RunLsds("import ue-mrq " + source.string() + " -o " + out.string());
  ASSERT_EQ(imported.exit_code, 0) << imported.output;
  EXPECT_NE(imported.output.find("warning: the source has no depth pass"), std::string::npos)
      << imported.output;
  const CommandResult validate = RunLsds("validate --fail-on warning " + out.string());
  EXPECT_EQ(validate.exit_code, 0) << validate.output;

  const CollectionReader reader(out);
  EXPECT_EQ(reader.header().FindLayerBySemantic("depth"), nullptr);
  EXPECT_EQ(reader.header().FindLayerBySemantic("worldposition"), nullptr);
  std::map<std::string, uint32_t> instance_of;
  uint32_t id = 1;
  for (const auto& [bits, name] : names) instance_of[name] = id++;
  const std::vector<std::string> decoded =
      Rank0Names(sample, "special_chars00.red", "special_chars00.green", names);
  int64_t differing = 0, labelled = 0;
  reader.ForEachFrame([&](const Frame& frame) {
    const std::vector<uint32_t> ids =
        exr::ReadFlatExr(reader.LayerPath(frame, "instanceid")).Get("id").uints;
    ASSERT_EQ(ids.size(), decoded.size());
    for (size_t p = 0; p < ids.size(); ++p) {
      const uint32_t want = decoded[p].empty() ? 0 : instance_of.at(decoded[p]);
      differing += ids[p] != want;
      labelled += want != 0;
    }
    EXPECT_NEAR(frame.camera.intrinsics.fx, 32 / std::tan(30 * kPi / 180), 1e-9);
  });
  EXPECT_GT(labelled, 0);
  EXPECT_EQ(differing, 0);
  std::cout << "Cryptomatte sample as MRQ: " << labelled << " labelled pixels, " << differing
            << " differing from the manifest decode\n";
}

TEST(CryptomatteSample, TheFovSpansTheWindowTheFlagNames) {
  TempDir dir;
  const fs::path source = dir / "Crop";
  fs::create_directories(source);
  // A data window of 48 x 56 inside a 64 x 64 display window (a crop render).
  WriteAsMrqFrame(source / "Crop.0000.exr", {8, 4, 55, 59}, {0, 0, 63, 63}, 60);
  const double tan_half = std::tan(30 * kPi / 180);
  const auto camera_of = [&](const std::string& flags, const std::string& name) {
    const fs::path out = dir / name;
    const CommandResult imported =
        RunLsds("import ue-mrq " + source.string() + " -o " + out.string() + flags);
    EXPECT_EQ(imported.exit_code, 0) << imported.output;
    PinholeCamera camera;
    CollectionReader(out).ForEachFrame([&](const Frame& f) { camera = f.camera.intrinsics; });
    return camera;
  };
  // MRQ's rule (default): the FOV spans the rendered data window.
  const PinholeCamera data = camera_of("", "data");
  EXPECT_EQ(data.width, 48);
  EXPECT_EQ(data.height, 56);
  EXPECT_NEAR(data.fx, 24 / tan_half, 1e-9);
  EXPECT_DOUBLE_EQ(data.cx, 24);
  // --fov-window display: the FOV spans the display window; the principal
  // point is the display centre in the data window's pixels.
  const PinholeCamera display = camera_of(" --fov-window display", "display");
  EXPECT_NEAR(display.fx, 32 / tan_half, 1e-9);
  EXPECT_NEAR(display.fy, display.fx, 1e-12);
  EXPECT_DOUBLE_EQ(display.cx, 32 - 8);
  EXPECT_DOUBLE_EQ(display.cy, 32 - 4);
}

}  // namespace
}  // namespace lsds::testing

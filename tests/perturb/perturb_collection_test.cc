// PerturbCollection on synthetic collections: the output is valid,
// reproducible, registered without touching the truth, states realized errors
// that match the data, and its statistics over thousands of frames match the
// requested sigmas; the report measures pixel motion that matches the geometry.
#include <cmath>
#include <set>

#include <gtest/gtest.h>

#include "libs/collection/collection_reader.h"
#include "libs/collection/json_io.h"
#include "libs/collection/json_stream.h"
#include "libs/collection/schema.h"
#include "libs/util/error.h"
#include "perturb/perturb_collection.h"
#include "tests/perturb/perturb_test_util.h"

namespace lsds::noise {
namespace {

using testing_perturb::ReadText;
using testing_perturb::TempDir;
using testing_perturb::WriteNadirCollection;
namespace fs = std::filesystem;

constexpr double kZ = 3.29;  // two-sided 99.9 %

PerturbOptions Options(const fs::path& collection, uint64_t seed) {
  PerturbOptions options;
  options.collection = collection;
  options.spec.seed = seed;
  options.progress = false;
  return options;
}

// Whole-document schema check (the file is small in these tests).
std::vector<SchemaIssue> SchemaIssues(const fs::path& path, const std::string& schema) {
  return JsonSchema::Get(schema).Validate(nlohmann::json::parse(ReadText(path)));
}

std::vector<nlohmann::json> Frames(const fs::path& path) {
  std::vector<nlohmann::json> frames;
  StreamJsonArrayMember(
      path, "frames", nullptr, [&](nlohmann::json&& frame, size_t) { frames.push_back(frame); });
  return frames;
}

TEST(PerturbCollection, WritesAValidRegisteredVariantAndLeavesTheTruthAlone) {
  TempDir dir;
  const fs::path root = WriteNadirCollection(dir.path() / "c", 20);
  const std::string collection_before = ReadText(root / "collection.json");
  const std::string metadata_before = ReadText(root / "metadata.json");
  const std::string layer_before = ReadText(root / "instanceid" / "000003.exr");

  PerturbOptions options = Options(root, 7);
  options.spec.sigma = {1, 1, 2, 0.1, 0.1, 0.2, 0.001, 0.1};
  const PerturbResult result = PerturbCollection(options);

  EXPECT_EQ(result.output, root / "metadata.perturbed-7.json");
  EXPECT_EQ(result.registered_as, "metadata.perturbed-7.json");
  EXPECT_EQ(result.frames, 20);
  EXPECT_TRUE(SchemaIssues(result.output, "metadata.schema.json").empty());
  EXPECT_TRUE(SchemaIssues(root / "collection.json", "collection.schema.json").empty());

  // Inputs: metadata.json and the layers byte-identical; collection.json frames
  // byte-identical.
  EXPECT_TRUE(ReadText(root / "metadata.json") == metadata_before);
  EXPECT_TRUE(ReadText(root / "instanceid" / "000003.exr") == layer_before);
  {
    const std::string after = ReadText(root / "collection.json");
    const std::string frames_before =
        collection_before.substr(collection_before.find("\"frames\": ["));
    EXPECT_EQ(after.substr(after.find("\"frames\": [")), frames_before);
  }

  // The header lists the new variant after the truth; everything else in it is
  // unchanged.
  const CollectionReader reader(root);
  ASSERT_EQ(reader.header().metadata.size(), 2u);
  EXPECT_EQ(reader.header().metadata[0].file, "metadata.json");
  EXPECT_FALSE(reader.header().metadata[0].perturbed);
  EXPECT_EQ(reader.header().metadata[1].file, "metadata.perturbed-7.json");
  EXPECT_TRUE(reader.header().metadata[1].perturbed);
  EXPECT_NE(reader.header().metadata[1].description.find("gaussian, seed 7"), std::string::npos);

  // The header records model, parameters, seed, source and the summary.
  const MetadataReader perturbed(result.output);
  EXPECT_TRUE(perturbed.header().perturbed);
  ASSERT_TRUE(perturbed.header().noise);
  EXPECT_EQ(perturbed.header().noise->model, "gaussian");
  EXPECT_EQ(perturbed.header().noise->seed, 7u);
  EXPECT_EQ(perturbed.header().noise->parameters["sigma"]["up_m"].get<double>(), 2.0);
  EXPECT_EQ(perturbed.header().source, "metadata.json");

  // Every frame passes the reader's own checks; the tightened schema knows the
  // error members.
  int64_t read = 0;
  perturbed.ForEachFrame([&](const MetadataFrame& frame) {
    EXPECT_TRUE(frame.error.contains("rotation_vector_deg"));
    ++read;
  });
  EXPECT_EQ(read, 20);
  nlohmann::json bad_frame = Frames(result.output).front();
  bad_frame["error"]["rotation"] = 1.0;
  EXPECT_FALSE(JsonSchema::Get("metadata.schema.json", "frame").Validate(bad_frame).empty());

  // A second variant with --force replaces its own entry instead of adding a
  // duplicate.
  options.force = true;
  PerturbCollection(options);
  EXPECT_EQ(CollectionReader(root).header().metadata.size(), 2u);
  options.spec.seed = 8;
  PerturbCollection(options);
  EXPECT_EQ(CollectionReader(root).header().metadata.size(), 3u);
}

TEST(PerturbCollection, RecordedErrorsAreTheDifferenceBetweenMeasuredAndTrue) {
  TempDir dir;
  const fs::path root = WriteNadirCollection(dir.path() / "c", 30);
  PerturbOptions options = Options(root, 3);
  options.spec.sigma = {2, 2, 4, 0.5, 0.5, 1.0, 0.01, 0.5};
  options.spec.bias[kUp] = 1.0;
  const PerturbResult result = PerturbCollection(options);
  const std::vector<nlohmann::json> truth = Frames(root / "metadata.json");
  const std::vector<nlohmann::json> measured = Frames(result.output);
  ASSERT_EQ(truth.size(), measured.size());
  for (size_t k = 0; k < truth.size(); ++k) {
    const MetadataFrame t = MetadataFrameFromJson(truth[k], "t", "");
    const MetadataFrame m = MetadataFrameFromJson(measured[k], "m", "");
    const nlohmann::json& e = m.error;
    EXPECT_EQ(m.index, t.index);
    for (int i = 0; i < 3; ++i) {
      EXPECT_NEAR(m.position[i] - t.position[i], e["position"][i].get<double>(), 1e-9);
    }
    const double angle =
        NedFromBody(t.attitude).angularDistance(NedFromBody(m.attitude)) * 180 / M_PI;
    EXPECT_NEAR(angle, e["rotation_deg"].get<double>(), 1e-6);
    EXPECT_NEAR(m.time - t.time, e["time_s"].get<double>(), 1e-12);
    EXPECT_NEAR(m.camera.HorizontalFovDeg() - t.camera.HorizontalFovDeg(),
                e["hfov_deg"].get<double>(),
                1e-9);
    EXPECT_EQ(m.camera.width, t.camera.width);
  }
}

TEST(PerturbCollection, SampleStdOverTwoThousandFramesMatchesSigmaPerField) {
  TempDir dir;
  const fs::path root = WriteNadirCollection(dir.path() / "c", 2000, 8, 8, false);
  PerturbOptions options = Options(root, 12345);
  options.spec.sigma = {0.8, 0.8, 2.5, 0.1, 0.2, 0.4, 0.005, 0.3};
  const PerturbResult result = PerturbCollection(options);
  // From the written file: per-field realized errors.
  std::vector<std::vector<double>> values(kFieldCount);
  for (const nlohmann::json& frame : Frames(result.output)) {
    const nlohmann::json& e = frame.at("error");
    for (int i = 0; i < 3; ++i) values[kEast + i].push_back(e["position_enu_m"][i].get<double>());
    for (int i = 0; i < 3; ++i)
      values[kRoll + i].push_back(e["rotation_vector_deg"][i].get<double>());
    values[kTime].push_back(e["time_s"].get<double>());
    values[kHfov].push_back(e["hfov_deg"].get<double>());
  }
  const double n = 2000;
  for (int f = 0; f < kFieldCount; ++f) {
    ASSERT_EQ(values[f].size(), 2000u);
    double mean = 0, m2 = 0;
    for (double v : values[f]) mean += v;
    mean /= n;
    for (double v : values[f]) m2 += (v - mean) * (v - mean);
    const double std_dev = std::sqrt(m2 / (n - 1));
    const double sigma = options.spec.sigma[f];
    // Normal law: sd(s) ~ sigma / sqrt(2 (n - 1)).
    EXPECT_NEAR(std_dev, sigma, kZ * sigma / std::sqrt(2 * (n - 1))) << FieldName(f);
    // The header's summary states the same statistics.
    EXPECT_NEAR(result.summary["fields"][FieldName(f)]["std"].get<double>(), std_dev, 1e-9 * sigma)
        << FieldName(f);
  }
  // The realized positions in the file are the truth plus these errors (ENU
  // collection).
  const std::vector<nlohmann::json> truth = Frames(root / "metadata.json");
  const std::vector<nlohmann::json> measured = Frames(result.output);
  double vertical = 0;
  for (size_t k = 0; k < truth.size(); ++k) {
    const double dz =
        measured[k]["position"][2].get<double>() - truth[k]["position"][2].get<double>();
    vertical += dz * dz;
  }
  EXPECT_NEAR(std::sqrt(vertical / n), 2.5, kZ * 2.5 / std::sqrt(2 * n));
}

TEST(PerturbCollection, ZeroSigmaGivesTheTruthExactly) {
  TempDir dir;
  const fs::path root = WriteNadirCollection(dir.path() / "c", 50);
  for (NoiseModel model : {NoiseModel::kGaussian, NoiseModel::kUniform, NoiseModel::kGaussMarkov}) {
    PerturbOptions options = Options(root, 1);
    options.force = true;
    options.spec.model = model;
    options.spec.tau = model == NoiseModel::kGaussMarkov ? 2.0 : 0.0;
    const PerturbResult result = PerturbCollection(options);
    const std::vector<nlohmann::json> truth = Frames(root / "metadata.json");
    std::vector<nlohmann::json> measured = Frames(result.output);
    ASSERT_EQ(truth.size(), measured.size());
    for (size_t k = 0; k < truth.size(); ++k) {
      EXPECT_EQ(measured[k].at("error").at("rotation_deg").get<double>(), 0.0);
      measured[k].erase("error");
      EXPECT_EQ(measured[k].dump(), truth[k].dump()) << NoiseModelName(model) << " frame " << k;
    }
  }
}

TEST(PerturbCollection, SameSeedIsByteIdenticalAndAnotherSeedIsNot) {
  TempDir dir;
  const fs::path a = WriteNadirCollection(dir.path() / "a", 40);
  fs::copy(a, dir.path() / "b", fs::copy_options::recursive);
  for (NoiseModel model : {NoiseModel::kGaussian, NoiseModel::kUniform, NoiseModel::kGaussMarkov}) {
    PerturbOptions options = Options(a, 99);
    options.force = true;
    options.report = true;
    options.spec.model = model;
    options.spec.tau = model == NoiseModel::kGaussMarkov ? 0.5 : 0.0;
    options.spec.sigma = {1, 1, 1, 0.3, 0.3, 0.3, 0.01, 0.2};
    const PerturbResult first = PerturbCollection(options);
    options.collection = dir.path() / "b";
    const PerturbResult second = PerturbCollection(options);
    EXPECT_TRUE(ReadText(first.output) == ReadText(second.output)) << NoiseModelName(model);
    EXPECT_TRUE(ReadText(*first.report) == ReadText(*second.report)) << NoiseModelName(model);
    EXPECT_TRUE(ReadText(a / "collection.json") == ReadText(dir.path() / "b" / "collection.json"));
    options.spec.seed = 100;
    options.output = dir.path() / "other.json";  // outside: b's collection.json stays as a's
    options.report = false;
    EXPECT_TRUE(ReadText(PerturbCollection(options).output) != ReadText(first.output));
  }
}

TEST(PerturbCollection, BadInputIsRefusedAndNothingIsWritten) {
  TempDir dir;
  const fs::path root = WriteNadirCollection(dir.path() / "c", 5);
  auto listing = [&] {
    std::set<std::string> names;
    for (const auto& entry : fs::recursive_directory_iterator(dir.path())) {
      names.insert(entry.path().string());
    }
    return names;
  };
  const std::set<std::string> before = listing();
  const std::string collection_before = ReadText(root / "collection.json");
  auto expect_refused = [&](PerturbOptions options, const std::string& words) {
    try {
      PerturbCollection(options);
      ADD_FAILURE() << "accepted; expected an error with '" << words << "'";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
    EXPECT_EQ(listing(), before);
    EXPECT_TRUE(ReadText(root / "collection.json") == collection_before);
  };
  PerturbOptions negative = Options(root, 1);
  negative.spec.sigma[kUp] = -0.5;
  expect_refused(negative, "--sigma-alt");
  PerturbOptions no_tau = Options(root, 1);
  no_tau.spec.model = NoiseModel::kGaussMarkov;
  expect_refused(no_tau, "--tau");
  PerturbOptions not_a_collection = Options(dir.path(), 1);
  expect_refused(not_a_collection, "not an lsds collection");
  PerturbOptions onto_truth = Options(root, 1);
  onto_truth.output = root / "metadata.json";
  onto_truth.force = true;
  expect_refused(onto_truth, "is the truth metadata");
  PerturbOptions no_folder = Options(root, 1);
  no_folder.output = dir.path() / "missing" / "x.json";
  expect_refused(no_folder, "folder does not exist");
  PerturbOptions too_wide = Options(root, 1);
  too_wide.spec.bias[kHfov] = 170;
  expect_refused(too_wide, "field of view");

  // An existing output without --force: refused, and the existing file is left
  // as it was.
  fs::create_directories(dir.path() / "keep");
  WriteFileAtomic(root / "metadata.perturbed-1.json", "precious");
  const std::set<std::string> with_existing = listing();
  PerturbOptions existing = Options(root, 1);
  existing.spec.sigma.fill(1.0);
  try {
    PerturbCollection(existing);
    ADD_FAILURE() << "overwrote an existing output";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("--force"), std::string::npos) << e.what();
  }
  EXPECT_EQ(ReadText(root / "metadata.perturbed-1.json"), "precious");
  EXPECT_EQ(listing(), with_existing);
}

TEST(PerturbCollection, CollectionWithoutMetadataIsRefused) {
  TempDir dir;
  const fs::path root = WriteNadirCollection(dir.path() / "c", 3);
  fs::remove(root / "metadata.json");
  PerturbOptions options = Options(root, 1);
  options.spec.sigma.fill(1.0);
  EXPECT_THROW(PerturbCollection(options), Error);
  EXPECT_FALSE(fs::exists(root / "metadata.perturbed-1.json"));
}

TEST(PerturbCollection, OutputOutsideTheCollectionIsWrittenButNotRegistered) {
  TempDir dir;
  const fs::path root = WriteNadirCollection(dir.path() / "c", 3);
  const std::string collection_before = ReadText(root / "collection.json");
  PerturbOptions options = Options(root, 1);
  options.spec.sigma.fill(1.0);
  options.output = dir.path() / "elsewhere.json";
  const PerturbResult result = PerturbCollection(options);
  EXPECT_TRUE(result.registered_as.empty());
  EXPECT_TRUE(fs::exists(dir.path() / "elsewhere.json"));
  EXPECT_TRUE(ReadText(root / "collection.json") == collection_before);
}

// The report: a rotation of the nadir camera about its right axis by theta
// moves points near the image centre by about f * theta pixels; a horizontal
// offset d at height h moves a point at depth z by f * d / z. Exact zero error
// moves nothing.
TEST(PerturbReport, PixelMotionMatchesTheGeometry) {
  TempDir dir;
  const fs::path root = WriteNadirCollection(dir.path() / "c", 4, 64, 48);
  const double f = PinholeCamera::FromHorizontalFov(64, 48, 60).fx;

  PerturbOptions options = Options(root, 1);
  options.report = true;
  options.force = true;
  options.spec.bias[kPitch] = 0.5;
  PerturbResult result = PerturbCollection(options);
  ASSERT_TRUE(result.report_summary);
  const double theta = 0.5 * M_PI / 180;
  const nlohmann::json& rotation = *result.report_summary;
  EXPECT_GT(rotation["corners"].get<int64_t>(), 0);
  // Corners up to tan(30 deg) from the axis: displacement between f theta
  // and 1.34 f theta.
  EXPECT_GE(rotation["mean_px"].get<double>(), f * theta * 0.999);
  EXPECT_LE(rotation["max_px"].get<double>(), f * theta * 1.34);
  EXPECT_GE(rotation["p95_px"].get<double>(), rotation["mean_px"].get<double>() * 0.99);
  EXPECT_LE(rotation["p95_px"].get<double>(), rotation["max_px"].get<double>() * 1.002);

  options.spec.bias[kPitch] = 0;
  options.spec.bias[kEast] = 1.0;
  result = PerturbCollection(options);
  // Corners lie between the ground (z = 20 m from the camera) and the box tops
  // (z = 18 m).
  const nlohmann::json& shift = *result.report_summary;
  EXPECT_GE(shift["mean_px"].get<double>(), f / 20.0 * 0.999);
  EXPECT_LE(shift["max_px"].get<double>(), f / 18.0 * 1.001);

  // Per-frame entries are written for every frame and agree with the summary.
  const nlohmann::json report = nlohmann::json::parse(ReadText(*result.report));
  ASSERT_EQ(report["frames"].size(), 4u);
  double max_px = 0;
  for (const nlohmann::json& frame : report["frames"])
    max_px = std::max(max_px, frame["max_px"].get<double>());
  EXPECT_EQ(max_px, shift["max_px"].get<double>());

  options.spec.bias[kEast] = 0;
  result = PerturbCollection(options);
  EXPECT_LT((*result.report_summary)["max_px"].get<double>(), 1e-9);
}

}  // namespace
}  // namespace lsds::noise

// Every distribution of the report counts exactly what the collection's truth
// says: expectations are recomputed here from the truth with plain loops, and
// the camera figures from the analytic scene.
#include <cmath>
#include <fstream>

#include <gtest/gtest.h>

#include "libs/collection/collection_reader.h"
#include "perturb/perturb_collection.h"
#include "report/frame_sampler.h"
#include "report/report.h"
#include "synth/synthetic_collection.h"
#include "tests/test_util.h"

namespace lsds::report {
namespace {

// The bin of `value` by linear search: [e_i, e_i+1), the last bin closed;
// -1 below, -2 above.
int BinOf(const std::vector<double>& edges, double value) {
  if (value < edges.front()) return -1;
  for (size_t i = 0; i + 1 < edges.size(); ++i) {
    const bool last = i + 2 == edges.size();
    if (value >= edges[i] && (value < edges[i + 1] || (last && value == edges[i + 1])))
      return static_cast<int>(i);
  }
  return -2;
}

struct Expected {
  std::vector<int64_t> counts;
  int64_t below = 0, above = 0, invalid = 0;
  explicit Expected(const Histogram& h) : counts(h.bins(), 0) {}
  void Add(const Histogram& h, double value) {
    if (std::isnan(value)) return void(++invalid);
    const int bin = BinOf(h.edges, value);
    if (bin == -1) return void(++below);
    if (bin == -2) return void(++above);
    ++counts[bin];
  }
};

void ExpectSame(const Histogram& actual, const Expected& expected) {
  EXPECT_EQ(actual.counts, expected.counts) << actual.id;
  EXPECT_EQ(actual.below, expected.below) << actual.id;
  EXPECT_EQ(actual.above, expected.above) << actual.id;
  EXPECT_EQ(actual.invalid, expected.invalid) << actual.id;
}

// Nadir frames over the boxes plus one oblique frame looking 26.6 degrees off
// nadir, so that every camera figure has more than one value.
synth::Spec TestSpec() {
  synth::Spec spec = synth::DefaultSpec();
  spec.width = 96, spec.height = 72;
  spec.cam_from_world.push_back(LookAt({0, -10, 20}, {0, 0, 0}, Eigen::Vector3d::UnitY()));
  spec.cam_from_world.push_back(synth::NadirCamFromWorld({0, 0, 12}));
  return spec;
}

TEST(Distributions, CountsEqualTheCollectionTruth) {
  testing::TempDir dir;
  const synth::Spec spec = TestSpec();
  synth::WriteCollection(dir / "c", spec);
  const CollectionReader reader(dir / "c");
  ReportOptions options;
  options.sample = 3;
  const ReportData data = CollectReportData(reader, options);
  const Distributions& d = data.distributions;
  const int frames = static_cast<int>(spec.cam_from_world.size());
  EXPECT_EQ(d.frames, frames);

  std::map<std::string, Expected> e;
  for (const Histogram& h : d.histograms) e.emplace(h.id, Expected(h));
  const auto add = [&](const std::string& id, double v) { e.at(id).Add(d.Get(id), v); };
  const PinholeCamera camera =
      PinholeCamera::FromHorizontalFov(spec.width, spec.height, spec.hfov_deg);
  const synth::AnalyticScene scene = spec.Scene();
  int64_t objects = 0, visible = 0;
  for (int f = 0; f < frames; ++f) {
    // The truth as the synthetic builder measured it for this frame.
    const Frame truth = synth::RenderFrame(spec, f).truth;
    const Rigid3d world_from_cam = spec.cam_from_world[f].Inverse();
    const Eigen::Vector3d centre = world_from_cam.translation;
    for (const ObjectTruth& o : truth.objects) {
      ++objects;
      add("visibility", o.visibility);
      add("in-frame", o.in_frame);
      if (o.visible_pixels == 0) continue;
      ++visible;
      ++e.at("class").counts[o.class_id - 1];  // classes 1, 2, 3 in order
      add("box-size", std::max(o.bbox->width(), o.bbox->height()));
      add("visible-pixels", static_cast<double>(o.visible_pixels));
      add("distance", (o.obb->center - centre).norm());
    }
    // The ray through the pixel that holds the principal point.
    const Eigen::Vector3d ray =
        (world_from_cam.rotation *
         camera.CamFromImage({std::floor(camera.cx) + 0.5, std::floor(camera.cy) + 0.5}))
            .normalized();
    const synth::Hit hit = scene.Intersect(centre, ray);
    ASSERT_TRUE(hit.hit);
    const Eigen::Vector3d point = centre + hit.t * ray;
    add("altitude", centre.z() - point.z());
    add("gsd", 100.0 * hit.t / camera.fx);
    const Eigen::Vector3d axis = world_from_cam.rotation * Eigen::Vector3d::UnitZ();
    add("off-nadir", std::acos(-axis.normalized().z()) * 180.0 / M_PI);
    add("sun-elevation", 0.0 / 0.0);  // synth frames carry no scene state
  }
  EXPECT_EQ(d.objects, objects);
  EXPECT_EQ(d.visible_objects, visible);
  for (const Histogram& h : d.histograms) ExpectSame(h, e.at(h.id));

  // The figures the cases above rely on really vary.
  const Histogram& off = d.Get("off-nadir");
  EXPECT_EQ(off.counts[0], frames - 1);
  EXPECT_EQ(off.counts[5], 1);  // atan(10 / 20) = 26.57 degrees
  int altitude_bins = 0;
  for (int64_t c : d.Get("altitude").counts) altitude_bins += c > 0;
  EXPECT_GE(altitude_bins, 2);
  EXPECT_EQ(d.Get("class").counts[0], 0);  // ground is not a target
  EXPECT_GT(d.Get("class").counts[1], 0);
  EXPECT_GT(d.Get("class").counts[2], 0);
}

TEST(Distributions, MetadataErrorsEqualTheRealizedErrors) {
  testing::TempDir dir;
  synth::Spec spec = synth::CircleSpec(30, 32, 24);
  synth::WriteCollection(dir / "c", spec);
  noise::PerturbOptions perturb;
  perturb.collection = dir / "c";
  perturb.spec.seed = 7;
  perturb.spec.sigma[noise::kEast] = perturb.spec.sigma[noise::kNorth] = 0.5;
  perturb.spec.sigma[noise::kYaw] = 1.0;
  perturb.progress = false;
  const noise::PerturbResult perturbed = noise::PerturbCollection(perturb);

  const CollectionReader reader(dir / "c");
  const ReportData data = CollectReportData(reader, ReportOptions());
  const Distributions& d = data.distributions;
  EXPECT_EQ(d.metadata_variant, perturbed.registered_as);
  Expected position(d.Get("metadata-position")), rotation(d.Get("metadata-rotation"));
  // The realized errors as the perturbed file records them.
  const nlohmann::json file = nlohmann::json::parse(std::ifstream(perturbed.output));
  int frames = 0;
  for (const nlohmann::json& frame : file.at("frames")) {
    const nlohmann::json& e = frame.at("error");
    const double de = e["position_enu_m"][0], dn = e["position_enu_m"][1],
                 du = e["position_enu_m"][2];
    position.Add(d.Get("metadata-position"), std::sqrt(de * de + dn * dn + du * du));
    rotation.Add(d.Get("metadata-rotation"), e["rotation_deg"].get<double>());
    ++frames;
  }
  EXPECT_EQ(frames, 30);
  ExpectSame(d.Get("metadata-position"), position);
  ExpectSame(d.Get("metadata-rotation"), rotation);
  EXPECT_EQ(d.Get("metadata-position").total(), 30);
}

TEST(Distributions, FrameRangeSelectsByIndex) {
  testing::TempDir dir;
  const synth::Spec spec = TestSpec();
  synth::WriteCollection(dir / "c", spec);
  const CollectionReader reader(dir / "c");
  ReportOptions options;
  options.frames = FrameRange{1, 3};
  const ReportData data = CollectReportData(reader, options);
  EXPECT_EQ(data.distributions.frames, 2);
  ASSERT_EQ(data.samples.size(), 2u);
  EXPECT_EQ(data.samples[0].frame.index, 1);
  EXPECT_EQ(data.samples[1].frame.index, 2);
}

TEST(Histogram, BinsEdgesAndOutliers) {
  Histogram h = MakeNumeric("v", "V", "v", "", "things", LinearEdges(0, 1, 0.1));
  ASSERT_EQ(h.bins(), 10u);
  h.Add(0.0), h.Add(0.1), h.Add(0.95), h.Add(1.0), h.Add(-0.5), h.Add(1.5), h.Add(0.0 / 0.0);
  EXPECT_EQ(h.counts[0], 1);
  EXPECT_EQ(h.counts[1], 1);
  EXPECT_EQ(h.counts[9], 2);  // 1.0 closes the last bin
  EXPECT_EQ(h.below, 1);
  EXPECT_EQ(h.above, 1);
  EXPECT_EQ(h.invalid, 1);
  EXPECT_EQ(h.total(), 6);
  EXPECT_EQ(OneTwoFiveEdges(0.1, 10), (std::vector<double>{0.1, 0.2, 0.5, 1, 2, 5, 10}));
}

TEST(FrameSampler, EvenSpreadInOnePassWithForcedFramesWithinTheTarget) {
  FrameSampler<int> sampler(10, {503});
  for (int i = 0; i < 1000; ++i) sampler.Offer(i, i);
  const std::vector<int> taken = sampler.Take();
  // --sample 10 is 10 frames, the forced one among them.
  ASSERT_EQ(taken.size(), 10u);
  EXPECT_TRUE(std::is_sorted(taken.begin(), taken.end()));
  EXPECT_NE(std::find(taken.begin(), taken.end(), 503), taken.end());
  std::vector<int> even;
  for (int t : taken) {
    if (t != 503) even.push_back(t);
  }
  // The other 9, one per ninth of the stream.
  ASSERT_EQ(even.size(), 9u);
  for (size_t k = 0; k < even.size(); ++k) {
    EXPECT_GE(even[k], static_cast<int>(k) * 1000 / 9) << k;
    EXPECT_LT(even[k], static_cast<int>(k + 1) * 1000 / 9) << k;
  }
  FrameSampler<int> few(10);
  for (int i = 0; i < 4; ++i) few.Offer(i, i);
  EXPECT_EQ(few.Take(), (std::vector<int>{0, 1, 2, 3}));
}

// More frames with findings than --sample: the sheet still holds --sample
// frames, the first ones with findings.
TEST(FrameSampler, ForcedFramesNeverExceedTheTarget) {
  FrameSampler<int> sampler(3, {10, 20, 30, 40, 50});
  for (int i = 0; i < 100; ++i) sampler.Offer(i, i);
  EXPECT_EQ(sampler.Take(), (std::vector<int>{10, 20, 30}));
}

}  // namespace
}  // namespace lsds::report

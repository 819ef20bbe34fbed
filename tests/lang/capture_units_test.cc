// The units of the LCAP evaluator (generator/lang/capture/), each on its own with inputs whose
// answer is known: flights, the camera setup, camera paths, the timeline and timing, quota draws,
// class swaps, object changes and motion, the placement kept across changes, re-scatter,
// clearance and targets.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>

#include "generator/lang/capture/camera_paths.h"
#include "generator/lang/capture/camera_setup.h"
#include "generator/lang/capture/change_rules.h"
#include "generator/lang/capture/class_swaps.h"
#include "generator/lang/capture/clearance.h"
#include "generator/lang/capture/flight.h"
#include "generator/lang/capture/keep_placement.h"
#include "generator/lang/capture/object_changes.h"
#include "generator/lang/capture/object_track.h"
#include "generator/lang/capture/quota_draws.h"
#include "generator/lang/capture/rescatter.h"
#include "generator/lang/capture/targets.h"
#include "generator/lang/capture/timeline.h"
#include "generator/lang/source.h"
#include "libs/geometry/attitude.h"
#include "libs/util/error.h"
#include "tests/generator/test_plans.h"
#include "tests/lang/plan_text.h"

namespace lsds {
namespace {

using gen::testing::Box;
using gen::testing::FlatPlan;

// A parsed LCAP (or LSCENE) text; kept in place, as its program points into its source.
struct Text {
  Text(const std::string& text, const std::string& start)
      : src(ParseSource(text, start == "LCAP" ? "c.lcap" : "s.lscene", false)),
        program(ReadProgram(src, start)) {}
  const Definition& Def(const std::string& symbol) const { return *program.Find(symbol); }
  // The single generator of path `symbol`.
  Node Generator(const std::string& symbol) const {
    return Def(symbol).body.Members().front().second;
  }
  SourceFile src;
  Program program;
};

std::unique_ptr<Text> Lcap(const std::string& text) { return std::make_unique<Text>(text, "LCAP"); }

using testing::ErrorOf;

// ---- flight.h

TEST(CaptureFlight, PolylineArcLengthPositionAndVelocity) {
  Flight flight;
  flight.speed = 2;
  flight.Build({{0, 0, 0}, {10, 0, 0}, {10, 10, 0}},
               std::vector<Eigen::Quaterniond>(3, Eigen::Quaterniond::Identity()),
               false);
  EXPECT_NEAR(flight.length, 20, 1e-12);
  const FlightSample at = flight.At(15);
  EXPECT_NEAR((at.centre - Eigen::Vector3d(10, 5, 0)).norm(), 0, 1e-12);
  EXPECT_NEAR((at.tangent - Eigen::Vector3d(0, 1, 0)).norm(), 0, 1e-12);
  EXPECT_NEAR((at.velocity - Eigen::Vector3d(0, 2, 0)).norm(), 0, 1e-12);
  EXPECT_NEAR((flight.At(99).centre - Eigen::Vector3d(10, 10, 0)).norm(), 0, 1e-12);  // clamped
}

TEST(CaptureFlight, SplinePassesThroughItsWaypoints) {
  Flight flight;
  const std::vector<Eigen::Vector3d> centres = {{0, 0, 0}, {10, 5, 0}, {20, 0, 3}};
  flight.Build(centres, std::vector<Eigen::Quaterniond>(3, Eigen::Quaterniond::Identity()), true);
  // Sample 64 of the dense curve is waypoint 1 (parameter 1).
  const size_t i = Flight::kSamplesPerSegment;
  EXPECT_DOUBLE_EQ(flight.param[i], 1.0);
  EXPECT_NEAR((flight.points[i] - centres[1]).norm(), 0, 1e-12);
  EXPECT_NEAR((flight.At(flight.along[i]).centre - centres[1]).norm(), 0, 1e-9);
  EXPECT_GT(flight.length, (centres[1] - centres[0]).norm() + (centres[2] - centres[1]).norm());
}

TEST(CaptureFlight, SettingsGiveSpeedSpacingAndInterpolation) {
  const auto c = Lcap(
      "LCAP = ONE(W) ONE(S)\nW = path{waypoints:{points:[[0,0,10],[100,0,10]],speed:5}}\n"
      "S = path{waypoints:{points:[[0,0,10],[100,0,10]],speed:5,interpolation:spline}}\n");
  Rng rng(1);
  Flight flight;
  EXPECT_FALSE(ReadFlightSettings(c->Generator("W"), 10, rng, &flight));
  EXPECT_EQ(flight.speed, 5);
  EXPECT_EQ(flight.spacing, 0.5);
  EXPECT_TRUE(ReadFlightSettings(c->Generator("S"), 10, rng, &flight));
  const auto bad = Lcap(
      "LCAP = ONE(W)\nW = path{waypoints:{points:[[0,0,1],[1,0,1]],speed:5,"
      "interpolation:cubic}}\n");
  EXPECT_NE(
      ErrorOf([&] { ReadFlightSettings(bad->Generator("W"), 10, rng, &flight); }).find("c.lcap:2:"),
      std::string::npos);
}

// ---- camera_setup.h

TEST(CaptureCameraSetup, SettingsAndWhatTheyWriteInThePlan) {
  const auto c = Lcap(
      "LCAP = ONE(CO)\nCO = camera{csettings:{fov:90,res:[640,480],fps:4,heights:agl,"
      "clearance:off,ev100:12},capture:{layers:[rgb,depth,rgb]},PPMaterial:[EdgeBlur]}\n");
  Plan plan;
  const CameraSetup setup = ReadCameraSetup(&c->Def("CO"), &plan);
  EXPECT_EQ(setup.fps, 4);
  EXPECT_TRUE(setup.heights_agl);
  EXPECT_FALSE(setup.clearance_m.has_value());
  EXPECT_EQ(setup.intrinsics.width, 640);
  EXPECT_NEAR(setup.intrinsics.fx, 320, 1e-9);  // 640 / 2 / tan(45 deg)
  EXPECT_EQ(plan.capture_settings["layers"], nlohmann::json({"rgb", "depth"}));
  EXPECT_EQ(plan.post_process, std::vector<std::string>{"EdgeBlur"});
  EXPECT_EQ(plan.exposure.ev100, 12);
}

TEST(CaptureCameraSetup, ThePapersLayerNamesNameTheirLayers) {
  const auto c = Lcap(
      "LCAP = ONE(CO)\nCO = camera{capture:{layers:[rgb,worlddepth,\"object IDs\",shadows,"
      "\"surface normals\",\"motion vectors\",\"world locations\"]}}\n");
  Plan plan;
  ReadCameraSetup(&c->Def("CO"), &plan);
  EXPECT_EQ(
      plan.capture_settings["layers"],
      nlohmann::json({"rgb", "depth", "classid", "shadow", "normal", "motion", "worldposition"}));
}

TEST(CaptureCameraSetup, NoCameraGivesTheDefaults) {
  Plan plan;
  const CameraSetup setup = ReadCameraSetup(nullptr, &plan);
  EXPECT_EQ(setup.fps, 10);
  EXPECT_EQ(setup.clearance_m, kDefaultClearanceM);
  EXPECT_EQ(setup.intrinsics.width, 1024);
  EXPECT_TRUE(plan.post_process.empty());
  EXPECT_FALSE(plan.rig);
}

TEST(CaptureCameraSetup, BadValuesAreLocated) {
  const auto c = Lcap("LCAP = ONE(CO)\nCO = camera{csettings:{heights:sea}}\n");
  Plan plan;
  EXPECT_NE(ErrorOf([&] {
              ReadCameraSetup(&c->Def("CO"), &plan);
            }).find("c.lcap:2:32: heights is agl (above the terrain) or datum"),
            std::string::npos)
      << ErrorOf([&] { ReadCameraSetup(&c->Def("CO"), &plan); });
}

// ---- camera_paths.h and timeline.h

constexpr const char* kTimelineLcap =
    "LCAP = ONE(CO) ONE(G) ONE(PT) ONE(CL)\n"
    "CO = camera{csettings:{fps:2}}\n"
    "G = path{grid:{x:[0,10,2],y:[0,10,2],altitude:20}}\n"
    "PT = path{create point:{position:[0,0,30],count:3}}\n"
    "CL = collection{CO:{move:[G:2,PT]}}\n";

struct TimelineFixture {
  TimelineFixture() : c(Lcap(kTimelineLcap)), plan(FlatPlan()) {
    setup = ReadCameraSetup(&c->Def("CO"), &plan);
    paths = std::make_unique<CameraPaths>(setup, plan, 1, "");
    timeline = std::make_unique<Timeline>(
        c->program,
        [](const std::string& key, const Node&) { return key == "CO"; },
        [this](const Definition& path, uint64_t segment) {
          return paths->FrameCount(path, segment);
        });
  }
  std::unique_ptr<Text> c;
  Plan plan;
  CameraSetup setup;
  std::unique_ptr<CameraPaths> paths;
  std::unique_ptr<Timeline> timeline;
};

// The camera paths of an LCAP text whose camera is CO, over flat ground; a grid's point
// blueprint may name the text's paths.
struct PathsFixture {
  explicit PathsFixture(const std::string& text, uint64_t seed = 1)
      : c(Lcap(text)),
        plan(FlatPlan()),
        setup(ReadCameraSetup(&c->Def("CO"), &plan)),
        paths(setup, plan, seed, "", &c->program) {}
  std::unique_ptr<Text> c;
  Plan plan;
  CameraSetup setup;
  CameraPaths paths;
};

TEST(CaptureTimeline, SegmentsFollowTheCameraMoves) {
  TimelineFixture t;
  const std::vector<Segment>& s = t.timeline->segments();
  ASSERT_EQ(s.size(), 3u);
  EXPECT_EQ(s[0].path->symbol, "G");
  EXPECT_EQ(s[1].repetition, 2);
  EXPECT_EQ(s[1].first, 4);
  EXPECT_EQ(s[2].path->symbol, "PT");
  EXPECT_EQ(s[2].first, 8);
  EXPECT_EQ(s[2].count, 3);
  EXPECT_EQ(t.timeline->steps(), 11);
  EXPECT_EQ(&t.timeline->At(9), &s[2]);
  const Node where = t.c->Def("CL").body;
  EXPECT_EQ(t.timeline->Span(where, "G", -1), std::make_pair(int64_t{0}, int64_t{8}));
  EXPECT_EQ(t.timeline->Span(where, "G", 2), std::make_pair(int64_t{4}, int64_t{8}));
  EXPECT_EQ(t.timeline->Span(where, "CL", -1), std::make_pair(int64_t{0}, int64_t{11}));
  const std::string error = ErrorOf([&] { t.timeline->Span(where, "GG", -1); });
  EXPECT_NE(error.find("c.lcap:5:6: 'GG' is not a path the camera moves along (did you mean 'G'?)"),
            std::string::npos)
      << error;
}

TEST(CaptureTimeline, SequenceNamesAreUniqueAcrossMovesAndCollections) {
  PathsFixture t(
      "LCAP = ONE(CO) ONE(W1) ONE(CL1) ONE(CL2)\nCO = camera{}\n"
      "W1 = path{create point:{position:[0,0,30],count:2}}\n"
      "CL1 = collection{CO:{move:[W1:2]}}\nCL2 = collection{CO:{move:[W1]}}\n");
  const auto& c = t.c;
  CameraPaths& paths = t.paths;
  const Timeline timeline(
      c->program,
      [](const std::string& key, const Node&) { return key == "CO"; },
      [&](const Definition& path, uint64_t segment) { return paths.FrameCount(path, segment); });
  ASSERT_EQ(timeline.segments().size(), 3u);
  EXPECT_EQ(timeline.segments()[2].repetition, 3);  // CL2's flight of W1 is W1(3), not W1(1)
  EXPECT_EQ(timeline.segments()[2].collection, &c->Def("CL2"));
  EXPECT_EQ(timeline.Span(c->Def("CL2").body, "W1", 3), std::make_pair(int64_t{4}, int64_t{6}));
}

TEST(CaptureTimeline, TimingResolvesAgainstTheSpans) {
  TimelineFixture t;
  const auto w = Lcap(
      "LCAP = ONE(A)\nA = collection{O:[{after:G:1},{during:PT},{when:{frame:3}},{during:5}]}\n");
  std::vector<RuleTiming> timings;
  for (const Node& block : Blocks(w->Def("A").body.Child("O"))) {
    RuleTiming timing;
    ReadTiming(block, *t.timeline, &timing);
    timings.push_back(timing);
  }
  ASSERT_EQ(timings.size(), 4u);
  EXPECT_EQ(timings[0].begin, 4);
  EXPECT_FALSE(timings[0].during);
  EXPECT_EQ(timings[1].begin, 8);
  EXPECT_EQ(timings[1].end, 11);
  EXPECT_TRUE(timings[1].during);
  EXPECT_EQ(timings[2].begin, 3);
  EXPECT_EQ(timings[3].begin, 5);
  EXPECT_EQ(timings[3].end, 6);
}

TEST(CaptureCameraPaths, GridIsFlownSerpentineAboveTheTerrain) {
  TimelineFixture t;
  const Definition& grid = t.c->Def("G");
  const Eigen::Vector3d expected[] = {{0, 0, 20}, {10, 0, 20}, {10, 10, 20}, {0, 10, 20}};
  for (int i = 0; i < 4; ++i) {
    Rng rng(5);
    const Rigid3d pose = t.paths->Pose(grid, i, rng, 0, nullptr, nullptr);
    EXPECT_NEAR((CameraCenterInWorld(pose) - expected[i]).norm(), 0, 1e-9) << i;
    EXPECT_EQ(t.paths->ShotStart(grid, 100, i), 100);  // one altitude level: one shot
  }
  EXPECT_EQ(t.paths->ShotStart(t.c->Def("PT"), 100, 2), 102);  // every point its own shot
}

TEST(CaptureCameraPaths, HemiLooksAtItsCentreFromItsRadius) {
  PathsFixture t(
      "LCAP = ONE(CO) ONE(H)\nCO = camera{}\n"
      "H = path{create hemi:{cam radius:[100,200,2],obj angle:[0,270,4],cam angle:[30,60,2],"
      "center:[5,5,0]}}\n");
  const auto& c = t.c;
  CameraPaths& paths = t.paths;
  EXPECT_EQ(paths.FrameCount(c->Def("H"), 0), 16);
  Rng rng(1);
  // Pose 13: radius 200 (13 / 8), elevation 30 deg ((13 / 4) % 2 = 1 -> 60), azimuth 90 deg.
  const Eigen::Vector3d eye =
      CameraCenterInWorld(paths.Pose(c->Def("H"), 13, rng, 0, nullptr, nullptr));
  const double deg = M_PI / 180;
  EXPECT_NEAR(
      (eye - Eigen::Vector3d(5, 5 + 200 * std::cos(60 * deg), 200 * std::sin(60 * deg))).norm(),
      0,
      1e-9);
}

TEST(CaptureCameraPaths, RandomAltitudeIsDrawnWithinTheDemandedBin) {
  PathsFixture t(
      "LCAP = ONE(CO) ONE(R)\nCO = camera{}\nR = path{random:{count:5,altitude:[15,60]}}\n");
  const auto& c = t.c;
  CameraPaths& paths = t.paths;
  Quota quota;
  quota.quantity = "altitude";
  quota.edges = {15, 30, 60};
  quota.weights = {0.5, 0.5};
  FrameDemand demand;
  demand.bins = {{&quota, 1}};
  for (uint64_t k = 0; k < 50; ++k) {
    Rng rng = Rng::For(3, StreamTag::kFrame, k);
    const double z = CameraCenterInWorld(paths.Pose(c->Def("R"), 0, rng, 0, nullptr, &demand)).z();
    EXPECT_GE(z, 30);
    EXPECT_LE(z, 60);
  }
}

// The bounds of the camera centre of pose `i` of `path` over 200 draws, each checked to look
// straight down (the optical axis, camera +z, is the world's -z).
std::pair<Eigen::Vector3d, Eigen::Vector3d> NadirEyeBounds(CameraPaths* paths,
                                                           const Definition& path,
                                                           int64_t i) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e9), hi = -lo;
  for (uint64_t k = 0; k < 200; ++k) {
    Rng rng = Rng::For(3, StreamTag::kFrame, k);
    const Rigid3d pose = paths->Pose(path, i, rng, 0, nullptr, nullptr);
    lo = lo.cwiseMin(CameraCenterInWorld(pose));
    hi = hi.cwiseMax(CameraCenterInWorld(pose));
    EXPECT_NEAR(
        (pose.rotation.inverse() * Eigen::Vector3d::UnitZ() - Eigen::Vector3d(0, 0, -1)).norm(),
        0,
        1e-9);
  }
  return {lo, hi};
}

TEST(CaptureCameraPaths, CreatePathDrawsItsPointsInItsSpaceLookingDown) {
  PathsFixture t(
      "LCAP = ONE(CO) ONE(P)\nCO = camera{}\n"
      "P = path{create path:{space:[[-10,-20,30],[10,20,60]],points:7}}\n"
      "Q = path{create path:{space:[[0,0,0],[1,1]],points:2}}\n");
  const auto& c = t.c;
  CameraPaths& paths = t.paths;
  EXPECT_EQ(paths.FrameCount(c->Def("P"), 0), 7);
  const auto [lo, hi] = NadirEyeBounds(&paths, c->Def("P"), 0);
  EXPECT_GE(lo.minCoeff(), -20);
  EXPECT_LE(hi.x(), 10);
  EXPECT_LE(hi.y(), 20);
  EXPECT_GE(lo.z(), 30);
  EXPECT_LE(hi.z(), 60);
  EXPECT_GT(hi.y() - lo.y(), 30);  // spread over the space, not one point
  EXPECT_NE(ErrorOf([&] { paths.FrameCount(c->Def("Q"), 0); }).find("c.lcap:4:"),
            std::string::npos);
}

// The paper's point blueprint fed to increment point (section 3.2): a generic point whose position
// box is the noise about each grid point and whose rotation is the attitude there.
TEST(CaptureCameraPaths, APointBlueprintPerturbsAndTurnsEveryGridPoint) {
  PathsFixture t(
      "LCAP = ONE(CO) ONE(N) ONE(G) ONE(J)\nCO = camera{}\n"
      "N = path{create point:{position:[1,2,3],rotation:[0,-60,45]}}\n"
      "G = path{increment point:{start:[0,0,20],step:[10,10,0],count:[2,2,1],point:N}}\n"
      "J = path{increment point:{x:[0,10,2],y:[0,10,2],altitude:20,"
      "point:{position:[[-1,-1,-0.5],[1,1,0.5]]}}}\n"
      "B1 = path{grid:{x:[0,10,2],y:[0,10,2],altitude:20,point:G}}\n"
      "B2 = path{grid:{x:[0,10,2],y:[0,10,2],altitude:20,perturb:[1,1,1],point:N}}\n"
      "B3 = path{grid:{x:[0,10,2],y:[0,10,2],altitude:20,point:{rotation:[0,-90,0]}}}\n");
  const auto& c = t.c;
  CameraPaths& paths = t.paths;
  ASSERT_EQ(paths.FrameCount(c->Def("G"), 0), 4);
  const Eigen::Vector3d grid[] = {{0, 0, 20}, {10, 0, 20}, {10, 10, 20}, {0, 10, 20}};
  for (int i = 0; i < 4; ++i) {
    Rng rng(5);
    const Rigid3d pose = paths.Pose(c->Def("G"), i, rng, 0, nullptr, nullptr);
    const Eigen::Vector3d eye = grid[i] + Eigen::Vector3d(1, 2, 3);
    EXPECT_NEAR((CameraCenterInWorld(pose) - eye).norm(), 0, 1e-9) << i;
    EXPECT_NEAR(
        pose.rotation.angularDistance(CamFromEnu(eye, Attitude{0, -60, 45}).rotation), 0, 1e-12)
        << i;
  }
  // A box of noise: every point within it about its grid point, spread over it, looking down.
  auto [lo, hi] = NadirEyeBounds(&paths, c->Def("J"), 2);
  lo -= Eigen::Vector3d(10, 10, 20);  // the noise about grid point 2
  hi -= Eigen::Vector3d(10, 10, 20);
  EXPECT_GE(lo.x(), -1);
  EXPECT_GE(lo.z(), -0.5);
  EXPECT_LE(hi.y(), 1);
  EXPECT_LE(hi.z(), 0.5);
  EXPECT_GT(hi.x() - lo.x(), 1.5);
  EXPECT_GT(hi.z() - lo.z(), 0.75);
  // A pair, not a structured binding: clang 14 (the sanitizer build) cannot capture a binding.
  for (const auto& symbol_message :
       std::vector<std::pair<std::string, std::string>>{{"B1", "c.lcap:6:57:"},
                                                        {"B1", "not a create point path"},
                                                        {"B2", "give one of them"},
                                                        {"B3", "needs a position"}}) {
    const std::string& symbol = symbol_message.first;
    const std::string error = ErrorOf([&] { paths.FrameCount(c->Def(symbol), 0); });
    EXPECT_NE(error.find(symbol_message.second), std::string::npos) << symbol << ": " << error;
  }
}

// ---- quota_draws.h

TEST(CaptureQuotaDraws, DemandedBinExcludesTheUpperEdgeButOfTheLastBin) {
  Quota quota;
  quota.quantity = "altitude";
  quota.edges = {0, 10, 20};
  quota.weights = {0.5, 0.5};
  FrameDemand demand;
  demand.bins = {{&quota, 0}};
  const auto first = DemandedBin(&demand, "altitude");
  ASSERT_TRUE(first);
  EXPECT_EQ(first->first, 0);
  EXPECT_EQ(first->second, std::nextafter(10.0, 0.0));
  demand.bins = {{&quota, 1}};
  EXPECT_EQ(DemandedBin(&demand, "altitude")->second, 20);
  EXPECT_FALSE(DemandedBin(&demand, "off_nadir"));
  EXPECT_FALSE(DemandedBin(nullptr, "altitude"));
  quota.importance = false;
  EXPECT_FALSE(DemandedBin(&demand, "altitude"));
}

TEST(CaptureQuotaDraws, RedrawsUntilTheDemandIsMetAndRecordsTheAttempts) {
  EXPECT_EQ(RedrawSeed(42, 0), 42u);
  EXPECT_NE(RedrawSeed(42, 1), RedrawSeed(42, 2));
  Plan plan = FlatPlan();
  RequirementSet set;
  set.requirements.push_back({"R", "", {{"altitude", 30, 35}}, 1.0});
  FrameDemand demand;
  demand.active = {&set.requirements[0]};
  const FrameEstimatorFactory estimator = [] {
    return [](const Plan&, const PlannedFrame&) { return FrameMeasure{}; };
  };
  QuotaDraws draws(set, estimator, plan, Location{});
  // Draw `attempt` puts the camera at 10 * attempt m: attempt 3 (30 m) is the first to meet it.
  const auto draw = [&](int attempt, const FrameDemand* d) {
    EXPECT_EQ(d, &demand);
    PlannedFrame f = plan.frames[0];
    f.cam_from_world = gen::testing::Nadir({0, 0, 10.0 * attempt});
    return std::vector<PlannedFrame>{f};
  };
  const std::vector<PlannedFrame> frames = draws.Step(0, demand, draw);
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_NEAR(CameraCenterInWorld(frames[0].cam_from_world).z(), 30, 1e-9);
  EXPECT_EQ((*frames[0].requirements)["attempts"], 4);
  // Without a demand, the first draw is taken as it is.
  EXPECT_EQ(draws
                .Step(0,
                      FrameDemand{},
                      [&](int attempt, const FrameDemand* d) {
                        EXPECT_EQ(attempt, 0);
                        EXPECT_EQ(d, nullptr);
                        return std::vector<PlannedFrame>{plan.frames[0]};
                      })
                .size(),
            1u);
}

TEST(CaptureQuotaDraws, AMissedBudgetFailsWhenAskedTo) {
  Plan plan = FlatPlan();
  RequirementSet set;
  set.requirements.push_back({"R", "", {{"altitude", 30, 35}}, 1.0});
  set.budget = 2;
  set.fail_on_budget = true;
  FrameDemand demand;
  demand.active = {&set.requirements[0]};
  QuotaDraws draws(
      set,
      [] { return [](const Plan&, const PlannedFrame&) { return FrameMeasure{}; }; },
      plan,
      Location{});
  const std::string error = ErrorOf([&] {
    draws.Step(7, demand, [&](int, const FrameDemand*) {
      PlannedFrame f = plan.frames[0];
      f.cam_from_world = gen::testing::Nadir({0, 0, 5});
      return std::vector<PlannedFrame>{f};
    });
  });
  EXPECT_NE(error.find("frame 7: no draw met the requirements in 3 attempts (budget 2)"),
            std::string::npos)
      << error;
}

// ---- class_swaps.h, targets.h

constexpr const char* kScene =
    "LSCENE = ONE(O1) ONE(O2)\nO1 = object{class:car}\nO2 = object{class:cube}\n";

TEST(CaptureClassSwaps, ADrawnClassJoinsTheTableAfterTheScenesIds) {
  const Text scene(kScene, "LSCENE");
  Plan plan;
  plan.classes = {{1, "ground"}, {2, "car"}, {7, "cube"}};  // O2 labelled 7, as the scene made it
  const auto targets = Lcap("LCAP = ONE(CO)\nCO = camera{targets:[O2:7,O1]}\n");
  ClassSwaps swaps(scene.program, ReadTargets(targets->program, scene.program), &plan);
  // A target with one label keeps it whatever it draws; O1 (no label) takes the class of the name.
  EXPECT_EQ(swaps.Class("O2", {"cube", "cube"}).second, 7u);
  EXPECT_EQ(swaps.Class("O2", {"truck", "truck"}).second, 7u);
  EXPECT_EQ(swaps.Class("O1", {"car", "car"}).second, 2u);
  EXPECT_EQ(swaps.Class("O1", {"truck", "truck"}).second, 8u);  // after every id and label
  ASSERT_EQ(plan.classes.size(), 4u);
  EXPECT_EQ(plan.classes.back().name, "truck");
  const auto c = Lcap("LCAP = ONE(A)\nA = collection{O1:{class:{truck:0.5,barrel:0.5}}}\n");
  const Node cls = c->Def("A").body.Members().front().second.Find("class");
  EXPECT_EQ(ClassSwaps::Options(cls), (std::vector<std::string>{"truck", "barrel"}));
  swaps.Declare("O1", cls);
  EXPECT_EQ(swaps.swapped_in(), (std::set<uint32_t>{8, 9}));
}

TEST(CaptureTargets, LabelsAndTheFirstTarget) {
  const Text scene(kScene, "LSCENE");
  const auto c = Lcap("LCAP = ONE(CO)\nCO = camera{targets:[O2:5,O1]}\n");
  TargetLabels expected;
  expected["O2"].first_id = 5;
  expected["O1"];
  EXPECT_EQ(ReadTargets(c->program, scene.program), expected);
  // A label per class, in the list and in the object form.
  const auto per_class = Lcap("LCAP = ONE(CO)\nCO = camera{targets:[O2:{car:3,truck:4}]}\n");
  const TargetLabels labels = ReadTargets(per_class->program, scene.program);
  EXPECT_EQ(labels.at("O2").by_class, (std::map<std::string, uint32_t>{{"car", 3}, {"truck", 4}}));
  EXPECT_TRUE(labels.at("O2").labelled());
  const auto zero = Lcap("LCAP = ONE(CO)\nCO = camera{targets:[O2:0]}\n");
  EXPECT_NE(ErrorOf([&] { ReadTargets(zero->program, scene.program); }).find("c.lcap:2:"),
            std::string::npos);
  EXPECT_EQ(FirstTarget(c->program), "O2");
  const auto bad = Lcap("LCAP = ONE(CO)\nCO = camera{targets:[O3:1]}\n");
  EXPECT_NE(ErrorOf([&] {
              ReadTargets(bad->program, scene.program);
            }).find("target 'O3' is not an object of the scene"),
            std::string::npos);
}

// ---- object_changes.h

// A rule over `block` of collection A's first entry, without timing or motion.
Rule RuleOf(const Text& c) {
  Rule rule;
  rule.block = c.Def("A").body.Members().front().second;
  rule.object_symbol = c.Def("A").body.Members().front().first;
  return rule;
}

TEST(CaptureObjectChanges, ScaleAndOffsetAreRelativeToThePlannedObject) {
  const auto c =
      Lcap("LCAP = ONE(A)\nA = collection{B:{scale:[2,2,2],offset:[1,0,0],material:rust}}\n");
  const PlannedObject o = Box("B", 5, {3, 4, 1.5}, {1, 2, 3});
  Plan plan;
  const Text scene(kScene, "LSCENE");
  ClassSwaps swaps(scene.program, {}, &plan);
  Rng rng(1);
  const ObjectChange change = DrawObjectChange(RuleOf(*c), o, rng, nullptr, &swaps);
  EXPECT_EQ(change.object, "B");
  EXPECT_EQ(*change.extent, Eigen::Vector3d(2, 4, 6));
  EXPECT_EQ(*change.position, Eigen::Vector3d(4, 4, 1.5));
  EXPECT_EQ(*change.material, "rust");
  EXPECT_FALSE(change.class_id);
}

TEST(CaptureObjectChanges, APositionChangeMovesTheObjectAndKeepsItOnItsSupport) {
  const std::string scene =
      "LSCENE = ONE(W) ONE(O)\nW = terrain{size:[100,100]}\n"
      "O = object{class:cube,extent:[1,1,1],position:{ON:W,within:[[-5,-5,0],[5,5,9]]}}\n";
  const Plan plan =
      testing::PlanText(scene,
                        "LCAP = ONE(P) ONE(A)\nP = path{create point:{position:[0,0,30],count:3}}\n"
                        "A = collection{O:{frame:1,position:[10,-5,7]}}\n");
  ASSERT_EQ(plan.frames.size(), 3u);
  EXPECT_TRUE(plan.frames[0].changes.empty());
  Eigen::Vector3d last = Eigen::Vector3d::Zero();
  for (const ObjectChange& c : plan.frames[2].changes)
    if (c.position) last = *c.position;
  // x and y as written; z set back on the (flat) terrain: the base at 0, the centre at 0.5.
  EXPECT_EQ(last, Eigen::Vector3d(10, -5, 0.5));
  EXPECT_NE(
      testing::PlanErrorOf(scene,
                           "LCAP = ONE(P) ONE(A)\nP = path{create point:{position:[0,0,30]}}\n"
                           "A = collection{O:{position:{ON:W}}}\n")
          .find("write rescatter:true"),
      std::string::npos);
}

TEST(CaptureObjectChanges, AMovingObjectFollowsItsLegsThenRests) {
  Plan plan = FlatPlan();
  PlannedObject o = Box("B", 5, {0, 0, 0.5}, {1, 1, 1});
  o.support = PlannedObject::Support::kTerrain;
  plan.objects = {o};
  Rule rule;
  rule.heading = true;
  Rule::Leg leg;
  leg.flight.speed = 2;
  leg.flight.Build({{0, 0, 0}, {0, 10, 0}},
                   std::vector<Eigen::Quaterniond>(2, Eigen::Quaterniond::Identity()),
                   false);
  rule.legs.push_back(leg);
  rule.when.begin = 4;
  ObjectChange c;
  MoveAlongLegs(rule, o, plan, plan.terrain, 7, 1, &c);  // 3 s after it began: 6 m along
  EXPECT_NEAR((*c.position - Eigen::Vector3d(0, 6, 0)).norm(), 0, 1e-12);
  EXPECT_NEAR((*c.velocity - Eigen::Vector3d(0, 2, 0)).norm(), 0, 1e-12);
  // Heading: yaw 90 degrees turns the object's x axis to +y.
  EXPECT_NEAR(((*c.world_from_object) * Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitY()).norm(),
              0,
              1e-12);
  ObjectChange after;
  MoveAlongLegs(rule, o, plan, plan.terrain, 20, 1, &after);
  EXPECT_NEAR((*after.position - Eigen::Vector3d(0, 10, 0)).norm(), 0, 1e-12);
  EXPECT_EQ(*after.velocity, Eigen::Vector3d::Zero());
}

// ---- object_track.h

TEST(CaptureObjectTrack, APolylineOnePointPerFrameOrAtASpeed) {
  ObjectTrack track;
  track.knots = {{0, 0, 0}, {10, 0, 0}, {10, 5, 0}};
  track.arcs.assign(2, std::nullopt);
  track.TimePerFrame(2);  // knot j at j / 2 s
  EXPECT_DOUBLE_EQ(track.Duration(), 1.0);
  EXPECT_EQ(track.At(0.5).centre, Eigen::Vector3d(10, 0, 0));  // exactly the knot
  EXPECT_NEAR((track.At(0.5).velocity - Eigen::Vector3d(0, 10, 0)).norm(), 0, 1e-12);
  EXPECT_NEAR((track.At(0.25).centre - Eigen::Vector3d(5, 0, 0)).norm(), 0, 1e-12);
  EXPECT_NEAR((track.At(0.25).velocity - Eigen::Vector3d(20, 0, 0)).norm(), 0, 1e-12);
  EXPECT_NEAR((track.At(0.25).tangent - Eigen::Vector3d(1, 0, 0)).norm(), 0, 1e-12);
  EXPECT_EQ(track.At(9).centre, Eigen::Vector3d(10, 5, 0));  // clamped to the end
  // At 5 m/s: 2 s along the first side, 1 s along the second.
  track.TimeAtSpeed(5);
  EXPECT_DOUBLE_EQ(track.Duration(), 3.0);
  EXPECT_NEAR((track.At(1.2).centre - Eigen::Vector3d(6, 0, 0)).norm(), 0, 1e-12);
  EXPECT_NEAR((track.At(2.6).centre - Eigen::Vector3d(10, 3, 0)).norm(), 0, 1e-12);
  EXPECT_NEAR((track.At(2.6).velocity - Eigen::Vector3d(0, 5, 0)).norm(), 0, 1e-12);
}

TEST(CaptureObjectTrack, AnArcIsFollowedOnItsCircle) {
  // A quarter circle of radius 4 about (1, 2, 3), from azimuth 0 to 90 degrees.
  ObjectTrack track;
  track.knots = {{5, 2, 3}, {1, 6, 3}};
  ObjectTrack::Arc arc;
  arc.centre = {1, 2, 3};
  arc.radius = 4;
  arc.from_deg = 0;
  arc.to_deg = 90;
  track.arcs = {arc};
  track.TimeAtSpeed(M_PI);  // the arc is 2 pi m long: 2 s
  EXPECT_NEAR(track.Duration(), 2, 1e-12);
  const FlightSample mid = track.At(1);  // 45 degrees
  const double c = 4 * std::cos(M_PI / 4);
  EXPECT_NEAR((mid.centre - Eigen::Vector3d(1 + c, 2 + c, 3)).norm(), 0, 1e-12);
  // Tangent to the circle at the track's speed.
  EXPECT_NEAR(mid.velocity.norm(), M_PI, 1e-12);
  EXPECT_NEAR(mid.velocity.dot(mid.centre - arc.centre), 0, 1e-12);
  EXPECT_NEAR((mid.tangent - Eigen::Vector3d(-1, 1, 0).normalized()).norm(), 0, 1e-12);
}

TEST(CaptureCameraPaths, AHemiTrackHasAnArcPerRingStep) {
  PathsFixture t(
      "LCAP = ONE(CO) ONE(P)\nCO = camera{}\n"
      "P = path{create hemi:{cam radius:[10,20,2],obj angle:[0,180,3],cam angle:[0,0,1],"
      "center:[1,2,0]}}\n",
      7);
  const auto& c = t.c;
  CameraPaths& paths = t.paths;
  Rng rng(1);
  const ObjectTrack track = paths.Track(c->Def("P"), rng);
  ASSERT_EQ(track.knots.size(), 6u);
  EXPECT_NEAR((track.knots[1] - Eigen::Vector3d(1, 12, 0)).norm(), 0, 1e-9);
  ASSERT_TRUE(track.arcs[0] && track.arcs[1]);
  EXPECT_FALSE(track.arcs[2]);  // radius 10 to radius 20: a line
  EXPECT_NEAR((track.arcs[3]->centre - Eigen::Vector3d(1, 2, 0)).norm(), 0, 1e-9);
  EXPECT_NEAR(track.arcs[3]->radius, 20, 1e-12);
  EXPECT_EQ(track.arcs[3]->from_deg, 0);
  EXPECT_EQ(track.arcs[3]->to_deg, 90);
}

// ---- keep_placement.h, rescatter.h

TEST(CaptureKeepPlacement, AGrownObjectIsReseatedOnTheTerrain) {
  Plan plan = FlatPlan();
  PlannedObject o = Box("B", 5, {0, 0, 0.5}, {1, 1, 1});
  o.support = PlannedObject::Support::kTerrain;
  plan.objects = {o};
  const auto c = Lcap("LCAP = ONE(A)\nA = collection{B:{extent:[1,1,4]}}\n");
  const Rule rule = RuleOf(*c);
  PlannedFrame f;
  ObjectChange grow;
  grow.object = "B";
  grow.extent = Eigen::Vector3d(1, 1, 4);
  f.changes = {grow};
  KeepPlacement(plan, {&rule}, &f);
  ASSERT_EQ(f.changes.size(), 2u);
  EXPECT_EQ(*f.changes[1].position, Eigen::Vector3d(0, 0, 2));  // its base stays at z = 0
}

TEST(CaptureKeepPlacement, AnOverlapItsPlacementForbidsIsAnErrorAtTheChange) {
  Plan plan = FlatPlan();
  PlannedObject a = Box("A1", 5, {0, 0, 0.5}, {1, 1, 1}), b = Box("B1", 6, {5, 0, 0.5}, {1, 1, 1});
  a.overlap_allowed = b.overlap_allowed = false;
  plan.objects = {a, b};
  const auto c = Lcap("LCAP = ONE(A)\nA = collection{A1:{offset:[4.5,0,0]}}\n");
  const Rule rule = RuleOf(*c);
  PlannedFrame f;
  f.index = 3;
  ObjectChange move;
  move.object = "A1";
  move.position = Eigen::Vector3d(4.5, 0, 0.5);
  f.changes = {move};
  EXPECT_NE(ErrorOf([&] {
              KeepPlacement(plan, {&rule}, &f);
            }).find("frame 3: this change makes A1 overlap B1"),
            std::string::npos);
}

TEST(CaptureRescatter, ANewPlaceInsideItsSpaceOnTheGround) {
  Plan plan = FlatPlan();
  PlannedObject o = Box("B", 5, {0, 0, 0.5}, {1, 1, 1});
  o.support = PlannedObject::Support::kTerrain;
  o.placement_lo = {0, 0, 0};
  o.placement_hi = {10, 10, 0};
  o.overlap_allowed = false;
  plan.objects = {o};
  const auto c = Lcap("LCAP = ONE(A)\nA = collection{B:{rescatter:true}}\n");
  const Rule rule = RuleOf(*c);
  for (uint64_t k = 0; k < 20; ++k) {
    Rng rng = Rng::For(1, StreamTag::kFrame, k);
    ObjectChange change;
    Rescatter(plan, rule, o, PlannedFrame{}, rng, &change);
    ASSERT_TRUE(change.position);
    EXPECT_GE(change.position->x(), 0.5);
    EXPECT_LE(change.position->x(), 9.5);
    EXPECT_GE(change.position->y(), 0.5);
    EXPECT_LE(change.position->y(), 9.5);
    EXPECT_EQ(change.position->z(), 0.5);
  }
}

// ---- clearance.h

TEST(CaptureClearance, ACameraUnderTheClearanceIsAnErrorNamingThePose) {
  const Plan plan = FlatPlan();
  const auto c = Lcap(kTimelineLcap);
  const auto pose = [] { return std::string("G(1) pose 2 (frame 2)"); };
  EXPECT_EQ(ErrorOf([&] {
              CheckClearance(
                  plan, plan.terrain, 1, gen::testing::Nadir({0, 0, 2}), pose, c->Def("G").body);
            }),
            "");
  const std::string error = ErrorOf([&] {
    CheckClearance(plan, plan.terrain, 1, gen::testing::Nadir({0, 0, 0.5}), pose, c->Def("G").body);
  });
  EXPECT_NE(error.find("c.lcap:3:5: G(1) pose 2 (frame 2): the camera at ("), std::string::npos)
      << error;
  EXPECT_NE(error.find(", 0.5) is 0.5 m above the terrain (height 0 m there), under the clearance "
                       "of 1 m"),
            std::string::npos)
      << error;
}

}  // namespace
}  // namespace lsds

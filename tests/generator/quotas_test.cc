// Quotas beyond the geometric ones (docs/languages.md, "Requirements and
// quotas"): class shares met by a `during` class swap, the sun's elevation and
// the time of day met by a `during` light change, and importance sampling (the
// free variable drawn within the frame's bin) against plain rejection.
#include <gtest/gtest.h>

#include <fstream>
#include <map>

#include <nlohmann/json.hpp>

#include "generator/estimate.h"
#include "generator/lang/planner.h"
#include "generator/lang/requirements.h"
#include "generator/plan/plan_json.h"
#include "tests/lang/plan_text.h"
#include "tests/test_util.h"

namespace lsds {
namespace {

// A target on flat ground, always in view of the poses below.
const char* kScene =
    "LSCENE = ONE(W) ONE(T) ONE(DL)\n"
    "W = terrain{size:[80,80]}\n"
    "T = object{class:cube,extent:[2,2,1],position:{ON:W,within:[[-1,-1,-9],[1,1,9]]}}\n"
    "DL = light{elevation:50,azimuth:135}\n";

// The same with a place and a sun by date and local time.
const char* kGeoScene =
    "LSCENE = ONE(G) ONE(W) ONE(T) ONE(DL)\n"
    "G = georeference{latitude:47.3769,longitude:8.5417,altitude:408}\n"
    "W = terrain{size:[80,80]}\n"
    "T = object{class:cube,extent:[2,2,1],position:{ON:W,within:[[-1,-1,-9],[1,1,9]]}}\n"
    "DL = light{date:\"2026-06-21\",time:\"12:00\",utc_offset:2}\n";

std::string Capture(int count,
                    const std::string& pose,
                    const std::string& changes,
                    const std::string& demand) {
  return "LCAP = ONE(CO) ONE(R) ONE(CL) ONE(Q)\n"
         "CO = camera{csettings:{fov:60,res:[32,24]},targets:[T]}\n"
         "R = path{random:{count:" +
         std::to_string(count) + ",x:[-8,8],y:[-8,8]," + pose +
         "}}\n"
         "CL = collection{CO:{move:[R]}" +
         changes + "}\n" + demand;
}

// Planned with the frame estimator (requirements need it).
Plan PlanText(const std::string& scene,
              const std::string& capture,
              uint64_t seed = 5,
              FrameRange frames = {}) {
  return testing::PlanText(scene, capture, seed, frames, gen::MakeFrameEstimatorFactory());
}

int64_t Attempts(const Plan& plan) {
  int64_t attempts = 0;
  for (const PlannedFrame& f : plan.frames) attempts += f.requirements->value("attempts", 1);
  return attempts;
}

uint32_t ClassId(const Plan& plan, const std::string& name) {
  for (const ClassInfo& c : plan.classes)
    if (c.name == name) return c.id;
  ADD_FAILURE() << "no class " << name;
  return 0;
}

// The class the target is drawn with on frame f (its last class change).
uint32_t TargetClass(const Plan& plan, const PlannedFrame& f) {
  uint32_t id = plan.objects[0].class_id;
  for (const PlannedObject& o : plan.objects)
    if (o.name == "T#1") id = o.class_id;
  for (const ObjectChange& c : f.changes)
    if (c.object == "T#1" && c.class_id) id = *c.class_id;
  return id;
}

const std::string kSwap = ",T:{during:R,class:{barrel:1,rock:1,cube:1}}";
const std::string kPose = "altitude:30,off_nadir:0,yaw:0";

TEST(ClassQuota, SharesLandOnTheirTargetOver200Frames) {
  for (const std::string sampling : {"importance", "rejection"}) {
    const Plan plan = PlanText(
        kScene,
        Capture(200,
                kPose,
                kSwap,
                "Q = quota{target:T,quantity:class,classes:{barrel:1,rock:1,cube:2},sampling:" +
                    sampling + "}\n"));
    ASSERT_EQ(plan.frames.size(), 200u);
    const auto& q = plan.requirements["quotas"][0];
    EXPECT_EQ(q["planned"], nlohmann::json({50, 50, 100})) << sampling;
    EXPECT_EQ(q["classes"], nlohmann::json({"barrel", "rock", "cube"}));
    std::map<uint32_t, int> drawn;
    int met = 0;
    for (const PlannedFrame& f : plan.frames) {
      ++drawn[TargetClass(plan, f)];
      met += f.requirements->at("met").get<bool>();
      // The record names the class and holds the estimated class id.
      const auto& check = f.requirements->at("checks")[0];
      EXPECT_EQ(check["quantity"], "class");
      EXPECT_EQ(check["estimate"].get<double>(), TargetClass(plan, f));
    }
    // The documented tolerance: 5 % of the frames (10 of 200) per bin.
    EXPECT_NEAR(drawn[ClassId(plan, "barrel")], 50, 10) << sampling;
    EXPECT_NEAR(drawn[ClassId(plan, "rock")], 50, 10) << sampling;
    EXPECT_NEAR(drawn[ClassId(plan, "cube")], 100, 10) << sampling;
    EXPECT_EQ(met, 200) << sampling;
    // Importance sampling draws the bin's class at once; rejection redraws
    // the two thirds of frames whose swap drew another class.
    if (sampling == "importance")
      EXPECT_EQ(Attempts(plan), 200);
    else
      EXPECT_GT(Attempts(plan), 300);
  }
  // The control: the swap alone gives the cube a third, not a half.
  const Plan free = PlanText(kScene, Capture(200, kPose, kSwap, "Q = require{altitude:[0,99]}\n"));
  int cubes = 0;
  for (const PlannedFrame& f : free.frames) cubes += TargetClass(free, f) == ClassId(free, "cube");
  EXPECT_LT(cubes, 85);
}

// The estimator keeps one scene and updates it in place from draw to draw,
// class swaps included (RenderScene::Update): frame by frame, its measures
// are those of a fresh estimator.
TEST(ClassQuota, AnEstimatorUpdatedFromDrawToDrawMeasuresAsAFreshOne) {
  // The target half under a plate: its visibility depends on its shape.
  const char* scene =
      "LSCENE = ONE(W) ONE(T) ONE(DL) ONE(PLATE)\n"
      "W = terrain{size:[80,80]}\n"
      "T = object{class:cube,extent:[2,2,1],position:{ON:W,within:[[-1,-1,-9],[1,1,9]]}}\n"
      "DL = light{elevation:50,azimuth:135}\n"
      "PLATE = object{class:cube,extent:[3,1.5,0.1],target:false,"
      "position:{within:[[-0.01,0.99,3],[0.01,1.01,3.01]]}}\n";
  // The swapped-in shapes keep T's 2 x 2 x 1 m box (an extent after the class), so that each stays
  // half under the plate.
  const Plan plan = PlanText(scene,
                             Capture(30,
                                     kPose,
                                     ",T:{during:R,class:{barrel:1,rock:1,cube:1},extent:[2,2,1]}",
                                     "Q = require{altitude:[0,99]}\n"));
  const FrameEstimatorFactory factory = gen::MakeFrameEstimatorFactory();
  const FrameEstimator kept = factory();
  int swaps = 0, partly_hidden = 0;
  uint32_t last = 0;
  for (const PlannedFrame& f : plan.frames) {
    const FrameMeasure updated = kept(plan, f);
    const FrameMeasure fresh = factory()(plan, f);
    ASSERT_EQ(updated.targets.size(), 1u);
    ASSERT_EQ(fresh.targets.size(), 1u);
    EXPECT_EQ(updated.targets[0].values, fresh.targets[0].values) << f.index;
    const double visibility = updated.targets[0].values.at("visibility");
    partly_hidden += visibility > 0.05 && visibility < 0.95;
    swaps += TargetClass(plan, f) != last;
    last = TargetClass(plan, f);
  }
  EXPECT_GT(swaps, 10);
  EXPECT_GT(partly_hidden, 10);
}

TEST(ClassQuota, WithoutATargetItCountsEveryTargetInView) {
  const Plan plan = PlanText(
      kScene, Capture(40, kPose, kSwap, "Q = quota{quantity:class,classes:[barrel,rock]}\n"));
  for (const PlannedFrame& f : plan.frames) {
    EXPECT_TRUE(f.requirements->at("met").get<bool>());
    EXPECT_EQ(f.requirements->at("checks")[0]["object"], "T#1");
  }
  EXPECT_EQ(plan.requirements["quotas"][0]["planned"], nlohmann::json({20, 20}));
}

TEST(SunQuota, SunElevationBinsAreMetByADuringLightChange) {
  const Plan plan = PlanText(kScene,
                             Capture(200,
                                     kPose,
                                     ",DL:{during:R,elevation:[5,85]}",
                                     "Q = quota{quantity:sun_elevation,bins:[5,25,45,65,85]}\n"));
  EXPECT_EQ(plan.requirements["quotas"][0]["planned"], nlohmann::json({50, 50, 50, 50}));
  std::map<int, int> bins;
  for (const PlannedFrame& f : plan.frames) {
    const double e = EnvironmentAt(plan, f).sun.elevation_deg;
    ++bins[static_cast<int>((e - 5) / 20)];
    EXPECT_TRUE(f.requirements->at("met").get<bool>()) << f.index;
  }
  for (int b = 0; b < 4; ++b) EXPECT_NEAR(bins[b], 50, 10) << b;
}

TEST(SunQuota, TimeOfDayBinsAreMetByADuringTimeChange) {
  const Plan plan =
      PlanText(kGeoScene,
               Capture(80,
                       kPose,
                       ",DL:{during:R,time:{\"07:00\":1,\"10:00\":1,\"13:00\":1,\"16:00\":1}}",
                       "Q = quota{quantity:time_of_day,bins:[6,9,12,15,18],weights:[1,1,1,1]}\n"));
  std::map<int, int> bins;
  for (const PlannedFrame& f : plan.frames) {
    const auto& check = f.requirements->at("checks")[0];
    ASSERT_TRUE(check.contains("estimate"));
    const double hours = check["estimate"];
    ++bins[static_cast<int>((hours - 6) / 3)];
    EXPECT_TRUE(f.requirements->at("met").get<bool>()) << f.index;
    // The sun follows the time: morning and afternoon are lower than noon.
    const double elevation = EnvironmentAt(plan, f).sun.elevation_deg;
    if (hours < 9) {
      EXPECT_LT(elevation, 40) << hours;
    }
    if (hours >= 12 && hours < 15) {
      EXPECT_GT(elevation, 55) << hours;
    }
  }
  for (int b = 0; b < 4; ++b) EXPECT_EQ(bins[b], 20) << b;
  // Without a clock the time of day is not measured: every frame misses.
  const Plan no_clock = PlanText(
      kScene, Capture(2, kPose, "", "Q = quota{quantity:time_of_day,bins:[0,24],budget:2}\n"));
  for (const PlannedFrame& f : no_clock.frames) EXPECT_FALSE(f.requirements->at("met").get<bool>());
}

TEST(ImportanceSampling, OffNadirAndAltitudeBinsAreDrawnWithinTheBin) {
  const std::string demand =
      "Q = quota{quantity:off_nadir,bins:[0,10,20,30]}\n"
      "Q2 = quota{quantity:altitude,bins:[20,30,60],weights:[3,1]}\n";
  const Plan plan = PlanText(
      kScene, Capture(120, "altitude:{normal:[40,10,20,60]},off_nadir:[0,30],yaw:0", "", demand));
  // One draw per frame: the pose is drawn inside both bins at once.
  EXPECT_EQ(Attempts(plan), 120);
  for (const PlannedFrame& f : plan.frames) EXPECT_TRUE(f.requirements->at("met").get<bool>());
  EXPECT_EQ(plan.requirements["quotas"][0]["planned"], nlohmann::json({40, 40, 40}));
  EXPECT_EQ(plan.requirements["quotas"][1]["planned"], nlohmann::json({90, 30}));
  // Rejection needs several draws per frame for the same demand.
  std::string rejection = demand;
  const std::string key = "sampling:rejection,";
  for (size_t at = 0; (at = rejection.find("bins:", at)) != std::string::npos; at += key.size() + 5)
    rejection.insert(at, key);
  const Plan rejected = PlanText(
      kScene,
      Capture(120, "altitude:{normal:[40,10,20,60]},off_nadir:[0,30],yaw:0", "", rejection));
  EXPECT_GT(Attempts(rejected), 2 * 120);
}

TEST(ClassQuota, GeneratedTruthReportsAchievedSharesAndShardsEqualTheSingleRun) {
  testing::TempDir dir;
  std::ofstream(dir / "s.lscene") << kScene;
  std::ofstream(dir / "c.lcap") << Capture(
      8,
      kPose,
      ",T:{during:R,class:{barrel:1,cube:1}},DL:{during:R,elevation:[10,80]}",
      "Q = quota{target:T,quantity:class,classes:{barrel:1,cube:1}}\n"
      "SUN = quota{quantity:sun_elevation,bins:[10,45,80]}\n");
  auto generate = [&](const std::string& name, const std::string& flags) {
    const auto r = testing::RunCommandLine(
        testing::LsdsBinary() + " generate " + (dir / "s.lscene").string() + " " +
        (dir / "c.lcap").string() + " -o " + (dir / name).string() + " --spp 1 --seed 3 " + flags);
    EXPECT_EQ(r.exit_code, 0) << r.output;
    std::ifstream in(dir / name / "collection.json");
    return std::make_pair(r.output, nlohmann::json::parse(in));
  };
  const auto [output, single] = generate("single", "");
  EXPECT_NE(
      output.find("quota Q class classes [\"barrel\",\"cube\"]: planned [4,4] achieved [4,4]"),
      std::string::npos)
      << output;
  EXPECT_NE(output.find("quota SUN sun_elevation bins [10.0,45.0,80.0]: planned [4,4] achieved "
                        "[4,4]"),
            std::string::npos)
      << output;
  EXPECT_EQ(single["provenance"]["requirements"]["quotas"][0]["classes"],
            nlohmann::json({"barrel", "cube"}));
  // The truth's own class ids, not the planner's word.
  std::map<std::string, int> truth;
  std::map<uint32_t, std::string> names;
  for (const auto& c : single["classes"]) names[c["id"]] = c["name"];
  for (const auto& frame : single["frames"])
    for (const auto& o : frame["objects"])
      if (o["name"] == "T#1") ++truth[names[o["class_id"].get<uint32_t>()]];
  EXPECT_EQ(truth["barrel"], 4);
  EXPECT_EQ(truth["cube"], 4);
  const auto validated = testing::RunCommandLine(testing::LsdsBinary() + " validate " +
                                                 (dir / "single").string() + " --fail-on warning");
  EXPECT_EQ(validated.exit_code, 0) << validated.output;
  for (const auto& [name, flags] : std::vector<std::pair<std::string, std::string>>{
           {"range", "--frames 2:5"}, {"shard", "--shard 1/2"}}) {
    const auto part = generate(name, flags).second;
    ASSERT_FALSE(part["frames"].empty());
    EXPECT_EQ(part["provenance"]["requirements"], single["provenance"]["requirements"]);
    for (const auto& frame : part["frames"])
      EXPECT_EQ(frame, single["frames"][frame["index"].get<size_t>()]) << name;
  }
}

// The case: a quota the scene cannot give (the lone target is never hidden, so no frame
// reaches the low-visibility bin) is a validate error naming the quota, its bins, the planned and
// the achieved counts, and the frames that missed it; `--checks` can leave it out.
TEST(QuotaGate, AMissedQuotaFailsValidate) {
  testing::TempDir dir;
  std::ofstream(dir / "s.lscene") << kScene;
  std::ofstream(dir / "c.lcap") << Capture(
      8, kPose, "", "Q = quota{target:T,quantity:visibility,bins:[0,0.5,1],budget:2}\n");
  const std::string out = (dir / "out").string();
  const auto generated =
      testing::RunCommandLine(testing::LsdsBinary() + " generate " + (dir / "s.lscene").string() +
                              " " + (dir / "c.lcap").string() + " -o " + out + " --spp 1 --seed 3");
  ASSERT_EQ(generated.exit_code, 0) << generated.output;
  EXPECT_NE(generated.output.find("planned [4,4] achieved [0,8]"), std::string::npos)
      << generated.output;
  const auto validated = testing::RunCommandLine(testing::LsdsBinary() + " validate " + out);
  EXPECT_EQ(validated.exit_code, 1) << validated.output;
  EXPECT_NE(validated.output.find("quota Q (visibility, bins [0.0,0.5,1.0]): planned [4,4] frames, "
                                  "achieved [0,8]; a bin is off by 4, over the tolerance 0.05 x 8"),
            std::string::npos)
      << validated.output;
  EXPECT_NE(validated.output.find("4 of 8 frames missed their requirements in the rendered truth"),
            std::string::npos)
      << validated.output;
  // Two shards validated apart and merged give the same verdict.
  for (const char* shard : {"0/2", "1/2"}) {
    const auto part = testing::RunCommandLine(
        testing::LsdsBinary() + " validate " + out + " --shard " + shard + " -o " +
        (dir / ("part" + std::string(1, shard[0]) + ".json")).string());
    EXPECT_EQ(part.exit_code, 0) << part.output;
  }
  const auto merged =
      testing::RunCommandLine(testing::LsdsBinary() + " merge-reports " +
                              (dir / "part0.json").string() + " " + (dir / "part1.json").string());
  EXPECT_EQ(merged.exit_code, 1) << merged.output;
  EXPECT_NE(merged.output.find("planned [4,4] frames, achieved [0,8]"), std::string::npos)
      << merged.output;
  const auto without = testing::RunCommandLine(testing::LsdsBinary() + " validate " + out +
                                               " --checks schema,structure,layer,cross,camera");
  EXPECT_EQ(without.exit_code, 0) << without.output;
}

TEST(ClassQuota, BadInputIsALocatedError) {
  const auto fails = [](const std::string& demand, const std::string& expected) {
    try {
      PlanText(kScene, Capture(2, kPose, kSwap, demand));
      ADD_FAILURE() << "no error for " << demand;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  };
  fails("Q = quota{target:T,quantity:class,classes:{barel:1}}\n", "c.lcap:5:");
  fails("Q = quota{target:T,quantity:class,classes:{barel:1}}\n", "did you mean 'barrel'");
  fails("Q = quota{target:T,quantity:class,bins:[0,1]}\n", "classes:{name: share");
  fails("Q = quota{target:T,quantity:class}\n", "a class quota needs classes");
  fails("Q = quota{quantity:altitude,bins:[0,1],classes:[cube]}\n", "quantity:class");
  fails("Q = require{target:T,class:[1,2]}\n", "class is a quota quantity");
  fails("Q = quota{quantity:altitude,bins:[0,1],sampling:lucky}\n", "importance");
}

}  // namespace
}  // namespace lsds

#include "generator/lang/planner.h"

#include "generator/lang/capture.h"
#include "generator/lang/capture/targets.h"
#include "generator/lang/scene.h"
#include "libs/collection/schema.h"

namespace lsds {

void ValidateSourceSchema(const SourceFile& source) {
  const bool capture = source.doc.contains("LCAP");
  const nlohmann::json plain = nlohmann::json::parse(source.doc.dump());
  const auto issues =
      JsonSchema::Get(capture ? "lcap.schema.json" : "lscene.schema.json").Validate(plain);
  if (!issues.empty())
    throw Error("does not match the " + std::string(capture ? "LCAP" : "LSCENE") +
                    " JSON form: " + issues.front().message,
                source.Where(issues.front().pointer));
}

nlohmann::ordered_json SourceToJson(const SourceFile& source) {
  ValidateSourceSchema(source);
  return source.doc;
}

Plan MakePlanFromSources(const SourceFile& scene_source,
                         const SourceFile* capture_source,
                         uint64_t seed,
                         FrameRange frames,
                         const FrameEstimatorFactory& estimator) {
  ValidateSourceSchema(scene_source);
  if (capture_source) ValidateSourceSchema(*capture_source);
  Plan plan;
  plan.seed = seed;
  plan.scene_source = scene_source.text;
  const Program scene = ReadProgram(scene_source, "LSCENE");
  std::optional<Program> capture;
  TargetLabels targets;
  if (capture_source) {
    plan.capture_source = capture_source->text;
    capture = ReadProgram(*capture_source, "LCAP");
    targets = ReadTargets(*capture, scene);
  }
  EvaluateScene(scene, seed, targets, &plan);
  if (capture)
    EvaluateCapture(*capture, scene, seed, frames.begin, frames.end, &plan, estimator);
  else
    DefaultCapture(frames.begin, frames.end, &plan);
  return plan;
}

Plan MakePlan(const std::filesystem::path& scene,
              const std::optional<std::filesystem::path>& capture,
              uint64_t seed,
              FrameRange frames,
              const FrameEstimatorFactory& estimator) {
  const SourceFile scene_source = LoadSource(scene.string());
  if (!capture) return MakePlanFromSources(scene_source, nullptr, seed, frames, estimator);
  const SourceFile capture_source = LoadSource(capture->string());
  return MakePlanFromSources(scene_source, &capture_source, seed, frames, estimator);
}

}  // namespace lsds

// lsds evaluate COLLECTION --predictions FILE [--format coco|dota|yolo|mot] [-o eval.json]
// [--iou-type bbox|segm|obb] [--ap voc07|voc12|coco] [--junit FILE] [--fail-under METRIC=VALUE]...
// |
// --coverage
#include <iostream>

#include "evaluate/evaluate_run.h"
#include "libs/util/error.h"
#include "libs/util/strings.h"
#include "tools/command.h"
#include "tools/shared_flags.h"

namespace lsds {

int RunEvaluate(int argc, char** argv) {
  CLI::App app(
      "Detection metrics of predictions against the collection's own truth, computed as "
      "pycocotools' COCOeval does, and broken down by every condition the collection records; "
      "or, with --coverage, how the collection fills that condition space (docs/evaluate.md).",
      "lsds evaluate");
  evaluate::EvaluateOptions options;
  std::string collection, predictions, output, junit;
  bool coverage = false;
  app.add_option("COLLECTION", collection, "collection folder (holds collection.json)")->required();
  app.add_option("--predictions",
                 predictions,
                 "COCO results file [{image_id, category_id, bbox, score}], or with --format dota "
                 "a folder of Task1_<class>.txt");
  app.add_option(
         "--format",
         options.format,
         "format of the predictions: coco (a results file), dota (a folder of "
         "Task1_<class>.txt files, with --iou-type obb), yolo (a folder of Ultralytics' "
         "<image>.txt predictions with confidences; boxes, or oriented with --iou-type obb), mot "
         "(a folder of TrackEval tracker files <SEQ>.txt)")
      ->check(CLI::IsMember({"coco", "dota", "yolo", "mot"}));
  app.add_option("--iou-type",
                 options.iou_type,
                 "COCOeval's iouType: bbox (boxes) or segm (masks: each prediction's "
                 "segmentation, RLE or polygons, against the collection's instance masks) or obb "
                 "(oriented boxes scored as the DOTA devkit's task-1 evaluation)")
      ->check(CLI::IsMember({"bbox", "segm", "obb"}));
  app.add_option("--ap",
                 options.ap,
                 "obb: the DOTA devkit's VOC AP, voc07 (11 points, the devkit's default) or voc12 "
                 "(area under the precision envelope); or coco (COCO's 12 numbers with the "
                 "polygon IoU)")
      ->check(CLI::IsMember({"voc07", "voc12", "coco"}));
  app.add_flag(
      "--coverage", coverage, "no predictions: how the collection fills the condition space");
  app.add_option(
      "-o,--output", output, "write the evaluation JSON here (schemas/evaluate.schema.json)");
  app.add_option("--junit", junit, "write a JUnit XML report here");
  std::string suggest;
  app.add_option("--suggest",
                 suggest,
                 "write the collection's LCAP capture with quotas asking for more frames where the "
                 "model did worst (for lsds plan / generate with the collection's scene)");
  app.add_option("--fail-under",
                 options.fail_under,
                 "METRIC=VALUE: exit 1 when the metric (AP, AP50, AP75, APs, APm, APl, AR1, AR10, "
                 "AR100, ARs, ARm, ARl) is under VALUE; repeatable");
  app.add_option(
         "--thin",
         options.thin_below,
         "strata and coverage cells with fewer objects (frames) are flagged thin (default 30)")
      ->check(CLI::NonNegativeNumber);
  app.add_option(
      "--classes", options.truth.classes, "as lsds convert: keep, rename, merge classes");
  app.add_flag("--keep-classes", options.truth.keep_classes, "as lsds convert: list every class");
  app.add_option("--min-visibility",
                 options.truth.min_visibility,
                 "as lsds convert: leave out objects less visible than this");
  app.add_option("--min-pixels",
                 options.truth.min_pixels,
                 "as lsds convert: leave out objects with fewer visible pixels");
  app.add_option("--mot-classes",
                 options.truth.mot_classes,
                 "with --format mot, as lsds convert: the class ids of the tracker rows' 8th "
                 "field, order (the COCO category id) or mot17 (MOT17's ids by class name)")
      ->check(CLI::IsMember({"order", "mot17"}));
  CommonFlags common;
  AddCommonFlags(app, &common, "replace existing output files");
  return RunCommand(app, common, argc, argv, [&] {
    if (coverage == !predictions.empty())
      throw Error(coverage ? "--coverage evaluates no predictions: leave out --predictions"
                           : "give --predictions FILE, or --coverage");
    options.truth.collection = collection;
    options.truth.frames = SelectCollectionFrames(common.frames, collection);
    options.predictions = predictions;
    options.output = output;
    options.junit = junit;
    options.suggest = suggest;
    options.force = common.force;
    const evaluate::EvaluateResult result = evaluate::RunEvaluate(options);
    if (!common.quiet) {
      std::cout << evaluate::ReportText(result.report);
      if (!suggest.empty())
        std::cout << "suggested capture: " << suggest << " (quotas: "
                  << (result.suggested_quotas.empty() ? "none"
                                                      : Join(result.suggested_quotas, ", "))
                  << ")\n";
    }
    return result.thresholds_passed ? 0 : 1;
  });
}

}  // namespace lsds

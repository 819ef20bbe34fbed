// lsds info COLLECTION [--json]
#include <iostream>

#include "libs/collection/summary.h"
#include "tools/command.h"

namespace lsds {

int RunInfo(int argc, char** argv) {
  CLI::App app("Summarize a collection: frames, layers, classes, cameras, units, size.",
               "lsds info");
  std::string collection;
  bool json = false;
  app.add_option("COLLECTION", collection, "collection folder (holds collection.json)")->required();
  app.add_flag("--json", json, "print the summary as JSON");
  CommonFlags common;
  AddCommonFlags(app,
                 &common,
                 "",
                 {{"--frames", "lsds info summarizes every frame of the collection"},
                  {"--force", "lsds info writes no file"}});
  return RunCommand(app, common, argc, argv, [&] {
    const CollectionInfo info = SummarizeCollection(collection);
    if (json) {
      std::cout << SummaryToJson(info).dump(2) << "\n";
    } else {
      std::cout << SummaryToText(info);
    }
    return 0;
  });
}

}  // namespace lsds

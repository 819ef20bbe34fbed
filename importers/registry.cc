#include "importers/registry.h"

#include <functional>
#include <utility>

#include "importers/airsim/airsim_importer.h"
#include "importers/bop/bop_importer.h"
#include "importers/kubric/kubric_importer.h"
#include "importers/replicator/replicator_importer.h"
#include "importers/solo/solo_importer.h"
#include "importers/ue_mrq/ue_mrq_importer.h"
#include "libs/util/error.h"
#include "libs/util/strings.h"

namespace lsds::import {

namespace {
using Factory = std::function<std::unique_ptr<Importer>()>;
const std::vector<std::pair<std::string, Factory>>& Table() {
  static const std::vector<std::pair<std::string, Factory>> table = {
      {"ue-mrq", [] { return std::make_unique<UeMrqImporter>(); }},
      {"airsim", [] { return std::make_unique<AirSimImporter>(); }},
      {"bop", [] { return std::make_unique<BopImporter>(); }},
      {"kubric", [] { return std::make_unique<KubricImporter>(); }},
      {"replicator", [] { return std::make_unique<ReplicatorImporter>(); }},
      {"solo", [] { return std::make_unique<SoloImporter>(); }},
  };
  return table;
}
}  // namespace

std::vector<std::string> ImporterNames() {
  std::vector<std::string> names;
  for (const auto& entry : Table()) names.push_back(entry.first);
  return names;
}

std::unique_ptr<Importer> MakeImporter(const std::string& name) {
  for (const auto& entry : Table()) {
    if (entry.first == name) return entry.second();
  }
  throw Error("unknown source format '" + name + "'" + DidYouMean(name, ImporterNames()) +
              " (known: " + Join(ImporterNames(), ", ") + ")");
}

}  // namespace lsds::import

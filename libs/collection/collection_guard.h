// The inputs a collection contributes to a command's OutputGuard
// (libs/util/output_guard.h): what no output of the command may be, contain or
// lie inside.
#pragma once

#include <filesystem>
#include <set>
#include <string>

#include "libs/util/output_guard.h"

namespace lsds {

enum class CollectionAccess {
  // The command only reads the collection (convert, validate, report, ...):
  // the whole folder is an input, and every place its symlinks lead to.
  kReadOnly,
  // The command also writes documented outputs into the collection
  // (perturb-metadata's variant, bundles' derived layers): outputs may lie
  // inside the folder, but not be it or contain it, and never be
  // collection.json or lie inside one of its subfolders (the layers) other
  // than `replaceable` ones (earlier outputs of the same command, replaced
  // with --force). The caller adds the files it reads (metadata).
  kAddsOutputs,
};

void GuardCollection(OutputGuard* guard,
                     const std::filesystem::path& root,
                     CollectionAccess access,
                     const std::set<std::string>& replaceable = {});

}  // namespace lsds

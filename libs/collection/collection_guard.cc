#include "libs/collection/collection_guard.h"

#include "libs/collection/model.h"

namespace lsds {

namespace fs = std::filesystem;

void GuardCollection(OutputGuard* guard,
                     const fs::path& root,
                     CollectionAccess access,
                     const std::set<std::string>& replaceable) {
  // The most specific inputs first: the message names the first match.
  guard->AddInput(root / kCollectionFile, "collection file");
  std::error_code ec;
  if (access == CollectionAccess::kAddsOutputs) {
    for (fs::directory_iterator it(root, ec), end; !ec && it != end; it.increment(ec)) {
      const std::string name = it->path().filename().string();
      if (replaceable.count(name) != 0) continue;
      if (it->is_directory(ec)) guard->AddInput(it->path(), "collection's layer folder");
    }
    guard->AddContainer(root, "collection folder");
  } else {
    guard->AddInput(root, "collection folder");
  }
  guard->AddSymlinkTargetsIn(root);
}

}  // namespace lsds

#include "generator/render/embree_abi.h"
#include "libs/util/plugin.h"

namespace lsds::gen {

const EmbreeTable& Embree() {
  return PluginTable<EmbreeTable>(kEmbreePlugin, kEmbreeEntry, kEmbreeAbiVersion);
}

}  // namespace lsds::gen

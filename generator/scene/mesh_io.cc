#include "generator/scene/mesh_io_abi.h"
#include "libs/util/plugin.h"

namespace lsds::gen {

const MeshIoTable& MeshIo() {
  return PluginTable<MeshIoTable>(kMeshIoPlugin, kMeshIoEntry, kMeshIoAbiVersion);
}

}  // namespace lsds::gen

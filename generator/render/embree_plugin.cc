// The Embree plug-in: Embree's functions in the table of generator/render/embree_abi.h, and
// nothing else. Built as a CMake MODULE, the only target of the product that links Embree
// (docs/architecture.md, "Plug-ins").
#include "generator/render/embree_abi.h"

namespace {

const lsds::gen::EmbreeTable kTable = {
    lsds::gen::kEmbreeAbiVersion,
    rtcNewDevice,
    rtcReleaseDevice,
    rtcGetDeviceError,
    rtcSetDeviceErrorFunction,
    rtcNewScene,
    rtcRetainScene,
    rtcReleaseScene,
    rtcSetSceneFlags,
    rtcSetSceneBuildQuality,
    rtcCommitScene,
    rtcNewGeometry,
    rtcRetainGeometry,
    rtcReleaseGeometry,
    rtcSetSharedGeometryBuffer,
    rtcCommitGeometry,
    rtcAttachGeometry,
    rtcAttachGeometryByID,
    rtcDetachGeometry,
    rtcIntersect1,
    rtcIntersect4,
    rtcIntersect8,
    rtcIntersect16,
    rtcOccluded1,
    rtcOccluded4,
    rtcOccluded8,
    rtcOccluded16,
};

}  // namespace

extern "C" __attribute__((visibility("default"))) const lsds::gen::EmbreeTable*
lsds_embree_table() {
  return &kTable;
}

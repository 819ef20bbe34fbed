// The boundary between lsds and its Embree plug-in (generator/render/embree_plugin.cc), the only
// code that links Embree. The renderer calls Embree's functions through this table, which the
// plug-in fills with Embree's own functions, so every ray is traced by the same code as before;
// Embree's types, constants and inline helpers (rtcInitIntersectContext) still come from its
// headers. One extern "C" entry point returns the table; the loader checks its ABI version.
#pragma once

#include <embree3/rtcore.h>

namespace lsds::gen {

// Raised whenever the table's layout or meaning changes; the loader refuses any other value.
constexpr int kEmbreeAbiVersion = 1;

// The Embree functions lsds calls, each with the signature of its namesake in rtcore.h.
struct EmbreeTable {
  int abi_version;
  decltype(&rtcNewDevice) new_device;
  decltype(&rtcReleaseDevice) release_device;
  decltype(&rtcGetDeviceError) get_device_error;
  decltype(&rtcSetDeviceErrorFunction) set_device_error_function;
  decltype(&rtcNewScene) new_scene;
  decltype(&rtcRetainScene) retain_scene;
  decltype(&rtcReleaseScene) release_scene;
  decltype(&rtcSetSceneFlags) set_scene_flags;
  decltype(&rtcSetSceneBuildQuality) set_scene_build_quality;
  decltype(&rtcCommitScene) commit_scene;
  decltype(&rtcNewGeometry) new_geometry;
  decltype(&rtcRetainGeometry) retain_geometry;
  decltype(&rtcReleaseGeometry) release_geometry;
  decltype(&rtcSetSharedGeometryBuffer) set_shared_geometry_buffer;
  decltype(&rtcCommitGeometry) commit_geometry;
  decltype(&rtcAttachGeometry) attach_geometry;
  decltype(&rtcAttachGeometryByID) attach_geometry_by_id;
  decltype(&rtcDetachGeometry) detach_geometry;
  decltype(&rtcIntersect1) intersect1;
  decltype(&rtcIntersect4) intersect4;
  decltype(&rtcIntersect8) intersect8;
  decltype(&rtcIntersect16) intersect16;
  decltype(&rtcOccluded1) occluded1;
  decltype(&rtcOccluded4) occluded4;
  decltype(&rtcOccluded8) occluded8;
  decltype(&rtcOccluded16) occluded16;
};

constexpr const char* kEmbreePlugin = "lsds_embree.so";
constexpr const char* kEmbreeEntry = "lsds_embree_table";

// The plug-in's table, opened on first use (libs/util/plugin.h); throws lsds::Error when it
// cannot be loaded.
const EmbreeTable& Embree();

}  // namespace lsds::gen

// Defined by the plug-in; looked up with dlsym by kEmbreeEntry.
extern "C" const lsds::gen::EmbreeTable* lsds_embree_table();

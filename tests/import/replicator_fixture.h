// An Omniverse Replicator BasicWriter folder synthesized from an lsds analytic
// scene (no Omniverse needed), in the writer's layout (docs/import.md,
// "Omniverse Replicator"): rgb_NNNN.png, distance_to_image_plane_NNNN.npy,
// instance_segmentation_NNNN.png (colourised) + _mapping / _semantics_mapping
// JSON, bounding_box_2d_tight and bounding_box_3d .npy records + _labels and
// _prim_paths JSON, camera_params_NNNN.json (row-major row-vector matrices).
// The stage is y up and in centimetres (metersPerSceneUnit 0.01), the harder
// case; box b is prim /World/<name>, the ground is unlabelled.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "synth/synthetic_collection.h"

namespace lsds::testing {

inline constexpr double kReplicatorMetersPerUnit = 0.01;

// The layouts BasicWriter.write() makes besides one product's flat folder.
struct ReplicatorLayout {
  // Several render products: each product's files in <folder>/<product>/<annotator>/ (here every
  // product sees the spec's frames). Empty: one product, every file in <folder>.
  std::vector<std::string> products;
  // With several products, use_common_output_dir=True: <folder>/<annotator>/<product>_<file>.
  bool common_output_dir = false;
  // The on_time triggers' counts before the frame number: "1_" -> rgb_1_0000.png.
  std::string trigger_prefix;
  // Whether the instance_segmentation annotator was on (its PNG and two mappings).
  bool instance_segmentation = true;
  // Boxes (by name) with no bounding_box_3d record, only their tight 2D box: prims whose
  // semantics the 3D annotator leaves out, as a semantic filter per annotator does.
  std::vector<std::string> without_3d_box;
};

void WriteReplicatorFixture(const std::filesystem::path& folder,
                            const synth::Spec& spec,
                            const ReplicatorLayout& layout = {});

}  // namespace lsds::testing

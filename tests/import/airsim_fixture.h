// An AirSim recording folder synthesized from an lsds analytic scene (no
// AirSim needed), in AirSim's layout (docs/import.md, "AirSim"):
// airsim_rec.txt with the vehicle pose in NED and the image names of each row,
// images/ with the Scene PNG, the DepthPlanar PFM written top row first (as
// AirSim's writer does) and the Segmentation PNG, settings.json with the
// camera mount, and the lsds_objects.json sidecar.
#pragma once

#include <array>
#include <filesystem>
#include <map>

#include "importers/airsim/airsim_importer.h"
#include "synth/synthetic_collection.h"

namespace lsds::testing {

// The camera of the fixture: named with an underscore, as AirSim's are.
inline constexpr const char* kAirSimCamera = "bottom_center";
import::AirSimMount AirSimFixtureMount();
// Segmentation colours of the scene's instances (the ground, the boxes).
std::map<uint32_t, std::array<uint8_t, 3>> AirSimFixtureColours();

void WriteAirSimFixture(const std::filesystem::path& folder, const synth::Spec& spec);

}  // namespace lsds::testing

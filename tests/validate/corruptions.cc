#include "tests/validate/corruptions.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>

#include <nlohmann/json.hpp>

#include "libs/collection/json_io.h"
#include "libs/collection/model.h"
#include "libs/collection/motion_layout.h"
#include "libs/collection/worldposition_layout.h"
#include "libs/exr/deep_image.h"
#include "libs/exr/flat_image.h"
#include "libs/util/atomic_file.h"
#include "libs/util/error.h"
#include "synth/synthetic_collection.h"

namespace lsds::validate::corpus {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

json ReadJson(const fs::path& path) {
  std::ifstream in(path);
  return json::parse(in);
}
void WriteJson(const fs::path& path, const json& j) { WriteFileAtomic(path, j.dump(1) + "\n"); }

void EditCollection(const fs::path& root, const std::function<void(json&)>& edit) {
  json j = ReadJson(root / "collection.json");
  edit(j);
  WriteJson(root / "collection.json", j);
}

std::string File(const std::string& layer, int frame) {
  char stem[16];
  std::snprintf(stem, sizeof(stem), "%06d", frame);
  return layer + "/" + stem + ".exr";
}

exr::Compression CompressionOf(const std::string& layer) {
  return StandardLayer(layer).compression;
}

void EditFlat(const fs::path& root,
              const std::string& layer,
              int frame,
              const std::function<void(exr::FlatImage&)>& edit) {
  exr::FlatImage image = exr::ReadFlatExr(root / File(layer, frame));
  edit(image);
  exr::WriteOptions options;
  options.compression = CompressionOf(layer);
  exr::WriteFlatExr(root / File(layer, frame), image, options);
}

// Rewrites one channel of a layer with another pixel type.
void RetypeChannel(const fs::path& root,
                   const std::string& layer,
                   int frame,
                   const std::string& channel,
                   exr::PixelType type) {
  EditFlat(root, layer, frame, [&](exr::FlatImage& image) {
    const exr::FlatChannel old = image.Get(channel);
    exr::FlatChannel& fresh = image.AddChannel(channel, type);
    for (size_t p = 0; p < image.pixel_count(); ++p) {
      const double v = old.type == exr::PixelType::kUint ? old.uints[p] : old.floats[p];
      if (type == exr::PixelType::kUint) {
        fresh.uints[p] = static_cast<uint32_t>(v);
      } else {
        fresh.floats[p] = static_cast<float>(v);
      }
    }
  });
}

Expected At(std::string check,
            std::string file,
            std::optional<int64_t> frame,
            std::string pointer = "") {
  Expected e;
  e.check = std::move(check);
  e.file = std::move(file);
  e.frame = frame;
  e.json_pointer = std::move(pointer);
  return e;
}

// A quota Q over the visibility of the first object, bins [0, 0.5, 1], planned [2, 2]: frames 0-1
// demanded the lower bin, 2-3 the upper; each frame's truth achieved `achieved[k]`, all recorded
// as met.
void AddVisibilityQuota(json* j, const std::vector<double>& achieved) {
  (*j)["provenance"]["requirements"] = {{"requirements", json::array()},
                                        {"quotas",
                                         {{{"name", "Q"},
                                           {"quantity", "visibility"},
                                           {"bins", {0, 0.5, 1}},
                                           {"weights", {0.5, 0.5}},
                                           {"tolerance", 0.05},
                                           {"planned", {2, 2}},
                                           {"sampling", "rejection"}}}},
                                        {"budget", 50},
                                        {"on_budget", "keep"}};
  for (size_t k = 0; k < achieved.size(); ++k) {
    const bool low = k < 2;
    (*j)["frames"][k]["requirements"] = {{"attempts", 1},
                                         {"met", true},
                                         {"achieved_met", true},
                                         {"checks",
                                          {{{"name", "Q"},
                                            {"quantity", "visibility"},
                                            {"min", low ? 0.0 : 0.5},
                                            {"max", low ? 0.5 : 1.0},
                                            {"met", true},
                                            {"achieved", achieved[k]},
                                            {"achieved_met", true}}}}};
  }
}

Expected AtPixel(std::string check, std::string file, int64_t frame, int x, int y) {
  Expected e = At(std::move(check), std::move(file), frame);
  e.pixel_x = x, e.pixel_y = y;
  return e;
}

// Sets every frame's intrinsics to a horizontal FOV of `hfov_deg`.
void SetFov(json& j, double hfov_deg) {
  for (json& frame : j["frames"]) {
    const int w = frame["camera"]["width"], h = frame["camera"]["height"];
    const PinholeCamera camera = PinholeCamera::FromHorizontalFov(w, h, hfov_deg);
    frame["camera"]["fx"] = camera.fx;
    frame["camera"]["fy"] = camera.fy;
  }
}

std::vector<Corruption> MakeCorruptions() {
  std::vector<Corruption> c;
  auto add = [&](std::string name,
                 std::string description,
                 std::function<Expected(const fs::path&)> apply) {
    c.push_back({std::move(name), std::move(description), std::move(apply)});
  };
  // --- schema and structure ---
  add("schema-violation", "a frame's fx is a string", [](const fs::path& root) {
    EditCollection(root, [](json& j) { j["frames"][1]["camera"]["fx"] = "wide"; });
    return At("schema", "collection.json", 1, "/frames/1/camera/fx");
  });
  add("schema-unknown-key", "an unknown key in the header", [](const fs::path& root) {
    EditCollection(root, [](json& j) { j["colour"] = "blue"; });
    return At("schema", "collection.json", std::nullopt, "/colour");
  });
  add("schema-missing-layers", "the header has no layer table", [](const fs::path& root) {
    EditCollection(root, [](json& j) { j.erase("layers"); });
    return At("schema", "collection.json", std::nullopt, "/");
  });
  add("metadata-not-json", "metadata.json cut in the middle", [](const fs::path& root) {
    const fs::path path = root / "metadata.json";
    fs::resize_file(path, fs::file_size(path) / 2);
    return At("schema", "metadata.json", std::nullopt);
  });
  add("metadata-schema-violation",
      "metadata.json frame without position",
      [](const fs::path& root) {
        json j = ReadJson(root / "metadata.json");
        j["frames"][2].erase("position");
        WriteJson(root / "metadata.json", j);
        return At("schema", "metadata.json", std::nullopt, "/frames/2");
      });
  add("frame-count", "frame_count says 5, the file has 4", [](const fs::path& root) {
    EditCollection(root, [](json& j) { j["frame_count"] = 5; });
    return At("structure.frame-count", "collection.json", std::nullopt, "/frame_count");
  });
  add("frame-order", "frames 1 and 2 swapped", [](const fs::path& root) {
    EditCollection(root, [](json& j) { std::swap(j["frames"][1], j["frames"][2]); });
    return At("structure.frame-order", "collection.json", 1, "/frames/2/index");
  });
  add("duplicate-frame", "frame 2 also says index 1", [](const fs::path& root) {
    EditCollection(root, [](json& j) { j["frames"][2]["index"] = 1; });
    return At("structure.duplicate-frame", "collection.json", 1, "/frames/2/index");
  });
  add("rig-camera-without-rig",
      "frame 1 names a rig camera; the collection has no rig",
      [](const fs::path& root) {
        EditCollection(root, [](json& j) { j["frames"][1]["rig_camera"] = "left"; });
        return At("structure.rig", "collection.json", 1, "/frames/1/rig_camera");
      });
  add("duplicate-class-id", "class id 2 twice in the class table", [](const fs::path& root) {
    EditCollection(root, [](json& j) { j["classes"].push_back({{"id", 2}, {"name", "box2"}}); });
    return At("structure.tables", "collection.json", std::nullopt, "/classes/3/id");
  });
  add("missing-layer-file", "depth/000002.exr deleted", [](const fs::path& root) {
    fs::remove(root / File("depth", 2));
    return At("structure.missing-file", File("depth", 2), 2);
  });
  add("unknown-layer", "frame 0 names a layer 'depht'", [](const fs::path& root) {
    EditCollection(root, [](json& j) { j["frames"][0]["files"]["depht"] = "depth/000000.exr"; });
    return At("structure.unknown-layer", "collection.json", 0, "/frames/0/files/depht");
  });
  add("stray-file", "rgb/000099.exr that no frame references", [](const fs::path& root) {
    fs::copy_file(root / File("rgb", 0), root / File("rgb", 99));
    return At("structure.stray-file", File("rgb", 99), std::nullopt);
  });
  add("unknown-class-id", "an object of class 7, not in the class table", [](const fs::path& root) {
    EditCollection(root, [](json& j) { j["frames"][1]["objects"][0]["class_id"] = 7; });
    return At("structure.class-id", "collection.json", 1, "/frames/1/objects/0/class_id");
  });
  add("duplicate-instance",
      "two objects of frame 1 share an instance id",
      [](const fs::path& root) {
        EditCollection(root, [](json& j) {
          j["frames"][1]["objects"][1]["instance_id"] = j["frames"][1]["objects"][0]["instance_id"];
        });
        return At("structure.duplicate-instance",
                  "collection.json",
                  1,
                  "/frames/1/objects/1/instance_id");
      });
  add("missing-metadata", "metadata.json deleted", [](const fs::path& root) {
    fs::remove(root / "metadata.json");
    return At("structure.metadata", "collection.json", std::nullopt, "/metadata/0/file");
  });
  add("left-handed-rotation",
      "frame 0's rotation has determinant -1 in a right-handed world",
      [](const fs::path& root) {
        EditCollection(root, [](json& j) {
          json& row = j["frames"][0]["camera"]["cam_from_world"]["rotation"][0];
          for (json& v : row) v = -v.get<double>();
        });
        return At("structure.handedness",
                  "collection.json",
                  0,
                  "/frames/0/camera/cam_from_world/rotation");
      });
  add("imported-absent-shadow",
      "the header declares an import whose source had no shadow layer",
      [](const fs::path& root) {
        EditCollection(root, [](json& j) {
          j["provenance"]["import"] = {
              {"format", "bop"}, {"truth_origin", {{"camera", "imported"}, {"shadow", "absent"}}}};
        });
        return At("structure.truth-origin",
                  "collection.json",
                  std::nullopt,
                  "/provenance/import/truth_origin/shadow");
      });
  add("cycles-depth-disagreement",
      "the rgb was rendered by Blender Cycles whose depth pass was 20 % off the depth layer",
      [](const fs::path& root) {
        EditCollection(root, [](json& j) {
          j["provenance"]["render"]["cycles_agreement"] = {{"frames", 4},
                                                           {"max_relative_depth_error", 0.2},
                                                           {"max_relative_depth_error_frame", 2},
                                                           {"max_id_mismatch_share", 0.001},
                                                           {"max_id_mismatch_share_frame", 1},
                                                           {"id_mismatch_share", 0.0005}};
        });
        return At("structure.cycles-agreement",
                  "collection.json",
                  std::nullopt,
                  "/provenance/render/cycles_agreement/max_relative_depth_error");
      });
  // --- per layer ---
  add("truncated-exr", "normal/000001.exr cut to 60% of its size", [](const fs::path& root) {
    const fs::path path = root / File("normal", 1);
    fs::resize_file(path, fs::file_size(path) * 6 / 10);
    return At("layer.readable", File("normal", 1), 1);
  });
  add("wrong-size", "shadow/000001.exr one column narrower", [](const fs::path& root) {
    const exr::FlatImage image = exr::ReadFlatExr(root / File("shadow", 1));
    exr::FlatImage narrow(image.width() - 1, image.height());
    exr::FlatChannel& y = narrow.AddChannel("Y", exr::PixelType::kFloat);
    for (int j = 0; j < narrow.height(); ++j) {
      for (int i = 0; i < narrow.width(); ++i)
        y.floats[narrow.Index(i, j)] = image.Get("Y").floats[image.Index(i, j)];
    }
    exr::WriteFlatExr(root / File("shadow", 1), narrow);
    return At("layer.dimensions", File("shadow", 1), 1);
  });
  add("wrong-channel-type", "depth/000001.exr Z stored as half", [](const fs::path& root) {
    RetypeChannel(root, "depth", 1, "Z", exr::PixelType::kHalf);
    return At("layer.channels", File("depth", 1), 1);
  });
  add("float-ids", "instanceid/000002.exr stored as float", [](const fs::path& root) {
    RetypeChannel(root, "instanceid", 2, "id", exr::PixelType::kFloat);
    return At("layer.id-type", File("instanceid", 2), 2);
  });
  add("negative-rgb", "rgb/000000.exr pixel (5, 6) R = -1", [](const fs::path& root) {
    EditFlat(root, "rgb", 0, [](exr::FlatImage& im) { im.F("R", 5, 6) = -1; });
    return AtPixel("layer.rgb-range", File("rgb", 0), 0, 5, 6);
  });
  add("nan-depth", "depth/000002.exr pixel (10, 7) = NaN", [](const fs::path& root) {
    EditFlat(root, "depth", 2, [](exr::FlatImage& im) { im.F("Z", 10, 7) = std::nanf(""); });
    return AtPixel("layer.depth-finite", File("depth", 2), 2, 10, 7);
  });
  add("non-unit-normals", "normal/000001.exr pixel (3, 4) scaled by 1.1", [](const fs::path& root) {
    EditFlat(root, "normal", 1, [](exr::FlatImage& im) {
      for (const char* c : {"X", "Y", "Z"}) im.F(c, 3, 4) *= 1.1f;
    });
    return AtPixel("layer.normal-unit", File("normal", 1), 1, 3, 4);
  });
  add("nan-worldposition",
      "worldposition/000000.exr pixel (1, 1) X = NaN",
      [](const fs::path& root) {
        EditFlat(
            root, "worldposition", 0, [](exr::FlatImage& im) { im.F("X", 1, 1) = std::nanf(""); });
        return AtPixel("layer.worldposition-finite", File("worldposition", 0), 0, 1, 1);
      });
  add("shadow-out-of-range", "shadow/000003.exr pixel (2, 3) = 1.5", [](const fs::path& root) {
    EditFlat(root, "shadow", 3, [](exr::FlatImage& im) { im.F("Y", 2, 3) = 1.5f; });
    return AtPixel("layer.shadow-range", File("shadow", 3), 3, 2, 3);
  });
  add("motion-half-invalid",
      "motion/000001.exr pixel (4, 4) X = NaN while Y has a value",
      [](const fs::path& root) {
        EditFlat(root, "motion", 1, [](exr::FlatImage& im) {
          im.F("X", 4, 4) = std::numeric_limits<float>::quiet_NaN();
        });
        return AtPixel("layer.motion-range", File("motion", 1), 1, 4, 4);
      });
  add("unknown-class-pixel", "classid/000000.exr pixel (0, 0) = 9", [](const fs::path& root) {
    EditFlat(root, "classid", 0, [](exr::FlatImage& im) { im.U("id", 0, 0) = 9; });
    return AtPixel("layer.classid-known", File("classid", 0), 0, 0, 0);
  });
  add("bundle-sample-position",
      "bundle/000001.exr pixel (6, 2) sample 1 at SX = 2",
      [](const fs::path& root) {
        exr::DeepImage deep = exr::ReadDeepExr(root / File("bundle", 1));
        deep.Get("SX").floats[deep.FirstSample(6, 2) + 1] = 2.0f;
        exr::WriteOptions options;
        options.compression = CompressionOf("bundle");
        exr::WriteDeepExr(root / File("bundle", 1), deep, options);
        return AtPixel("layer.bundle", File("bundle", 1), 1, 6, 2);
      });
  // --- cross-layer ---
  add("bbox-off-by-one", "frame 1 object 0: bbox x1 one pixel too far", [](const fs::path& root) {
    EditCollection(root, [](json& j) {
      json& bbox = j["frames"][1]["objects"][0]["bbox"];
      bbox[2] = bbox[2].get<double>() + 1;
    });
    return At("cross.bbox-tight", "collection.json", 1, "/frames/1/objects/0/bbox");
  });
  add("visible-pixels", "frame 2 object 1: visible_pixels + 1", [](const fs::path& root) {
    EditCollection(root, [](json& j) {
      json& n = j["frames"][2]["objects"][1]["visible_pixels"];
      n = n.get<int64_t>() + 1;
    });
    return At("cross.visible-pixels", "collection.json", 2, "/frames/2/objects/1/visible_pixels");
  });
  add("obb-moved", "frame 1 object 0: OBB centre moved 10 m", [](const fs::path& root) {
    EditCollection(root, [](json& j) {
      json& centre = j["frames"][1]["objects"][0]["obb"]["center"];
      centre[0] = centre[0].get<double>() + 10;
    });
    return At("cross.obb-contains-bbox", "collection.json", 1, "/frames/1/objects/0/bbox");
  });
  // The oriented boxes of format 1.2 (docs/format.md, "Oriented boxes"); each
  // edit keeps a rectangle unless it means to break one.
  add("oriented-box-too-large",
      "frame 1 object 0: bbox_oriented grown by 10% about its centre (covers, not minimal)",
      [](const fs::path& root) {
        EditCollection(root, [](json& j) {
          json& box = j["frames"][1]["objects"][0].at("bbox_oriented");
          const double cx = (box[0][0].get<double>() + box[2][0].get<double>()) / 2;
          const double cy = (box[0][1].get<double>() + box[2][1].get<double>()) / 2;
          for (json& corner : box) {
            corner[0] = cx + 1.1 * (corner[0].get<double>() - cx);
            corner[1] = cy + 1.1 * (corner[1].get<double>() - cy);
          }
        });
        return At("cross.oriented-box", "collection.json", 1, "/frames/1/objects/0/bbox_oriented");
      });
  add("oriented-box-shifted",
      "frame 2 object 1: bbox_oriented moved 1.5 px right (misses the mask's left column)",
      [](const fs::path& root) {
        EditCollection(root, [](json& j) {
          for (json& corner : j["frames"][2]["objects"][1].at("bbox_oriented"))
            corner[0] = corner[0].get<double>() + 1.5;
        });
        return At("cross.oriented-box", "collection.json", 2, "/frames/2/objects/1/bbox_oriented");
      });
  add("oriented-box-counter-clockwise",
      "frame 3 object 0: bbox_oriented_projected corners listed counter-clockwise",
      [](const fs::path& root) {
        EditCollection(root, [](json& j) {
          json& box = j["frames"][3]["objects"][0].at("bbox_oriented_projected");
          std::swap(box[1], box[3]);
        });
        return At("cross.oriented-box",
                  "collection.json",
                  3,
                  "/frames/3/objects/0/bbox_oriented_projected");
      });
  add("wrong-object-class",
      "frame 1 object 0 declared a crate, its pixels say box",
      [](const fs::path& root) {
        int x = -1, y = -1;
        EditCollection(root, [&](json& j) {
          json& object = j["frames"][1]["objects"][0];
          object["class_id"] = object["class_id"].get<int>() == 3 ? 2 : 3;
          const uint32_t instance = object["instance_id"];
          const exr::FlatImage ids = exr::ReadFlatExr(root / File("instanceid", 1));
          for (int b = 0; b < ids.height() && x < 0; ++b) {
            for (int a = 0; a < ids.width() && x < 0; ++a) {
              if (ids.Get("id").uints[ids.Index(a, b)] == instance) x = a, y = b;
            }
          }
        });
        return AtPixel("cross.class-instance", File("classid", 1), 1, x, y);
      });
  add("worldposition-off",
      "worldposition/000002.exr pixel (7, 5) moved 0.5 m",
      [](const fs::path& root) {
        EditFlat(root, "worldposition", 2, [](exr::FlatImage& im) { im.F("X", 7, 5) += 0.5f; });
        return AtPixel("cross.worldpos-depth", File("worldposition", 2), 2, 7, 5);
      });
  add("bundle-centre",
      "bundle/000002.exr pixel (9, 9) sample 0 instance id changed",
      [](const fs::path& root) {
        exr::DeepImage deep = exr::ReadDeepExr(root / File("bundle", 2));
        deep.Get("instanceid").uints[deep.FirstSample(9, 9)] += 17;
        exr::WriteOptions options;
        options.compression = CompressionOf("bundle");
        exr::WriteDeepExr(root / File("bundle", 2), deep, options);
        return AtPixel("cross.bundle-centre", File("bundle", 2), 2, 9, 9);
      });
  add("static-motion",
      "motion/000002.exr says no motion while the camera moved 1 m",
      [](const fs::path& root) {
        EditFlat(root, "motion", 2, [](exr::FlatImage& im) {
          for (float& v : im.Get("X").floats) v = 0.5f;
          for (float& v : im.Get("Y").floats) v = 0.5f;
        });
        return AtPixel("cross.motion-pose", File("motion", 2), 2, 0, 0);
      });
  add("motion-on-shot-start",
      "motion/000000.exr, the first frame of the shot, says no motion (0.5)",
      [](const fs::path& root) {
        EditFlat(root, "motion", 0, [](exr::FlatImage& im) {
          im.F("X", 3, 2) = 0.5f;
          im.F("Y", 3, 2) = 0.5f;
        });
        return AtPixel("cross.motion-invalid", File("motion", 0), 0, 3, 2);
      });
  add("motion-reference-none",
      "motion/000002.exr rewritten in the residual layout against no previous camera, "
      "although frame 2 continues the shot",
      [](const fs::path& root) {
        const json j = ReadJson(root / "collection.json");
        const CollectionHeader header = HeaderFromJson(j, "collection.json");
        const Frame frame = FrameFromJson(j.at("frames").at(2), "collection.json", "/frames/2");
        const exr::FlatImage motion = exr::ReadFlatExr(root / File("motion", 2));
        const WorldPositionPrediction prediction = PredictionOfFrame(root, header, frame, "depth");
        exr::WriteOptions options;
        options.compression = CompressionOf("motion");
        WriteMotionExr(root / File("motion", 2),
                       motion,
                       FlatLayout::kResidual,
                       &prediction,
                       std::nullopt,
                       "depth",
                       options);
        return At("layer.motion-reference", File("motion", 2), 2);
      });
  add("metadata-pose",
      "metadata.json frame 2 position off by 0.5 m, not declared perturbed",
      [](const fs::path& root) {
        json j = ReadJson(root / "metadata.json");
        json& position = j["frames"][2]["position"];
        position[0] = position[0].get<double>() + 0.5;
        WriteJson(root / "metadata.json", j);
        return At("cross.metadata-pose", "metadata.json", 2, "/frames");
      });
  // --- camera geometry ---
  add("fov-plus-10", "declared FOV 70 degrees, rendered with 60", [](const fs::path& root) {
    EditCollection(root, [](json& j) { SetFov(j, 70); });
    return At("camera.fov", File("worldposition", 0), 0);
  });
  add("principal-point", "declared cx 3 px off", [](const fs::path& root) {
    EditCollection(root, [](json& j) {
      for (json& frame : j["frames"])
        frame["camera"]["cx"] = frame["camera"]["cx"].get<double>() + 3;
    });
    return At("camera.principal-point", File("worldposition", 0), 0);
  });
  add("depth-in-cm",
      "depth layers scaled by 100 (centimetres in a metre collection)",
      [](const fs::path& root) {
        for (int k = 0; k < 4; ++k) {
          EditFlat(root, "depth", k, [](exr::FlatImage& im) {
            for (float& v : im.Get("Z").floats) v *= 100;
          });
        }
        return At("camera.depth-unit", File("depth", 0), 0);
      });
  add("planar-declared-perspective",
      "planar depth declared as perspective",
      [](const fs::path& root) {
        EditCollection(root, [](json& j) {
          for (json& layer : j["layers"]) {
            if (layer.contains("depth_kind")) layer["depth_kind"] = "perspective";
          }
        });
        return At("camera.depth-kind", File("depth", 0), 0);
      });
  add("y-axis-flipped",
      "world-position layers with y negated (flipped handedness)",
      [](const fs::path& root) {
        for (int k = 0; k < 4; ++k) {
          EditFlat(root, "worldposition", k, [](exr::FlatImage& im) {
            for (float& v : im.Get("Y").floats) v = -v;
          });
        }
        return At("camera.handedness", File("worldposition", 0), 0);
      });
  add("image-mirrored",
      "worldposition/000000.exr stored mirrored (columns reversed)",
      [](const fs::path& root) {
        EditFlat(root, "worldposition", 0, [](exr::FlatImage& im) {
          for (const char* c : {"X", "Y", "Z"}) {
            std::vector<float>& v = im.Get(c).floats;
            for (int j = 0; j < im.height(); ++j) {
              std::reverse(v.begin() + im.Index(0, j), v.begin() + im.Index(0, j) + im.width());
            }
          }
        });
        return At("camera.image-flip", File("worldposition", 0), 0);
      });
  add("camera-rolled",
      "frame 1's declared camera rolled 5 degrees about its optical axis",
      [](const fs::path& root) {
        EditCollection(root, [](json& j) {
          json& camera = j["frames"][1]["camera"]["cam_from_world"];
          Eigen::Matrix3d r;
          Eigen::Vector3d t;
          for (int a = 0; a < 3; ++a) {
            t[a] = camera["translation"][a];
            for (int b = 0; b < 3; ++b) r(a, b) = camera["rotation"][a][b];
          }
          const Eigen::Matrix3d roll =
              Eigen::AngleAxisd(5 * M_PI / 180, Eigen::Vector3d::UnitZ()).toRotationMatrix();
          r = roll * r, t = roll * t;
          for (int a = 0; a < 3; ++a) {
            camera["translation"][a] = t[a];
            for (int b = 0; b < 3; ++b) camera["rotation"][a][b] = r(a, b);
          }
        });
        return At("camera.pose", File("worldposition", 1), 1);
      });
  // --- statistics ---
  add("unused-class", "class 4 'tree' has no object and no pixel", [](const fs::path& root) {
    EditCollection(root, [](json& j) { j["classes"].push_back({{"id", 4}, {"name", "tree"}}); });
    return At("stats.class-unused", "collection.json", std::nullopt, "/classes/3");
  });
  add("zero-visible-target",
      "frame 3 object 0 declared with no visible pixels",
      [](const fs::path& root) {
        EditCollection(root, [](json& j) {
          json& object = j["frames"][3]["objects"][0];
          object["visible_pixels"] = 0;
          object["bbox"] = nullptr;
        });
        return At("stats.zero-visible-target", "collection.json", 3, "/frames/3/objects/0");
      });
  // --- LCAP requirements (a quota of two visibility bins over the 4 frames) ---
  add("requirements-missed",
      "frame 2's rendered truth missed its demand (achieved_met false)",
      [](const fs::path& root) {
        EditCollection(root, [](json& j) {
          AddVisibilityQuota(&j, {0.2, 0.2, 0.9, 0.9});
          j["frames"][2]["requirements"]["achieved_met"] = false;
        });
        return At("requirements.met", "collection.json", 2, "/frames");
      });
  add("requirements-quota",
      "every frame's achieved visibility in the upper bin of a [2,2] quota",
      [](const fs::path& root) {
        EditCollection(root, [](json& j) { AddVisibilityQuota(&j, {0.9, 0.9, 0.9, 0.9}); });
        return At("requirements.quota",
                  "collection.json",
                  std::nullopt,
                  "/provenance/requirements/quotas/0");
      });
  add("class-imbalance",
      "100 extra (hidden) boxes per frame against one crate",
      [](const fs::path& root) {
        EditCollection(root, [](json& j) {
          for (json& frame : j["frames"]) {
            json extra = frame["objects"][0];
            extra["class_id"] = 2;
            extra["visible_pixels"] = 0;
            extra["bbox"] = nullptr;
            extra["visibility"] = 0;
            for (int k = 0; k < 100; ++k) {
              extra["instance_id"] = 100 + k;
              frame["objects"].push_back(extra);
            }
          }
        });
        return At("stats.class-imbalance", "collection.json", std::nullopt, "/classes");
      });
  add("empty-frame", "frame 3 has no objects", [](const fs::path& root) {
    EditCollection(root, [](json& j) { j["frames"][3]["objects"] = json::array(); });
    return At("stats.empty-frame", "collection.json", 3, "/frames/3/objects");
  });
  return c;
}

}  // namespace

const std::vector<Corruption>& Corruptions() {
  static const std::vector<Corruption> corruptions = MakeCorruptions();
  return corruptions;
}

const Corruption& FindCorruption(const std::string& name) {
  for (const Corruption& c : Corruptions()) {
    if (c.name == name) return c;
  }
  throw Error("unknown corruption '" + name + "'");
}

void WriteGoodCollection(const fs::path& root) {
  synth::WriteCollection(root, synth::DefaultSpec());
}

void CopyCollection(const fs::path& from, const fs::path& to) {
  fs::create_directories(to);
  fs::copy(from, to, fs::copy_options::recursive | fs::copy_options::overwrite_existing);
}

}  // namespace lsds::validate::corpus

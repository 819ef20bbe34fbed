// The interface every target format implements, and what the driver (convert.h)
// hands it.
//
// The driver reads frames in batches; for each batch it prepares every frame in
// parallel (filters, masks from the instanceid layer, the shared display image)
// and calls EncodeFrame in parallel, then calls AddFrame serially in frame
// order. Converters keep only what the output needs between frames (streamed
// fragments on disk), so memory does not grow with the number of frames.
#pragma once

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "converters/class_map.h"
#include "converters/loss_report.h"
#include "converters/options.h"
#include "converters/split.h"
#include "libs/collection/model.h"
#include "libs/geometry/box2d.h"
#include "libs/geometry/oriented_box2d.h"
#include "libs/masks/instance_masks.h"

namespace lsds::convert {

// An object that passed the filters.
struct KeptObject {
  const ObjectTruth* truth = nullptr;
  int class_index = 0;  // 0-based output class (ClassMap order)
  Box2d box;            // pixel-edge, inside the image: the truth box (tight, visible),
                        // clipped
  const masks::BoxMask* mask =
      nullptr;  // from the instanceid layer; null when no format needs masks
  // The visible oriented box in this image (docs/format.md, "Oriented boxes"):
  // from the truth (format 1.2) or measured on the mask; set only when a
  // format NeedsOrientedBoxes().
  std::optional<OrientedBox2d> oriented;
};

struct FrameContext {
  const Frame* frame = nullptr;
  std::string split;
  std::string stem;        // "000007": file names of the image and the label files
  std::string image_name;  // "000007.png" (the name is written even with --images none)
  int width = 0, height = 0;
  // Unique per output image, in output order: the frame index, or with --tile
  // the running number of the tile (the COCO image id is this + 1).
  int64_t image_index = 0;
  std::vector<KeptObject> objects;  // in the collection's order
  std::vector<masks::BoxMask> mask_storage;
};

struct ConvertSetup {
  std::filesystem::path root;        // the folder being written (temporary until the end)
  std::filesystem::path final_root;  // where it will be (absolute), for files that name it
  const CollectionHeader* header = nullptr;
  const ClassMap* classes = nullptr;
  std::vector<SplitPart> splits;
  const ConvertOptions* options = nullptr;
};

// What EncodeFrame hands to AddFrame; each converter defines its own.
struct FramePiece {
  virtual ~FramePiece() = default;
};

class Converter {
 public:
  virtual ~Converter() = default;
  virtual std::string name() const = 0;
  virtual bool NeedsMasks() const = 0;
  virtual bool NeedsOrientedBoxes() const { return false; }
  virtual void Begin(const ConvertSetup& setup) = 0;
  // Thread-safe (called for several frames at once); counts its own losses into
  // `loss`.
  virtual std::unique_ptr<FramePiece> EncodeFrame(const FrameContext& frame,
                                                  LossReport* loss) const = 0;
  // Serial, in frame order.
  virtual void AddFrame(const FrameContext& frame, std::unique_ptr<FramePiece> piece) = 0;
  virtual void Finish() = 0;
};

}  // namespace lsds::convert

// A COCO `segmentation` read into the RLE that COCOeval compares for iouType
// "segm": a compressed RLE {size, counts: "string"}, an uncompressed one
// {size, counts: [runs]} or polygons [[x0, y0, x1, y1, ...], ...], the three
// forms COCO.annToRLE accepts (coco.py:414-432; docs/evaluate.md, "Masks").
#pragma once

#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "libs/masks/coco_rle.h"

namespace lsds::evaluate {

// The mask of `segmentation` on an image of `height` x `width`. Throws
// lsds::Error at `file#at` (or deeper) for a form that is none of the three,
// a size other than the image's, a counts string the COCO API cannot decode,
// runs that do not add up to the image, a polygon with fewer than three
// points or a coordinate that is not a finite number.
masks::CocoRle ReadSegmentation(const nlohmann::json& segmentation,
                                int64_t height,
                                int64_t width,
                                const std::string& file,
                                const std::string& at);

}  // namespace lsds::evaluate

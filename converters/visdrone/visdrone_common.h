// What VisDrone DET and VID share (docs/convert.md, "visdrone"): the object
// categories, the truncation and occlusion levels and the annotation columns
// after the frame and target ids.
#pragma once

#include <string>
#include <vector>

#include "converters/track_sequences.h"

namespace lsds::convert::visdrone {

// VisDrone's category of an output class name: 1 pedestrian, 2 people,
// 3 bicycle, 4 car, 5 van, 6 truck, 7 tricycle, 8 awning-tricycle, 9 bus,
// 10 motor by name (lower case, '_' and ' ' read as '-'), 11 others for
// every other name (0, ignored regions, is never written).
int CategoryOf(const std::string& class_name);
const char* CategoryName(int category);

// Per output class, its category; and the file that writes the map down
// ("class,category,category_name" lines).
std::vector<int> Categories(const ClassMap& classes);
std::string CategoryMapText(const ClassMap& classes);

// VisDrone's levels from a ratio in percent, rounded: truncation 0 (0 %) or
// 1 (1 % to 50 %, and also above: the format has no higher level); occlusion
// 0 (0 %), 1 (1 % to 50 %) or 2 (above 50 %).
int TruncationLevel(double in_frame);
int OcclusionLevel(double visibility);

// "bbox_left,bbox_top,bbox_width,bbox_height,score,object_category,truncation,
// occlusion": the visible box in 0-based integer pixels, score 1 (considered)
// or 0 (ignored), and the loss-report counts (under `format`) of what the
// columns cannot say.
std::string Columns(const TrackObject& object,
                    int category,
                    const std::string& class_name,
                    const std::string& format,
                    LossReport* loss);

}  // namespace lsds::convert::visdrone

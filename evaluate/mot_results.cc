#include "evaluate/mot_results.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "evaluate/text_number.h"
#include "libs/util/error.h"
#include "libs/util/input_file.h"

namespace lsds::evaluate {

namespace fs = std::filesystem;

namespace {

// TrackEval's reader takes commas, or spaces when a line has none.
std::vector<std::string> Fields(const std::string& line) {
  std::string text = line;
  if (text.find(',') != std::string::npos) std::replace(text.begin(), text.end(), ',', ' ');
  std::istringstream words(text);
  std::vector<std::string> fields;
  for (std::string word; words >> word;) fields.push_back(word);
  return fields;
}

}  // namespace

std::vector<DetectionBox> ReadMotDetections(const fs::path& folder,
                                            const EvaluationTruth& truth,
                                            const MotSequences& sequences) {
  if (truth.coco.category_ids.size() != 1)
    throw Error("MOT tracker files carry no class and the ground truth has " +
                std::to_string(truth.coco.category_ids.size()) +
                " categories: keep one with --classes (as the MOT export was made)");
  if (!fs::is_directory(folder))
    throw Error("--format mot reads a folder of <SEQ>.txt tracker files (TrackEval's data/)",
                Location(folder.string()));
  std::map<int64_t, int64_t> image_of_frame;
  for (const auto& [image, frame] : truth.frame_of_image) {
    if (!image_of_frame.emplace(frame, image).second)
      throw Error("frame " + std::to_string(frame) +
                  " has several images (a rig): MOT predictions are read for one camera only");
  }
  std::vector<fs::path> files;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder))
    if (entry.path().extension() == ".txt") files.push_back(entry.path());
  if (files.empty()) throw Error("no <SEQ>.txt file in the folder", Location(folder.string()));
  std::sort(files.begin(), files.end());
  std::vector<DetectionBox> detections;
  for (const fs::path& file : files) {
    const auto sequence = sequences.find(file.stem().string());
    if (sequence == sequences.end())
      throw Error("'" + file.stem().string() +
                      "' is not a sequence of lsds convert --to mot (its seqmaps list them)",
                  Location(file.string()));
    std::istringstream in(ReadTextFile(file));
    int number = 0;
    for (std::string line; std::getline(in, line);) {
      const Location at = Location::Text(file.string(), ++number, 0);
      const std::vector<std::string> fields = Fields(line);
      if (fields.empty()) continue;
      if (fields.size() < 7)
        throw Error("expected 'frame,id,bb_left,bb_top,bb_width,bb_height,conf[,x,y,z]', got " +
                        std::to_string(fields.size()) + " fields",
                    at);
      const double frame_number = FiniteNumber(fields[0], at);
      const std::vector<int64_t>& frames = sequence->second;
      if (frame_number < 1 || frame_number > static_cast<double>(frames.size()) ||
          frame_number != std::floor(frame_number))
        throw Error("frame " + fields[0] + " is not a frame of the sequence (1.." +
                        std::to_string(frames.size()) + ")",
                    at);
      const auto image = image_of_frame.find(frames[static_cast<size_t>(frame_number) - 1]);
      if (image == image_of_frame.end())
        throw Error("frame " + fields[0] + " has no image in the ground truth", at);
      DetectionBox d;
      d.image_id = image->second;
      d.category_id = truth.coco.category_ids.front();
      // MOT's boxes are 1-based: bb_left 1 is the first pixel column.
      d.bbox = {FiniteNumber(fields[2], at) - 1,
                FiniteNumber(fields[3], at) - 1,
                FiniteNumber(fields[4], at),
                FiniteNumber(fields[5], at)};
      if (d.bbox.w < 0 || d.bbox.h < 0) throw Error("negative width or height", at);
      d.score = FiniteNumber(fields[6], at);
      detections.push_back(d);
    }
  }
  return detections;
}

}  // namespace lsds::evaluate

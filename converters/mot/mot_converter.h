// MOTChallenge (MOT17) ground truth as TrackEval reads it (docs/convert.md,
// "mot").
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "converters/converter.h"

namespace lsds::convert {

std::unique_ptr<Converter> MakeMotConverter();

// MOT17's class id of a class name (TrackEval's class_name_to_class_id,
// trackeval/datasets/mot_challenge_2d_box.py:76): lower case, with ' ' and '-'
// read as '_'; none for a name MOT17 does not have.
std::optional<int> Mot17ClassId(const std::string& name);

}  // namespace lsds::convert

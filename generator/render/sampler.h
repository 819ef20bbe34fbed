// The generator's sub-pixel sampler: the documented rule of
// libs/collection/sample_positions.h, shared with the bundle readers.
#pragma once

#include "libs/collection/sample_positions.h"

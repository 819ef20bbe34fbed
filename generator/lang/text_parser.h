// The text notation of LSCENE/LCAP (docs/languages.md, "Grammar"), parsed into
// the generic tree of source.h. Errors are lsds::Error with file:line:column
// and what was expected.
#pragma once

#include <string>

#include "generator/lang/source.h"

namespace lsds {

// Fills doc, positions and warnings of a SourceFile from the text notation.
void ParseTextNotation(SourceFile* source);

}  // namespace lsds

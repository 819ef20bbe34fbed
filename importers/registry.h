// The registry of source formats: one line per importer in registry.cc.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "importers/importer.h"

namespace lsds::import {

std::vector<std::string> ImporterNames();  // ue-mrq, ...
// Throws lsds::Error for an unknown name (with a did-you-mean).
std::unique_ptr<Importer> MakeImporter(const std::string& name);

}  // namespace lsds::import

// The consumers `lsds check-export` knows: one line per consumer in
// registry.cc (its name, the lsds convert formats it reads, its rules and
// its check), and the run over an export folder.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "converters/check/consumer.h"
#include "converters/check/finding.h"

namespace lsds::check {

const std::vector<Consumer>& Consumers();
// The formats some consumer reads, in registry order without repeats.
std::vector<std::string> CheckedFormats();
// The consumers that read `format`.
std::vector<std::string> ConsumerNames(const std::string& format);

// Applies the rules of `consumer` (empty: every consumer of `format`) to the
// export at `dir`. Throws lsds::Error (exit 2) for an unknown format or
// consumer, a consumer that does not read `format`, or a `dir` that is not a
// readable folder.
ExportReport CheckExport(const std::string& format,
                         const std::filesystem::path& dir,
                         const std::string& consumer,
                         const CheckOptions& options);

}  // namespace lsds::check

// The command table of the lsds binary and the pieces every command shares.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "tools/shared_flags.h"

namespace lsds {

struct Command {
  std::string name;
  std::string summary;  // one line for `lsds help`
  int (*run)(int argc, char** argv);
};

// Every command, in the order `lsds help` lists them. One line per command in
// command.cc.
const std::vector<Command>& Commands();

// Parses `argv` with `app` and runs `body`, mapping the outcome to the exit
// codes of the brief: 0 success, 1 findings (returned by `body`), 2 bad usage
// or unreadable input (lsds::Error, printed as "lsds NAME: error: WHERE: WHAT",
// and CLI11 errors, printed as "lsds NAME: error: WHAT" with a did-you-mean
// for a mistyped option). The common flags (tools/shared_flags.h, added to
// `app` with AddCommonFlags) are applied here for the whole command: unused
// ones refused, --memory-budget set, -q silencing the progress line, and
// --threads capping TBB's workers while `body` runs.
int RunCommand(CLI::App& app,
               const CommonFlags& common,
               int argc,
               char** argv,
               const std::function<int()>& body);

// Command entry points, one per file, each in its feature's folder
// (<feature>/<name>_command.cc, docs/architecture.md).
int RunGenerate(int argc, char** argv);
int RunPlan(int argc, char** argv);
int RunExportScene(int argc, char** argv);
int RunLanguage(int argc, char** argv);
int RunInfo(int argc, char** argv);
int RunValidate(int argc, char** argv);
int RunConvert(int argc, char** argv);
int RunCheckExport(int argc, char** argv);
int RunPerturbMetadata(int argc, char** argv);
int RunBundles(int argc, char** argv);
int RunBackproject(int argc, char** argv);
int RunExportLayers(int argc, char** argv);
int RunReport(int argc, char** argv);
int RunSynth(int argc, char** argv);
int RunImport(int argc, char** argv);
int RunMerge(int argc, char** argv);
int RunMergeReports(int argc, char** argv);
int RunSubmit(int argc, char** argv);
int RunEvaluate(int argc, char** argv);

}  // namespace lsds

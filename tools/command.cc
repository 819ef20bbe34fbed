#include "tools/command.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <new>

#include "converters/check/registry.h"
#include "converters/registry.h"
#include "importers/registry.h"
#include "libs/util/check.h"
#include "libs/util/error.h"
#include "libs/util/limits.h"
#include "libs/util/progress.h"
#include "libs/util/strings.h"
#include "libs/util/thread_limit.h"

namespace lsds {

const std::vector<Command>& Commands() {
  static const std::vector<Command> commands = {
      {"generate",
       "render a scene (LSCENE/LCAP, a plan, or --demo) into a collection",
       RunGenerate},
      {"plan", "expand an LSCENE scene and LCAP capture into the frame plan (JSON)", RunPlan},
      {"export-scene",
       "each planned frame's scene as glTF 2.0 and JSON for Blender, Unreal or Omniverse",
       RunExportScene},
      {"language",
       "the LSCENE/LCAP vocabulary: kinds, keys, spellings, types, units, ranges (--json)",
       RunLanguage},
      {"info", "summarize a collection: frames, layers, classes, cameras, size", RunInfo},
      {"validate",
       "check a collection: schemas, structure, layers, cross-layer truth, "
       "camera geometry",
       RunValidate},
      // The formats come from the registries, so that help never lists fewer than there are.
      {"convert",
       "truth into " + Join(convert::ConverterNames(), ", ") + " with a loss report",
       RunConvert},
      {"check-export",
       "predict what each consumer (Ultralytics, MMRotate, Datumaro, DOTA devkit, TrackEval, "
       "pycocotools) drops or rejects of an export of " +
           Join(check::CheckedFormats(), ", "),
       RunCheckExport},
      {"evaluate",
       "detection metrics of predictions (COCOeval) per condition of the collection; --coverage",
       RunEvaluate},
      {"perturb-metadata",
       "write a perturbed copy of the metadata with the noise and errors "
       "recorded",
       RunPerturbMetadata},
      {"bundles",
       "mixed-pixel statistics of the pixel bundles; bundle-derived truth "
       "layers",
       RunBundles},
      {"backproject",
       "depth layers to point clouds (PCD/PLY), per frame or fused; --check",
       RunBackproject},
      {"export-layers",
       "layers as .npy, 16-bit PNG or float TIFF with units and scales",
       RunExportLayers},
      {"report", "one offline HTML page: contact sheet, layers, distributions", RunReport},
      {"merge", "join the shards of one generate run into the single run's collection", RunMerge},
      {"merge-reports",
       "join the partial reports of validate --shard into the single run's "
       "report",
       RunMergeReports},
      {"submit", "write and submit a Slurm job array of generate shards and its merge", RunSubmit},
      {"synth", "write a synthetic collection with exact analytic truth (for tests)", RunSynth},
      {"import",
       "another simulator's output (" + Join(import::ImporterNames(), ", ") + ") into a collection",
       RunImport},
  };
  return commands;
}

namespace {

// The visible option names of `app` ("--frames", "-o", ...): the candidates of
// a did-you-mean. Hidden (deprecated) aliases are never suggested.
std::vector<std::string> OptionNames(const CLI::App& app) {
  std::vector<std::string> names;
  for (const CLI::Option* option : app.get_options()) {
    if (option->get_group().empty()) continue;
    for (const std::string& name : option->get_lnames()) names.push_back("--" + name);
    for (const std::string& name : option->get_snames()) names.push_back("-" + name);
  }
  return names;
}

// A CLI11 parse error as the documented one-line message, with a suggestion
// for a mistyped option.
std::string UsageMessage(CLI::App& app, const CLI::ParseError& error) {
  if (dynamic_cast<const CLI::ExtrasError*>(&error) != nullptr) {
    const std::vector<std::string> extras = app.remaining();
    std::vector<std::string> parts;
    for (const std::string& extra : extras) {
      if (extra.size() > 1 && extra[0] == '-') {
        const std::string name = extra.substr(0, extra.find('='));
        parts.push_back("unknown option '" + name + "'" + DidYouMean(name, OptionNames(app)));
      } else {
        parts.push_back("unexpected argument '" + extra + "'");
      }
    }
    if (!parts.empty()) return Join(parts, "; ");
  }
  return error.what();
}

// The one range check of numeric flags, for every command: CLI11 converts
// "nan", "inf" and "1e999" into non-finite doubles and (in some versions) "-1"
// into a huge unsigned value. The option's type name says what it holds.
void CheckNumericFlags(const CLI::App& app) {
  for (const CLI::Option* option : app.get_options()) {
    const std::string type = option->get_type_name();
    const bool real = type.find("FLOAT") != std::string::npos;
    const bool natural = type.find("UINT") != std::string::npos;
    if (!real && !natural) continue;
    const std::string name =
        option->get_lnames().empty() ? option->get_name() : "--" + option->get_lnames().front();
    for (const std::string& value : option->results()) {
      const size_t first = value.find_first_not_of(" \t");
      if (first == std::string::npos) continue;
      if (natural && value[first] == '-') {
        throw Error(name + ": expected a number >= 0, got '" + value + "'");
      }
      if (real) {
        errno = 0;
        char* end = nullptr;
        const double number = std::strtod(value.c_str(), &end);
        if (end != value.c_str() && (!std::isfinite(number) || errno == ERANGE) &&
            std::fabs(number) > 1.0) {
          throw Error(name + ": expected a finite number, got '" + value + "'");
        }
        if (end != value.c_str() && std::isnan(number))
          throw Error(name + ": expected a finite number, got '" + value + "'");
      }
    }
  }
  for (const CLI::App* sub : app.get_subcommands({})) CheckNumericFlags(*sub);
}

}  // namespace

int RunCommand(CLI::App& app,
               const CommonFlags& common,
               int argc,
               char** argv,
               const std::function<int()>& body) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) {
      app.exit(e);  // --help
      return kExitOk;
    }
    std::cerr << app.get_name() << ": error: " << UsageMessage(app, e) << "; run '"
              << app.get_name() << " --help' for the options\n";
    return kExitUsage;
  }
  // Three kinds of failure (docs/reliability.md): bad input (lsds::Error,
  // exit 2, located), findings (exit 1, returned by `body`), and bugs in lsds
  // (everything else, exit 70 with a request for a bug report).
  try {
    CheckNumericFlags(app);
    // Every command's image-shaped allocations (films, decoded layers) are
    // checked against one budget (libs/util/limits.h) before they are made.
    if (!common.memory_budget.empty()) SetMemoryBudget(common.memory_budget);
  } catch (const Error& e) {
    std::cerr << app.get_name() << ": error: " << e.what() << "; run '" << app.get_name()
              << " --help' for the options\n";
    return kExitUsage;
  }
  try {
    RefuseUnusedFlags(app, common);
    if (common.quiet) Progress::Silence();
    const ThreadLimit thread_limit(common.threads);
    return body();
  } catch (const Error& e) {
    std::cerr << app.get_name() << ": error: " << e.what() << "\n";
    return kExitUsage;
  } catch (const std::filesystem::filesystem_error& e) {
    // The operating system refused a path the user gave (permissions, a full
    // disk): the message names the path.
    std::cerr << app.get_name() << ": error: " << e.what() << "\n";
    return kExitUsage;
  } catch (const std::bad_alloc&) {
    std::cerr << app.get_name()
              << ": error: out of memory; lower --threads or --batch, or "
                 "work on fewer frames\n";
    return kExitUsage;
  } catch (const InternalError& e) {
    std::cerr << app.get_name() << ": internal error: " << e.what() << "; " << InternalErrorAdvice()
              << "\n";
    return kExitInternal;
  } catch (const std::exception& e) {
    std::cerr << app.get_name() << ": internal error: unexpected exception: " << e.what() << "; "
              << InternalErrorAdvice() << "\n";
    return kExitInternal;
  }
}

}  // namespace lsds

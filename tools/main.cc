// lsds: one binary, one command table (tools/command.cc), one file per command.
#include <cstring>
#include <iostream>

#include "libs/util/check.h"
#include "libs/util/error.h"
#include "libs/util/strings.h"
#include "tools/command.h"

namespace {

void PrintHelp() {
  std::cout << "lsds " << LSDS_VERSION << ": simulated datasets for AI/ML and UAV imagery\n\n"
            << "usage: lsds COMMAND [ARGS...]   (lsds COMMAND --help for its "
               "options)\n\ncommands:\n";
  for (const lsds::Command& command : lsds::Commands()) {
    std::cout << "  " << command.name
              << std::string(18 - std::min<size_t>(17, command.name.size()), ' ') << command.summary
              << "\n";
  }
  std::cout << "\nexit codes: 0 success, 1 findings at or above the failure "
               "level, 2 bad usage or unreadable input, 70 internal error (a "
               "bug in lsds: please report it)\n";
}

}  // namespace

namespace {

int Dispatch(int argc, char** argv);

}  // namespace

// The last line of defence: anything that escapes a command (which maps its
// own failures to exit codes in RunCommand) is a bug in lsds.
int main(int argc, char** argv) {
  try {
    return Dispatch(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "lsds: internal error: " << e.what() << "; " << lsds::InternalErrorAdvice()
              << "\n";
  } catch (...) {
    std::cerr << "lsds: internal error: unknown exception; " << lsds::InternalErrorAdvice() << "\n";
  }
  return lsds::kExitInternal;
}

namespace {

int Dispatch(int argc, char** argv) {
  if (argc < 2) {
    PrintHelp();
    return lsds::kExitUsage;
  }
  const std::string name = argv[1];
  if (name == "help" || name == "--help" || name == "-h") {
    if (argc >= 3) {
      for (const lsds::Command& command : lsds::Commands()) {
        if (command.name == argv[2]) {
          char help[] = "--help";
          char* args[] = {argv[2], help};
          return command.run(2, args);
        }
      }
    }
    PrintHelp();
    return lsds::kExitOk;
  }
  if (name == "--version" || name == "version") {
    std::cout << "lsds " << LSDS_VERSION << "\n";
    return lsds::kExitOk;
  }
  std::vector<std::string> names;
  for (const lsds::Command& command : lsds::Commands()) {
    if (command.name == name) return command.run(argc - 1, argv + 1);
    names.push_back(command.name);
  }
  std::cerr << "lsds: error: unknown command '" << name << "'" << lsds::DidYouMean(name, names)
            << "; run 'lsds help' for the list\n";
  return lsds::kExitUsage;
}

}  // namespace

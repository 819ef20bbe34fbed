#include "libs/util/plugin.h"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <system_error>

#include "libs/util/error.h"
#include "libs/util/plugin_build_dir.h"
#include "libs/util/process.h"

namespace lsds {

namespace {

// The folder of the shared object that holds this code when that is not the running executable
// (the Python module, loaded by python3), from dladdr; empty in the lsds binary and its tests.
std::string SharedObjectDir() {
  Dl_info info{};
  if (dladdr(reinterpret_cast<const void*>(&PluginSearchDirs), &info) == 0 ||
      info.dli_fname == nullptr || *info.dli_fname == '\0') {
    return {};
  }
  std::error_code ec;
  const std::filesystem::path object = std::filesystem::absolute(info.dli_fname, ec);
  if (ec) return {};
  // For the executable itself glibc names argv[0]; equivalent() fails (ec) when that is not a
  // path from here, and either way the executable is rule 2's business.
  if (std::filesystem::equivalent(object, "/proc/self/exe", ec) || ec) return {};
  return object.parent_path().string();
}

// The loader's last message. glibc keeps dlerror()'s state per thread, so this is safe to call
// from any thread.
std::string LastDlError() {
  // NOLINTNEXTLINE(concurrency-mt-unsafe): per-thread state in glibc
  const char* why = dlerror();
  return why != nullptr ? why : "no reason given";
}

}  // namespace

std::vector<std::string> PluginSearchDirs() {
  std::vector<std::string> dirs;
  // NOLINTNEXTLINE(concurrency-mt-unsafe): lsds never sets the environment
  if (const char* env = std::getenv("LSDS_PLUGIN_DIR"); env != nullptr && *env != '\0')
    dirs.emplace_back(env);
  if (const std::string exe_dir = ExecutableDir(); !exe_dir.empty())
    dirs.push_back((std::filesystem::path(exe_dir) / ".." / "lib" / "lsds").lexically_normal());
  if (const std::string object_dir = SharedObjectDir(); !object_dir.empty()) {
    dirs.push_back(
        (std::filesystem::path(object_dir) / PluginDirFromPythonPackage()).lexically_normal());
  }
  dirs.emplace_back(PluginBuildDir());
  return dirs;
}

void* LoadPluginSymbol(const std::string& file_name, const std::string& symbol) {
  std::string tried;
  for (const std::string& dir : PluginSearchDirs()) {
    const std::string path = (std::filesystem::path(dir) / file_name).string();
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) {
      tried += "\n  " + path + ": not found";
      continue;
    }
    // A plug-in that is present but does not open (missing dependency, wrong architecture,
    // missing symbol) is reported rather than skipped: a later folder's copy would hide it.
    void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (handle == nullptr) throw Error("cannot load the plug-in " + path + ": " + LastDlError());
    void* address = dlsym(handle, symbol.c_str());
    if (address == nullptr) {
      throw Error("the plug-in " + path + " does not export " + symbol + ": " + LastDlError());
    }
    return address;
  }
  throw Error("cannot find the plug-in " + file_name +
              " (set LSDS_PLUGIN_DIR to the folder that holds it); tried:" + tried);
}

void CheckPluginAbiVersion(const std::string& file_name, const int* found, int wanted) {
  if (found != nullptr && *found == wanted) return;
  throw Error("the plug-in " + file_name + " has ABI version " +
              (found != nullptr ? std::to_string(*found) : "none") + ", lsds needs " +
              std::to_string(wanted) + ": reinstall lsds");
}

}  // namespace lsds

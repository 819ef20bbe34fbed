#include "generator/scene/asset_library.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <regex>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "generator/scene/mesh_formats.h"
#include "libs/util/error.h"

namespace lsds::gen {
namespace {

namespace fs = std::filesystem;

std::string ReadString(const nlohmann::json& j,
                       const std::string& manifest,
                       const std::string& pointer,
                       const std::string& what) {
  if (!j.is_string() || j.get<std::string>().empty())
    throw Error(what + " must be a non-empty string", Location(manifest, pointer));
  return j.get<std::string>();
}

LibraryAsset ReadEntry(const nlohmann::json& e,
                       const std::string& root,
                       const std::string& manifest,
                       const std::string& pointer) {
  if (!e.is_object())
    throw Error("an asset is an object {file, class, tags, unit, up}", Location(manifest, pointer));
  static const std::set<std::string> kKeys = {"file", "class", "tags", "unit", "up"};
  for (const auto& [key, value] : e.items())
    if (!kKeys.count(key))
      throw Error("unknown key '" + key + "' (expected file, class, tags, unit, up)",
                  Location(manifest, pointer + "/" + key));
  LibraryAsset a;
  if (!e.contains("file")) throw Error("an asset needs a file", Location(manifest, pointer));
  a.path = fs::path(ReadString(e["file"], manifest, pointer + "/file", "file"))
               .lexically_normal()
               .generic_string();
  if (fs::path(a.path).is_absolute() || a.path.rfind("..", 0) == 0)
    throw Error("file must lie inside the library folder", Location(manifest, pointer + "/file"));
  a.file = (fs::path(root) / a.path).lexically_normal().generic_string();
  if (!fs::is_regular_file(a.file))
    throw Error("file '" + a.path + "' not found in the library folder " + root,
                Location(manifest, pointer + "/file"));
  if (!e.contains("class")) throw Error("an asset needs a class", Location(manifest, pointer));
  a.class_name = ReadString(e["class"], manifest, pointer + "/class", "class");
  if (e.contains("tags")) {
    const nlohmann::json& tags = e["tags"];
    if (!tags.is_array())
      throw Error("tags must be an array of strings", Location(manifest, pointer + "/tags"));
    for (size_t i = 0; i < tags.size(); ++i)
      a.tags.push_back(
          ReadString(tags[i], manifest, pointer + "/tags/" + std::to_string(i), "a tag"));
  }
  if (e.contains("unit")) {
    static const std::map<std::string, double> kUnits = {{"m", 1.0}, {"cm", 0.01}, {"mm", 0.001}};
    const std::string unit = ReadString(e["unit"], manifest, pointer + "/unit", "unit");
    const auto it = kUnits.find(unit);
    if (it == kUnits.end())
      throw Error("unit must be m, cm or mm, not '" + unit + "'",
                  Location(manifest, pointer + "/unit"));
    a.metres_per_unit = it->second;
    a.unit_declared = true;
  }
  if (e.contains("up")) {
    const std::string up = ReadString(e["up"], manifest, pointer + "/up", "up");
    if (up != "y" && up != "z")
      throw Error("up must be y or z, not '" + up + "'", Location(manifest, pointer + "/up"));
    a.y_up = up == "y";
  } else {
    a.y_up = IsYUpByFormat(a.path);
  }
  return a;
}

}  // namespace

// A library without a manifest: every mesh file under the folder, in path order; its class the
// folder it lies in (the file's name for a file at the root), its tags every folder on its path.
static std::vector<LibraryAsset> ScanLibraryFolder(const std::string& root) {
  std::vector<std::string> paths;
  std::error_code error;
  for (fs::recursive_directory_iterator it(root, error), end; !error && it != end;
       it.increment(error))
    if (it->is_regular_file() && IsMeshPath(it->path().string()))
      paths.push_back(fs::relative(it->path(), root).lexically_normal().generic_string());
  if (error) throw Error("cannot list the asset library: " + error.message(), Location(root));
  if (paths.empty())
    throw Error(std::string("the asset library has neither a manifest (") + kAssetManifestName +
                    ") nor mesh files",
                Location(root));
  std::sort(paths.begin(), paths.end());
  std::vector<LibraryAsset> assets;
  for (const std::string& path : paths) {
    LibraryAsset a;
    a.path = path;
    a.file = (fs::path(root) / path).lexically_normal().generic_string();
    const fs::path folder = fs::path(path).parent_path();
    a.class_name = folder.empty() ? fs::path(path).stem().string() : folder.filename().string();
    for (const fs::path& part : folder) a.tags.push_back(part.string());
    a.unit_declared = false;
    a.y_up = IsYUpByFormat(a.path);
    assets.push_back(std::move(a));
  }
  return assets;
}

AssetLibrary AssetLibrary::Load(const std::string& root) {
  AssetLibrary library;
  library.root_ = fs::path(root).lexically_normal().generic_string();
  const std::string manifest = (fs::path(library.root_) / kAssetManifestName).generic_string();
  if (!fs::exists(manifest)) {
    library.assets_ = ScanLibraryFolder(library.root_);
    return library;
  }
  std::ifstream in(manifest);
  if (!in) throw Error("cannot read the asset library's manifest", Location(manifest));
  std::stringstream text;
  text << in.rdbuf();
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text.str());
  } catch (const nlohmann::json::parse_error& e) {
    throw Error(std::string("not valid JSON: ") + e.what(), Location(manifest));
  }
  if (!j.is_object() || !j.contains("assets") || !j["assets"].is_array())
    throw Error("the manifest is {\"assets\": [{file, class, tags, unit, up}, ...]}",
                Location(manifest, j.is_object() && j.contains("assets") ? "/assets" : ""));
  std::set<std::string> seen;
  for (size_t i = 0; i < j["assets"].size(); ++i) {
    const std::string pointer = "/assets/" + std::to_string(i);
    LibraryAsset a = ReadEntry(j["assets"][i], library.root_, manifest, pointer);
    if (!seen.insert(a.path).second)
      throw Error("file '" + a.path + "' is listed twice", Location(manifest, pointer + "/file"));
    library.assets_.push_back(std::move(a));
  }
  return library;
}

std::vector<std::string> AssetLibrary::Tags() const {
  std::set<std::string> tags;
  for (const LibraryAsset& a : assets_) tags.insert(a.tags.begin(), a.tags.end());
  return {tags.begin(), tags.end()};
}

std::vector<const LibraryAsset*> AssetLibrary::WithTags(
    const std::vector<std::string>& tags) const {
  std::vector<const LibraryAsset*> out;
  for (const LibraryAsset& a : assets_)
    if (std::all_of(tags.begin(), tags.end(), [&](const std::string& t) {
          return std::find(a.tags.begin(), a.tags.end(), t) != a.tags.end();
        }))
      out.push_back(&a);
  return out;
}

std::vector<const LibraryAsset*> AssetLibrary::Match(const std::string& option) const {
  std::vector<const LibraryAsset*> out;
  for (const LibraryAsset& a : assets_)
    if (a.path == option || fs::path(a.path).stem().string() == option) out.push_back(&a);
  if (!out.empty()) return out;
  std::regex pattern;
  try {
    pattern = std::regex(option, std::regex::ECMAScript);
  } catch (const std::regex_error& e) {
    throw Error("'" + option + "' is not a valid regular expression: " + e.what());
  }
  for (const LibraryAsset& a : assets_)
    if (std::regex_match(a.path, pattern)) out.push_back(&a);
  return out;
}

bool LooksLikePattern(const std::string& option) {
  return option.find_first_of("*+?[](){}|^$\\") != std::string::npos;
}

std::optional<LibraryAsset> LibraryAssetOf(const std::string& mesh_path) {
  static std::mutex mutex;
  static std::map<std::string, std::optional<AssetLibrary>> cache;  // by folder
  const fs::path file = fs::absolute(mesh_path).lexically_normal();
  for (fs::path dir = file.parent_path(); !dir.empty(); dir = dir.parent_path()) {
    if (fs::is_regular_file(dir / kAssetManifestName)) {
      std::lock_guard<std::mutex> lock(mutex);
      auto it = cache.find(dir.generic_string());
      if (it == cache.end())
        it = cache.emplace(dir.generic_string(), AssetLibrary::Load(dir.generic_string())).first;
      const std::string relative = file.lexically_relative(dir).generic_string();
      for (const LibraryAsset& a : it->second->assets())
        if (a.path == relative) return a;
      return std::nullopt;
    }
    if (dir == dir.root_path()) break;
  }
  return std::nullopt;
}

}  // namespace lsds::gen

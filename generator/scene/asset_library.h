// A user asset library: a folder of meshes with a manifest, `lsds_assets.json`
// at its root (docs/languages.md, "Asset library"), naming for each mesh file
// its class, tags, unit (m, cm, mm) and up axis (y or z). LSCENE selects
// assets by name, by tags or by a regular expression over the library's
// relative paths; the mesh loader applies the up axis to any file the
// manifest lists, so a plan that names the file renders it upright anywhere.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace lsds::gen {

inline constexpr const char* kAssetManifestName = "lsds_assets.json";

struct LibraryAsset {
  std::string path;  // relative to the library root, '/'-separated (what patterns match)
  std::string file;  // the mesh file as the plan names it (root / path)
  std::string class_name;
  std::vector<std::string> tags;
  double metres_per_unit = 1.0;
  bool unit_declared = false;  // the manifest gives `unit` (else metres, checked for plausibility)
  bool y_up = false;

  std::optional<double> DeclaredMetresPerUnit() const {
    return unit_declared ? std::optional<double>(metres_per_unit) : std::nullopt;
  }
};

class AssetLibrary {
 public:
  // Reads `root`/lsds_assets.json. Throws lsds::Error naming the manifest and
  // the JSON pointer of a malformed entry, or a listed file that is missing.
  // Without a manifest, every mesh file under `root` is an asset: its class the
  // folder it lies in (the file name's stem at the root), its tags the folders
  // on its path, its unit undeclared (metres), its up axis its format's.
  static AssetLibrary Load(const std::string& root);

  const std::string& root() const { return root_; }
  const std::vector<LibraryAsset>& assets() const { return assets_; }
  std::vector<std::string> Tags() const;  // every tag, sorted, once

  // Assets carrying every one of `tags`.
  std::vector<const LibraryAsset*> WithTags(const std::vector<std::string>& tags) const;
  // Assets an option names: its relative path, its file name without the
  // extension, or else the assets whose relative path the option matches in
  // full as an ECMAScript regular expression. Throws lsds::Error (no
  // location) for an invalid expression.
  std::vector<const LibraryAsset*> Match(const std::string& option) const;

 private:
  std::string root_;
  std::vector<LibraryAsset> assets_;
};

// True when `option` uses regular-expression syntax (so that matching nothing
// is an error rather than a fall-back to a plain file name).
bool LooksLikePattern(const std::string& option);

// The manifest entry of a mesh file inside a library: the nearest folder
// above it holding lsds_assets.json that lists it. Cached per manifest.
std::optional<LibraryAsset> LibraryAssetOf(const std::string& mesh_path);

}  // namespace lsds::gen

// LSCENE's side of a user asset library (generator/scene/asset_library.h):
// the library a scene names with `L = asset_library{path:"DIR"}` and the
// assets a class option selects, by name, by tags (`class:{tags:[a,b]}`) or by
// a regular expression over the library's relative paths.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "generator/lang/scene.h"
#include "generator/scene/asset_library.h"

namespace lsds {

// Loads the library of an asset_library definition; its path is relative to
// the scene file. A bad manifest is an error naming the manifest and pointer.
gen::AssetLibrary LoadSceneAssetLibrary(const Program& scene, const Definition& def);

// A class node of the form {tags: [...]}.
bool IsTagSelection(const Node& cls);

// The library assets option `option` of class node `cls` selects ("tags" for
// a tag selection). Empty when it is no library selection (no library, a
// built-in or classes{} name, or a plain name the library does not hold):
// then the usual class resolution applies. An unknown tag, a pattern that
// matches nothing or an invalid pattern is an error at the option's place.
std::vector<const gen::LibraryAsset*> SelectAssets(const gen::AssetLibrary* library,
                                                   const Node& cls,
                                                   const std::string& option);

// The class a library asset is labelled with: a built-in's other spelling
// (`rocks`) is the built-in's name.
std::string AssetClassName(const gen::LibraryAsset& asset);

}  // namespace lsds

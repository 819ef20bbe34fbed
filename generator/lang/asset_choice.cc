#include "generator/lang/asset_choice.h"

#include <algorithm>
#include <filesystem>

#include "generator/lang/vocabulary.h"
#include "generator/scene/object_library.h"
#include "libs/util/strings.h"

namespace lsds {

gen::AssetLibrary LoadSceneAssetLibrary(const Program& scene, const Definition& def) {
  CheckKeys(def.body, KindVocabulary("asset_library"), def.symbol);
  const Node path = def.body.Find("path");
  if (!path) def.body.Fail("asset_library needs a path (the library folder)");
  const std::string dir = (std::filesystem::path(scene.src->path).parent_path() / ReadString(path))
                              .lexically_normal()
                              .generic_string();
  if (!std::filesystem::is_directory(dir))
    path.Fail("asset library folder '" + dir + "' not found");
  return gen::AssetLibrary::Load(dir);
}

bool IsTagSelection(const Node& cls) {
  return cls->is_object() && cls->size() == 1 && bool(cls.Child("tags"));
}

std::vector<const gen::LibraryAsset*> SelectAssets(const gen::AssetLibrary* library,
                                                   const Node& cls,
                                                   const std::string& option) {
  if (IsTagSelection(cls)) {
    const Node tags_node = cls.Child("tags");
    if (!library)
      cls.Fail("class:{tags:[...]} selects from an asset library: add L = asset_library{path:DIR}");
    std::vector<std::string> tags;
    if (tags_node->is_string()) {
      tags.push_back(ReadString(tags_node));
    } else {
      if (!tags_node->is_array() || tags_node->empty())
        tags_node.Fail("tags is a list of tag names, e.g. tags:[desert,rock]");
      for (size_t i = 0; i < tags_node->size(); ++i) tags.push_back(ReadString(tags_node.Item(i)));
    }
    const std::vector<std::string> known = library->Tags();
    for (size_t i = 0; i < tags.size(); ++i)
      if (std::find(known.begin(), known.end(), tags[i]) == known.end()) {
        const Node at = tags_node->is_array() ? tags_node.Item(i) : tags_node;
        at.Fail("no asset of the library " + library->root() + " has tag '" + tags[i] + "'" +
                DidYouMean(tags[i], known) + "; its tags: " + Join(known, ", "));
      }
    std::vector<const gen::LibraryAsset*> out = library->WithTags(tags);
    if (out.empty())
      tags_node.Fail("no asset of the library " + library->root() + " has all the tags [" +
                     Join(tags, ", ") + "]");
    return out;
  }
  if (!library || !gen::CanonicalClassName(option).empty()) return {};
  const Location where =
      cls->is_object() ? cls.src->WhereKey(cls.Child(option).pointer) : cls.src->Where(cls.pointer);
  std::vector<const gen::LibraryAsset*> out;
  try {
    out = library->Match(option);
  } catch (const Error& e) {
    throw Error(e.message(), where);
  }
  if (out.empty() && gen::LooksLikePattern(option))
    throw Error("the pattern '" + option + "' matches no asset of the library " + library->root() +
                    " (a pattern must match a whole relative path, e.g. clutter/.*\\.obj)",
                where);
  return out;
}

std::string AssetClassName(const gen::LibraryAsset& asset) {
  const std::string canonical = gen::CanonicalClassName(asset.class_name);
  return canonical.empty() ? asset.class_name : canonical;
}

}  // namespace lsds

// JSON Schema validation (valijson) against the schemas of schemas/, compiled
// into the binary.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace lsds {

struct SchemaIssue {
  std::string pointer;  // JSON pointer of the offending value, e.g.
                        // "/frames/3/camera/fx"
  std::string message;
};

class JsonSchema {
 public:
  // The schema `file` of schemas/ (e.g. "collection.schema.json"), or one of
  // its definitions (e.g. "frame") so that large arrays can be validated
  // element by element. Cached; thread-safe.
  static const JsonSchema& Get(const std::string& file, const std::string& definition = "");

  // The most specific issues (no issue whose location contains another's),
  // pointers prefixed.
  std::vector<SchemaIssue> Validate(const nlohmann::json& document,
                                    const std::string& pointer_prefix = "") const;
  // Throws lsds::Error naming `file_for_messages` and the pointer of the first
  // issue.
  void ValidateOrThrow(const nlohmann::json& document,
                       const std::string& file_for_messages,
                       const std::string& pointer_prefix = "") const;

  ~JsonSchema();
  struct Impl;

 private:
  explicit JsonSchema(const nlohmann::json& schema_document);
  Impl* impl_;
};

// Text of an embedded schema; throws lsds::Error for an unknown name.
const std::string& EmbeddedSchemaText(const std::string& file);
std::vector<std::string> EmbeddedSchemaNames();

}  // namespace lsds

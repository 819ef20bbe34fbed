#include "libs/collection/schema.h"

#include <map>
#include <memory>
#include <mutex>

#include <valijson/adapters/nlohmann_json_adapter.hpp>
#include <valijson/schema.hpp>
#include <valijson/schema_parser.hpp>
#include <valijson/validation_results.hpp>
#include <valijson/validator.hpp>

#include "libs/util/error.h"
#include "libs/util/strings.h"

namespace lsds {

const std::map<std::string, std::string>& EmbeddedSchemas();  // generated, schemas/CMakeLists.txt

struct JsonSchema::Impl {
  nlohmann::json document;  // the adapter refers to it while parsing
  valijson::Schema schema;
};

JsonSchema::JsonSchema(const nlohmann::json& schema_document) : impl_(new Impl) {
  impl_->document = schema_document;
  valijson::SchemaParser parser(valijson::SchemaParser::kDraft7);
  valijson::adapters::NlohmannJsonAdapter adapter(impl_->document);
  parser.populateSchema(adapter, impl_->schema);
}

JsonSchema::~JsonSchema() { delete impl_; }

const std::string& EmbeddedSchemaText(const std::string& file) {
  const auto& schemas = EmbeddedSchemas();
  const auto it = schemas.find(file);
  if (it == schemas.end()) {
    throw Error("unknown schema '" + file + "'" + DidYouMean(file, EmbeddedSchemaNames()));
  }
  return it->second;
}

std::vector<std::string> EmbeddedSchemaNames() {
  std::vector<std::string> names;
  for (const auto& [name, text] : EmbeddedSchemas()) names.push_back(name);
  return names;
}

const JsonSchema& JsonSchema::Get(const std::string& file, const std::string& definition) {
  static std::mutex mutex;
  static std::map<std::string, std::unique_ptr<JsonSchema>> cache;
  std::lock_guard<std::mutex> lock(mutex);
  const std::string key = file + "#" + definition;
  auto& slot = cache[key];
  if (!slot) {
    nlohmann::json document = nlohmann::json::parse(EmbeddedSchemaText(file));
    if (!definition.empty()) {
      if (!document["definitions"].contains(definition)) {
        throw Error("schema " + file + " has no definition '" + definition + "'");
      }
      // The definition as the root, with all definitions beside it so that its
      // $refs resolve.
      document = nlohmann::json{{"$schema", document["$schema"]},
                                {"definitions", document["definitions"]},
                                {"$ref", "#/definitions/" + definition}};
    }
    slot.reset(new JsonSchema(document));
  }
  return *slot;
}

namespace {

std::string EscapePointerToken(const std::string& token) {
  std::string out;
  for (char c : token) {
    if (c == '~') {
      out += "~0";
    } else if (c == '/') {
      out += "~1";
    } else {
      out += c;
    }
  }
  return out;
}

// valijson's context is {"<root>", "[frames]", "[3]", ...}.
std::string PointerFromContext(const std::vector<std::string>& context) {
  std::string pointer;
  for (const std::string& part : context) {
    if (part.size() >= 2 && part.front() == '[' && part.back() == ']') {
      pointer += "/" + EscapePointerToken(part.substr(1, part.size() - 2));
    }
  }
  return pointer;
}

bool IsPrefix(const std::string& prefix, const std::string& pointer) {
  return pointer.size() > prefix.size() && pointer.compare(0, prefix.size(), prefix) == 0 &&
         pointer[prefix.size()] == '/';
}

}  // namespace

std::vector<SchemaIssue> JsonSchema::Validate(const nlohmann::json& document,
                                              const std::string& pointer_prefix) const {
  // valijson's Validator keeps only its compiled `pattern` regexes between calls. One per thread
  // keeps them: a fresh one compiled the frame schema's file-name patterns again for every frame
  // (about 7 % of `lsds info` on small frames).
  thread_local valijson::Validator validator;
  valijson::ValidationResults results;
  valijson::adapters::NlohmannJsonAdapter adapter(document);
  if (validator.validate(impl_->schema, adapter, &results)) return {};
  std::vector<SchemaIssue> all;
  valijson::ValidationResults::Error error;
  while (results.popError(error)) {
    std::string pointer = PointerFromContext(error.context);
    // Point at an unknown key itself rather than at the object holding it.
    static const std::string kUnknown =
        "could not be validated using 'properties' or 'additionalProperties'";
    if (error.description.find(kUnknown) != std::string::npos) {
      const size_t open = error.description.rfind(": '");
      if (open != std::string::npos && error.description.size() > open + 4) {
        const std::string key =
            error.description.substr(open + 3, error.description.size() - open - 5);
        pointer += "/" + EscapePointerToken(key);
        error.description = "unknown key '" + key + "'";
      }
    }
    all.push_back({pointer, error.description});
  }
  // Keep the most specific issues: drop any whose pointer contains another
  // issue's pointer.
  std::vector<SchemaIssue> specific;
  for (const SchemaIssue& issue : all) {
    bool has_deeper = false;
    for (const SchemaIssue& other : all) {
      if (IsPrefix(issue.pointer, other.pointer)) has_deeper = true;
    }
    bool duplicate = false;
    for (const SchemaIssue& kept : specific) {
      if (kept.pointer == pointer_prefix + issue.pointer && kept.message == issue.message)
        duplicate = true;
    }
    if (!has_deeper && !duplicate)
      specific.push_back({pointer_prefix + issue.pointer, issue.message});
  }
  return specific;
}

void JsonSchema::ValidateOrThrow(const nlohmann::json& document,
                                 const std::string& file_for_messages,
                                 const std::string& pointer_prefix) const {
  const std::vector<SchemaIssue> issues = Validate(document, pointer_prefix);
  if (issues.empty()) return;
  Location where;
  where.file = file_for_messages;
  where.json_pointer = issues.front().pointer.empty() ? "/" : issues.front().pointer;
  std::string message = "does not match its schema: " + issues.front().message;
  if (issues.size() > 1) message += " (and " + std::to_string(issues.size() - 1) + " more issues)";
  throw Error(message, where);
}

}  // namespace lsds

#include "libs/collection/json_stream.h"

#include <fstream>

#include "libs/util/atomic_file.h"
#include "libs/util/error.h"
#include "libs/util/json_errors.h"

namespace lsds {

namespace {

// "... parse error at line 3, column 5: syntax error ..." -> line/column into
// the Location.
Error SyntaxError(const std::filesystem::path& path,
                  const nlohmann::json::parse_error& e) {
  Location where{path.string()};
  std::string message = e.what();
  const size_t at_line = message.find("at line ");
  if (at_line != std::string::npos) {
    std::sscanf(message.c_str() + at_line,
                "at line %d, column %d",
                &where.line,
                &where.column);
  }
  const size_t colon =
      message.find(": ", at_line == std::string::npos ? 0 : at_line);
  if (colon != std::string::npos) message = message.substr(colon + 2);
  return Error("invalid JSON: " + message, where);
}

}  // namespace

size_t StreamJsonArrayMember(
    const std::filesystem::path& path,
    const std::string& array_key,
    nlohmann::json* header,
    const std::function<void(nlohmann::json&&, size_t)>& on_element) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot open for reading", Location(path.string()));
  std::string top_key;  // the member of the root object being parsed
  size_t count = 0;
  using Event = nlohmann::json::parse_event_t;
  auto callback = [&](int depth, Event event, nlohmann::json& parsed) -> bool {
    if (event == Event::key && depth == 1) {
      top_key = parsed.get<std::string>();
      return true;
    }
    if (depth == 2 && top_key == array_key &&
        (event == Event::object_end || event == Event::array_end ||
         event == Event::value)) {
      if (on_element) on_element(std::move(parsed), count);
      ++count;
      return false;  // discard: the element is not kept in the parent array
    }
    return true;
  };
  nlohmann::json root;
  try {
    root = nlohmann::json::parse(in, callback);
  } catch (const nlohmann::json::parse_error& e) {
    throw SyntaxError(path, e);
  } catch (const nlohmann::json::out_of_range& e) {
    // A number beyond double (1e999): nlohmann gives no position; the error
    // path reads the file again to find it.
    throw JsonParseError(ReadFile(path), path.string(), e);
  }
  if (!root.is_object())
    throw Error("top level must be a JSON object",
                Location(path.string(), "/"));
  if (header != nullptr) {
    if (root.contains(array_key) && root[array_key].is_array())
      root[array_key] = nlohmann::json::array();
    *header = std::move(root);
  }
  return count;
}

struct JsonArrayWriter::Impl {
  AtomicFile file;
  explicit Impl(const std::filesystem::path& path) : file(path) {}
};

JsonArrayWriter::JsonArrayWriter(const std::filesystem::path& path,
                                 const nlohmann::json& header,
                                 const std::string& array_key)
    : impl_(std::make_unique<Impl>(path)) {
  nlohmann::json members = header;
  members.erase(array_key);
  std::string text = members.dump(2);  // "{\n  ...\n}"
  text.erase(text.find_last_of('}'));
  while (!text.empty() && (text.back() == '\n' || text.back() == ' '))
    text.pop_back();
  auto& out = impl_->file.stream();
  out << text << (members.empty() ? "\n" : ",\n") << "  "
      << nlohmann::json(array_key).dump() << ": [";
}

JsonArrayWriter::~JsonArrayWriter() = default;

void JsonArrayWriter::Append(const nlohmann::json& element) {
  impl_->file.stream() << (count_ == 0 ? "\n    " : ",\n    ")
                       << element.dump();
  ++count_;
}

void JsonArrayWriter::Commit() {
  impl_->file.stream() << (count_ == 0 ? "]\n}\n" : "\n  ]\n}\n");
  impl_->file.Commit();
}

}  // namespace lsds

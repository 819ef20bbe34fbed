#include "libs/collection/json_stream.h"

#include <algorithm>
#include <fstream>

#include "libs/util/atomic_file.h"
#include "libs/util/error.h"
#include "libs/util/input_file.h"
#include "libs/util/limits.h"

namespace lsds {

namespace {

// "[json.exception.out_of_range.406] number overflow ..." -> "number
// overflow ...".
std::string WithoutLibraryPrefix(std::string message) {
  if (!message.empty() && message[0] == '[') {
    const size_t end = message.find("] ");
    if (end != std::string::npos) message = message.substr(end + 2);
  }
  return message;
}

// "... parse error at line 3, column 5: syntax error ..." -> line/column into
// the Location.
Error SyntaxError(const std::filesystem::path& path,
                  const nlohmann::json::exception& e,
                  std::streamoff byte) {
  Location where{path.string()};
  if (dynamic_cast<const nlohmann::json::parse_error*>(&e) == nullptr) {
    // Not a syntax error (a number out of range): no line from the parser.
    return Error("invalid JSON: " + WithoutLibraryPrefix(e.what()) +
                     " (near byte " + std::to_string(byte) + ")",
                 where);
  }
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

Error JsonTextError(const nlohmann::json::exception& e,
                    std::string_view text,
                    const std::string& file) {
  Location where(file);
  size_t offset = std::string_view::npos;
  if (const auto* parse = dynamic_cast<const nlohmann::json::parse_error*>(&e)) {
    offset = parse->byte > 0 ? parse->byte - 1 : 0;
  } else {
    // "number overflow parsing '1e999'": find the literal.
    const std::string message = e.what();
    const size_t open = message.find('\'');
    const size_t close = open == std::string::npos
                             ? std::string::npos
                             : message.find('\'', open + 1);
    if (close != std::string::npos)
      offset = text.find(message.substr(open + 1, close - open - 1));
  }
  if (offset != std::string_view::npos) {
    LineColumnFromOffset(std::string(text), std::min(offset, text.size()),
                         &where.line, &where.column);
  }
  std::string message = WithoutLibraryPrefix(e.what());
  const size_t colon = message.find(": ");
  if (message.rfind("parse error", 0) == 0 && colon != std::string::npos)
    message = message.substr(colon + 2);
  return Error("invalid JSON: " + message, where);
}

size_t StreamJsonArrayMember(
    const std::filesystem::path& path,
    const std::string& array_key,
    nlohmann::json* header,
    const std::function<void(nlohmann::json&&, size_t)>& on_element) {
  RequireRegularFile(path, "JSON file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot open for reading", Location(path.string()));
  std::string top_key;  // the member of the root object being parsed
  size_t count = 0;
  using Event = nlohmann::json::parse_event_t;
  auto callback = [&](int depth, Event event, nlohmann::json& parsed) -> bool {
    // The parser itself does not recurse, but schema checks and printing do:
    // refuse documents nested deeper than any lsds file before they are built.
    if ((event == Event::object_start || event == Event::array_start) &&
        depth >= kMaxNestingDepth) {
      const std::string pointer = top_key == array_key && depth >= 2
                                      ? "/" + array_key + "/" +
                                            std::to_string(count)
                                      : "";
      throw Error("nesting deeper than " + std::to_string(kMaxNestingDepth) +
                      " levels (objects and arrays) near byte " +
                      std::to_string(static_cast<long long>(in.tellg())) +
                      "; lsds refuses such documents",
                  Location(path.string(), pointer));
    }
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
  } catch (const nlohmann::json::exception& e) {
    throw SyntaxError(path, e, static_cast<std::streamoff>(in.tellg()));
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
    : impl_(new Impl(path)) {
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

JsonArrayWriter::~JsonArrayWriter() { delete impl_; }

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

#include "libs/collection/json_stream.h"

#include <algorithm>
#include <cstring>
#include <fstream>
#include <streambuf>
#include <vector>

#include "libs/util/atomic_file.h"
#include "libs/util/error.h"
#include "libs/util/input_file.h"
#include "libs/util/json_errors.h"
#include "libs/util/limits.h"
#include "libs/util/text_check.h"

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
    return Error("invalid JSON: " + WithoutLibraryPrefix(e.what()) + " (near byte " +
                     std::to_string(byte) + ")",
                 where);
  }
  std::string message = e.what();
  const size_t at_line = message.find("at line ");
  if (at_line != std::string::npos) {
    std::sscanf(message.c_str() + at_line, "at line %d, column %d", &where.line, &where.column);
  }
  const size_t colon = message.find(": ", at_line == std::string::npos ? 0 : at_line);
  if (colon != std::string::npos) message = message.substr(colon + 2);
  return Error("invalid JSON: " + message, where);
}

// The file as the parser reads it, cut at its first NUL byte. nlohmann takes a
// NUL outside a string for the end of the input, so a document followed by a
// NUL and anything at all would parse as if the rest were not there; cut here,
// the parse stops at the NUL and the reader reports it at its line and column,
// whether the text before it parsed or not.
class NulStopBuf : public std::streambuf {
 public:
  explicit NulStopBuf(std::filebuf* file) : file_(file), buffer_(size_t{1} << 16) {}
  bool stopped() const { return stopped_; }
  // The offset of the NUL in the file, once stopped().
  uint64_t nul_offset() const { return start_ + static_cast<uint64_t>(egptr() - eback()); }

 protected:
  int_type underflow() override {
    if (gptr() < egptr()) return traits_type::to_int_type(*gptr());
    if (stopped_) return traits_type::eof();
    start_ += static_cast<uint64_t>(egptr() - eback());
    const std::streamsize got =
        file_->sgetn(buffer_.data(), static_cast<std::streamsize>(buffer_.size()));
    size_t n = got > 0 ? static_cast<size_t>(got) : 0;
    if (const void* nul = std::memchr(buffer_.data(), '\0', n)) {
      n = static_cast<size_t>(static_cast<const char*>(nul) - buffer_.data());
      stopped_ = true;
    }
    setg(buffer_.data(), buffer_.data(), buffer_.data() + n);
    return n == 0 ? traits_type::eof() : traits_type::to_int_type(*gptr());
  }
  // Only where the reader is (tellg), for messages.
  pos_type seekoff(off_type off, std::ios_base::seekdir dir, std::ios_base::openmode) override {
    if (off != 0 || dir != std::ios_base::cur) return pos_type(off_type(-1));
    return pos_type(static_cast<off_type>(start_ + static_cast<uint64_t>(gptr() - eback())));
  }

 private:
  std::filebuf* file_;
  std::vector<char> buffer_;
  uint64_t start_ = 0;  // the file offset of buffer_'s first byte
  bool stopped_ = false;
};

// Builds the document like nlohmann's DOM parser, except that the elements of
// the root's arrays named in `array_keys` (or of the root itself when it is an
// array and `array_keys` is empty) are handed out one at a time and not kept.
// (nlohmann's callback parser scans the parent container at every
// object_end, which is quadratic in the objects of one frame: 10^6 objects
// did not load in 15 minutes.)
class ArrayMemberSax : public nlohmann::json_sax<nlohmann::json> {
 public:
  using Json = nlohmann::json;
  ArrayMemberSax(const std::vector<std::string>& array_keys,
                 const JsonElementHandler& on_element,
                 const std::filesystem::path& path,
                 std::istream& in)
      : array_keys_(array_keys), on_element_(on_element), path_(path), in_(in) {}

  Json root;
  size_t count = 0;

  bool null() override { return Add(nullptr); }
  bool boolean(bool value) override { return Add(value); }
  bool number_integer(number_integer_t value) override { return Add(value); }
  bool number_unsigned(number_unsigned_t value) override { return Add(value); }
  bool number_float(number_float_t value, const string_t&) override { return Add(value); }
  bool string(string_t& value) override { return Add(std::move(value)); }
  bool binary(binary_t& value) override { return Add(Json::binary(std::move(value))); }
  bool start_object(std::size_t) override {
    CheckDepth();
    stack_.push_back(Place(Json::object()));
    return true;
  }
  bool key(string_t& value) override {
    key_ = std::move(value);
    return true;
  }
  bool end_object() override { return End(); }
  bool start_array(std::size_t) override {
    CheckDepth();
    Json* array = Place(Json::array());
    const bool streamed_root = stack_.empty() && array_keys_.empty();
    const bool streamed_member =
        stack_.size() == 1 && stack_[0]->is_object() &&
        std::find(array_keys_.begin(), array_keys_.end(), key_) != array_keys_.end();
    if (streamed_root || streamed_member) {
      target_ = array;
      target_key_ = streamed_root ? "" : key_;
      count = 0;
    }
    stack_.push_back(array);
    return true;
  }
  bool end_array() override { return End(); }
  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception& e) override {
    // Rethrown with its own type (the base class would slice it).
    if (const auto* syntax = dynamic_cast<const Json::parse_error*>(&e)) throw *syntax;
    if (const auto* range = dynamic_cast<const Json::out_of_range*>(&e)) throw *range;
    throw Error(e.what());
  }

 private:
  // The parser itself does not recurse, but schema checks and printing do:
  // refuse documents nested deeper than any lsds file before they are built.
  void CheckDepth() const {
    if (stack_.size() < static_cast<size_t>(kMaxNestingDepth)) return;
    const bool in_element =
        target_ != nullptr && stack_.size() >= 2 && (stack_[1] == target_ || stack_[0] == target_);
    const std::string pointer =
        in_element ? (target_key_.empty() ? "" : "/" + target_key_) + "/" + std::to_string(count)
                   : "";
    throw Error("nesting deeper than " + std::to_string(kMaxNestingDepth) +
                    " levels (objects and arrays) near byte " +
                    std::to_string(static_cast<long long>(in_.tellg())) +
                    "; lsds refuses such documents",
                Location(path_.string(), pointer));
  }
  // Puts `value` where the parser is; returns where it went.
  Json* Place(Json value) {
    if (stack_.empty()) {
      root = std::move(value);
      return &root;
    }
    Json* parent = stack_.back();
    if (parent == target_) {  // an element: built on its own
      element_ = std::move(value);
      return &element_;
    }
    if (parent->is_array()) {
      parent->push_back(std::move(value));
      return &parent->back();
    }
    Json& slot = (*parent)[key_];
    slot = std::move(value);
    return &slot;
  }
  bool Add(Json value) {
    Json* placed = Place(std::move(value));
    if (placed == &element_ && stack_.back() == target_) HandOut();
    return true;
  }
  bool End() {
    Json* done = stack_.back();
    stack_.pop_back();
    if (done == &element_ && !stack_.empty() && stack_.back() == target_) HandOut();
    return true;
  }
  void HandOut() {
    if (on_element_) on_element_(target_key_, std::move(element_), count);
    element_ = Json();
    ++count;
  }

  const std::vector<std::string>& array_keys_;
  const JsonElementHandler& on_element_;
  const std::filesystem::path& path_;
  std::istream& in_;
  std::vector<Json*> stack_;
  std::string key_;
  Json* target_ = nullptr;  // the array being streamed
  std::string target_key_;  // its member name ("" for the root)
  Json element_;            // the element of that array being built
};

}  // namespace

size_t StreamJsonArrays(const std::filesystem::path& path,
                        const std::vector<std::string>& array_keys,
                        nlohmann::json* header,
                        const JsonElementHandler& on_element) {
  RequireRegularFile(path, "JSON file");
  std::filebuf file;
  if (file.open(path, std::ios::in | std::ios::binary) == nullptr)
    throw Error("cannot open for reading", Location(path.string()));
  NulStopBuf cut(&file);
  std::istream in(&cut);
  size_t count = 0;
  const JsonElementHandler counted =
      [&](const std::string& key, nlohmann::json&& element, size_t index) {
        ++count;
        if (on_element) on_element(key, std::move(element), index);
      };
  ArrayMemberSax sax(array_keys, counted, path, in);
  const auto nul_error = [&] {
    return Error(NulByteMessage(cut.nul_offset()), TextLocationInFile(path, cut.nul_offset()));
  };
  try {
    nlohmann::json::sax_parse(in, &sax);
  } catch (const nlohmann::json::parse_error& e) {
    if (cut.stopped()) throw nul_error();
    throw SyntaxError(path, e, static_cast<std::streamoff>(in.tellg()));
  } catch (const nlohmann::json::out_of_range& e) {
    // A number beyond double (1e999): nlohmann gives no position; the error
    // path reads the file again to find it.
    throw JsonParseError(ReadFile(path), path.string(), e);
  }
  if (cut.stopped()) throw nul_error();
  nlohmann::json& root = sax.root;
  if (array_keys.empty()) {
    if (!root.is_array())
      throw Error("top level must be a JSON list", Location(path.string(), "/"));
    return count;
  }
  if (!root.is_object())
    throw Error("top level must be a JSON object", Location(path.string(), "/"));
  if (header != nullptr) {
    for (const std::string& key : array_keys)
      if (root.contains(key) && root[key].is_array()) root[key] = nlohmann::json::array();
    *header = std::move(root);
  }
  return count;
}

size_t StreamJsonArrayMember(const std::filesystem::path& path,
                             const std::string& array_key,
                             nlohmann::json* header,
                             const std::function<void(nlohmann::json&&, size_t)>& on_element) {
  return StreamJsonArrays(
      path, {array_key}, header, [&](const std::string&, nlohmann::json&& element, size_t index) {
        if (on_element) on_element(std::move(element), index);
      });
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
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
  auto& out = impl_->file.stream();
  out << text << (members.empty() ? "\n" : ",\n") << "  " << nlohmann::json(array_key).dump()
      << ": [";
}

JsonArrayWriter::~JsonArrayWriter() = default;

void JsonArrayWriter::Append(const nlohmann::json& element) {
  impl_->file.stream() << (count_ == 0 ? "\n    " : ",\n    ") << element.dump();
  ++count_;
}

void JsonArrayWriter::Commit() {
  impl_->file.stream() << (count_ == 0 ? "]\n}\n" : "\n  ]\n}\n");
  impl_->file.Commit();
}

}  // namespace lsds

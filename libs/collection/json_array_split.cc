#include "libs/collection/json_array_split.h"

#include <array>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <memory>
#include <vector>

#include "libs/util/limits.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace lsds {

namespace {

constexpr size_t kBlockBytes = size_t{1} << 22;  // read 4 MiB at a time

// Inside an element only brackets and strings move the split; every other
// byte is skipped by one table look-up (the element's own parser checks it).
constexpr std::array<bool, 256> ElementStops() {
  std::array<bool, 256> stops{};
  for (const char c : {'"', '{', '}', '[', ']'}) stops[static_cast<uint8_t>(c)] = true;
  return stops;
}
constexpr std::array<bool, 256> kElementStops = ElementStops();

// The first byte from `i` on (or `end`) that is a quote or a bracket: inside
// an element nothing else moves the split. 16 bytes at a time where SSE2 is
// there (every x86-64).
size_t NextElementStop(const char* text, size_t i, size_t end) {
#if defined(__SSE2__)
  const __m128i quote = _mm_set1_epi8('"');
  const __m128i open_brace = _mm_set1_epi8('{');
  const __m128i close_brace = _mm_set1_epi8('}');
  const __m128i open_bracket = _mm_set1_epi8('[');
  const __m128i close_bracket = _mm_set1_epi8(']');
  for (; i + 16 <= end; i += 16) {
    const __m128i bytes = _mm_loadu_si128(reinterpret_cast<const __m128i*>(text + i));
    const __m128i stops = _mm_or_si128(
        _mm_or_si128(_mm_cmpeq_epi8(bytes, quote), _mm_cmpeq_epi8(bytes, open_brace)),
        _mm_or_si128(
            _mm_or_si128(_mm_cmpeq_epi8(bytes, close_brace), _mm_cmpeq_epi8(bytes, open_bracket)),
            _mm_cmpeq_epi8(bytes, close_bracket)));
    const int mask = _mm_movemask_epi8(stops);
    if (mask != 0) return i + static_cast<size_t>(__builtin_ctz(static_cast<unsigned>(mask)));
  }
#endif
  while (i < end && !kElementStops[static_cast<uint8_t>(text[i])]) ++i;
  return i;
}

// The first byte from `i` on (or `end`) that ends a plain run of string
// bytes: a quote, a backslash or a control character.
size_t NextStringStop(const char* text, size_t i, size_t end) {
#if defined(__SSE2__)
  const __m128i quote = _mm_set1_epi8('"');
  const __m128i backslash = _mm_set1_epi8('\\');
  const __m128i last_control = _mm_set1_epi8(0x1f);
  for (; i + 16 <= end; i += 16) {
    const __m128i bytes = _mm_loadu_si128(reinterpret_cast<const __m128i*>(text + i));
    const __m128i control = _mm_cmpeq_epi8(_mm_max_epu8(bytes, last_control), last_control);
    const __m128i stops = _mm_or_si128(
        _mm_or_si128(_mm_cmpeq_epi8(bytes, quote), _mm_cmpeq_epi8(bytes, backslash)), control);
    const int mask = _mm_movemask_epi8(stops);
    if (mask != 0) return i + static_cast<size_t>(__builtin_ctz(static_cast<unsigned>(mask)));
  }
#endif
  while (i < end) {
    const auto c = static_cast<uint8_t>(text[i]);
    if (c == '"' || c == '\\' || c < 0x20) break;
    ++i;
  }
  return i;
}

// Nesting deeper than this is left to the DOM reader, which refuses documents
// nested deeper than kMaxNestingDepth with its own message.
constexpr size_t kMaxSplitDepth = kMaxNestingDepth / 2;

using OnElement = std::function<bool(std::string_view element, size_t index)>;

// One pass over the file: the state of the scan between bytes. Every method
// returning bool returns false for "not the fast path's layout".
class ArraySplitter {
 public:
  ArraySplitter(std::FILE* file,
                std::string_view array_key,
                std::string* header_text,
                const OnElement& on_element,
                size_t* elements_done,
                bool stop_at_array = false)
      : file_(file),
        stop_at_array_(stop_at_array),
        array_key_(array_key),
        header_text_(header_text),
        on_element_(on_element),
        elements_done_(elements_done),
        buffer_(kBlockBytes + kElementTextPadding) {}

  bool Run() {
    for (;;) {
      if (i_ == end_ && !Refill()) break;
      if (in_string_ && !escaped_ && !in_key_) {
        i_ = NextStringStop(buffer_.data(), i_, end_);
        if (i_ == end_) continue;
      } else if (in_element_ && !in_string_) {
        i_ = NextElementStop(buffer_.data(), i_, end_);
        if (i_ == end_) continue;
      }
      const auto c = static_cast<uint8_t>(buffer_[i_]);
      if (!(in_string_ ? StringByte(c) : Structural(c))) return false;
      ++i_;
      if (stop_at_array_ && in_array_) return true;
    }
    if (nul_ || !root_closed_ || !array_seen_) return false;
    AppendHeader(end_);
    return true;
  }

 private:
  // More bytes after end_, keeping the element being split; false at the end
  // of the file (or at a NUL byte, which the DOM reader reports).
  bool Refill() {
    if (at_eof_) return false;
    if (copying_header_) AppendHeader(end_);
    const size_t keep = in_element_ ? element_start_ : end_;
    const size_t kept = end_ - keep;
    std::memmove(buffer_.data(), buffer_.data() + keep, kept);
    element_start_ -= in_element_ ? keep : 0;
    header_from_ = 0;
    i_ -= keep;
    end_ = kept;
    if (buffer_.size() - kElementTextPadding - end_ < kBlockBytes / 2) {
      buffer_.resize(2 * buffer_.size());  // an element larger than a block
    }
    const size_t got =
        std::fread(buffer_.data() + end_, 1, buffer_.size() - kElementTextPadding - end_, file_);
    if (got == 0 || std::memchr(buffer_.data() + end_, '\0', got) != nullptr) {
      nul_ = got != 0;
      at_eof_ = true;
      return false;
    }
    end_ += got;
    return true;
  }

  void AppendHeader(size_t to) {
    if (header_text_ != nullptr)
      header_text_->append(buffer_.data() + header_from_, to - header_from_);
    header_from_ = to;
  }

  bool AtArrayLevel() const { return in_array_ && stack_.size() == 2; }

  bool StringByte(uint8_t c) {
    if (c < 0x20) return false;  // a raw control character: the DOM reader reports it
    if (escaped_) {
      escaped_ = false;
    } else if (c == '\\') {
      escaped_ = true;
      key_has_escape_ = key_has_escape_ || in_key_;
    } else if (c == '"') {
      in_string_ = false;
      return !in_key_ || KeyEnd();
    } else if (in_key_) {
      key_.push_back(static_cast<char>(c));
    }
    return true;
  }

  bool KeyEnd() {
    in_key_ = false;
    if (key_has_escape_) return false;
    if (key_ != array_key_) return true;
    if (array_seen_) return false;
    array_seen_ = true;
    array_key_state_ = 1;
    return true;
  }

  bool Structural(uint8_t c) {
    switch (c) {
      case ' ':
      case '\t':
      case '\n':
      case '\r':
        return true;
      case '"':
        return Quote();
      case '{':
      case '[':
        return Open(c);
      case '}':
      case ']':
        return Close(c);
      case ',':
        return Comma();
      case ':':
        if (stack_.empty()) return false;
        if (stack_.size() == 1 && array_key_state_ == 1) array_key_state_ = 2;
        return true;
      default:  // a number or literal: never the array nor an element
        return !(stack_.empty() || AtArrayLevel() || array_key_state_ == 2);
    }
  }

  bool Quote() {
    if (stack_.empty() || AtArrayLevel() || array_key_state_ == 2) return false;
    in_string_ = true;
    if (stack_.size() == 1 && key_expected_) {
      in_key_ = true;
      key_.clear();
      key_has_escape_ = false;
      key_expected_ = false;
    }
    return true;
  }

  bool Open(uint8_t c) {
    if (root_closed_ || (stack_.empty() && c != '{')) return false;
    if (array_key_state_ == 2) {
      if (c != '[' || stack_.size() != 1) return false;
      array_key_state_ = 0;
      in_array_ = true;
      element_expected_ = true;
      AppendHeader(i_ + 1);
      copying_header_ = false;
    } else if (AtArrayLevel()) {
      if (c != '{' || !element_expected_) return false;
      element_expected_ = false;
      in_element_ = true;
      element_start_ = i_;
    }
    stack_.push_back(static_cast<char>(c));
    if (stack_.size() > kMaxSplitDepth) return false;
    if (c == '{' && stack_.size() == 1) key_expected_ = true;
    return true;
  }

  bool Close(uint8_t c) {
    if (stack_.empty() || stack_.back() != (c == '}' ? '{' : '[')) return false;
    if (AtArrayLevel()) {  // the array closes
      if (element_expected_ && done_ > 0) return false;
      in_array_ = false;
      copying_header_ = true;
      header_from_ = i_;
    }
    stack_.pop_back();
    if (in_element_ && stack_.size() == 2) {
      in_element_ = false;
      const std::string_view element(buffer_.data() + element_start_, i_ + 1 - element_start_);
      if (!on_element_(element, done_)) return false;
      ++done_;
      if (elements_done_ != nullptr) *elements_done_ = done_;
    }
    root_closed_ = stack_.empty();
    return true;
  }

  bool Comma() {
    if (stack_.empty()) return false;
    if (stack_.size() == 1) {
      key_expected_ = true;
    } else if (AtArrayLevel()) {
      if (element_expected_) return false;
      element_expected_ = true;
    }
    return true;
  }

  std::FILE* file_;
  bool stop_at_array_;  // done once the array opens (its header text ends with '[')
  std::string_view array_key_;
  std::string* header_text_;
  const OnElement& on_element_;
  size_t* elements_done_;
  std::vector<char> buffer_;
  size_t end_ = 0;  // bytes of the file in buffer_
  size_t i_ = 0;    // the byte being scanned
  bool at_eof_ = false;
  bool nul_ = false;
  bool copying_header_ = true;
  size_t header_from_ = 0;  // header bytes from here to i_ are not copied yet
  bool in_element_ = false;
  size_t element_start_ = 0;
  size_t done_ = 0;
  std::vector<char> stack_;  // '{' or '[' of every open container
  bool in_array_ = false;    // inside the root's array_key array
  bool array_seen_ = false;
  int array_key_state_ = 0;  // 1: its key was read, 2: its ':' too (the array comes next)
  bool element_expected_ = false;
  bool key_expected_ = false;  // the next string of the root object is a key
  bool in_string_ = false;
  bool escaped_ = false;
  bool in_key_ = false;
  bool key_has_escape_ = false;
  std::string key_;
  bool root_closed_ = false;
};

using File = std::unique_ptr<std::FILE, int (*)(std::FILE*)>;

// `path` opened for reading, or null when it is not a regular file (no FIFO:
// it could block) or cannot be opened.
File OpenRegularFile(const std::filesystem::path& path) {
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error)) return File(nullptr, &std::fclose);
  return File(std::fopen(path.c_str(), "rb"), &std::fclose);
}

}  // namespace

bool SplitJsonArrayMember(const std::filesystem::path& path,
                          std::string_view array_key,
                          std::string* header_text,
                          const OnElement& on_element,
                          size_t* elements_done) {
  if (elements_done != nullptr) *elements_done = 0;
  const File file = OpenRegularFile(path);
  if (file == nullptr) return false;
  ArraySplitter splitter(file.get(), array_key, header_text, on_element, elements_done);
  return splitter.Run();
}

bool ReadJsonTextBeforeArray(const std::filesystem::path& path,
                             std::string_view array_key,
                             std::string* text_before) {
  const File file = OpenRegularFile(path);
  if (file == nullptr) return false;
  const OnElement no_elements = [](std::string_view, size_t) { return false; };
  ArraySplitter splitter(
      file.get(), array_key, text_before, no_elements, nullptr, /*stop_at_array=*/true);
  return splitter.Run() && !text_before->empty() && text_before->back() == '[';
}

}  // namespace lsds

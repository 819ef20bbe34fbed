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

}  // namespace

bool SplitJsonArrayMember(
    const std::filesystem::path& path,
    std::string_view array_key,
    std::string* header_text,
    const std::function<bool(std::string_view element, size_t index)>& on_element,
    size_t* elements_done) {
  size_t done = 0;
  if (elements_done != nullptr) *elements_done = 0;
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error)) return false;  // no FIFO: it could block
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rb"),
                                                       &std::fclose);
  if (file == nullptr) return false;

  std::vector<char> buffer(kBlockBytes + kElementTextPadding);
  size_t end = 0;  // bytes of the file in buffer
  size_t i = 0;    // the byte being scanned
  bool copying_header = true;
  size_t header_from = 0;  // header bytes from here to i are not copied yet
  bool in_element = false;
  size_t element_start = 0;
  bool at_eof = false;
  bool nul = false;

  // More bytes after `end`, keeping the element being split; false at the end
  // of the file (or at a NUL byte, which the DOM reader reports).
  const auto refill = [&]() -> bool {
    if (at_eof) return false;
    if (copying_header && header_text != nullptr)
      header_text->append(buffer.data() + header_from, end - header_from);
    const size_t keep = in_element ? element_start : end;
    const size_t kept = end - keep;
    std::memmove(buffer.data(), buffer.data() + keep, kept);
    element_start -= in_element ? keep : 0;
    header_from = 0;
    i -= keep;
    end = kept;
    if (buffer.size() - kElementTextPadding - end < kBlockBytes / 2) {
      buffer.resize(2 * buffer.size());  // an element larger than a block
    }
    const size_t got =
        std::fread(buffer.data() + end, 1, buffer.size() - kElementTextPadding - end, file.get());
    if (got == 0) {
      at_eof = true;
      return false;
    }
    if (std::memchr(buffer.data() + end, '\0', got) != nullptr) {
      nul = true;
      at_eof = true;
      return false;
    }
    end += got;
    return true;
  };

  std::vector<char> stack;  // '{' or '[' of every open container
  bool in_array = false;    // inside the root's array_key array
  bool array_seen = false;
  int array_key_state = 0;  // 1: its key was read, 2: its ':' too (the array comes next)
  bool element_expected = false;
  bool key_expected = false;  // the next string of the root object is a key
  bool in_string = false;
  bool escaped = false;
  bool in_key = false;
  bool key_has_escape = false;
  std::string key;
  bool root_closed = false;
  const auto at_array_level = [&] { return in_array && stack.size() == 2; };

  for (;;) {
    if (i == end && !refill()) break;
    if (in_string && !escaped && !in_key) {
      i = NextStringStop(buffer.data(), i, end);
      if (i == end) continue;
    } else if (in_element && !in_string) {
      i = NextElementStop(buffer.data(), i, end);
      if (i == end) continue;
    }
    const auto c = static_cast<uint8_t>(buffer[i]);
    if (in_string) {
      if (c < 0x20) return false;  // a raw control character: the DOM reader reports it
      if (escaped) {
        escaped = false;
      } else if (c == '\\') {
        escaped = true;
        key_has_escape = key_has_escape || in_key;
      } else if (c == '"') {
        in_string = false;
        if (in_key) {
          in_key = false;
          if (key_has_escape) return false;
          if (key == array_key) {
            if (array_seen) return false;
            array_seen = true;
            array_key_state = 1;
          }
        }
      } else if (in_key) {
        key.push_back(static_cast<char>(c));
      }
      ++i;
      continue;
    }
    switch (c) {
      case ' ':
      case '\t':
      case '\n':
      case '\r':
        break;
      case '"':
        if (stack.empty() || at_array_level() || array_key_state == 2) return false;
        in_string = true;
        if (stack.size() == 1 && key_expected) {
          in_key = true;
          key.clear();
          key_has_escape = false;
          key_expected = false;
        }
        break;
      case '{':
      case '[':
        if (root_closed || (stack.empty() && c != '{')) return false;
        if (array_key_state == 2) {
          if (c != '[' || stack.size() != 1) return false;
          array_key_state = 0;
          in_array = true;
          element_expected = true;
          if (header_text != nullptr)
            header_text->append(buffer.data() + header_from, i + 1 - header_from);
          copying_header = false;
        } else if (at_array_level()) {
          if (c != '{' || !element_expected) return false;
          element_expected = false;
          in_element = true;
          element_start = i;
        }
        stack.push_back(static_cast<char>(c));
        if (stack.size() > kMaxSplitDepth) return false;
        if (c == '{' && stack.size() == 1) key_expected = true;
        break;
      case '}':
      case ']':
        if (stack.empty() || stack.back() != (c == '}' ? '{' : '[')) return false;
        if (at_array_level()) {  // the array closes
          if (element_expected && done > 0) return false;
          in_array = false;
          copying_header = true;
          header_from = i;
        }
        stack.pop_back();
        if (in_element && stack.size() == 2) {
          in_element = false;
          if (!on_element(std::string_view(buffer.data() + element_start, i + 1 - element_start),
                          done))
            return false;
          ++done;
          if (elements_done != nullptr) *elements_done = done;
        }
        root_closed = stack.empty();
        break;
      case ',':
        if (stack.empty()) return false;
        if (stack.size() == 1) {
          key_expected = true;
        } else if (at_array_level()) {
          if (element_expected) return false;
          element_expected = true;
        }
        break;
      case ':':
        if (stack.empty()) return false;
        if (stack.size() == 1 && array_key_state == 1) array_key_state = 2;
        break;
      default:  // a number or literal: never the array nor an element
        if (stack.empty() || at_array_level() || array_key_state == 2) return false;
        break;
    }
    ++i;
  }
  if (nul || !root_closed || !array_seen) return false;
  if (header_text != nullptr) header_text->append(buffer.data() + header_from, end - header_from);
  return true;
}

}  // namespace lsds

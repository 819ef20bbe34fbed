#include "libs/util/text_check.h"

#include <charconv>
#include <cmath>
#include <cstdio>

#include "libs/util/error.h"
#include "libs/util/strings.h"

namespace lsds {

namespace {

// Length of the well-formed UTF-8 sequence at `text[i]`, 0 if malformed
// (RFC 3629, table 3-7 of the Unicode standard).
size_t SequenceLength(std::string_view text, size_t i) {
  const auto byte = [&](size_t k) { return static_cast<unsigned char>(text[k]); };
  const unsigned char b0 = byte(i);
  if (b0 < 0x80) return 1;
  size_t n = 0;
  unsigned char lo = 0x80, hi = 0xBF;
  if (b0 >= 0xC2 && b0 <= 0xDF) {
    n = 2;
  } else if (b0 >= 0xE0 && b0 <= 0xEF) {
    n = 3;
    if (b0 == 0xE0) lo = 0xA0;
    if (b0 == 0xED) hi = 0x9F;
  } else if (b0 >= 0xF0 && b0 <= 0xF4) {
    n = 4;
    if (b0 == 0xF0) lo = 0x90;
    if (b0 == 0xF4) hi = 0x8F;
  } else {
    return 0;
  }
  if (i + n > text.size()) return 0;
  if (byte(i + 1) < lo || byte(i + 1) > hi) return 0;
  for (size_t k = 2; k < n; ++k)
    if (byte(i + k) < 0x80 || byte(i + k) > 0xBF) return 0;
  return n;
}

std::string Hex(unsigned char c) {
  char buffer[8];
  std::snprintf(buffer, sizeof(buffer), "\\x%02X", c);
  return buffer;
}

}  // namespace

std::optional<size_t> FindInvalidUtf8(std::string_view text) {
  for (size_t i = 0; i < text.size();) {
    const size_t n = SequenceLength(text, i);
    if (n == 0) return i;
    i += n;
  }
  return std::nullopt;
}

void CheckUtf8(std::string_view text, const std::string& file) {
  const std::optional<size_t> bad = FindInvalidUtf8(text);
  if (!bad) return;
  int line = 0, column = 0;
  LineColumnFromOffset(std::string(text.substr(0, *bad)), *bad, &line, &column);
  throw Error("not valid UTF-8 (byte 0x" + Hex(static_cast<unsigned char>(text[*bad])).substr(2) +
                  " at byte offset " + std::to_string(*bad) + "); save the file as UTF-8",
              Location::Text(file, line, column));
}

std::string NulByteMessage(uint64_t offset) {
  return "a NUL byte (0x00) at byte offset " + std::to_string(offset) +
         "; a text input holds none (a binary or damaged file?)";
}

void CheckNoNulBytes(std::string_view text, const std::string& file) {
  const size_t nul = text.find('\0');
  if (nul == std::string_view::npos) return;
  int line = 0, column = 0;
  LineColumnFromOffset(std::string(text.substr(0, nul)), nul, &line, &column);
  throw Error(NulByteMessage(nul), Location::Text(file, line, column));
}

std::string Utf8Escaped(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (size_t i = 0; i < text.size();) {
    const size_t n = SequenceLength(text, i);
    if (n == 0) {
      out += Hex(static_cast<unsigned char>(text[i]));
      ++i;
    } else {
      out.append(text.data() + i, n);
      i += n;
    }
  }
  return out;
}

std::string Excerpt(std::string_view text, size_t max_bytes, bool keep_lines) {
  std::string out;
  size_t i = 0;
  while (i < text.size() && out.size() < max_bytes) {
    const size_t n = SequenceLength(text, i);
    const unsigned char c = static_cast<unsigned char>(text[i]);
    const bool line = c == '\n' || c == '\t' || c == '\r';
    if (n == 0 || (n == 1 && c < 0x20 && !(keep_lines && line))) {
      out += c == '\n' ? std::string("\\n") : Hex(c);
      ++i;
    } else {
      out.append(text.data() + i, n);
      i += n;
    }
  }
  if (i < text.size()) out += "... (" + std::to_string(text.size() - i) + " more bytes)";
  return out;
}

double CheckFinite(double value, const std::string& what) {
  if (!std::isfinite(value))
    throw Error(what + ": expected a finite number, got " + FormatNumber(value));
  return value;
}

int64_t CheckNonNegative(int64_t value, const std::string& what) {
  if (value < 0) throw Error(what + ": expected a number >= 0, got " + std::to_string(value));
  return value;
}

std::optional<int64_t> ParseInteger(std::string_view text, int64_t lo, int64_t hi) {
  int64_t value = 0;
  const char* end = text.data() + text.size();
  // from_chars takes no '+', no spaces and no "0x"; a lone '-' fails.
  const auto [ptr, ec] = std::from_chars(text.data(), end, value);
  if (text.empty() || ec != std::errc() || ptr != end || value < lo || value > hi)
    return std::nullopt;
  return value;
}

}  // namespace lsds

// Checks on text that comes from users: valid UTF-8, readable excerpts for
// messages, and numbers in range.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace lsds {

// Offset of the first byte of `text` that does not belong to well-formed UTF-8
// (overlong forms, surrogates and code points past U+10FFFF count as
// malformed); nullopt when all of `text` is valid.
std::optional<size_t> FindInvalidUtf8(std::string_view text);

// Throws lsds::Error "not valid UTF-8 (byte 0xE9 at byte offset N)" at
// `file:line:column` when `text` is not valid UTF-8.
void CheckUtf8(std::string_view text, const std::string& file);

// A NUL byte is never part of a text input (JSON escapes it as \u0000), and
// nlohmann's parser takes one outside a string for the end of the input: a
// document followed by a NUL and anything at all would parse as if the rest
// were not there. Throws lsds::Error at `file:line:column` of the first NUL of
// `text`.
void CheckNoNulBytes(std::string_view text, const std::string& file);
// The message of that error, for readers that find the NUL themselves.
std::string NulByteMessage(uint64_t offset);

// `text` fit for a message: invalid UTF-8 bytes and control characters shown
// as \xNN (line breaks kept with `keep_lines`), and cut to about `max_bytes`
// with a note of how much was left out.
std::string Excerpt(std::string_view text, size_t max_bytes = 200, bool keep_lines = false);

// `text` with invalid UTF-8 bytes replaced by \xNN, so that it can go into a
// JSON string (used for file paths, which need not be UTF-8).
std::string Utf8Escaped(std::string_view text);

// Range checks shared by the CLI and the readers: finite, >= 0, within int.
// `what` names the value (a flag such as "--voxel" or a JSON pointer); throw
// lsds::Error saying what is wrong.
double CheckFinite(double value, const std::string& what);
int64_t CheckNonNegative(int64_t value, const std::string& what);

// The decimal integer `text` (ASCII digits with an optional leading '-',
// nothing else) when it lies in [lo, hi], else nullopt: no wrap, no exception,
// no locale. The one parser of integers written as text in inputs (file names,
// JSON keys, CSV cells); the caller reports a nullopt with its location.
std::optional<int64_t> ParseInteger(std::string_view text, int64_t lo, int64_t hi);

}  // namespace lsds

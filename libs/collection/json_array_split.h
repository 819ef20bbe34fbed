// Splitting a JSON file whose top level is an object holding one large array
// (collection.json's "frames") into the text of each element and the text of
// everything else, read in blocks: memory is bounded by the largest element,
// not by the file. The split checks only structure (brackets, strings, the
// place of the array); each element's text is parsed by the caller.
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>

namespace lsds {

// Readable bytes that follow every element text handed out (simdjson reads
// up to this far past the end of a document).
inline constexpr size_t kElementTextPadding = 64;

// Reads `path` and hands each element of the root's `array_key` array to
// `on_element` with its index, as text followed by kElementTextPadding
// readable bytes. `header_text` (when not null) receives the rest of the
// document with the array left empty ("frames": []). Returns true when the
// whole file was split; false as soon as anything is not the plain layout
// this fast path takes (the root is not an object, `array_key` is missing,
// repeated, spelled with escapes or not an array, an element is not an
// object, a NUL byte, a raw control character in a string, deep nesting,
// unbalanced brackets, text after the root) or `on_element` returns false.
// `*elements_done` is then the number of elements `on_element` accepted: a
// caller falls back to the DOM reader (json_stream.h) from there, which
// reports what is wrong at its line and column.
bool SplitJsonArrayMember(
    const std::filesystem::path& path,
    std::string_view array_key,
    std::string* header_text,
    const std::function<bool(std::string_view element, size_t index)>& on_element,
    size_t* elements_done);

// The text of `path` up to and including the '[' that opens the root's
// `array_key` array, read as SplitJsonArrayMember reads it (nothing after the
// '[' is read): the members before the array, for a reader that takes the
// array as the root's last member. False where SplitJsonArrayMember would
// refuse the file before the array, or the file has no such array.
bool ReadJsonTextBeforeArray(const std::filesystem::path& path,
                             std::string_view array_key,
                             std::string* text_before);

}  // namespace lsds

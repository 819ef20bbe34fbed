// Reading label files the way the Python consumers do: whitespace tokens,
// Python's float() and int(), universal newlines.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace lsds::check {

// Python's str.split(): runs of whitespace separate, none at the ends.
std::vector<std::string> SplitWhitespace(const std::string& text);
// Python's str.splitlines() after "\r\n" -> "\n" (what open() in text mode
// gives): the lines without their ends.
std::vector<std::string> SplitLines(const std::string& text);
// Python's str.strip().
std::string Strip(const std::string& text);
// float(token) in Python: decimal or exponent notation, "nan", "inf",
// surrounding whitespace; false when Python would raise ValueError.
bool ParsePythonFloat(const std::string& token, double* value);
// int(token) in Python: an optionally signed decimal integer (no "1.0").
bool ParsePythonInt(const std::string& token, long long* value);

// The files under `root` (recursive), sorted; none when `root` is not a folder.
std::vector<std::filesystem::path> ListFiles(const std::filesystem::path& root);
// The lowercase extension of `path` without its dot ("png").
std::string LowerExtension(const std::filesystem::path& path);
// Whether OpenCV decodes `path`; its size when it does.
bool DecodeImageSize(const std::filesystem::path& path, int* width, int* height);
// A whole file as bytes; false (nothing thrown) when it cannot be read.
bool ReadBytes(const std::filesystem::path& path, std::string* bytes);

}  // namespace lsds::check

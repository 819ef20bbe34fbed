// Small string helpers shared by the parsers and the CLI.
#pragma once

#include <string>
#include <vector>

namespace lsds {

// Levenshtein edit distance.
int EditDistance(const std::string& a, const std::string& b);

// The candidate closest to `word` if it is close enough to be a likely
// misspelling, else "".
std::string ClosestMatch(const std::string& word, const std::vector<std::string>& candidates);

// " (did you mean 'x'?)" or "" when nothing is close.
std::string DidYouMean(const std::string& word, const std::vector<std::string>& candidates);

std::vector<std::string> Split(const std::string& text, char separator);
std::string Join(const std::vector<std::string>& parts, const std::string& separator);

// Text escaped for XML attributes and content; control characters XML 1.0
// forbids become spaces.
std::string XmlEscape(const std::string& text);

// Zero-padded frame file stem: 7 -> "000007".
std::string FrameStem(int64_t index);
// A number for a message: `significant` digits, shortest form ("1.5", "1e+06").
// The one number formatter of the project: messages, reports and metadata
// text all go through these two.
std::string FormatNumber(double value, int significant = 6);
// A short number for an axis or a legend: FormatNumber's 6 digits in
// [1e-3, 1e5) and 0, else one significant digit in exponent form ("2e+05",
// "5e-04") so that tick labels stay narrow.
std::string FormatAxisNumber(double value);
// A byte count for people: "512 B", "1.5 KiB", "8.0 GiB" (powers of 1024).
std::string FormatBytes(double bytes);

}  // namespace lsds

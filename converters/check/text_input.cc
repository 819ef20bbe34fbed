#include "converters/check/text_input.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <system_error>

#include "libs/imaging/image_codecs.h"

namespace lsds::check {

namespace {

bool IsSpace(char c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
}

std::string Lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) {
    return static_cast<char>(std::tolower(c));
  });
  return text;
}

}  // namespace

std::vector<std::string> SplitWhitespace(const std::string& text) {
  std::vector<std::string> tokens;
  size_t i = 0;
  while (i < text.size()) {
    while (i < text.size() && IsSpace(text[i])) ++i;
    const size_t start = i;
    while (i < text.size() && !IsSpace(text[i])) ++i;
    if (i > start) tokens.push_back(text.substr(start, i - start));
  }
  return tokens;
}

std::vector<std::string> SplitLines(const std::string& text) {
  std::vector<std::string> lines;
  std::string line;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '\r' || c == '\n') {
      lines.push_back(line);
      line.clear();
      if (c == '\r' && i + 1 < text.size() && text[i + 1] == '\n') ++i;
    } else {
      line += c;
    }
  }
  if (!line.empty()) lines.push_back(line);
  return lines;
}

std::string Strip(const std::string& text) {
  size_t begin = 0, end = text.size();
  while (begin < end && IsSpace(text[begin])) ++begin;
  while (end > begin && IsSpace(text[end - 1])) --end;
  return text.substr(begin, end - begin);
}

bool ParsePythonFloat(const std::string& token, double* value) {
  const std::string text = Strip(token);
  if (text.empty()) return false;
  const std::string lower = Lower(text);
  const size_t sign = (lower[0] == '+' || lower[0] == '-') ? 1 : 0;
  const std::string word = lower.substr(sign);
  if (word == "nan" || word == "inf" || word == "infinity") {
    *value = std::strtod(lower.c_str(), nullptr);
    return true;
  }
  // strtod also takes hexadecimal and "infinite"-like prefixes that Python
  // refuses: only digits, one point and one exponent are Python's float().
  for (char c : word) {
    if (!(std::isdigit(static_cast<unsigned char>(c)) || c == '.' || c == 'e' || c == '+' ||
          c == '-' || c == '_'))
      return false;
  }
  std::string digits;
  for (char c : text) {
    if (c != '_') digits += c;
  }
  errno = 0;
  char* end = nullptr;
  *value = std::strtod(digits.c_str(), &end);
  return end == digits.c_str() + digits.size() && end != digits.c_str();
}

bool ParsePythonInt(const std::string& token, long long* value) {
  const std::string text = Strip(token);
  size_t i = (!text.empty() && (text[0] == '+' || text[0] == '-')) ? 1 : 0;
  if (i == text.size()) return false;
  for (size_t j = i; j < text.size(); ++j) {
    if (!std::isdigit(static_cast<unsigned char>(text[j]))) return false;
  }
  errno = 0;
  *value = std::strtoll(text.c_str(), nullptr, 10);
  return errno == 0;
}

std::vector<std::filesystem::path> ListFiles(const std::filesystem::path& root) {
  std::vector<std::filesystem::path> files;
  std::error_code error;
  if (!std::filesystem::is_directory(root, error)) return files;
  for (auto it = std::filesystem::recursive_directory_iterator(root, error);
       !error && it != std::filesystem::recursive_directory_iterator();
       it.increment(error)) {
    if (it->is_regular_file(error)) files.push_back(it->path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::string LowerExtension(const std::filesystem::path& path) {
  const std::string extension = path.extension().string();
  return Lower(extension.empty() ? extension : extension.substr(1));
}

bool DecodeImageSize(const std::filesystem::path& path, int* width, int* height) {
  // The header alone would not find a truncated file; the consumers decode
  // the whole image (PIL's verify, OpenCV's imread), so this does too.
  const cv::Mat image = imaging::ImRead(path.string(), cv::IMREAD_UNCHANGED);
  if (image.empty()) return false;
  *width = image.cols;
  *height = image.rows;
  return true;
}

bool ReadBytes(const std::filesystem::path& path, std::string* bytes) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::ostringstream buffer;
  buffer << in.rdbuf();
  *bytes = buffer.str();
  return !in.bad();
}

}  // namespace lsds::check

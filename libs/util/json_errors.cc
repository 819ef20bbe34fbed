#include "libs/util/json_errors.h"

#include <cctype>

#include "libs/util/input_file.h"
#include "libs/util/limits.h"
#include "libs/util/text_check.h"

namespace lsds {

namespace {

bool NumberChar(char c) {
  return std::isdigit(static_cast<unsigned char>(c)) || c == '-' || c == '+' || c == '.' ||
         c == 'e' || c == 'E';
}

// Where the number token `token` stands in `text` (outside strings); npos if
// not found.
size_t FindNumberToken(std::string_view text, std::string_view token) {
  bool in_string = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\')
        ++i;
      else if (c == '"')
        in_string = false;
      continue;
    }
    if (c == '"') {
      in_string = true;
      continue;
    }
    if ((i == 0 || !NumberChar(text[i - 1])) && text.substr(i, token.size()) == token &&
        (i + token.size() == text.size() || !NumberChar(text[i + token.size()]))) {
      return i;
    }
  }
  return std::string_view::npos;
}

// nlohmann's "[json.exception.parse_error.101] parse error at line 1, column
// 2: syntax error while parsing value - invalid literal; last read: 'x'" ->
// "syntax error while parsing value - invalid literal".
std::string Reason(const nlohmann::json::exception& e) {
  std::string message = e.what();
  const size_t bracket = message.find("] ");
  if (bracket != std::string::npos) message = message.substr(bracket + 2);
  const size_t at = message.find(" at line ");
  if (at != std::string::npos) {
    const size_t colon = message.find(": ", at);
    if (colon != std::string::npos) message = message.substr(colon + 2);
  }
  const size_t last_read = message.find("; last read: ");
  if (last_read != std::string::npos) message.erase(last_read);
  return message;
}

}  // namespace

Error JsonParseError(std::string_view text,
                     const std::string& file,
                     const nlohmann::json::exception& e,
                     int first_line) {
  size_t offset = std::string_view::npos;
  if (const auto* parse = dynamic_cast<const nlohmann::json::parse_error*>(&e)) {
    // `byte` counts from 1 and points at the character that failed.
    if (parse->byte > 0) offset = std::min(parse->byte - 1, text.size());
  } else if (e.id == 406) {
    const std::string message = e.what();
    const size_t open = message.find('\''), close = message.rfind('\'');
    if (open != std::string::npos && close > open) {
      offset = FindNumberToken(text, std::string_view(message).substr(open + 1, close - open - 1));
    }
  }
  std::string reason = Reason(e);
  if (e.id == 406) reason = "number out of range: " + reason;
  if (offset == std::string_view::npos) return Error("invalid JSON: " + reason, Location(file));
  int line = 0, column = 0;
  LineColumnFromOffset(std::string(text.substr(0, offset)), offset, &line, &column);
  // A short excerpt of the text where it failed, so that the message shows
  // the place even for a one-line file.
  const size_t from = offset > 20 ? offset - 20 : 0;
  const std::string near = Excerpt(text.substr(from, 40), 60);
  return Error("invalid JSON: " + reason + " (near '" + near + "')",
               Location::Text(file, line + first_line - 1, column));
}

nlohmann::json ParseJsonText(std::string_view text, const std::string& file) {
  CheckNoNulBytes(text, file);
  try {
    return nlohmann::json::parse(text.begin(), text.end());
  } catch (const nlohmann::json::parse_error& e) {
    throw JsonParseError(text, file, e);
  } catch (const nlohmann::json::out_of_range& e) {
    throw JsonParseError(text, file, e);
  }
}

nlohmann::json ReadJsonFile(const std::filesystem::path& path) {
  const std::string text = ReadTextFile(path);
  CheckJsonNesting(text, path.string());
  return ParseJsonText(text, path.string());
}

}  // namespace lsds

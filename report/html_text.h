// The page's markup, escaping by construction: every piece of the report page
// is appended to an `Html`, which takes string literals (markup written in
// lsds's own source) as they are and escapes everything else. Text read from
// any input (class, layer and object names, provenance, validation findings,
// error messages quoting paths) therefore reaches the page as text, never as
// markup or script (docs/report.md, "What the page trusts").
#pragma once

#include <cstddef>
#include <cstdio>
#include <string>
#include <string_view>
#include <type_traits>

namespace lsds::report {

// `text` for HTML content and quoted attribute values: & < > " ' become
// entities, control characters XML 1.0 forbids become spaces (XmlEscape).
std::string HtmlEscape(std::string_view text);

class Html {
 public:
  Html() = default;

  // Markup: only arrays of const char, i.e. string literals of the source.
  template <size_t N>
  static Html Markup(const char (&literal)[N]) {
    Html html;
    html << literal;
    return html;
  }
  // Text from anywhere else, escaped.
  static Html Text(std::string_view text) {
    Html html;
    html << text;
    return html;
  }

  template <size_t N>
  Html& operator<<(const char (&literal)[N]) {
    static_assert(N > 0);
    markup_.append(literal, N - 1);
    return *this;
  }
  // A char buffer filled at run time is not markup of the source: pass it as
  // std::string, which is escaped.
  template <size_t N>
  Html& operator<<(char (&buffer)[N]) = delete;
  // std::string, std::string_view and `const char*` (exception messages) are
  // text.
  Html& operator<<(std::string_view text) {
    markup_ += HtmlEscape(text);
    return *this;
  }
  Html& operator<<(const Html& html) {
    markup_ += html.markup_;
    return *this;
  }
  // Numbers as std::ostream writes them by default (%g with 6 digits for
  // floating point), so that SVG coordinates read as before.
  template <typename T, std::enable_if_t<std::is_arithmetic_v<T>, int> = 0>
  Html& operator<<(T number) {
    static_assert(!std::is_same_v<T, bool> && !std::is_same_v<T, char>,
                  "a bool or char is not a number of the page: write text");
    if constexpr (std::is_integral_v<T>) {
      markup_ += std::to_string(number);
    } else {
      char buffer[32];
      std::snprintf(buffer, sizeof(buffer), "%g", static_cast<double>(number));
      markup_ += static_cast<const char*>(buffer);
    }
    return *this;
  }

  const std::string& str() const { return markup_; }
  bool empty() const { return markup_.empty(); }
  size_t size() const { return markup_.size(); }

 private:
  std::string markup_;
};

}  // namespace lsds::report

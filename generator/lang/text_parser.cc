#include "generator/lang/text_parser.h"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <set>

#include "libs/util/limits.h"
#include "libs/util/strings.h"

namespace lsds {
namespace {

enum class Tok { kIdent, kNumber, kString, kPunct, kEnd };

struct Token {
  Tok kind = Tok::kEnd;
  std::string text;  // identifier, number text, string content, or the
                     // punctuation character
  size_t offset = 0;
};

std::string Describe(const Token& t) {
  switch (t.kind) {
    case Tok::kIdent:
      return "'" + t.text + "'";
    case Tok::kNumber:
      return "number " + t.text;
    case Tok::kString:
      return "string \"" + t.text + "\"";
    case Tok::kPunct:
      return "'" + t.text + "'";
    default:
      return "end of file";
  }
}

bool IsIdentStart(char c) { return std::isalpha(static_cast<unsigned char>(c)) || c == '_'; }
bool IsIdentChar(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.' || c == '/' ||
         c == '-';
}

class Parser {
 public:
  explicit Parser(SourceFile* source) : src_(source), text_(source->text) {}

  void Run() {
    Lex();
    OJson doc = OJson::object();
    while (Peek().kind != Tok::kEnd) Statement(&doc);
    src_->doc = std::move(doc);
  }

 private:
  // --- lexer ---
  // A lexer: one switch over the next character.
  // NOLINTNEXTLINE(readability-function-cognitive-complexity)
  void Lex() {
    size_t i = 0;
    const size_t n = text_.size();
    while (i < n) {
      const char c = text_[i];
      if (std::isspace(static_cast<unsigned char>(c))) {
        ++i;
      } else if (c == '#' || (c == '/' && i + 1 < n && text_[i + 1] == '/')) {
        while (i < n && text_[i] != '\n') ++i;
      } else if (IsIdentStart(c)) {
        const size_t start = i;
        while (i < n && IsIdentChar(text_[i])) ++i;
        tokens_.push_back({Tok::kIdent, text_.substr(start, i - start), start});
      } else if (IsUnquotedDate(i)) {  // 2026-06-21: read as the string "2026-06-21"
        tokens_.push_back({Tok::kString, text_.substr(i, 10), i});
        i += 10;
      } else if (std::isdigit(static_cast<unsigned char>(c)) || c == '-' || c == '+' ||
                 (c == '.' && i + 1 < n &&
                  std::isdigit(static_cast<unsigned char>(text_[i + 1])))) {
        const size_t start = i;
        if (c == '-' || c == '+') ++i;
        bool digits = false;
        while (i < n && std::isdigit(static_cast<unsigned char>(text_[i]))) ++i, digits = true;
        if (i < n && text_[i] == '.') {
          ++i;
          while (i < n && std::isdigit(static_cast<unsigned char>(text_[i]))) ++i, digits = true;
        }
        if (digits && i < n && (text_[i] == 'e' || text_[i] == 'E')) {
          size_t j = i + 1;
          if (j < n && (text_[j] == '-' || text_[j] == '+')) ++j;
          if (j < n && std::isdigit(static_cast<unsigned char>(text_[j]))) {
            i = j;
            while (i < n && std::isdigit(static_cast<unsigned char>(text_[i]))) ++i;
          }
        }
        if (!digits) Fail(start, "expected a number after '" + std::string(1, c) + "'");
        tokens_.push_back({Tok::kNumber, text_.substr(start, i - start), start});
      } else if (c == '"' || c == '\'') {
        const size_t start = i++;
        std::string content;
        while (i < n && text_[i] != c) {
          if (text_[i] == '\n') Fail(start, "unterminated string");
          if (text_[i] == '\\' && i + 1 < n) ++i;
          content += text_[i++];
        }
        if (i >= n) Fail(start, "unterminated string");
        ++i;
        tokens_.push_back({Tok::kString, content, start});
      } else if (std::string("=:,{}[]()").find(c) != std::string::npos) {
        tokens_.push_back({Tok::kPunct, std::string(1, c), i});
        ++i;
      } else {
        Fail(i, std::string("unexpected character '") + c + "'");
      }
    }
    tokens_.push_back({Tok::kEnd, "", n});
  }

  // A date YYYY-MM-DD at `i` (the paper's values have no arithmetic, so digits, '-', digits is no
  // number).
  bool IsUnquotedDate(size_t i) const {
    if (i + 10 > text_.size()) return false;
    for (size_t k = 0; k < 10; ++k) {
      const bool dash = k == 4 || k == 7;
      if (dash ? text_[i + k] != '-' : !std::isdigit(static_cast<unsigned char>(text_[i + k])))
        return false;
    }
    return i + 10 == text_.size() || !IsIdentChar(text_[i + 10]);
  }

  // --- helpers ---
  [[noreturn]] void Fail(size_t offset, const std::string& message) const {
    int line = 0, column = 0;
    LineColumnFromOffset(text_, offset, &line, &column);
    throw Error(message, Location::Text(src_->path, line, column));
  }
  [[noreturn]] void Unclosed(size_t open_offset, char close) const {
    Fail(open_offset,
         std::string("unclosed '") + (close == '}' ? '{' : '[') + "': expected '" + close +
             "' before the end of the file");
  }
  const Token& Peek(size_t ahead = 0) const {
    return tokens_[std::min(pos_ + ahead, tokens_.size() - 1)];
  }
  Token Next() {
    Token t = Peek();
    if (pos_ < tokens_.size() - 1) ++pos_;
    return t;
  }
  bool IsPunct(const Token& t, char c) const { return t.kind == Tok::kPunct && t.text[0] == c; }
  bool AcceptPunct(char c) {
    if (!IsPunct(Peek(), c)) return false;
    Next();
    return true;
  }
  Token ExpectPunct(char c, const std::string& context) {
    if (!IsPunct(Peek(), c))
      Fail(Peek().offset,
           "expected '" + std::string(1, c) + "' " + context + ", found " + Describe(Peek()));
    return Next();
  }
  void Mark(const std::string& pointer, size_t offset) {
    int line = 0, column = 0;
    LineColumnFromOffset(text_, offset, &line, &column);
    src_->positions[pointer] = std::make_pair(line, column);
  }
  void MarkKey(const std::string& pointer, size_t offset) {
    int line = 0, column = 0;
    LineColumnFromOffset(text_, offset, &line, &column);
    src_->key_positions[pointer] = std::make_pair(line, column);
    src_->positions.emplace(pointer, std::make_pair(line, column));
  }
  void Warn(size_t offset, const std::string& message) {
    int line = 0, column = 0;
    LineColumnFromOffset(text_, offset, &line, &column);
    src_->warnings.push_back(Location::Text(src_->path, line, column).ToString() + ": " + message);
  }

  // --- grammar ---
  // statement = IDENT ("=" | ":") ( start_rule | definition )
  void Statement(OJson* doc) {
    const Token name = Next();
    if (name.kind != Tok::kIdent)
      Fail(name.offset,
           "expected a symbol name (e.g. 'O1 = object{...}'), found " + Describe(name));
    if (!AcceptPunct('=') && !AcceptPunct(':'))
      Fail(Peek().offset,
           "expected '=' after symbol '" + name.text + "', found " + Describe(Peek()));
    const std::string pointer = PointerJoin("", name.text);
    if (doc->contains(name.text)) Fail(name.offset, "symbol '" + name.text + "' is defined twice");
    Mark(pointer, name.offset);
    if (name.text == "LSCENE" || name.text == "LCAP") {
      (*doc)[name.text] = StartRule(pointer);
      return;
    }
    Token kind = Next();
    if (kind.kind != Tok::kIdent)
      Fail(kind.offset,
           "expected a symbol kind (skybox, terrain, object, camera, path, "
           "...) after '" +
               name.text + " =', found " + Describe(kind));
    // Table 3 spells some kinds in words: `scene change{...}`, `create
    // path{...}`. They are joined with '_' as in their JSON form.
    while (Peek().kind == Tok::kIdent) kind.text += "_" + Next().text;
    const std::string body_pointer = PointerJoin(pointer, kind.text);
    Mark(body_pointer, kind.offset);
    ExpectPunct('{', "to open the body of " + name.text);
    OJson body = Members(body_pointer, '}');
    // Paper typo: "object{...,extent[..]},position:{...}}" closes the body
    // early. A ',' right after the closing brace continues the same body.
    while (IsPunct(Peek(), ',')) {
      Warn(Peek().offset, "stray '}' before ',' in " + name.text + " ignored (the body continues)");
      Next();
      OJson more = Members(body_pointer, '}');
      for (auto& item : more.items()) body[item.key()] = item.value();
    }
    (*doc)[name.text] = OJson{{kind.text, std::move(body)}};
  }

  // start_rule = { ("ONE" | "MANY") "(" IDENT [ "," count ] ")" }
  OJson StartRule(const std::string& pointer) {
    OJson list = OJson::array();
    while (Peek().kind == Tok::kIdent && (Peek().text == "ONE" || Peek().text == "MANY") &&
           IsPunct(Peek(1), '(')) {
      const Token op = Next();
      Next();  // (
      const Token sym = Next();
      if (sym.kind != Tok::kIdent)
        Fail(sym.offset,
             "expected a symbol name inside " + op.text + "(...), found " + Describe(sym));
      OJson entry = OJson::object();
      entry[op.text] = sym.text;
      const std::string item_pointer = PointerJoin(pointer, std::to_string(list.size()));
      Mark(item_pointer, op.offset);
      Mark(PointerJoin(item_pointer, op.text), sym.offset);
      if (AcceptPunct(',')) entry["count"] = Value(PointerJoin(item_pointer, "count"));
      ExpectPunct(')', "to close " + op.text + "(" + sym.text);
      list.push_back(std::move(entry));
      AcceptPunct(',');
    }
    if (list.empty())
      Fail(Peek().offset,
           "expected ONE(...) or MANY(...) in the start rule, found " + Describe(Peek()));
    return list;
  }

  // members = [ member { "," member } [ "," ] ] close
  // member  = key (":" | "=") value | key "{" members "}" | key "[" items "]"
  //         | "{" members "}" | "[" items "]"          (keyless: continues the
  //         previous member)
  // One recursive-descent step: a member list and its errors.
  // NOLINTNEXTLINE(readability-function-cognitive-complexity)
  OJson Members(const std::string& pointer, char close) {
    OJson object = OJson::object();
    std::string last_key;
    const size_t open_offset = pos_ > 0 ? tokens_[pos_ - 1].offset : 0;
    while (!AcceptPunct(close)) {
      const Token& t = Peek();
      if (t.kind == Tok::kEnd) Unclosed(open_offset, close);
      if (IsPunct(t, '{') || IsPunct(t, '[')) {
        if (last_key.empty())
          Fail(t.offset, "a value without a key must follow a 'key: value' member");
        // "range:[0,0,0],[360,360,360]" and "O1:{...},{...}": the previous
        // member becomes a list.
        OJson& previous = object[last_key];
        const std::string member_pointer = PointerJoin(pointer, last_key);
        if (!previous.is_array() || !continued_.count(member_pointer)) {
          OJson first = std::move(previous);
          previous = OJson::array();
          previous.push_back(std::move(first));
          continued_.insert(member_pointer);
          RelocateChildren(member_pointer);
        }
        previous.push_back(Value(PointerJoin(member_pointer, std::to_string(previous.size()))));
      } else if (t.kind == Tok::kIdent || t.kind == Tok::kString ||
                 (t.kind == Tok::kNumber && IsPunct(Peek(1), ':'))) {  // {30:0.5,60:0.5}
        const Token first = Next();
        std::string key = first.text;
        while (first.kind == Tok::kIdent && Peek().kind == Tok::kIdent)
          key += "_" + Next().text;  // "create hemi"
        if (object.contains(key)) Fail(first.offset, "key '" + key + "' appears twice");
        const std::string member_pointer = PointerJoin(pointer, key);
        MarkKey(member_pointer, first.offset);
        if (AcceptPunct(':') || AcceptPunct('=')) {
          object[key] = Value(member_pointer);
        } else if (IsPunct(Peek(), '{') || IsPunct(Peek(), '[')) {
          if (IsPunct(Peek(), '[')) Warn(Peek().offset, "'" + key + "[' read as '" + key + ":['");
          object[key] = Value(member_pointer);  // csettings{...}, extent[...]
        } else {
          Fail(Peek().offset,
               "expected ':' or '=' after key '" + key + "', found " + Describe(Peek()));
        }
        last_key = key;
      } else {
        Fail(t.offset, "expected a key or '" + std::string(1, close) + "', found " + Describe(t));
      }
      if (Peek().kind == Tok::kEnd) Unclosed(open_offset, close);
      if (IsPunct(Peek(), ':') && pos_ > 0 && tokens_[pos_ - 1].kind == Tok::kNumber)
        Fail(tokens_[pos_ - 1].offset,
             "a value with ':' in it is written in quotes, e.g. a time of day time:\"08:00\"");
      if (!IsPunct(Peek(), close) && !AcceptPunct(','))
        Fail(Peek().offset,
             std::string("expected ',' or '") + close + "', found " + Describe(Peek()));
    }
    return object;
  }

  // After turning "key: v" into "key: [v, ...]", v's positions move one level
  // down.
  void RelocateChildren(const std::string& member_pointer) {
    std::map<std::string, std::pair<int, int>> moved;
    for (auto it = src_->positions.lower_bound(member_pointer + "/");
         it != src_->positions.end();) {
      if (it->first.compare(0, member_pointer.size() + 1, member_pointer + "/") != 0) break;
      moved.emplace(member_pointer + "/0" + it->first.substr(member_pointer.size()), it->second);
      it = src_->positions.erase(it);
    }
    auto self = src_->positions.find(member_pointer);
    if (self != src_->positions.end()) moved.emplace(member_pointer + "/0", self->second);
    src_->positions.insert(moved.begin(), moved.end());
  }

  // value = NUMBER | STRING | "true" | "false" | IDENT [ ":" (NUMBER | IDENT) ]
  // | "{" members "}"
  //       | "[" items "]"
  OJson Value(const std::string& pointer) {
    const Token t = Next();
    Mark(pointer, t.offset);
    // Braces and lists recurse: a hostile file must not reach the stack's end.
    struct DepthGuard {
      int* depth;
      ~DepthGuard() {
        if (depth != nullptr) --*depth;
      }
    };
    const bool nests = IsPunct(t, '{') || IsPunct(t, '[');
    if (nests && ++depth_ > kMaxNestingDepth) {
      Fail(t.offset,
           "nesting deeper than " + std::to_string(kMaxNestingDepth) +
               " levels (braces and lists); lsds refuses such documents");
    }
    const DepthGuard depth_guard{nests ? &depth_ : nullptr};
    if (IsPunct(t, '{')) return Members(pointer, '}');
    if (IsPunct(t, '[')) {
      OJson list = OJson::array();
      while (!AcceptPunct(']')) {
        if (Peek().kind == Tok::kEnd) Unclosed(t.offset, ']');
        list.push_back(Value(PointerJoin(pointer, std::to_string(list.size()))));
        if (Peek().kind == Tok::kEnd) Unclosed(t.offset, ']');
        if (!IsPunct(Peek(), ']') && !AcceptPunct(','))
          Fail(Peek().offset, "expected ',' or ']' in the list, found " + Describe(Peek()));
      }
      return list;
    }
    if (t.kind == Tok::kNumber) return NumberValue(t);
    if (t.kind == Tok::kString) return OJson(t.text);
    if (t.kind == Tok::kIdent) return WordValue(t, pointer);
    Fail(t.offset, "expected a value (number, name, {...} or [...]), found " + Describe(t));
  }

  OJson NumberValue(const Token& t) const {
    const bool integral = t.text.find_first_of(".eE") == std::string::npos;
    errno = 0;
    if (integral) {
      char* end = nullptr;
      const long long v = std::strtoll(t.text.c_str(), &end, 10);
      if (errno == 0) return OJson(static_cast<int64_t>(v));
    }
    errno = 0;
    const double d = std::strtod(t.text.c_str(), nullptr);
    if (errno != 0 || !std::isfinite(d)) Fail(t.offset, "number " + t.text + " is out of range");
    return OJson(d);
  }

  // A word: true, false, a named block "V1:{car:1,truck:2}" (the object {V1: {...}}, in a list),
  // a reference with a count or index ("P1:3": 3 repetitions, "O1:5": label 5, "P1:1"), or a name.
  OJson WordValue(const Token& t, const std::string& pointer) {
    if (t.text == "true") return OJson(true);
    if (t.text == "false") return OJson(false);
    if (IsPunct(Peek(), ':') && IsPunct(Peek(1), '{')) {
      Next();
      const std::string member_pointer = PointerJoin(pointer, t.text);
      MarkKey(member_pointer, t.offset);
      OJson named = OJson::object();
      named[t.text] = Value(member_pointer);
      return named;
    }
    if (IsPunct(Peek(), ':') && (Peek(1).kind == Tok::kNumber || Peek(1).kind == Tok::kIdent) &&
        !IsPunct(Peek(2), ':') && !IsPunct(Peek(2), '=') && !IsPunct(Peek(2), '{')) {
      Next();
      return OJson(t.text + ":" + Next().text);
    }
    return OJson(t.text);
  }

  SourceFile* src_;
  const std::string& text_;
  std::vector<Token> tokens_;
  size_t pos_ = 0;
  std::set<std::string> continued_;
  int depth_ = 0;  // braces and lists open around the current value
};

}  // namespace

void ParseTextNotation(SourceFile* source) { Parser(source).Run(); }

}  // namespace lsds

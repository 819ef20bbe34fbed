#include "libs/util/npy.h"

#include <cctype>
#include <charconv>
#include <cstring>
#include <fstream>
#include <memory>
#include <string_view>

#include "libs/util/atomic_file.h"
#include "libs/util/error.h"
#include "libs/util/input_file.h"
#include "libs/util/limits.h"
#include "libs/util/text_check.h"

namespace lsds {

namespace {

// The Python literal of a .npy header: dicts, lists, tuples, strings,
// integers and True/False. Tuples and lists are both sequences.
struct PyValue {
  enum Kind { kString, kInt, kBool, kSequence, kDict } kind = kInt;
  std::string text;
  int64_t number = 0;
  std::vector<PyValue> items;                            // sequence
  std::vector<std::pair<std::string, PyValue>> entries;  // dict

  const PyValue* Find(const std::string& key) const {
    for (const auto& [k, v] : entries)
      if (k == key) return &v;
    return nullptr;
  }
};

// Recursive descent over the header's literal, bounded: the nesting depth by
// kMaxNestingDepth (a header of 10^5 '(' would otherwise overflow the stack),
// every step linear (numbers read in place, never from a copy of the rest).
class PyParser {
 public:
  PyParser(const std::string& text, const std::string& file, size_t file_offset)
      : text_(text), file_(file), file_offset_(file_offset) {}
  PyValue Parse() {
    PyValue v = Value(0);
    Skip();
    if (at_ < text_.size() && text_[at_] != '\n' && text_[at_] != '\0')
      Fail("unexpected text after the header's dictionary");
    return v;
  }

 private:
  [[noreturn]] void Fail(const std::string& what) const {
    throw Error("bad .npy header at byte " + std::to_string(file_offset_ + at_) + ": " + what,
                Location(file_));
  }
  void Skip() {
    while (at_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[at_]))) ++at_;
  }
  bool Eat(char c) {
    Skip();
    if (at_ < text_.size() && text_[at_] == c) return ++at_, true;
    return false;
  }
  // One recursive-descent step of the .npy header parser (a Python literal).
  // NOLINTNEXTLINE(readability-function-cognitive-complexity)
  PyValue Value(int depth) {
    Skip();
    if (at_ >= text_.size()) Fail("unexpected end");
    const char c = text_[at_];
    PyValue v;
    if (c == '\'' || c == '"') {
      v.kind = PyValue::kString;
      const size_t end = text_.find(c, at_ + 1);
      if (end == std::string::npos) Fail("unterminated string");
      v.text = text_.substr(at_ + 1, end - at_ - 1);
      at_ = end + 1;
    } else if (c == '{' || c == '(' || c == '[') {
      if (depth >= kMaxNestingDepth)
        Fail("nesting deeper than " + std::to_string(kMaxNestingDepth) + " levels");
      const char close = c == '{' ? '}' : c == '(' ? ')' : ']';
      ++at_;
      v.kind = c == '{' ? PyValue::kDict : PyValue::kSequence;
      while (!Eat(close)) {
        if (v.kind == PyValue::kDict) {
          PyValue key = Value(depth + 1);
          if (key.kind != PyValue::kString) Fail("expected a string key");
          if (!Eat(':')) Fail("expected ':'");
          v.entries.emplace_back(std::move(key.text), Value(depth + 1));
        } else {
          v.items.push_back(Value(depth + 1));
        }
        if (!Eat(',') && (Skip(), at_ >= text_.size() || text_[at_] != close))
          Fail("expected ',' or '" + std::string(1, close) + "'");
      }
    } else if (text_.compare(at_, 4, "True") == 0) {
      v.kind = PyValue::kBool, v.number = 1, at_ += 4;
    } else if (text_.compare(at_, 5, "False") == 0) {
      v.kind = PyValue::kBool, v.number = 0, at_ += 5;
    } else if (std::isdigit(static_cast<unsigned char>(c)) || c == '-') {
      const char* first = text_.data() + at_;
      const auto [end, ec] = std::from_chars(first, text_.data() + text_.size(), v.number);
      if (ec != std::errc()) Fail("not an integer in the range of int64");
      at_ += static_cast<size_t>(end - first);
    } else {
      Fail(std::string("unexpected '") + Excerpt(std::string_view(&text_[at_], 1)) + "'");
    }
    return v;
  }
  const std::string& text_;
  const std::string& file_;
  size_t file_offset_;  // of text_[0] in the file, for messages
  size_t at_ = 0;
};

// a * b, or an error naming `what` when it leaves int64 (a hostile shape
// would wrap to a small size that the payload then "matches").
int64_t CheckedProduct(int64_t a, int64_t b, const std::string& what, const std::string& file) {
  int64_t product = 0;
  if (a < 0 || b < 0 || __builtin_mul_overflow(a, b, &product))
    throw Error(what + " overflows a 64-bit size", Location(file));
  return product;
}

// numpy itself refuses headers over 10,000 bytes unless told otherwise.
constexpr size_t kMaxHeaderBytes = size_t{1} << 20;

NpyField ParseType(const std::string& type, const std::string& file) {
  // '<f4', '|u1', '|b1': byte order, kind, size.
  if (type.size() < 3 || (type[0] != '<' && type[0] != '|' && type[0] != '='))
    throw Error("unsupported dtype '" + type + "' (only little-endian bool, int and float)",
                Location(file));
  NpyField field;
  field.kind = type[1];
  const auto [end, ec] = std::from_chars(type.data() + 2, type.data() + type.size(), field.size);
  const bool ok = ec == std::errc() && end == type.data() + type.size() &&
                  ((field.kind == 'f' && (field.size == 4 || field.size == 8)) ||
                   ((field.kind == 'u' || field.kind == 'i') &&
                    (field.size == 1 || field.size == 2 || field.size == 4 || field.size == 8)) ||
                   (field.kind == 'b' && field.size == 1));
  if (!ok) throw Error("unsupported dtype '" + type + "'", Location(file));
  return field;
}

}  // namespace

int64_t NpyArray::size() const {
  int64_t n = 1;
  for (int64_t d : shape) n *= d;
  return n;
}

const NpyField& NpyArray::Field(const std::string& name, const std::string& file) const {
  for (const NpyField& f : fields)
    if (f.name == name) return f;
  throw Error("no field '" + name + "' in the array's dtype", Location(file));
}

double NpyArray::Get(int64_t record, const NpyField& field, int64_t element) const {
  const char* p = data.data() + static_cast<size_t>(record) * record_size + field.offset +
                  static_cast<size_t>(element) * field.size;
  // .npy payloads are little-endian, as is every machine lsds builds on.
  auto read = [p](auto value) {
    std::memcpy(&value, p, sizeof value);
    return static_cast<double>(value);
  };
  switch (field.kind) {
    case 'f':
      return field.size == 4 ? read(float{}) : read(double{});
    case 'u':
      return field.size == 1   ? read(uint8_t{})
             : field.size == 2 ? read(uint16_t{})
             : field.size == 4 ? read(uint32_t{})
                               : read(uint64_t{});
    case 'i':
      return field.size == 1   ? read(int8_t{})
             : field.size == 2 ? read(int16_t{})
             : field.size == 4 ? read(int32_t{})
                               : read(int64_t{});
    default:
      return read(uint8_t{});
  }
}

namespace {

// The header's text, streamed: the magic, its length, then just its bytes
// (`start`: where they begin). The length is checked against the file and
// lsds's limit before any is read.
std::string ReadHeaderText(std::ifstream& in,
                           const std::string& file,
                           uint64_t file_size,
                           size_t* start) {
  char lead[12] = {};
  in.read(lead, sizeof lead);
  const auto got = static_cast<size_t>(in.gcount());
  if (got < 10 || std::memcmp(lead, "\x93NUMPY", 6) != 0)
    throw Error("not a .npy file (no \\x93NUMPY magic)", Location(file));
  const int major = static_cast<unsigned char>(lead[6]);
  uint64_t header_length = 0;
  if (major == 1) {
    header_length =
        static_cast<unsigned char>(lead[8]) | (static_cast<unsigned char>(lead[9]) << 8);
    *start = 10;
  } else if (major == 2 || major == 3) {
    if (got < 12) throw Error("truncated .npy header", Location(file));
    for (int b = 3; b >= 0; --b)
      header_length = (header_length << 8) | static_cast<unsigned char>(lead[8 + b]);
    *start = 12;
  } else {
    throw Error("unsupported .npy version " + std::to_string(major), Location(file));
  }
  if (*start + header_length > file_size) {
    throw Error("truncated .npy header: it declares " + std::to_string(header_length) +
                    " bytes, the file has " + std::to_string(file_size - *start) + " after byte " +
                    std::to_string(*start),
                Location(file));
  }
  if (header_length > kMaxHeaderBytes) {
    throw Error("the .npy header declares " + std::to_string(header_length) +
                    " bytes, over lsds's limit of " + std::to_string(kMaxHeaderBytes),
                Location(file));
  }
  std::string header(static_cast<size_t>(header_length), '\0');
  in.seekg(static_cast<std::streamoff>(*start));
  in.read(header.data(), static_cast<std::streamsize>(header.size()));
  if (static_cast<uint64_t>(in.gcount()) != header_length)
    throw Error("truncated .npy header", Location(file));
  return header;
}

// The array's dimensions into `shape`; returns their product, the element count.
int64_t ReadShape(const PyValue& value, const std::string& file, std::vector<int64_t>* shape) {
  int64_t elements = 1;
  for (const PyValue& d : value.items) {
    if (d.kind != PyValue::kInt || d.number < 0)
      throw Error("bad shape in the .npy header: dimensions must be integers >= 0", Location(file));
    shape->push_back(d.number);
    elements = CheckedProduct(elements, d.number, "the .npy shape", file);
  }
  return elements;
}

// One field of a structured dtype: (name, type[, shape]).
NpyField ReadStructuredField(const PyValue& item, const std::string& file) {
  if (item.kind != PyValue::kSequence || item.items.size() < 2 || item.items.size() > 3 ||
      item.items[0].kind != PyValue::kString || item.items[1].kind != PyValue::kString)
    throw Error("bad structured dtype in the .npy header (a field is (name, type[, shape]))",
                Location(file));
  NpyField field = ParseType(item.items[1].text, file);
  field.name = item.items[0].text;
  if (item.items.size() <= 2) return field;
  const PyValue& sub = item.items[2];
  const std::string what = "the shape of field '" + field.name + "'";
  if (sub.kind == PyValue::kInt && sub.number >= 0) {
    field.count = sub.number;
  } else if (sub.kind == PyValue::kSequence) {
    for (const PyValue& d : sub.items) {
      if (d.kind != PyValue::kInt || d.number < 0)
        throw Error(what + " in the .npy header must hold integers >= 0", Location(file));
      field.count = CheckedProduct(field.count, d.number, what, file);
    }
  } else {
    throw Error(what + " in the .npy header must be an integer >= 0 or a tuple of them",
                Location(file));
  }
  return field;
}

// The fields of the dtype `descr` (one plain type, or a structured dtype) at
// their offsets; returns the record size.
int64_t ReadFields(const PyValue& descr, const std::string& file, std::vector<NpyField>* fields) {
  if (descr.kind == PyValue::kString) {
    fields->push_back(ParseType(descr.text, file));
    return fields->front().size;
  }
  if (descr.kind != PyValue::kSequence) throw Error("bad descr in the .npy header", Location(file));
  int64_t record_size = 0;
  for (const PyValue& item : descr.items) {
    NpyField field = ReadStructuredField(item, file);
    field.offset = static_cast<size_t>(record_size);
    const int64_t bytes =
        CheckedProduct(field.count, field.size, "the size of field '" + field.name + "'", file);
    if (__builtin_add_overflow(record_size, bytes, &record_size))
      throw Error("the .npy record size overflows a 64-bit size", Location(file));
    fields->push_back(field);
  }
  return record_size;
}

}  // namespace

NpyArray ReadNpy(const std::filesystem::path& path) {
  const std::string file = path.string();
  if (!std::filesystem::exists(path)) throw Error("missing file", Location(file));
  RequireRegularFile(path, ".npy file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot open for reading", Location(file));
  std::error_code ec;
  const uint64_t file_size = std::filesystem::file_size(path, ec);
  if (ec) throw Error("cannot read: " + ec.message(), Location(file));
  // The header is streamed; the payload is read only once its size is known
  // to match the file.
  size_t start = 0;
  const std::string header = ReadHeaderText(in, file, file_size, &start);
  const PyValue dict = PyParser(header, file, start).Parse();
  const PyValue* descr = dict.Find("descr");
  const PyValue* fortran = dict.Find("fortran_order");
  const PyValue* shape = dict.Find("shape");
  if (dict.kind != PyValue::kDict || !descr || !fortran || !shape ||
      shape->kind != PyValue::kSequence)
    throw Error("the .npy header lacks descr, fortran_order or shape", Location(file));
  if (fortran->number != 0)
    throw Error("Fortran-order .npy arrays are not supported", Location(file));
  NpyArray array;
  const int64_t elements = ReadShape(*shape, file, &array.shape);
  const int64_t record_size = ReadFields(*descr, file, &array.fields);
  array.record_size = static_cast<size_t>(record_size);
  const int64_t want = CheckedProduct(elements, record_size, "the .npy payload size", file);
  const uint64_t have = file_size - start - header.size();
  if (have != static_cast<uint64_t>(want))
    throw Error("the .npy payload holds " + std::to_string(have) + " bytes, its header says " +
                    std::to_string(want),
                Location(file));
  CheckMemoryBudget(static_cast<double>(want), "the .npy payload", file);
  array.data.resize(static_cast<size_t>(want));
  in.read(array.data.data(), static_cast<std::streamsize>(want));
  if (in.gcount() != static_cast<std::streamsize>(want))
    throw Error("the .npy payload is shorter than the file's size said", Location(file));
  return array;
}

void WriteNpy(const std::filesystem::path& path,
              const std::string& descr,
              const std::vector<int64_t>& shape,
              const std::string& data) {
  // Python's tuple spelling: (), (3,), (2, 3).
  std::string dims;
  for (size_t k = 0; k < shape.size(); ++k) dims += (k ? ", " : "") + std::to_string(shape[k]);
  if (shape.size() == 1) dims += ",";
  std::string header =
      "{'descr': " + descr + ", 'fortran_order': False, 'shape': (" + dims + "), }";
  const size_t total = 10 + header.size() + 1;
  header.append((64 - total % 64) % 64, ' ');
  header += '\n';
  std::string bytes = "\x93NUMPY";
  bytes += '\x01';
  bytes += '\x00';
  bytes += static_cast<char>(header.size() & 0xff);
  bytes += static_cast<char>(header.size() >> 8);
  bytes += header;
  bytes += data;
  WriteFileAtomic(path, bytes);
}

}  // namespace lsds

#include "libs/util/npy.h"

#include <cctype>
#include <cstring>
#include <fstream>
#include <memory>
#include <sstream>
#include <variant>

#include "libs/util/atomic_file.h"
#include "libs/util/error.h"

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

class PyParser {
 public:
  PyParser(const std::string& text, const std::string& file) : text_(text), file_(file) {}
  PyValue Parse() {
    PyValue v = Value();
    Skip();
    return v;
  }

 private:
  [[noreturn]] void Fail(const std::string& what) {
    throw Error("bad .npy header at character " + std::to_string(at_ + 1) + ": " + what,
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
  PyValue Value() {
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
    } else if (c == '{') {
      ++at_;
      v.kind = PyValue::kDict;
      while (!Eat('}')) {
        PyValue key = Value();
        if (key.kind != PyValue::kString) Fail("expected a string key");
        if (!Eat(':')) Fail("expected ':'");
        v.entries.emplace_back(key.text, Value());
        if (!Eat(',') && (Skip(), text_[at_] != '}')) Fail("expected ',' or '}'");
      }
    } else if (c == '(' || c == '[') {
      const char close = c == '(' ? ')' : ']';
      ++at_;
      v.kind = PyValue::kSequence;
      while (!Eat(close)) {
        v.items.push_back(Value());
        if (!Eat(',') && (Skip(), at_ >= text_.size() || text_[at_] != close))
          Fail("expected ',' or '" + std::string(1, close) + "'");
      }
    } else if (text_.compare(at_, 4, "True") == 0) {
      v.kind = PyValue::kBool, v.number = 1, at_ += 4;
    } else if (text_.compare(at_, 5, "False") == 0) {
      v.kind = PyValue::kBool, v.number = 0, at_ += 5;
    } else if (std::isdigit(static_cast<unsigned char>(c)) || c == '-') {
      size_t used = 0;
      v.number = std::stoll(text_.substr(at_), &used);
      at_ += used;
    } else {
      Fail(std::string("unexpected '") + c + "'");
    }
    return v;
  }
  const std::string& text_;
  const std::string& file_;
  size_t at_ = 0;
};

NpyField ParseType(const std::string& type, const std::string& file) {
  // '<f4', '|u1', '|b1': byte order, kind, size.
  if (type.size() < 3 || (type[0] != '<' && type[0] != '|' && type[0] != '='))
    throw Error("unsupported dtype '" + type + "' (only little-endian bool, int and float)",
                Location(file));
  NpyField field;
  field.kind = type[1];
  field.size = std::atoi(type.c_str() + 2);
  const bool ok = (field.kind == 'f' && (field.size == 4 || field.size == 8)) ||
                  ((field.kind == 'u' || field.kind == 'i') &&
                   (field.size == 1 || field.size == 2 || field.size == 4 || field.size == 8)) ||
                  (field.kind == 'b' && field.size == 1);
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

NpyArray ReadNpy(const std::filesystem::path& path) {
  const std::string file = path.string();
  if (!std::filesystem::is_regular_file(path)) throw Error("missing file", Location(file));
  const std::string bytes = ReadFile(path);
  if (bytes.size() < 10 || bytes.compare(0, 6, "\x93NUMPY") != 0)
    throw Error("not a .npy file (no \\x93NUMPY magic)", Location(file));
  const int major = static_cast<unsigned char>(bytes[6]);
  size_t header_length = 0, start = 0;
  if (major == 1) {
    header_length =
        static_cast<unsigned char>(bytes[8]) | (static_cast<unsigned char>(bytes[9]) << 8);
    start = 10;
  } else if (major == 2 || major == 3) {
    if (bytes.size() < 12) throw Error("truncated .npy header", Location(file));
    for (int b = 3; b >= 0; --b)
      header_length = (header_length << 8) | static_cast<unsigned char>(bytes[8 + b]);
    start = 12;
  } else {
    throw Error("unsupported .npy version " + std::to_string(major), Location(file));
  }
  if (start + header_length > bytes.size()) throw Error("truncated .npy header", Location(file));
  const std::string header = bytes.substr(start, header_length);
  const PyValue dict = PyParser(header, file).Parse();
  const PyValue* descr = dict.Find("descr");
  const PyValue* fortran = dict.Find("fortran_order");
  const PyValue* shape = dict.Find("shape");
  if (dict.kind != PyValue::kDict || !descr || !fortran || !shape ||
      shape->kind != PyValue::kSequence)
    throw Error("the .npy header lacks descr, fortran_order or shape", Location(file));
  if (fortran->number != 0)
    throw Error("Fortran-order .npy arrays are not supported", Location(file));
  NpyArray array;
  for (const PyValue& d : shape->items) {
    if (d.kind != PyValue::kInt || d.number < 0)
      throw Error("bad shape in the .npy header", Location(file));
    array.shape.push_back(d.number);
  }
  if (descr->kind == PyValue::kString) {
    array.fields.push_back(ParseType(descr->text, file));
    array.record_size = array.fields[0].size;
  } else if (descr->kind == PyValue::kSequence) {
    for (const PyValue& item : descr->items) {
      if (item.kind != PyValue::kSequence || item.items.size() < 2 ||
          item.items[0].kind != PyValue::kString || item.items[1].kind != PyValue::kString)
        throw Error("bad structured dtype in the .npy header", Location(file));
      NpyField field = ParseType(item.items[1].text, file);
      field.name = item.items[0].text;
      if (item.items.size() > 2) {
        const PyValue& sub = item.items[2];
        if (sub.kind == PyValue::kInt) field.count = sub.number;
        for (const PyValue& d : sub.items) field.count *= d.number;
      }
      field.offset = array.record_size;
      array.record_size += static_cast<size_t>(field.size * field.count);
      array.fields.push_back(field);
    }
  } else {
    throw Error("bad descr in the .npy header", Location(file));
  }
  array.data = bytes.substr(start + header_length);
  const size_t want = static_cast<size_t>(array.size()) * array.record_size;
  if (array.data.size() != want)
    throw Error("the .npy payload holds " + std::to_string(array.data.size()) +
                    " bytes, its header says " + std::to_string(want),
                Location(file));
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

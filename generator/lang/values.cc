#include "generator/lang/values.h"

#include <cctype>
#include <cmath>

#include <Eigen/Geometry>

#include "generator/lang/distributions.h"
#include "libs/util/strings.h"

namespace lsds {

std::string CanonicalKey(const std::string& key) {
  std::string out;
  for (char c : key) {
    if (c == '_' || c == ' ' || c == '-') continue;
    out += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  }
  return out;
}

void Node::Fail(const std::string& message) const { throw Error(message, Where()); }
void Node::FailKey(const std::string& message) const {
  throw Error(message, src->WhereKey(pointer));
}

Node Node::Child(const std::string& key) const {
  if (!value || !value->is_object() || !value->contains(key))
    return Node{src, nullptr, PointerJoin(pointer, key)};
  return Node{src, &(*value)[key], PointerJoin(pointer, key)};
}

Node Node::Item(size_t i) const {
  return Node{src, &(*value)[i], PointerJoin(pointer, std::to_string(i))};
}

Node Node::Find(const std::string& canonical) const {
  if (value && value->is_object()) {
    for (auto it = value->begin(); it != value->end(); ++it)
      if (CanonicalKey(it.key()) == canonical)
        return Node{src, &it.value(), PointerJoin(pointer, it.key())};
  }
  return Node{src, nullptr, pointer};
}

std::vector<std::pair<std::string, Node>> Node::Members() const {
  std::vector<std::pair<std::string, Node>> out;
  if (!value || !value->is_object()) return out;
  for (auto it = value->begin(); it != value->end(); ++it)
    out.emplace_back(it.key(), Node{src, &it.value(), PointerJoin(pointer, it.key())});
  return out;
}

void Node::CheckKeys(const std::vector<std::string>& known, const std::string& what) const {
  if (!value || !value->is_object()) Fail("expected {key: value, ...} for " + what);
  std::vector<std::string> canon;
  canon.reserve(known.size());
  for (const std::string& k : known) canon.push_back(CanonicalKey(k));
  for (auto it = value->begin(); it != value->end(); ++it) {
    const std::string c = CanonicalKey(it.key());
    bool found = false;
    for (const std::string& k : canon) found = found || k == c;
    if (!found) {
      const std::string close = ClosestMatch(c, canon);
      std::string hint;
      for (size_t i = 0; i < canon.size(); ++i)
        if (canon[i] == close) hint = " (did you mean '" + known[i] + "'?)";
      if (hint.empty()) hint = "; known keys: " + Join(known, ", ");
      Node{src, &it.value(), PointerJoin(pointer, it.key())}.FailKey("unknown key '" + it.key() +
                                                                     "' in " + what + hint);
    }
  }
}

bool IsNumber(const OJson& v) { return v.is_number(); }

double ReadNumber(const Node& node) {
  if (!node.value || !node->is_number())
    node.Fail("expected a number, found " + (node.value ? node->dump() : "nothing"));
  const double d = node->get<double>();
  if (!std::isfinite(d)) node.Fail("expected a finite number");
  return d;
}

std::string ReadString(const Node& node) {
  if (!node.value || !node->is_string())
    node.Fail("expected a name, found " + (node.value ? node->dump() : "nothing"));
  return node->get<std::string>();
}

size_t SampleWeighted(const std::vector<double>& weights, Rng& rng) {
  double total = 0;
  for (double w : weights) total += w;
  double u = rng.Uniform() * total;
  for (size_t i = 0; i < weights.size(); ++i) {
    if (u < weights[i]) return i;
    u -= weights[i];
  }
  for (size_t i = weights.size(); i-- > 0;)
    if (weights[i] > 0) return i;
  return 0;
}

namespace {

// {key: weight, ...} -> chosen key and its node.
std::string SampleChoiceKey(const Node& node, Rng& rng) {
  std::vector<std::string> keys;
  std::vector<double> weights;
  for (const auto& [key, child] : node.Members()) {
    const double w = ReadNumber(child);
    if (w < 0) child.Fail("a choice weight must be >= 0");
    keys.push_back(key);
    weights.push_back(w);
  }
  double total = 0;
  for (double w : weights) total += w;
  if (keys.empty() || total <= 0)
    node.Fail("a choice needs at least one positive weight, e.g. {a:0.2, b:0.8}");
  return keys[SampleWeighted(weights, rng)];
}

}  // namespace

double SampleScalar(const Node& node, Rng& rng) {
  if (!node.value) node.Fail("expected a number");
  const OJson& v = *node;
  if (v.is_number()) return ReadNumber(node);
  if (v.is_array() && v.size() == 2 && v[0].is_number() && v[1].is_number()) {
    const double lo = ReadNumber(node.Item(0)), hi = ReadNumber(node.Item(1));
    if (lo > hi) node.Fail("interval [lo, hi] needs lo <= hi");
    return rng.Uniform(lo, hi);
  }
  if (const std::optional<double> d = SampleDistribution(node, rng)) return *d;
  if (v.is_object()) {
    const std::string key = SampleChoiceKey(node, rng);
    char* end = nullptr;
    const double d = std::strtod(key.c_str(), &end);
    if (end == key.c_str() || *end != '\0')
      node.Child(key).FailKey("choice '" + key + "' is not a number");
    return d;
  }
  node.Fail(
      "expected a number, an interval [lo, hi] or a choice {value: weight, "
      "...}, found " +
      v.dump());
}

int64_t SampleCount(const Node& node, Rng& rng) {
  const OJson& v = *node;
  if (v.is_array() && v.size() == 2 && v[0].is_number() && v[1].is_number()) {
    const double lo = ReadNumber(node.Item(0)), hi = ReadNumber(node.Item(1));
    if (lo < 0 || lo > hi || hi > 1e6 || lo != std::floor(lo) || hi != std::floor(hi))
      node.Fail("a count interval needs whole numbers 0 <= lo <= hi <= 1000000");
    return rng.UniformInt(static_cast<int64_t>(lo), static_cast<int64_t>(hi));
  }
  const double d = SampleScalar(node, rng);
  if (d < 0 || d > 1e6 || d != std::floor(d))
    node.Fail("a count must be a whole number in [0, 1000000]");
  return static_cast<int64_t>(d);
}

std::string SampleString(const Node& node, Rng& rng) {
  if (!node.value) node.Fail("expected a name");
  if (node->is_string()) return node->get<std::string>();
  if (node->is_object()) return SampleChoiceKey(node, rng);
  node.Fail("expected a name or a choice {name: weight, ...}, found " + node->dump());
}

std::vector<std::string> StringOptions(const Node& node) {
  if (node->is_string()) return {node->get<std::string>()};
  std::vector<std::string> out;
  if (node->is_object())
    for (const auto& [key, child] : node.Members()) out.push_back(key);
  return out;
}

bool SampleBool(const Node& node, Rng& rng) {
  if (!node.value) node.Fail("expected true or false");
  if (node->is_boolean()) return node->get<bool>();
  if (node->is_object()) {
    const std::string key = SampleChoiceKey(node, rng);
    if (key == "true") return true;
    if (key == "false") return false;
    node.Child(key).FailKey("choice '" + key + "' is not true or false");
  }
  node.Fail("expected true, false or a choice {true: p, false: q}, found " + node->dump());
}

Eigen::Vector3d SampleVec3(const Node& node, Rng& rng) {
  if (!node.value) node.Fail("expected a vector [x, y, z]");
  const OJson& v = *node;
  if (v.is_object()) {
    node.CheckKeys({"range"}, "a vector range");
    const Node range = node.Find("range");
    if (!range) node.Fail("expected {range: [[x0,y0,z0],[x1,y1,z1]]}");
    return SampleVec3(range, rng);
  }
  if (v.is_number()) {
    const double d = ReadNumber(node);
    return {d, d, d};
  }
  if (!v.is_array()) node.Fail("expected a vector [x, y, z], found " + v.dump());
  if (v.size() == 2 && v[0].is_array() && v[1].is_array()) {  // [[lo..], [hi..]]
    const Node lo = node.Item(0), hi = node.Item(1);
    if (lo->size() != 3 || hi->size() != 3)
      node.Fail("a vector range needs two vectors of 3 numbers");
    Eigen::Vector3d out;
    for (int i = 0; i < 3; ++i) {
      const double a = ReadNumber(lo.Item(i)), b = ReadNumber(hi.Item(i));
      if (a > b) hi.Item(i).Fail("range end is below its start");
      out[i] = rng.Uniform(a, b);
    }
    return out;
  }
  if (v.size() != 3)
    node.Fail("expected 3 components [x, y, z], found " + std::to_string(v.size()));
  Eigen::Vector3d out;
  for (int i = 0; i < 3; ++i) out[i] = SampleScalar(node.Item(i), rng);
  return out;
}

Eigen::Vector3d SampleScale(const Node& node, Rng& rng) {
  if (node.value && node->is_array() && !(node->size() == 2 && (*node)[0].is_number()))
    return SampleVec3(node, rng);
  return Eigen::Vector3d::Constant(SampleScalar(node, rng));
}

Eigen::Vector2d SampleVec2(const Node& node, Rng& rng) {
  if (!node.value) node.Fail("expected a vector [x, y]");
  if (node->is_number()) {
    const double d = ReadNumber(node);
    return {d, d};
  }
  if (!node->is_array() || node->size() != 2)
    node.Fail("expected 2 components [x, y], found " + node->dump());
  return {SampleScalar(node.Item(0), rng), SampleScalar(node.Item(1), rng)};
}

std::vector<double> ExpandRange(const Node& node) {
  if (node->is_number()) return {ReadNumber(node)};
  if (!node->is_array() || (node->size() != 3 && node->size() != 2))
    node.Fail("expected a range [start, stop, count] or a number, found " + node->dump());
  const double start = ReadNumber(node.Item(0)), stop = ReadNumber(node.Item(1));
  double count_value = node->size() == 3 ? ReadNumber(node.Item(2)) : 2;
  if (count_value < 1 || count_value > 100000 || count_value != std::floor(count_value))
    node.Item(node->size() - 1).Fail("a range count must be a whole number in [1, 100000]");
  const int count = static_cast<int>(count_value);
  if (count == 1) return {start};
  const bool full_turn = std::abs(std::abs(stop - start) - 360.0) < 1e-9;
  const int divisions = full_turn ? count : count - 1;
  std::vector<double> out;
  out.reserve(count);
  for (int i = 0; i < count; ++i) out.push_back(start + (stop - start) * i / divisions);
  return out;
}

Eigen::Matrix3d RotationFromEulerDeg(const Eigen::Vector3d& rpy) {
  const double k = M_PI / 180.0;
  return (Eigen::AngleAxisd(rpy.z() * k, Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(rpy.y() * k, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(rpy.x() * k, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

}  // namespace lsds

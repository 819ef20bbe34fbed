// Reading and sampling the values of LSCENE/LCAP (docs/languages.md, "Values"):
//   crisp            5, grassy, [1,2,3]
//   discrete choice  {cumulus:0.5, nimbostratus:0.5}     weights, normalised
//   interval         [lo, hi]                            uniform
//   vector range     [[x0,y0,z0],[x1,y1,z1]] or {range:[[..],[..]]}   uniform
//   per component LCAP range       [start, stop, count]                count
//   evenly spaced values
// Every error names the file and the place of the value (text line:column or
// JSON pointer).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "generator/lang/random.h"
#include "generator/lang/source.h"

namespace lsds {

// Canonical form of a key for matching: lower case without '_', ' ', '-'
// ("PPMaterial" == "pp_material", "create hemi" == "create_hemi" ==
// "CreateHemi").
std::string CanonicalKey(const std::string& key);

// A value and where it is.
struct Node {
  const SourceFile* src = nullptr;
  const OJson* value = nullptr;
  std::string pointer;

  explicit operator bool() const { return value != nullptr; }
  const OJson& operator*() const { return *value; }
  const OJson* operator->() const { return value; }
  Location Where() const { return src->Where(pointer); }
  [[noreturn]] void Fail(const std::string& message) const;
  // Fails at the member's key (text) - for unknown keys and choice options.
  [[noreturn]] void FailKey(const std::string& message) const;
  Node Child(const std::string& key) const;  // exact key, for objects
  Node Item(size_t i) const;                 // for arrays
  // The member whose canonical key is `canonical` (nullptr-valued Node when
  // absent).
  Node Find(const std::string& canonical) const;
  // Throws for any member not in `known` (snake_case names), suggesting the
  // closest one.
  void CheckKeys(const std::vector<std::string>& known, const std::string& what) const;
  // Members as (key, Node) in file order.
  std::vector<std::pair<std::string, Node>> Members() const;
};

double ReadNumber(const Node& node);
std::string ReadString(const Node& node);
bool IsNumber(const OJson& v);

double SampleScalar(const Node& node, Rng& rng);
int64_t SampleCount(const Node& node,
                    Rng& rng);  // integer >= 0; interval sampled inclusively
std::string SampleString(const Node& node, Rng& rng);
bool SampleBool(const Node& node, Rng& rng);
Eigen::Vector3d SampleVec3(const Node& node, Rng& rng);
Eigen::Vector2d SampleVec2(const Node& node, Rng& rng);
// A scale: a scalar (number, [lo, hi], choice) applied to all axes, or a vector
// of 3 / a vector range.
Eigen::Vector3d SampleScale(const Node& node, Rng& rng);
// Index into weights chosen with probability proportional to the weight.
size_t SampleWeighted(const std::vector<double>& weights, Rng& rng);

// The options a string value may take (one for crisp, each key for a choice),
// in order.
std::vector<std::string> StringOptions(const Node& node);

// [start, stop, count] -> count values; a plain number -> itself; full turns
// ([0,360,4]) leave out the end that repeats the start.
std::vector<double> ExpandRange(const Node& node);

// Rotation from roll/pitch/yaw in degrees about x, y, z: Rz(yaw) * Ry(pitch) *
// Rx(roll).
Eigen::Matrix3d RotationFromEulerDeg(const Eigen::Vector3d& roll_pitch_yaw);

}  // namespace lsds

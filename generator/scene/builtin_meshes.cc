#include "generator/scene/builtin_meshes.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "generator/scene/perlin.h"
#include "libs/util/counter_rng.h"

namespace lsds::gen {
namespace {

// A seeded uniform stream in [0, 1) (splitmix-style hash chain).
class Uniform {
 public:
  explicit Uniform(uint64_t seed) : state_(seed) {}
  double operator()() {
    state_ = HashCombine(state_, 0x9e3779b97f4a7c15ull);
    return static_cast<double>(state_ >> 11) / static_cast<double>(uint64_t{1} << 53);
  }
  double In(double lo, double hi) { return lo + (hi - lo) * (*this)(); }

 private:
  uint64_t state_;
};

// Tyre rubber and a painted alloy rim (8-bit sRGB).
constexpr unsigned char kTyre[3] = {25, 25, 27};
constexpr unsigned char kRim[3] = {170, 172, 176};

// A part whose albedo is a fixed colour (8-bit sRGB), not the material's.
TriangleMesh Tinted(TriangleMesh part, unsigned char r, unsigned char g, unsigned char b) {
  const unsigned char rgb[3] = {r, g, b};
  part.albedo_maps = {MakeImageTexture(1, 1, rgb)};
  part.uvs.assign(part.positions.size(), Eigen::Vector2f(0.5f, 0.5f));
  part.triangle_map.assign(part.triangles.size(), 0);
  return part;
}

// A box of `size` centred at `centre`.
void AddBox(TriangleMesh* mesh, const Eigen::Vector3f& size, const Eigen::Vector3f& centre) {
  mesh->Append(MakeBoxMesh(), size.asDiagonal(), centre);
}

// A frustum of a box between heights z0 and z1: a rectangle of half sizes
// `bottom` centred at x = bottom_x below, `top` at top_x above (cabins with a
// sloped windscreen and rear window).
struct Frustum {
  Eigen::Vector2f bottom, top;
  float bottom_x, top_x, z0, z1;

  // The section between heights a and b, grown by `margin` on every side
  // (a window band just proud of the cabin).
  Frustum Section(float a, float b, float margin) const {
    auto at = [this](float z) {
      const float f = (z - z0) / (z1 - z0);
      return std::make_pair(Eigen::Vector2f(bottom + f * (top - bottom)),
                            bottom_x + f * (top_x - bottom_x));
    };
    const auto [half_a, x_a] = at(a);
    const auto [half_b, x_b] = at(b);
    const Eigen::Vector2f grow = Eigen::Vector2f::Constant(margin);
    return {half_a + grow, half_b + grow, x_a, x_b, a, b};
  }
  TriangleMesh Mesh() const {
    TriangleMesh box = MakeBoxMesh();
    for (Eigen::Vector3f& p : box.positions) {
      const bool up = p.z() > 0;
      const Eigen::Vector2f& half = up ? top : bottom;
      p = Eigen::Vector3f(
          (up ? top_x : bottom_x) + 2 * p.x() * half.x(), 2 * p.y() * half.y(), up ? z1 : z0);
    }
    return box;
  }
};

// The rotation taking +z to `axis` (unit).
Eigen::Matrix3f ZTo(const Eigen::Vector3f& axis) {
  return Eigen::Quaternionf::FromTwoVectors(Eigen::Vector3f::UnitZ(), axis).toRotationMatrix();
}

// A cylinder of `radius` from `a` to `b`.
void AddLimb(TriangleMesh* mesh,
             const Eigen::Vector3f& a,
             const Eigen::Vector3f& b,
             float radius,
             int segments = 10) {
  const Eigen::Vector3f d = b - a;
  const float length = d.norm();
  if (length <= 0) return;
  const Eigen::Matrix3f linear =
      ZTo(d / length) * Eigen::Vector3f(2 * radius, 2 * radius, length).asDiagonal();
  mesh->Append(MakeCylinderMesh(segments), linear, 0.5f * (a + b));
}

void AddSphere(TriangleMesh* mesh,
               const Eigen::Vector3f& centre,
               const Eigen::Vector3f& size,
               int segments = 12) {
  mesh->Append(MakeSphereMesh(segments, segments / 2), size.asDiagonal(), centre);
}

// A wheel with its axis along y: a dark tyre and, on its outer side (the side
// `outer_y` lies on), a light rim disc whose face is at y = outer_y. Two tinted
// parts, so that the tyre/rim contrast survives any body paint.
void AddWheel(TriangleMesh* mesh, float x, float outer_y, float radius, float width) {
  const float side = outer_y < 0 ? -1.f : 1.f;
  const float rim_depth = std::min(0.03f, 0.2f * width);
  TriangleMesh tyre, rim;
  AddLimb(&tyre,
          {x, outer_y - side * width, radius},
          {x, outer_y - side * rim_depth / 2, radius},
          radius,
          20);
  AddLimb(&rim, {x, outer_y - side * rim_depth, radius}, {x, outer_y, radius}, 0.6f * radius, 16);
  mesh->Append(Tinted(std::move(tyre), kTyre[0], kTyre[1], kTyre[2]));
  mesh->Append(Tinted(std::move(rim), kRim[0], kRim[1], kRim[2]));
}

// A dark band of glass just proud of a cabin between heights a and b.
void AddWindows(TriangleMesh* mesh, const Frustum& cabin, float a, float b) {
  mesh->Append(Tinted(cabin.Section(a, b, 0.012f).Mesh(), 30, 38, 48));
}

// One car shape: a body box between two heights over the full length and
// width, a cabin frustum on it with its window band, optionally a pickup's bed
// walls behind the cab, and four wheels whose rims are flush with the sides.
struct CarLayout {
  const char* name;
  float length, width;
  float body_z0, body_z1;
  Frustum cabin;  // from body_z1 up to the roof
  float window_z0, window_z1;
  float front_axle_x, rear_axle_x, wheel_radius, tyre_width;
  bool bed = false;  // pickup: an open bed from the rear to the cab
};

const std::vector<CarLayout>& CarLayouts() {
  // Sizes of common models: a mid-size saloon, a compact hatchback, a mid-size
  // SUV, a crew-cab pickup, a high-roof panel van (metres).
  static const std::vector<CarLayout> layouts = {
      {"sedan",
       4.6f,
       1.8f,
       0.30f,
       0.88f,
       {{1.25f, 0.84f}, {0.78f, 0.72f}, -0.15f, -0.30f, 0.88f, 1.45f},
       0.93f,
       1.33f,
       1.40f,
       -1.35f,
       0.32f,
       0.22f},
      {"hatchback",
       4.0f,
       1.75f,
       0.30f,
       0.90f,
       {{1.35f, 0.82f}, {0.95f, 0.70f}, -0.55f, -0.80f, 0.90f, 1.50f},
       0.95f,
       1.38f,
       1.30f,
       -1.25f,
       0.31f,
       0.20f},
      {"suv",
       4.7f,
       1.9f,
       0.40f,
       1.10f,
       {{1.75f, 0.88f}, {1.50f, 0.80f}, -0.45f, -0.65f, 1.10f, 1.75f},
       1.15f,
       1.62f,
       1.42f,
       -1.42f,
       0.38f,
       0.25f},
      {"pickup",
       5.3f,
       1.9f,
       0.42f,
       1.05f,
       {{0.90f, 0.90f}, {0.70f, 0.85f}, 0.75f, 0.60f, 1.05f, 1.85f},
       1.12f,
       1.72f,
       1.70f,
       -1.60f,
       0.40f,
       0.26f,
       true},
      {"van",
       5.0f,
       2.0f,
       0.36f,
       1.15f,
       {{2.28f, 0.98f}, {1.98f, 0.96f}, -0.20f, -0.50f, 1.15f, 2.10f},
       1.25f,
       1.85f,
       1.75f,
       -1.70f,
       0.35f,
       0.23f},
  };
  return layouts;
}

TriangleMesh CarOfLayout(const CarLayout& car) {
  TriangleMesh mesh;
  AddBox(&mesh,
         {car.length, car.width, car.body_z1 - car.body_z0},
         {0, 0, 0.5f * (car.body_z0 + car.body_z1)});
  mesh.Append(car.cabin.Mesh());
  AddWindows(&mesh, car.cabin, car.window_z0, car.window_z1);
  if (car.bed) {  // side walls and a tailgate, 8 cm thick, 45 cm high, from the rear to the cab
    const float wall = 0.08f, high = 0.45f;
    const float rear = -car.length / 2;
    const float cab_back = car.cabin.bottom_x - car.cabin.bottom.x();
    const float z = car.body_z1 + high / 2;
    for (float y : {-1.f, 1.f})
      AddBox(&mesh,
             {cab_back - rear, wall, high},
             {0.5f * (rear + cab_back), y * (car.width - wall) / 2, z});
    AddBox(&mesh, {wall, car.width, high}, {rear + wall / 2, 0, z});
  }
  for (float x : {car.front_axle_x, car.rear_axle_x})
    for (float y : {-car.width / 2, car.width / 2})
      AddWheel(&mesh, x, y, car.wheel_radius, car.tyre_width);
  return mesh;
}

}  // namespace

const std::vector<CarShape>& CarShapes() {
  // Each shape's size is its mesh's bounds, so that the box drawn at that size
  // is the mesh undistorted.
  static const std::vector<CarShape> shapes = [] {
    std::vector<CarShape> out;
    for (const CarLayout& layout : CarLayouts()) {
      const TriangleMesh mesh = CarOfLayout(layout);
      Eigen::Vector3f lo = mesh.positions.front(), hi = lo;
      for (const Eigen::Vector3f& p : mesh.positions) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
      }
      out.push_back({layout.name, (hi - lo).cast<double>()});
    }
    return out;
  }();
  return shapes;
}

size_t CarShapeOfKey(uint64_t key) {
  constexpr uint64_t kShapeField = 0x636172;  // "car"
  return std::min(CarShapes().size() - 1,
                  static_cast<size_t>(Uniform01(key, kShapeField, 0, 0) *
                                      static_cast<double>(CarShapes().size())));
}

size_t CarShapeNearest(const Eigen::Vector3d& extent) {
  // Proportions only: log(l/w) and log(l/h), so that a car scaled as a whole
  // keeps its shape.
  auto proportions = [](const Eigen::Vector3d& e) {
    return Eigen::Vector2d(std::log(e.x() / e.y()), std::log(e.x() / e.z()));
  };
  const Eigen::Vector2d wanted = proportions(extent);
  size_t best = 0;
  double best_distance = INFINITY;
  for (size_t i = 0; i < CarShapes().size(); ++i) {
    const double d = (proportions(CarShapes()[i].size) - wanted).squaredNorm();
    if (d < best_distance) best = i, best_distance = d;
  }
  return best;
}

TriangleMesh CarMesh(size_t shape) { return CarOfLayout(CarLayouts().at(shape)); }

const std::vector<std::pair<std::string, double>>& CarPaintPalette() {
  // Shares of new cars' colours worldwide (Axalta's global automotive colour
  // popularity report 2022, rounded): white 35 %, black 19 %, grey 17 %,
  // silver 10 %, blue 8 %, red 7 %, beige/brown 2 %, green 2 %.
  static const std::vector<std::pair<std::string, double>> palette = {{"car_white", 0.35},
                                                                      {"car_black", 0.19},
                                                                      {"car_grey", 0.17},
                                                                      {"car_silver", 0.10},
                                                                      {"car_blue", 0.08},
                                                                      {"car_red", 0.07},
                                                                      {"car_beige", 0.02},
                                                                      {"car_green", 0.02}};
  return palette;
}

const std::string& CarPaint(uint64_t seed) {
  constexpr uint64_t kPaintField = 0x7061696e74;  // "paint"
  const double u = Uniform01(seed, kPaintField, 0, 0);
  double cumulative = 0;
  for (const auto& [material, share] : CarPaintPalette()) {
    cumulative += share;
    if (u < cumulative) return material;
  }
  return CarPaintPalette().back().first;
}

TriangleMesh TruckMesh() {
  TriangleMesh mesh;
  AddBox(&mesh, {7.6f, 1.1f, 0.35f}, {0, 0, 0.9f});        // chassis
  AddBox(&mesh, {5.6f, 2.5f, 2.15f}, {-1.3f, 0, 2.125f});  // cargo box above the wheels
  const Frustum cab{{1.0f, 1.2f}, {0.8f, 1.15f}, 2.9f, 2.75f, 1.0f, 3.0f};
  mesh.Append(cab.Mesh());
  mesh.Append(Tinted(cab.Section(2.1f, 2.8f, 0.015f).Mesh(), 30, 38, 48));
  for (float x : {-3.0f, -1.9f, 2.7f})
    for (float y : {-1.25f, 1.25f}) AddWheel(&mesh, x, y, 0.5f, 0.56f);
  return mesh;
}

TriangleMesh HumanMesh(uint64_t seed) {
  Uniform uniform(HashCombine(seed, 0x68756d616eull));
  // A walking pose: the figure faces +y (its 0.5 m shoulder width along x);
  // legs and arms swing in opposition about the hips and shoulders in the
  // y-z plane, elbows and knees bend. Seeded: every person walks their own.
  const float swing = static_cast<float>(uniform.In(-0.25, 0.25));  // radians
  const float elbow = static_cast<float>(uniform.In(0.1, 0.5));
  const float knee = static_cast<float>(uniform.In(0.0, 0.3));
  auto along = [](float angle) {  // a unit vector hanging down, rotated about x
    return Eigen::Vector3f(0, std::sin(angle), -std::cos(angle));
  };
  TriangleMesh clothes, skin;
  // Legs: hips at z = 0.92, thigh 0.44, shin 0.43, feet on z = 0.
  for (int side : {-1, 1}) {
    const float leg_swing = side * swing * 0.8f;
    const Eigen::Vector3f hip(side * 0.1f, 0, 0.92f);
    const Eigen::Vector3f knee_at = hip + 0.44f * along(leg_swing);
    Eigen::Vector3f ankle = knee_at + 0.43f * along(leg_swing - knee);
    AddLimb(&clothes, hip, knee_at, 0.075f);
    AddSphere(&clothes, knee_at, Eigen::Vector3f::Constant(0.14f), 10);
    AddLimb(&clothes, knee_at, ankle, 0.06f);
    ankle.z() = std::max(ankle.z(), 0.05f);
    AddBox(&clothes, {0.1f, 0.24f, 0.08f}, {ankle.x(), ankle.y() + 0.05f, 0.04f});  // foot
  }
  // Pelvis, torso, neck and head.
  AddSphere(&clothes, {0, 0, 0.95f}, {0.34f, 0.22f, 0.22f});
  clothes.Append(Frustum{{0.15f, 0.1f}, {0.19f, 0.1f}, 0, 0, 0.98f, 1.5f}.Mesh());  // torso
  AddLimb(&skin, {0, 0, 1.48f}, {0, 0, 1.58f}, 0.05f);
  AddSphere(&skin, {0, 0.01f, 1.68f}, {0.19f, 0.21f, 0.24f});
  // Arms: shoulders at z = 1.45, upper arm 0.3, forearm 0.27, hands.
  for (int side : {-1, 1}) {
    const float arm_swing = -side * swing;
    const Eigen::Vector3f shoulder(side * 0.2f, 0, 1.45f);
    const Eigen::Vector3f elbow_at = shoulder + 0.3f * along(arm_swing);
    const Eigen::Vector3f wrist = elbow_at + 0.27f * along(arm_swing + elbow);
    AddSphere(&clothes, shoulder, Eigen::Vector3f::Constant(0.11f), 10);
    AddLimb(&clothes, shoulder, elbow_at, 0.045f);
    AddLimb(&clothes, elbow_at, wrist, 0.038f);
    AddSphere(&skin, wrist + 0.05f * along(arm_swing + elbow), {0.06f, 0.08f, 0.11f}, 8);
  }
  TriangleMesh mesh = std::move(clothes);
  mesh.Append(Tinted(std::move(skin), 198, 150, 120));
  return mesh;
}

TriangleMesh TreeMesh(uint64_t seed) {
  // A bracketed L-system (Lindenmayer; Prusinkiewicz & Lindenmayer 1990):
  //   axiom  F F X
  //   X ->   F [ & X ] / [ & X ] / [ & X ]
  // F draws a segment, [ ] push and pop the turtle, & pitches the heading
  // down by the branching angle, / rolls by about 120 degrees; X is a bud
  // (foliage where the derivation stops). Seeded jitter of the angles and
  // lengths makes each tree its own.
  std::string word = "FFX";
  for (int i = 0; i < 4; ++i) {
    std::string next;
    for (char c : word) next += c == 'X' ? std::string("F[&X]/[&X]/[&X]") : std::string(1, c);
    word = std::move(next);
  }
  Uniform uniform(HashCombine(seed, 0x74726565ull));
  const double branch_angle = uniform.In(0.45, 0.65);
  struct Turtle {
    Eigen::Vector3f position;
    Eigen::Matrix3f frame;  // columns: heading (up the branch), left, up
    float length, radius;
  };
  Turtle turtle{Eigen::Vector3f::Zero(), Eigen::Matrix3f::Identity(), 1.1f, 0.16f};
  // Heading along +z: frame columns (heading, x1, x2) = (z, x, y).
  turtle.frame << 0, 1, 0, 0, 0, 1, 1, 0, 0;
  std::vector<Turtle> stack;
  TriangleMesh wood, crown;
  for (char c : word) {
    switch (c) {
      case 'F': {
        const Eigen::Vector3f end = turtle.position + turtle.length * turtle.frame.col(0);
        AddLimb(&wood, turtle.position, end, turtle.radius, 8);
        turtle.position = end;
        turtle.length *= 0.86f;
        turtle.radius *= 0.8f;
        break;
      }
      case '[':
        stack.push_back(turtle);
        turtle.length *= static_cast<float>(uniform.In(0.75, 0.95));
        turtle.radius *= 0.65f;
        break;
      case ']':
        turtle = stack.back();
        stack.pop_back();
        break;
      case '&': {  // pitch about the turtle's first side axis
        const float a = static_cast<float>(branch_angle + uniform.In(-0.1, 0.1));
        turtle.frame = turtle.frame * Eigen::AngleAxisf(a, Eigen::Vector3f::UnitY()).matrix();
        break;
      }
      case '/': {  // roll about the heading
        const float a = static_cast<float>(2.09 + uniform.In(-0.3, 0.3));
        turtle.frame = turtle.frame * Eigen::AngleAxisf(a, Eigen::Vector3f::UnitX()).matrix();
        break;
      }
      case 'X': {  // a bud left at the end: a clump of leaves
        const float r = static_cast<float>(uniform.In(0.55, 0.8));
        TriangleMesh clump = MakeSphereMesh(10, 6);
        const Perlin noise(HashCombine(seed, crown.positions.size()));
        for (Eigen::Vector3f& p : clump.positions)
          p *= static_cast<float>(1 + 0.3 * noise.Fbm(3 * p.x(), 3 * p.y(), 3 * p.z(), 3));
        crown.Append(clump, Eigen::Matrix3f::Identity() * 2 * r, turtle.position);
        break;
      }
      default:
        break;
    }
  }
  TriangleMesh mesh = std::move(crown);  // foliage: the material's albedo
  mesh.Append(Tinted(std::move(wood), 92, 70, 50));
  return mesh;
}

TriangleMesh RockMesh(uint64_t seed) {
  TriangleMesh mesh = MakeIcosphereMesh(3);
  const Perlin noise(seed);
  Uniform uniform(HashCombine(seed, 0x726f636bull));
  const double frequency = uniform.In(1.5, 2.5);
  for (Eigen::Vector3f& p : mesh.positions) {
    const double n =
        noise.Fbm(p.x() * frequency + 11.3, p.y() * frequency + 7.1, p.z() * frequency + 3.7, 4);
    p *= static_cast<float>(1 + 0.45 * n);
    // A flat base: the rock sits on the ground rather than on a point.
    p.z() = std::max(p.z(), -0.3f);
  }
  return mesh;
}

TriangleMesh CrateMesh() {
  TriangleMesh mesh;
  AddBox(&mesh, {0.96f, 0.76f, 0.76f}, Eigen::Vector3f::Zero());
  // Battens along every edge, 4 cm wide, 2 cm proud.
  const Eigen::Vector3f size(1.0f, 0.8f, 0.8f);
  const float w = 0.04f;
  for (int axis = 0; axis < 3; ++axis) {
    const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
    for (int s1 : {-1, 1})
      for (int s2 : {-1, 1}) {
        Eigen::Vector3f box = Eigen::Vector3f::Constant(w);
        box[axis] = size[axis];
        Eigen::Vector3f centre = Eigen::Vector3f::Zero();
        centre[a1] = s1 * (size[a1] - w) / 2;
        centre[a2] = s2 * (size[a2] - w) / 2;
        AddBox(&mesh, box, centre);
      }
  }
  return mesh;
}

TriangleMesh BarrelMesh() {
  TriangleMesh mesh =
      MakeLatheMesh(24, 8, [](double t) { return 0.44 + 0.06 * std::sin(M_PI * t); });
  // Two rolling hoops, slightly proud of the staves.
  for (float z : {-0.22f, 0.22f})
    mesh.Append(MakeTorusMesh(24, 6, 0.04), Eigen::Matrix3f::Identity() * 0.48f, {0, 0, z});
  return mesh;
}

}  // namespace lsds::gen

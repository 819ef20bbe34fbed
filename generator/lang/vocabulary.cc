#include "generator/lang/vocabulary.h"

#include <cmath>
#include <cstdlib>
#include <limits>
#include <map>
#include <stdexcept>

#include "libs/util/strings.h"

namespace lsds {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

using T = ValueType;

Range AtLeast(double lo, std::string note = "") { return Range{lo, kInf, false, false, note}; }
Range Above(double lo) { return Range{lo, kInf, true, false, ""}; }
Range Within(double lo, double hi, std::string note = "") {
  return Range{lo, hi, false, false, note};
}
Range WholeWithin(double lo, double hi) { return Range{lo, hi, false, true, ""}; }

// One row: name, aliases, type, range, unit, doc, example.
KeySpec Key(std::string name,
            std::vector<std::string> aliases,
            ValueType type,
            std::optional<Range> range,
            std::string unit,
            std::string doc,
            std::string example = "") {
  KeySpec k;
  k.name = std::move(name);
  k.aliases = std::move(aliases);
  k.type = type;
  k.range = std::move(range);
  k.unit = std::move(unit);
  k.doc = std::move(doc);
  k.example = std::move(example);
  return k;
}
KeySpec Block(KeySpec k, std::string block) {
  k.block = std::move(block);
  return k;
}
KeySpec NotInChange(KeySpec k) {
  k.in_change = false;
  return k;
}

std::vector<KindSpec> BuildVocabulary() {
  std::vector<KindSpec> v;
  // ---- LSCENE (docs/languages.md, Table 1 and Table 2) ----
  v.push_back(KindSpec{
      "skybox",
      "LSCENE",
      {"sky"},
      "S",
      "skybox",
      "",
      "`S = skybox{color=white,clouds:{type={cumulus:0.5,nimbostratus:0.5},density=[0.1,0.2]}}`, "
      "`S = skybox{color:blue,luminance:[5000,8000]}`",
      true,
      {Key("color",
           {},
           T::kColor,
           {},
           "",
           "name: white black gray grey blue red green orange yellow, or `[r,g,b]` in 0-1 or "
           "0-255"),
       Block(Key("clouds", {}, T::kBlock, {}, "", "`{type, density}`: Cloud, Density"), "clouds"),
       Key("cloud_type", {}, T::kName, {}, "", "none, cumulus, nimbostratus, cirrus, stratus"),
       Key("cloud_density", {}, T::kNumber, Within(0, 1), "", "the cloud cover"),
       Key("intensity",
           {},
           T::kNumber,
           AtLeast(0),
           "",
           "Intensity: a unitless scale of the colour, see \"Light units\"; not with `luminance`"),
       Key("luminance",
           {},
           T::kNumber,
           AtLeast(0),
           "cd/m^2",
           "zenith luminance, cd/m^2, default 7000")}});
  v.push_back(KindSpec{
      "light",
      "LSCENE",
      {"directional_light", "sun"},
      "DL",
      "light",
      "",
      "`DL = light{elevation:[20,70],azimuth:[0,360],intensity:100000}`, "
      "`DL = light{date:\"2026-06-21\",time:\"08:00\",utc_offset:2}`",
      true,
      {Key("elevation", {}, T::kNumber, Within(-90, 90), "degrees", "deg above horizon"),
       Key("azimuth", {}, T::kNumber, {}, "degrees", "deg from north, clockwise"),
       Key("intensity",
           {},
           T::kNumber,
           AtLeast(0),
           "",
           "lux, the paper's unit; below 100 the legacy unitless scale, see \"Light units\"; "
           "not with `illuminance`"),
       Key("illuminance", {}, T::kNumber, AtLeast(0), "lux", "lux, always; default 100000"),
       Key("date",
           {},
           T::kDate,
           {},
           "",
           "`\"YYYY-MM-DD\"`: the sun by date, time and UTC offset at the georeference, see "
           "\"Time of day and place\""),
       Key("time", {}, T::kTime, {}, "", "local `\"HH:MM[:SS]\"`"),
       Key("utc_offset", {}, T::kNumber, Within(-14, 14), "hours", "hours")}});
  v.push_back(KindSpec{
      "atmosphere",
      "LSCENE",
      {},
      "A",
      "atmosphere",
      "",
      "`A = atmosphere{density:0.1}` (1 km visibility), `A = atmosphere{visibility:[2000,8000]}`",
      true,
      {Key("fog",
           {"fog_density"},
           T::kNumber,
           Within(0,
                  0.3912,
                  "fog is an extinction per metre (0.3912 /m: a visibility of 10 m); or give "
                  "density (a fraction) or visibility (metres)"),
           "/m",
           "extinction per metre; give one of fog, density, visibility"),
       Key("density",
           {},
           T::kNumber,
           Within(0, 1, "density is a fraction (1: a fog of 100 m visibility); write 10 % as 0.1"),
           "",
           "the paper's fraction of the range from clear air to a fog of 100 m visibility: "
           "extinction = density x 0.03912 /m"),
       Key("visibility",
           {},
           T::kNumber,
           AtLeast(10, "visibility is the meteorological visibility in metres"),
           "m",
           "meteorological visibility in metres: extinction = 3.912 / visibility, Koschmieder's "
           "2 % contrast; see \"Atmosphere\"")}});
  v.push_back(KindSpec{"skylight",
                       "LSCENE",
                       {},
                       "SL",
                       "skylight",
                       "",
                       "`SL = skylight{intensity:0.3}`",
                       true,
                       {Key("intensity",
                            {},
                            T::kNumber,
                            AtLeast(0),
                            "",
                            "ambient: unitless, times the sky's mean luminance; default 0.3")}});
  v.push_back(KindSpec{
      "terrain",
      "LSCENE",
      {},
      "W",
      "terrain",
      "",
      "`W = terrain{size=[201,201],height:{Perlin:0.2},material:grassy}`",
      true,
      {NotInChange(Key("size", {}, T::kVector2, Above(0), "m", "`[x,y]`, metres")),
       NotInChange(Block(Key("height",
                             {},
                             T::kBlock,
                             {},
                             "",
                             "`{Perlin: amplitude}` or `{perlin:{amplitude, frequency}}` (Perlin)"),
                         "terrain_height")),
       NotInChange(Block(Key("perlin",
                             {},
                             T::kNumberOrBlock,
                             {},
                             "",
                             "the Perlin amplitude (m), or `{amplitude, frequency}`"),
                         "perlin")),
       NotInChange(
           Key("frequency", {}, T::kNumber, AtLeast(0), "cycles/m", "cycles/m, default 0.05")),
       Key("material", {}, T::kName, {}, "", "a name (or choice) recorded for the renderer"),
       NotInChange(Key("seed",
                       {},
                       T::kWhole,
                       WholeWithin(0, 9007199254740992.0),
                       "",
                       "Perlin seed; default derived from `--seed`"))}});
  v.push_back(KindSpec{
      "object",
      "LSCENE",
      {},
      "O",
      "object",
      "see \"Object keys (Table 2)\" below",
      "`O1 = object{class:{A:0.5,B:0.5},position:{ON:W}}`",
      true,
      {Key("class",
           {},
           T::kClass,
           {},
           "",
           "Class: a built-in (`cube sphere cylinder cone barrel tire jerrycan watercan crate rock "
           "bush tree person car truck`, each also in its plural or other spelling, below; sizes "
           "and shapes: docs/generator.md \"Built-in classes\"), a mesh file (`.obj .ply .gltf "
           ".glb`, relative to the scene file), a `classes` alias, or assets of the scene's asset "
           "library by name, tags or pattern (\"Asset library\"); or a choice of them",
           "`class:{bush:0.2,rocks:0.8}`, `class:{tags:[desert,rock]}`, "
           "`class:{\"clutter/.*\\\\.obj\":1}`"),
       Key("rotation",
           {},
           T::kVector3,
           {},
           "degrees",
           "Rotation: roll, pitch, yaw in degrees about x, y, z; `R = Rz(yaw) Ry(pitch) Rx(roll)`",
           "`rotation:{range:[0,0,0],[360,360,360]}`"),
       Block(Key("position",
                 {},
                 T::kBlock,
                 {},
                 "",
                 "Position (Algorithm 1) with constraints `ON`, `IN`, `AROUND`, `within` and the "
                 "relations `NEAR`, `BEHIND`, `IN FRONT OF`, `FACING` in order",
                 "`position:{ON:W,AROUND:O1}`, `position:{ON:W,NEAR:{T:8},FACING:T}`"),
             "position"),
       Key("extent",
           {},
           T::kVector3,
           Above(0),
           "m",
           "Extent: full box size in metres (default: the class's size; a mesh keeps its native "
           "size, see `unit`)",
           "`extent:[20,20,1]`"),
       Key("scale",
           {},
           T::kScale,
           Above(0),
           "",
           "Scale: a scalar (all axes) or per-axis factor on the extent",
           "`scale:[1.0,1.5]`, `scale:[[0.3,0.3,0.3],[2.5,2,1.5]]`"),
       Key("visible",
           {"visibility"},
           T::kBool,
           {},
           "",
           "Visible: false = an invisible helper (placement zone), placed but not rendered",
           "`visibility:false`"),
       Key("overlap",
           {},
           T::kBool,
           {},
           "",
           "Overlap: true allows this object to overlap others",
           "`overlap:true`"),
       Key("on_overlap",
           {},
           T::kName,
           {},
           "",
           "what to do when no overlap-free place is found after `retries` (default 100) draws: "
           "`move` (default: report an error), `delete` (drop the copy), `hide` (keep it "
           "invisible), `allow` (keep it overlapping)",
           "`on_overlap:delete,retries:20`"),
       Key("retries",
           {},
           T::kWhole,
           WholeWithin(0, 100000),
           "",
           "draws of a place before `on_overlap` applies (default 100)",
           "`retries:20`"),
       Key("separation",
           {},
           T::kNumber,
           Within(0, 10000),
           "m",
           "a placement requirement: metres kept free around the object - no other visible "
           "object's box may enter its box grown by this much on every side (the larger "
           "separation of two objects counts; the objects it stands on or is in excepted). "
           "Enforced by the overlap test of step 4 (same `retries` and `on_overlap`) and by LCAP "
           "re-scatters; needs `overlap:false` (the default). For UAV scenes: vehicles parked "
           "apart, targets that do not touch clutter, so that their boxes and masks stay separate",
           "`separation:2.5`"),
       Key("material",
           {},
           T::kName,
           {},
           "",
           "Material: a name (or choice) recorded for the renderer",
           "`material:{rust:0.5,paint:0.5}`"),
       Key("bound",
           {},
           T::kReference,
           {},
           "",
           "Bound: the extent of (the first copy of) another object",
           "`bound:O1`"),
       Key("target",
           {},
           T::kBool,
           {},
           "",
           "whether the object gets truth entries (default: visible, and listed in the LCAP "
           "`targets` if there are any)",
           "`target:false`"),
       Key("count",
           {},
           T::kCount,
           {},
           "",
           "the number of copies (overrides the start rule)",
           "`count:[10,20]`"),
       Key("unit",
           {},
           T::kName,
           {},
           "",
           "the length unit of a mesh file: `m` (default; glTF's own), `cm`, `mm`, `in`, `ft`. "
           "glTF/GLB are y-up by their specification and turned z-up; OBJ/PLY are read as z-up",
           "`unit:cm`")}});
  v.push_back(KindSpec{"classes",
                       "LSCENE",
                       {},
                       "",
                       "classes",
                       "`NAME: builtin-or-mesh` aliases (user class names like the paper's A, B)",
                       "`K = classes{A:jerrycan,B:\"meshes/b.obj\"}`",
                       false,
                       {}});
  v.push_back(KindSpec{
      "asset_library",
      "LSCENE",
      {"assets"},
      "",
      "asset library",
      "",
      "`L = asset_library{path:\"assets\"}`",
      true,
      {Key("path",
           {},
           T::kName,
           {},
           "",
           "a folder of meshes with a manifest, relative to the scene file (one per scene); see "
           "\"Asset library\"")}});
  v.push_back(KindSpec{
      "georeference",
      "LSCENE",
      {"georef", "geo"},
      "",
      "georeference",
      "",
      "`G = georeference{latitude:47.3769,longitude:8.5417,altitude:408}`",
      true,
      {Key("latitude", {}, T::kNumber, Within(-90, 90), "degrees", "WGS84, degrees"),
       Key("longitude", {}, T::kNumber, Within(-180, 180), "degrees", "WGS84, degrees"),
       Key("altitude",
           {},
           T::kNumber,
           {},
           "m",
           "of the world origin, m above mean sea level: the world frame is local ENU (x east, "
           "y north, z up) at that point; see \"Time of day and place\"")}});
  // ---- LCAP (docs/languages.md, Table 3) ----
  v.push_back(KindSpec{
      "camera",
      "LCAP",
      {},
      "CO",
      "camera",
      "",
      "`CO = camera{csettings{fov:30,res:[2048,2048]},targets:[O1:5],"
      "PPMaterial:[EdgeBlur,CartoonStyle]}`",
      true,
      {Block(Key("csettings",
                 {"camera_settings", "settings"},
                 T::kBlock,
                 {},
                 "",
                 "Camera Settings, see \"Camera settings\""),
             "camera_settings"),
       Key("targets",
           {},
           T::kList,
           {},
           "",
           "Target `[O1:5, O2]` (label ids optional, see \"Class names\")"),
       Key("PPMaterial",
           {"post_process"},
           T::kList,
           {},
           "",
           "PP Material names, recorded in the plan and applied by `lsds generate` to the RGB "
           "only, in order ([generator.md](generator.md#post-process-materials): EdgeBlur/Defocus, "
           "MotionBlur, SensorNoise, Vignetting, JpegCompression, CartoonStyle; other names are "
           "recorded with a warning and not applied)"),
       Block(Key("capture",
                 {"capture_settings"},
                 T::kBlock,
                 {},
                 "",
                 "Capture Settings `{layers:[...], folder:...}`, see \"Capture settings\""),
             "capture_settings"),
       Key("rig", {}, T::kBlock, {}, "", "several cameras on the platform, see \"Camera rigs\"")}});
  v.push_back(KindSpec{
      "path",
      "LCAP",
      {"create_path"},
      "P",
      "path",
      "exactly one generator, see \"Path generators\"",
      "`P1 = path{create hemi:{...}}`",
      true,
      {Block(
           Key("create_hemi",
               {"hemi"},
               T::kBlock,
               {},
               "",
               "radius-major, then elevation, then azimuth. The camera sits at `center + r (cos e "
               "cos a, cos e sin a, sin e)` looking at the centre. `create hemi:{cam "
               "radius:[10,20,5],obj angle:[0,360,4],cam angle:[45,45,1]}` = 20 frames"),
           "create_hemi"),
       Block(Key("grid",
                 {"increment_points", "increment_point"},
                 T::kBlock,
                 {},
                 "",
                 "serpentine rows (lawnmower), "
                 "`grid:{x:[-60,60,7],y:[-60,60,7],altitude:40,perturb:[1.5,1.5,0.5]}` = 49; by "
                 "`start`, `step`, `count`: nx ny nz"),
             "grid"),
       Block(Key("random",
                 {"random_poses"},
                 T::kBlock,
                 {},
                 "",
                 "`random:{count:50,altitude:[15,60],off_nadir:[0,40]}`"),
             "random"),
       Block(Key("waypoints",
                 {},
                 T::kAny,
                 {},
                 "",
                 "`waypoints:[[0,-50,30,0,-30,0],{position:[50,0,25],look_at:WALKER}]`, "
                 "`waypoints:{points:[[0,0,40],[30,0,40]],speed:10,interpolation:spline}`"),
             "flight"),
       Block(
           Key("create_point",
               {"point"},
               T::kBlock,
               {},
               "",
               "`point:{position:[[-5,-5,20],[5,5,30]],rotation:[0,[-90,-60],[0,360]],count:10}`"),
           "create_point")}});
  v.push_back(KindSpec{"collection",
                       "LCAP",
                       {},
                       "CL",
                       "collection",
                       "Create Set: camera moves and scene changes, below",
                       "`CL1 = collection{CO:{move:[P1:3]}}`",
                       false,
                       {}});
  v.push_back(KindSpec{"scene_change",
                       "LCAP",
                       {"scene_change_set", "set"},
                       "SCS",
                       "scene change",
                       "Scene Change: named change blocks per object, applied from a collection",
                       "`SCS1 = scene_change{O1:{material:MetalGold}}`",
                       false,
                       {}});
  v.push_back(KindSpec{"require",
                       "LCAP",
                       {"requirement"},
                       "",
                       "requirement",
                       "per-frame bounds on how a target (or the frame) is seen, hard or soft; see "
                       "\"Requirements and quotas\"",
                       "`REQ = require{target:T,occlusion:[0.4,0.6]}`",
                       false,
                       {}});
  v.push_back(KindSpec{"quota",
                       "LCAP",
                       {},
                       "",
                       "quota",
                       "a target distribution of a quantity over the collection; see "
                       "\"Requirements and quotas\"",
                       "`Q = quota{target:T,quantity:visibility,bins:[0,0.5,1]}`",
                       false,
                       {}});
  // ---- nested blocks ----
  v.push_back(KindSpec{"clouds",
                       "",
                       {},
                       "",
                       "clouds",
                       "",
                       "",
                       true,
                       {Key("type", {}, T::kName, {}, "", "Cloud: the cloud type, as `cloud_type`"),
                        Key("density",
                            {},
                            T::kNumber,
                            Within(0, 1),
                            "",
                            "Density: the cloud cover, as `cloud_density`")}});
  v.push_back(KindSpec{
      "terrain_height",
      "",
      {},
      "",
      "terrain height",
      "",
      "",
      true,
      {Block(Key("perlin", {}, T::kNumberOrBlock, {}, "", "as the terrain's `perlin`"), "perlin"),
       Key("frequency", {}, T::kNumber, AtLeast(0), "cycles/m", "as the terrain's `frequency`")}});
  v.push_back(KindSpec{"perlin",
                       "",
                       {},
                       "",
                       "Perlin",
                       "",
                       "",
                       true,
                       {Key("amplitude", {}, T::kNumber, AtLeast(0), "m", "metres"),
                        Key("frequency", {}, T::kNumber, AtLeast(0), "cycles/m", "cycles/m")}});
  v.push_back(
      KindSpec{"position",
               "",
               {},
               "",
               "position",
               "",
               "",
               true,
               {Key("ON", {}, T::kReference, {}, "", "stand on the terrain or an object's top"),
                Key("IN", {}, T::kReference, {}, "", "inside an object's box"),
                Key("AROUND", {}, T::kAny, {}, "", "around an object (`{X: margin}` optional)"),
                Key("within", {}, T::kVector3, {}, "m", "a box `[[x0,y0,z0],[x1,y1,z1]]`"),
                Key("NEAR", {}, T::kAny, {}, "m", "near an object, `{X: distance}` optional"),
                Key("BEHIND", {}, T::kAny, {}, "m", "behind an object"),
                Key("in_front_of", {}, T::kAny, {}, "m", "in front of an object"),
                Key("FACING", {}, T::kAny, {}, "", "turned towards an object or a point"),
                Key("visible_from", {}, T::kAny, {}, "", "seen from an object or a point")}});
  KindSpec hemi{"create_hemi",
                "",
                {},
                "",
                "create hemi",
                "",
                "",
                true,
                {Key("cam_radius", {}, T::kAny, {}, "m", "LCAP range `[start, stop, count]`"),
                 Key("obj_angle", {}, T::kAny, {}, "degrees", "azimuth, LCAP range"),
                 Key("cam_angle",
                     {},
                     T::kAny,
                     {},
                     "degrees",
                     "elevation above the target's horizontal plane, LCAP range"),
                 Key("center",
                     {"target"},
                     T::kAny,
                     {},
                     "",
                     "`[x,y,z]` or an object (default: the first camera target, else the "
                     "origin)")}};
  hemi.paper = "Create Hemi";
  v.push_back(hemi);
  KindSpec grid{"grid",
                "",
                {},
                "",
                "grid",
                "",
                "",
                true,
                {Key("x", {}, T::kAny, {}, "m", "LCAP range"),
                 Key("y", {}, T::kAny, {}, "m", "LCAP range"),
                 Key("altitude", {}, T::kAny, {}, "m", "above the terrain, LCAP range"),
                 Key("start",
                     {},
                     T::kVector3,
                     {},
                     "m",
                     "`[x,y,alt]`, with `step` and `count` instead of x, y, altitude"),
                 Key("step", {}, T::kVector3, {}, "m", "`[dx,dy,dz]`"),
                 Key("count", {}, T::kList, {}, "", "`[nx,ny,nz]`"),
                 Key("perturb",
                     {},
                     T::kVector3,
                     {},
                     "m",
                     "`[dx,dy,dz]`: uniform noise in +-d per axis, drawn per frame"),
                 Key("roll", {}, T::kNumber, {}, "degrees", "crisp or interval, per frame"),
                 Key("pitch", {}, T::kNumber, {}, "degrees", "default -90, nadir"),
                 Key("yaw", {}, T::kNumber, {}, "degrees", "crisp or interval, per frame")}};
  grid.paper = "Increment Points, UC3";
  v.push_back(grid);
  KindSpec random{
      "random",
      "",
      {},
      "",
      "random poses",
      "",
      "",
      true,
      {Key("count", {}, T::kCount, {}, "", "the number of frames"),
       Key("x", {}, T::kNumber, {}, "m", "default: the terrain"),
       Key("y", {}, T::kNumber, {}, "m", "default: the terrain"),
       Key("altitude", {}, T::kNumber, {}, "m", "above the terrain (default 50)"),
       Key("off_nadir",
           {},
           T::kNumber,
           Within(0, 90),
           "degrees",
           "deg from straight down, default 0"),
       Key("yaw", {}, T::kNumber, {}, "degrees", "default [0,360]; all drawn per frame")}};
  random.paper = "UC2";
  v.push_back(random);
  v.push_back(KindSpec{
      "flight",
      "",
      {},
      "",
      "waypoints",
      "a list of `[x,y,z]` (nadir), `[x,y,z,roll,pitch,yaw]`, or `{position, attitude:[r,p,y] or "
      "look_at:[x,y,z] or an object}`: one frame per waypoint; or a **smooth flight** "
      "`{points:[...], speed: m/s, interpolation: linear or spline}` (see \"Smooth flights\")",
      "",
      true,
      {Key("points", {}, T::kList, {}, "", "at least two waypoints"),
       Key("speed", {}, T::kNumber, Range{0, 1000, true, false, ""}, "m/s", "m/s"),
       Key("interpolation", {}, T::kName, {}, "", "`linear` (default) or `spline`")}});
  v.push_back(KindSpec{"waypoint",
                       "",
                       {},
                       "",
                       "waypoint",
                       "",
                       "",
                       true,
                       {Key("position", {}, T::kVector3, {}, "m", "`[x,y,z]`"),
                        Key("attitude", {}, T::kVector3, {}, "degrees", "`[roll,pitch,yaw]`"),
                        Key("look_at", {}, T::kAny, {}, "", "`[x,y,z]` or an object")}});
  KindSpec point{
      "create_point",
      "",
      {},
      "",
      "create point",
      "",
      "",
      true,
      {Key("position", {}, T::kVector3, {}, "m", "vector or vector range"),
       Key("rotation", {"attitude"}, T::kVector3, {}, "degrees", "roll, pitch, yaw; default nadir"),
       Key("look_at", {}, T::kAny, {}, "", "instead of `rotation`"),
       Key("count", {}, T::kCount, {}, "", "default 1; drawn per frame")}};
  point.paper = "Create Point";
  v.push_back(point);
  // The blocks of a collection entry (docs/languages.md, "Collections: move, when, after,
  // during", "Objects that move", "Class swaps and re-scatters").
  v.push_back(
      KindSpec{"object_change",
               "",
               {},
               "",
               "object change",
               "",
               "",
               true,
               {Key("material", {}, T::kName, {}, "", "a new material"),
                Key("rotation", {}, T::kVector3, {}, "degrees", "a new rotation"),
                Key("scale", {}, T::kScale, {}, "", "a factor on the extent"),
                Key("extent", {}, T::kVector3, {}, "m", "a new extent"),
                Key("visible", {"visibility"}, T::kBool, {}, "", "shown or hidden"),
                Key("offset", {}, T::kVector3, {}, "m", "a move of the object by [dx,dy,dz]"),
                Key("class", {}, T::kClass, {}, "", "a class swap"),
                Key("rescatter", {}, T::kBool, {}, "", "a new place drawn by Algorithm 1"),
                Key("move", {}, T::kList, {}, "", "a smooth flight the object moves along"),
                Key("heading", {}, T::kName, {}, "", "how a moving object turns")}});
  v.push_back(KindSpec{"timing",
                       "",
                       {},
                       "",
                       "timing",
                       "",
                       "",
                       true,
                       {Key("when", {}, T::kBlock, {}, "", "`{after, during, frame}`"),
                        Key("after", {}, T::kAny, {}, "", "from a path repetition on"),
                        Key("during", {}, T::kAny, {}, "", "during a path repetition"),
                        Key("frame", {}, T::kAny, {}, "", "from a frame on")}});
  v.push_back(KindSpec{
      "camera_settings",
      "",
      {},
      "",
      "camera settings",
      "",
      "",
      true,
      {Key("fov", {}, T::kNumber, {}, "degrees", "horizontal, deg, default 60"),
       Key("res", {"resolution"}, T::kVector2, {}, "px", "`[w,h]` (default 1024 x 1024)"),
       Key("focal_length", {}, T::kNumber, {}, "mm", "mm, with `sensor_width`; overrides fov"),
       Key("sensor_width", {}, T::kNumber, {}, "mm", "mm"),
       Key("fps", {}, T::kNumber, Above(0), "", "frame time step, default 10"),
       Key("clearance",
           {},
           T::kAny,
           {},
           "m",
           "metres in [0, 10000], default 1; `off` opts out; see \"Cameras where a drone can "
           "be\""),
       Key("heights",
           {},
           T::kName,
           {},
           "",
           "`datum` default, or `agl` for waypoint and point z above the terrain"),
       Key("iso", {}, T::kNumber, Above(0), "", "the exposure by `shutter` + `f_number` + `iso`"),
       Key("shutter", {}, T::kNumber, Above(0), "s", "seconds; needs `f_number`"),
       Key("f_number", {}, T::kNumber, Above(0), "", "also `fnumber`"),
       Key("ev100", {}, T::kNumber, Within(-30, 30), "", "the exposure value; not with `shutter`"),
       Key("exposure_compensation",
           {},
           T::kNumber,
           Within(-10, 10),
           "EV",
           "EV; see \"Exposure\"; default: auto exposure")}});
  v.push_back(KindSpec{
      "capture_settings",
      "",
      {},
      "",
      "capture settings",
      "",
      "",
      true,
      {Key("layers",
           {},
           T::kList,
           {},
           "",
           "the layers written (`rgb` always; names from docs/format.md, a misspelt one is a "
           "located error with a suggestion); the generator does no work for a bundle not asked "
           "for, and `lsds validate` checks only the declared layers"),
       Key("folder",
           {"output"},
           T::kName,
           {},
           "",
           "the output folder when `lsds generate` gets no `-o` (relative to the current "
           "directory; `-o` wins). Both keys are recorded in `collection.json` "
           "(`provenance.render.capture_settings`)")}});
  return v;
}

}  // namespace

const char* ValueTypeName(ValueType type) {
  switch (type) {
    case T::kNumber:
      return "number";
    case T::kWhole:
      return "whole number";
    case T::kCount:
      return "count";
    case T::kBool:
      return "bool";
    case T::kName:
      return "name";
    case T::kColor:
      return "colour";
    case T::kVector2:
      return "vector [x, y]";
    case T::kVector3:
      return "vector [x, y, z]";
    case T::kScale:
      return "scale";
    case T::kReference:
      return "symbol";
    case T::kClass:
      return "class";
    case T::kDate:
      return "date";
    case T::kTime:
      return "time";
    case T::kList:
      return "list";
    case T::kBlock:
      return "block";
    case T::kNumberOrBlock:
      return "number or block";
    case T::kAny:
      return "see doc";
  }
  return "";
}

bool Range::Contains(double v) const {
  if (lo_open ? !(v > lo) : !(v >= lo)) return false;
  if (!(v <= hi)) return false;
  return !whole || v == std::floor(v);
}

namespace {
// The shortest text that reads back as `v` (0.3912, not 0.39119999999999999).
std::string Shortest(double v) {
  for (int digits = 6; digits < 17; ++digits) {
    const std::string text = FormatNumber(v, digits);
    if (std::strtod(text.c_str(), nullptr) == v) return text;
  }
  return FormatNumber(v, 17);
}
}  // namespace

std::string Range::Text(bool say_whole) const {
  std::string out = whole && say_whole ? "a whole number " : "";
  if (hi == kInf) return out + (lo_open ? "> " : ">= ") + Shortest(lo);
  return out + "within " + (lo_open ? "(" : "[") + Shortest(lo) + ", " + Shortest(hi) + "]";
}

std::vector<std::string> KeySpec::Spellings() const {
  std::vector<std::string> out = {name};
  out.insert(out.end(), aliases.begin(), aliases.end());
  return out;
}

const KeySpec* KindSpec::Find(const std::string& canonical) const {
  for (const KeySpec& k : keys)
    for (const std::string& s : k.Spellings())
      if (CanonicalKey(s) == canonical) return &k;
  return nullptr;
}

const KeySpec& KindSpec::Key(const std::string& name) const {
  if (const KeySpec* k = Find(CanonicalKey(name))) return *k;
  throw std::out_of_range("no key '" + name + "' in the vocabulary of " + id);
}

std::vector<std::string> KindSpec::Spellings(bool in_change) const {
  std::vector<std::string> out;
  for (const KeySpec& k : keys)
    if (!in_change || k.in_change)
      for (const std::string& s : k.Spellings()) out.push_back(s);
  return out;
}

const std::vector<KindSpec>& Vocabulary() {
  static const std::vector<KindSpec> vocabulary = BuildVocabulary();
  return vocabulary;
}

const KindSpec& KindVocabulary(const std::string& id) {
  for (const KindSpec& k : Vocabulary())
    if (k.id == id) return k;
  throw std::out_of_range("no vocabulary table for '" + id + "'");
}

namespace {
const std::map<std::string, std::string>& KindBySpelling() {
  static const std::map<std::string, std::string> kinds = [] {
    std::map<std::string, std::string> out;
    for (const KindSpec& k : Vocabulary()) {
      if (k.language.empty()) continue;
      out[CanonicalKey(k.id)] = k.id;
      for (const std::string& a : k.aliases) out[CanonicalKey(a)] = k.id;
    }
    return out;
  }();
  return kinds;
}
}  // namespace

std::string KindOfSpelling(const std::string& canonical_spelling) {
  const auto it = KindBySpelling().find(canonical_spelling);
  return it == KindBySpelling().end() ? std::string() : it->second;
}

std::vector<std::string> KindSpellings() {
  std::vector<std::string> out;
  for (const auto& [spelling, kind] : KindBySpelling()) out.push_back(spelling);
  return out;
}

void CheckKeys(const Node& body, const KindSpec& kind, const std::string& what, bool in_change) {
  body.CheckKeys(kind.Spellings(in_change), what);
  // Two spellings of one function ("visible" and "visibility") would leave
  // the reader guessing which one wins.
  std::map<const KeySpec*, std::string> seen;
  for (const auto& [key, node] : body.Members()) {
    const KeySpec* spec = kind.Find(CanonicalKey(key));
    if (!spec) continue;
    const auto [it, fresh] = seen.emplace(spec, key);
    if (!fresh)
      node.FailKey("'" + key + "' and '" + it->second + "' are two spellings of " + spec->name +
                   " in " + what + "; give one");
  }
}

Node FindKey(const Node& body, const KindSpec& kind, const std::string& key) {
  const KeySpec& spec = kind.Key(key);
  for (const std::string& s : spec.Spellings())
    if (const Node n = body.Find(CanonicalKey(s))) return n;
  return Node{body.src, nullptr, body.pointer};
}

double CheckRange(const Node& node, const KeySpec& key, double value) {
  if (key.range && !key.range->Contains(value)) {
    std::string message = key.name + " must be " + key.range->Text();
    if (!key.unit.empty()) message += " " + key.unit;
    message += ", " + std::string(node->is_number() ? "found " : "sampled ") + FormatNumber(value);
    if (!key.range->note.empty()) message += "; " + key.range->note;
    node.Fail(message);
  }
  return value;
}

double SampleInRange(const Node& node, const KeySpec& key, Rng& rng) {
  return CheckRange(node, key, SampleScalar(node, rng));
}

double ReadInRange(const Node& node, const KeySpec& key) {
  return CheckRange(node, key, ReadNumber(node));
}

}  // namespace lsds

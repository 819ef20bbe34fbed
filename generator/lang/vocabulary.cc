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

Range AtLeast(double lo, std::string note = "") {
  return Range{lo, kInf, false, false, std::move(note)};
}
Range Above(double lo) { return Range{lo, kInf, true, false, ""}; }
Range Within(double lo, double hi, std::string note = "") {
  return Range{lo, hi, false, false, std::move(note)};
}
Range WholeWithin(double lo, double hi) { return Range{lo, hi, false, true, ""}; }

// A row of a table: Row("elevation").Is(T::kNumber).Range(Within(-90, 90)).Unit("degrees")
// .Doc("deg above horizon").
struct Row : KeySpec {
  explicit Row(std::string canonical) { name = std::move(canonical); }
  Row& Aliases(std::vector<std::string> spellings) {
    aliases = std::move(spellings);
    return *this;
  }
  Row& Is(ValueType t) {
    type = t;
    return *this;
  }
  Row& Range(lsds::Range r) {
    range = std::move(r);
    return *this;
  }
  Row& Unit(std::string u) {
    unit = std::move(u);
    return *this;
  }
  Row& Doc(std::string d) {
    doc = std::move(d);
    return *this;
  }
  Row& Example(std::string e) {
    example = std::move(e);
    return *this;
  }
  Row& Block(std::string id) {  // the nested table of a kBlock / kNumberOrBlock value
    block = std::move(id);
    return *this;
  }
  Row& Default(nlohmann::json value) {
    default_value = std::move(value);
    return *this;
  }
  Row& DefaultIs(std::string words) {  // a default that depends on the context
    default_text = std::move(words);
    return *this;
  }
  Row& Role(std::string group) {
    role = std::move(group);
    return *this;
  }
  Row& NotInChange() {  // an environment key an LCAP scene change may not call
    in_change = false;
    return *this;
  }
};

// A table: Kind("skybox", "LSCENE").Aliases({"sky"}).Category("S").Keys({...}); a nested
// block has no language. `what` (for messages) defaults to the id with spaces.
struct Kind : KindSpec {
  explicit Kind(std::string kind_id, std::string kind_language = "") {
    id = std::move(kind_id);
    language = std::move(kind_language);
    what = id;
    for (char& c : what)
      if (c == '_') c = ' ';
  }
  Kind& Aliases(std::vector<std::string> spellings) {
    aliases = std::move(spellings);
    return *this;
  }
  Kind& Category(std::string symbol) {
    category = std::move(symbol);
    return *this;
  }
  Kind& What(std::string w) {
    what = std::move(w);
    return *this;
  }
  Kind& Doc(std::string d) {
    doc = std::move(d);
    return *this;
  }
  Kind& Example(std::string e) {
    example = std::move(e);
    return *this;
  }
  Kind& Paper(std::string p) {
    paper = std::move(p);
    return *this;
  }
  Kind& KeysInCode() {  // the kind's own code checks its keys (free names, generators)
    keys_listed = false;
    return *this;
  }
  Kind& Keys(std::vector<KeySpec> rows) {
    keys = std::move(rows);
    return *this;
  }
};

// A declarative table: one entry per LSCENE/LCAP keyword.
// NOLINTNEXTLINE(readability-function-size,readability-function-cognitive-complexity)
std::vector<KindSpec> BuildVocabulary() {
  std::vector<KindSpec> v;
  // ---- LSCENE (docs/languages.md, Table 1 and Table 2) ----
  v.push_back(
      Kind("skybox", "LSCENE")
          .Aliases({"sky"})
          .Category("S")
          .Example("`S = "
                   "skybox{color=white,clouds:{type={cumulus:0.5,nimbostratus:0.5},density=[0.1,0."
                   "2]}}`, `S = skybox{color:blue,luminance:[5000,8000]}`")
          .Keys(
              {Row("color").Is(T::kColor).Doc("name: white black gray grey blue red green orange "
                                              "yellow, or `[r,g,b]` in 0-1 or 0-255"),
               Row("clouds").Is(T::kBlock).Doc("`{type, density}`: Cloud, Density").Block("clouds"),
               Row("cloud_type").Is(T::kName).Doc("none, cumulus, nimbostratus, cirrus, stratus"),
               Row("cloud_density").Is(T::kNumber).Range(Within(0, 1)).Doc("the cloud cover"),
               Row("intensity")
                   .Is(T::kNumber)
                   .Range(AtLeast(0))
                   .Unit("lux")
                   .Doc("Intensity: the sky's illuminance on the ground, lux (a clear sky "
                        "10000-25000), see \"Light units\"; not with `luminance`"),
               Row("luminance")
                   .Is(T::kNumber)
                   .Range(AtLeast(0))
                   .Unit("cd/m^2")
                   .Default(7000)
                   .Doc("zenith luminance, cd/m^2")}));
  v.push_back(
      Kind("light", "LSCENE")
          .Aliases({"directional_light", "sun"})
          .Category("DL")
          .Example("`DL = light{elevation:[20,70],azimuth:[0,360],intensity:100000}`, `DL = "
                   "light{date:\"2026-06-21\",time:\"08:00\",utc_offset:2}`")
          .Keys({Row("elevation")
                     .Is(T::kNumber)
                     .Range(Within(-90, 90))
                     .Unit("degrees")
                     .Default(50)
                     .Doc("deg above horizon"),
                 Row("azimuth")
                     .Is(T::kNumber)
                     .Unit("degrees")
                     .Default(135)
                     .Doc("deg from north, clockwise"),
                 Row("intensity")
                     .Is(T::kNumber)
                     .Range(AtLeast(0))
                     .Unit("lux")
                     .Doc("lux, the paper's unit (a clear noon 100000, dusk 10-400); not with "
                          "`illuminance`"),
                 Row("illuminance")
                     .Is(T::kNumber)
                     .Range(AtLeast(0))
                     .Unit("lux")
                     .Default(100000)
                     .Doc("lux, always"),
                 Row("date").Is(T::kDate).Doc(
                     "`\"YYYY-MM-DD\"`: the sun by date, time and UTC offset at the georeference, "
                     "see \"Time of day and place\""),
                 Row("time").Is(T::kTime).Doc("local `\"HH:MM[:SS]\"`, or an interval "
                                              "`[\"08:00\",\"17:00\"]` drawn uniformly"),
                 Row("utc_offset")
                     .Is(T::kNumber)
                     .Range(Within(-14, 14))
                     .Unit("hours")
                     .Doc("hours")}));
  v.push_back(
      Kind("atmosphere", "LSCENE")
          .Category("A")
          .Example("`A = atmosphere{density:0.1}` (1 km visibility), `A = "
                   "atmosphere{visibility:[2000,8000]}`")
          .Keys({Row("fog")
                     .Aliases({"fog_density"})
                     .Is(T::kNumber)
                     .Range(Within(0,
                                   0.3912,
                                   "fog is an extinction per metre (0.3912 /m: a visibility of 10 "
                                   "m); or give density (a fraction) or visibility (metres)"))
                     .Unit("/m")
                     .Doc("extinction per metre; give one of fog, density, visibility"),
                 Row("density")
                     .Is(T::kNumber)
                     .Range(Within(
                         0,
                         1,
                         "density is a fraction (1: a fog of 100 m visibility); write 10 % as 0.1"))
                     .Doc("the paper's fraction of the range from clear air to a fog of 100 m "
                          "visibility: extinction = density x 0.03912 /m"),
                 Row("visibility")
                     .Is(T::kNumber)
                     .Range(AtLeast(10, "visibility is the meteorological visibility in metres"))
                     .Unit("m")
                     .Doc("meteorological visibility in metres: extinction = 3.912 / visibility, "
                          "Koschmieder's 2 % contrast; see \"Atmosphere\"")}));
  v.push_back(Kind("skylight", "LSCENE")
                  .Category("SL")
                  .Example("`SL = skylight{intensity:0.3}`")
                  .Keys({Row("intensity")
                             .Is(T::kNumber)
                             .Range(AtLeast(0))
                             .Default(0.3)
                             .Doc("ambient: unitless, times the sky's mean luminance")}));
  v.push_back(
      Kind("terrain", "LSCENE")
          .Category("W")
          .Example("`W = terrain{size=[201,201],height:{Perlin:0.2},material:grassy}`")
          .Keys({Row("size")
                     .Is(T::kVector2)
                     .Range(Above(0))
                     .Unit("m")
                     .Doc("`[x,y]`, metres")
                     .NotInChange(),
                 Row("height")
                     .Is(T::kBlock)
                     .Doc("`{Perlin: amplitude}` or `{perlin:{amplitude, frequency}}` (Perlin)")
                     .Block("terrain_height"),
                 Row("perlin")
                     .Is(T::kNumberOrBlock)
                     .Doc("the Perlin amplitude (m), or `{amplitude, frequency}`")
                     .Block("perlin"),
                 Row("frequency")
                     .Is(T::kNumber)
                     .Range(AtLeast(0))
                     .Unit("cycles/m")
                     .Default(0.05)
                     .Doc("cycles/m"),
                 Row("material").Is(T::kName).Doc("a name (or choice) recorded for the renderer"),
                 Row("seed")
                     .Is(T::kWhole)
                     .Range(WholeWithin(0, 9007199254740992.0))
                     .DefaultIs("derived from `--seed`")
                     .Doc("Perlin seed")
                     .NotInChange(),
                 Row("vegetation")
                     .Is(T::kBlock)
                     .Doc("`{density, kind, height}`: ground vegetation scattered on the terrain "
                          "and part of it (its class and instance ids; \"Ground vegetation\")")
                     .Block("vegetation")
                     .NotInChange()}));
  v.push_back(
      Kind("object", "LSCENE")
          .Category("O")
          .Doc("see \"Object keys (Table 2)\" below")
          .Example("`O1 = object{class:{A:0.5,B:0.5},position:{ON:W}}`")
          .Keys(
              {Row("class")
                   .Is(T::kClass)
                   .Doc("Class: a built-in (`cube sphere cylinder cone barrel tire jerrycan "
                        "watercan crate rock bush tree person car truck`, each also in its plural "
                        "or other spelling, below; sizes and shapes: docs/generator.md \"Built-in "
                        "classes\"), a mesh file (`.obj .ply .gltf .glb .fbx .stl .dae .3ds .off`, "
                        "any case, relative to the scene "
                        "file), a `classes` alias, or assets of the scene's asset library by name, "
                        "tags or pattern (\"Asset library\"); or a choice of them")
                   .Example("`class:{bush:0.2,rocks:0.8}`, `class:{tags:[desert,rock]}`, "
                            "`class:{\"clutter/.*\\\\.obj\":1}`"),
               Row("rotation")
                   .Is(T::kVector3)
                   .Unit("degrees")
                   .Doc("Rotation: roll, pitch, yaw in degrees about x, y, z; `R = Rz(yaw) "
                        "Ry(pitch) Rx(roll)`")
                   .Example("`rotation:{range:[0,0,0],[360,360,360]}`"),
               Row("position")
                   .Is(T::kBlock)
                   .Doc("Position (Algorithm 1) with constraints `ON`, `IN`, `AROUND`, `within` "
                        "and the relations `NEAR`, `BEHIND`, `IN FRONT OF`, `FACING` in order")
                   .Example("`position:{ON:W,AROUND:O1}`, `position:{ON:W,NEAR:{T:8},FACING:T}`")
                   .Block("position"),
               Row("extent")
                   .Is(T::kVector3)
                   .Range(Above(0))
                   .Unit("m")
                   .DefaultIs("the class's size; a mesh's native size, see `unit`")
                   .Doc("Extent: full box size in metres")
                   .Example("`extent:[20,20,1]`"),
               Row("scale")
                   .Is(T::kScale)
                   .Range(Above(0))
                   .Doc("Scale: a scalar (all axes) or per-axis factor on the extent")
                   .Example("`scale:[1.0,1.5]`, `scale:[[0.3,0.3,0.3],[2.5,2,1.5]]`"),
               Row("visible")
                   .Aliases({"visibility"})
                   .Is(T::kBool)
                   .Doc("Visible: false = an invisible helper (placement zone), placed but not "
                        "rendered")
                   .Example("`visibility:false`"),
               Row("overlap")
                   .Is(T::kBool)
                   .Doc("Overlap: true allows this object to overlap others")
                   .Example("`overlap:true`"),
               Row("on_overlap")
                   .Is(T::kName)
                   .Doc("what to do when no overlap-free place is found after `retries` (default "
                        "100) draws: `move` (default: report an error), `delete` (drop the copy), "
                        "`hide` (keep it invisible), `allow` (keep it overlapping)")
                   .Example("`on_overlap:delete,retries:20`"),
               Row("retries")
                   .Is(T::kWhole)
                   .Range(WholeWithin(0, 100000))
                   .Default(100)
                   .Doc("draws of a place before `on_overlap` applies")
                   .Example("`retries:20`"),
               Row("separation")
                   .Is(T::kNumber)
                   .Range(Within(0, 10000))
                   .Unit("m")
                   .Doc("a placement requirement: metres kept free around the object - no other "
                        "visible object's box may enter its box grown by this much on every side "
                        "(the larger separation of two objects counts; the objects it stands on or "
                        "is in excepted). Enforced by the overlap test of step 4 (same `retries` "
                        "and `on_overlap`) and by LCAP re-scatters; needs `overlap:false` (the "
                        "default). For UAV scenes: vehicles parked apart, targets that do not "
                        "touch clutter, so that their boxes and masks stay separate")
                   .Example("`separation:2.5`"),
               Row("material")
                   .Is(T::kName)
                   .Doc("Material: a name (or choice) recorded for the renderer")
                   .Example("`material:{rust:0.5,paint:0.5}`"),
               Row("bound")
                   .Is(T::kReference)
                   .Doc("Bound: the extent of (the first copy of) another object")
                   .Example("`bound:O1`"),
               Row("target")
                   .Is(T::kBool)
                   .DefaultIs("visible, and listed in the LCAP `targets` if there are any")
                   .Doc("whether the object gets truth entries")
                   .Example("`target:false`"),
               Row("count")
                   .Is(T::kCount)
                   .Doc("the number of copies (overrides the start rule)")
                   .Example("`count:[10,20]`"),
               Row("occlusion")
                   .Is(T::kAny)
                   .Doc("the allowable occlusion `[min, max]` (a share in [0, 1], the paper's "
                        "section 4.2): each frame of the capture must see the object that much "
                        "hidden, as `require{target:X, occlusion:[min,max]}` (\"Requirements and "
                        "quotas\")")
                   .Example("`occlusion:[0.2,0.5]`"),
               Row("unit")
                   .Is(T::kName)
                   .Doc("the length unit of a mesh file: `m` (default; glTF's own), `cm`, `mm`, "
                        "`in`, `ft`; a mesh over 100 m on a side needs it said. glTF/GLB are y-up "
                        "by their specification and turned z-up; OBJ/PLY are read as z-up")
                   .Example("`unit:cm`")}));
  v.push_back(Kind("classes", "LSCENE")
                  .Doc("`NAME: builtin-or-mesh` aliases (user class names like the paper's A, B)")
                  .Example("`K = classes{A:jerrycan,B:\"meshes/b.obj\"}`")
                  .KeysInCode());
  v.push_back(Kind("blueprint", "LSCENE")
                  .Aliases({"blueprint_class"})
                  .Doc("the paper's Blueprint Class: `NAME:{class, at, rotation, extent, scale, "
                       "material}` members placed together; an object whose class names the "
                       "blueprint places the group (see \"Blueprint classes\")")
                  .Example("`CAMP = blueprint{TENT:{class:crate,extent:[3,2,2]},FIRE:{class:barrel,"
                           "at:[3,1,0]}}`")
                  .KeysInCode());
  v.push_back(
      Kind("blueprint_member")
          .What("blueprint member")
          .Keys({Row("class").Is(T::kClass).Doc("as an object's (not a blueprint)"),
                 Row("at")
                     .Is(T::kVector3)
                     .Unit("m")
                     .Default({0, 0, 0})
                     .Doc("its base centre in the group's frame (z: above the group's base)"),
                 Row("rotation").Is(T::kVector3).Unit("degrees").Doc("in the group's frame"),
                 Row("extent")
                     .Is(T::kVector3)
                     .Unit("m")
                     .DefaultIs("its class's size")
                     .Doc("its size"),
                 Row("scale").Is(T::kScale).Doc("a factor on the size"),
                 Row("material").Is(T::kName).Doc("as an object's")}));
  v.push_back(Kind("asset_library", "LSCENE")
                  .Aliases({"assets"})
                  .Example("`L = asset_library{path:\"assets\"}`")
                  .Keys({Row("path").Is(T::kName).Doc(
                      "a folder of meshes with a manifest, relative to the scene file (one per "
                      "scene); see \"Asset library\"")}));
  v.push_back(
      Kind("georeference", "LSCENE")
          .Aliases({"georef", "geo"})
          .Example("`G = georeference{latitude:47.3769,longitude:8.5417,altitude:408}`")
          .Keys(
              {Row("latitude")
                   .Is(T::kNumber)
                   .Range(Within(-90, 90))
                   .Unit("degrees")
                   .Doc("WGS84, degrees"),
               Row("longitude")
                   .Is(T::kNumber)
                   .Range(Within(-180, 180))
                   .Unit("degrees")
                   .Doc("WGS84, degrees"),
               Row("altitude")
                   .Is(T::kNumber)
                   .Unit("m")
                   .Doc("of the world origin, m above mean sea level: the world frame is local ENU "
                        "(x east, y north, z up) at that point; see \"Time of day and place\""),
               Row("wgs84").Is(T::kList).Doc(
                   "`[latitude, longitude]` or `[latitude, longitude, altitude]` in one key "
                   "(degrees, metres); not with the separate keys")}));
  // ---- LCAP (docs/languages.md, Table 3) ----
  v.push_back(
      Kind("camera", "LCAP")
          .Category("CO")
          .Example("`CO = "
                   "camera{csettings{fov:30,res:[2048,2048]},targets:[O1:5],PPMaterial:[EdgeBlur,"
                   "CartoonStyle]}`")
          .Keys({Row("csettings")
                     .Aliases({"camera_settings", "settings"})
                     .Is(T::kBlock)
                     .Doc("Camera Settings, see \"Camera settings\"")
                     .Block("camera_settings"),
                 Row("targets").Is(T::kList).Doc(
                     "Target `[O1:5, V1:{car:1,truck:2}, O2]` (label ids optional, one per class "
                     "drawn, see \"Class names\")"),
                 Row("PPMaterial")
                     .Aliases({"post_process"})
                     .Is(T::kList)
                     .Doc("PP Material names, recorded in the plan and applied by `lsds generate` "
                          "to the RGB only, in order "
                          "([generator.md](generator.md#post-process-materials): EdgeBlur/Defocus, "
                          "MotionBlur, SensorNoise, Vignetting, JpegCompression, CartoonStyle; "
                          "other names are recorded with a warning and not applied)"),
                 Row("capture")
                     .Aliases({"capture_settings"})
                     .Is(T::kBlock)
                     .Doc("Capture Settings `{layers:[...], folder:...}`, see \"Capture settings\"")
                     .Block("capture_settings"),
                 Row("rig").Is(T::kBlock).Doc(
                     "several cameras on the platform, see \"Camera rigs\"")}));
  v.push_back(
      Kind("path", "LCAP")
          .Aliases({"create_path"})
          .Category("P")
          .Doc("exactly one generator, see \"Path generators\"")
          .Example("`P1 = path{create hemi:{...}}`")
          .Keys({Row("create_hemi")
                     .Aliases({"hemi"})
                     .Is(T::kBlock)
                     .Doc("radius-major, then elevation, then azimuth. The camera sits at `center "
                          "+ r (cos e cos a, cos e sin a, sin e)` looking at the centre. `create "
                          "hemi:{cam radius:[10,20,5],obj angle:[0,360,4],cam angle:[45,45,1]}` = "
                          "20 frames")
                     .Block("create_hemi"),
                 Row("grid")
                     .Aliases({"increment_points", "increment_point"})
                     .Is(T::kBlock)
                     .Doc("serpentine rows (lawnmower), "
                          "`grid:{x:[-60,60,7],y:[-60,60,7],altitude:40,perturb:[1.5,1.5,0.5]}` = "
                          "49; by `start`, `step`, `count`: nx ny nz")
                     .Block("grid"),
                 Row("random")
                     .Aliases({"random_poses"})
                     .Is(T::kBlock)
                     .Doc("`random:{count:50,altitude:[15,60],off_nadir:[0,40]}`")
                     .Block("random"),
                 Row("waypoints")
                     .Is(T::kAny)
                     .Doc("`waypoints:[[0,-50,30,0,-30,0],{position:[50,0,25],look_at:WALKER}]`, "
                          "`waypoints:{points:[[0,0,40],[30,0,40]],speed:10,interpolation:spline}`")
                     .Block("flight"),
                 Row("create_point")
                     .Aliases({"point"})
                     .Is(T::kBlock)
                     .Doc("`point:{position:[[-5,-5,20],[5,5,30]],rotation:[0,[-90,-60],[0,360]],"
                          "count:10}`")
                     .Block("create_point"),
                 Row("create_path")
                     .Is(T::kBlock)
                     .Doc("`create path:{space:[[-50,-50,30],[50,50,60]],points:20}`: the paper's "
                          "Create Path, `points` camera positions drawn uniformly in the box "
                          "`space`, one frame each, looking straight down (or by `rotation`)")
                     .Block("create_path")}));
  v.push_back(Kind("collection", "LCAP")
                  .Category("CL")
                  .Doc("Create Set: camera moves and scene changes, below")
                  .Example("`CL1 = collection{CO:{move:[P1:3]}}`")
                  .KeysInCode());
  v.push_back(Kind("scene_change", "LCAP")
                  .Aliases({"scene_change_set", "set"})
                  .Category("SCS")
                  .Doc("Scene Change: named change blocks per object, applied from a collection")
                  .Example("`SCS1 = scene_change{O1:{material:MetalGold}}`")
                  .KeysInCode());
  // Requirements and quotas (docs/languages.md, "Requirements and quotas"): the keys both
  // kinds share, a require's bounds (`quantity:[min, max]`) and relations to the camera.
  const auto target =
      Row("target")
          .Is(T::kReference)
          .Doc(
              "an LSCENE object symbol; the bounds hold for every copy of it in the camera's view");
  const std::vector<KeySpec> shared = {
      Row("budget")
          .Is(T::kWhole)
          .Range(WholeWithin(0, 100000))
          .Doc("draws per frame after the first before giving up (default 50; the largest given "
               "counts)"),
      Row("on_budget").Is(T::kName).Doc("`keep` (default) or `fail`"),
      Row("cameras").Is(T::kName).Doc("with a camera rig: `all` (default) or `any`")};
  auto bound = [](const char* name, const char* role, const char* doc) {
    return Row(name).Is(T::kAny).Role(role).Doc(std::string("`[min, max]`: ") + doc);
  };
  auto relation = [](const char* name, const char* doc) {
    return Row(name).Is(T::kAny).Role("camera relation").Doc(doc);
  };
  std::vector<KeySpec> require = {
      target,
      bound("visibility", "target quantity", "the visible share of the target"),
      bound("occlusion", "target quantity", "1 - visibility"),
      bound("in_frame", "target quantity", "the share of the target inside the image"),
      bound("size_px", "target quantity", "the larger side of the projected box, pixels"),
      bound("gsd", "target quantity", "m/px at the target"),
      bound("distance", "target quantity", "m, camera centre to box centre"),
      bound("view_angle", "target quantity", "degrees from the vertical"),
      bound("altitude", "frame quantity", "m above the terrain under the camera"),
      bound("off_nadir", "frame quantity", "degrees"),
      bound("sun_elevation", "frame quantity", "degrees above the horizon"),
      bound("time_of_day", "frame quantity", "local hours of the sun's clock"),
      bound("facing_angle",
            "target quantity",
            "degrees between the target's heading and its direction to the camera"),
      bound("ahead_of_camera", "target quantity", "m along the camera's heading"),
      Row("class").Is(T::kAny).Role("target quantity").Doc("a quota quantity only"),
      relation("FACING", "`FACING:CAMERA` or `{CAMERA: degrees}`"),
      relation("in_front_of", "`IN FRONT OF:CAMERA` or `{CAMERA: m}`"),
      relation("BEHIND", "`BEHIND:CAMERA` or `{CAMERA: m}`"),
      relation("NEAR", "`NEAR:{CAMERA: m}`"),
      relation("visible_from", "`VISIBLE FROM:CAMERA`"),
      Row("probability")
          .Aliases({"p"})
          .Is(T::kNumber)
          .Range(Within(0, 1))
          .Doc("soft requirement: demanded of a frame with this probability (default 1: hard)")};
  require.insert(require.end(), shared.begin(), shared.end());
  v.push_back(Kind("require", "LCAP")
                  .Aliases({"requirement"})
                  .What("requirement")
                  .Doc("per-frame bounds on how a target (or the frame) is seen, hard or soft; see "
                       "\"Requirements and quotas\"")
                  .Example("`REQ = require{target:T,occlusion:[0.4,0.6]}`")
                  .Keys(require));
  std::vector<KeySpec> quota = {
      target,
      Row("quantity").Is(T::kName).Doc("one quantity of `require`, or `class`"),
      Row("bins").Is(T::kList).Doc("bin edges ascending"),
      Row("classes").Is(T::kAny).Doc("the bins of `quantity:class`: `{name: share}` or `[name]`"),
      Row("weights").Is(T::kList).Doc("the target share of each bin (default equal)"),
      Row("tolerance")
          .Is(T::kNumber)
          .Range(Within(0, 1))
          .Doc("the share by which a bin may miss its target in the report (default 0.05)"),
      Row("sampling").Is(T::kName).Doc("`importance` (default) or `rejection`")};
  quota.insert(quota.end(), shared.begin(), shared.end());
  v.push_back(Kind("quota", "LCAP")
                  .Doc("a target distribution of a quantity over the collection; see "
                       "\"Requirements and quotas\"")
                  .Example("`Q = quota{target:T,quantity:visibility,bins:[0,0.5,1]}`")
                  .Keys(quota));
  // ---- nested blocks ----
  v.push_back(
      Kind("clouds").Keys({Row("type").Is(T::kName).Doc("Cloud: the cloud type, as `cloud_type`"),
                           Row("density")
                               .Is(T::kNumber)
                               .Range(Within(0, 1))
                               .Doc("Density: the cloud cover, as `cloud_density`")}));
  v.push_back(Kind("vegetation")
                  .What("Ground vegetation")
                  .Keys({Row("density")
                             .Is(T::kNumber)
                             .Range(Within(0, 100))
                             .Unit("plants/m^2")
                             .Doc("plants per square metre of terrain (required; 0: none)"),
                         Row("kind").Is(T::kName).Default("grass").Doc(
                             "`grass` (tufts of blades) or `plants` (small leafy plants)"),
                         Row("height")
                             .Is(T::kNumber)
                             .Range(Within(0.01, 2))
                             .Unit("m")
                             .Default(0.25)
                             .Doc("a plant's mean height; each varies by +-30 %")}));
  v.push_back(
      Kind("terrain_height")
          .Keys(
              {Row("perlin").Is(T::kNumberOrBlock).Doc("as the terrain's `perlin`").Block("perlin"),
               Row("frequency")
                   .Is(T::kNumber)
                   .Range(AtLeast(0))
                   .Unit("cycles/m")
                   .Doc("as the terrain's `frequency`")}));
  v.push_back(Kind("perlin").What("Perlin").Keys(
      {Row("amplitude").Is(T::kNumber).Range(AtLeast(0)).Unit("m").Doc("metres"),
       Row("frequency").Is(T::kNumber).Range(AtLeast(0)).Unit("cycles/m").Doc("cycles/m")}));
  v.push_back(
      Kind("position")
          .Keys({Row("ON").Is(T::kReference).Doc("stand on the terrain or an object's top"),
                 Row("IN").Is(T::kReference).Doc("inside an object's box"),
                 Row("AROUND").Is(T::kAny).Doc("around an object (`{X: margin}` optional)"),
                 Row("within").Is(T::kVector3).Unit("m").Doc("a box `[[x0,y0,z0],[x1,y1,z1]]`"),
                 Row("NEAR").Is(T::kAny).Unit("m").Doc("near an object, `{X: distance}` optional"),
                 Row("BEHIND").Is(T::kAny).Unit("m").Doc("behind an object"),
                 Row("in_front_of").Is(T::kAny).Unit("m").Doc("in front of an object"),
                 Row("FACING").Is(T::kAny).Doc("turned towards an object or a point"),
                 Row("visible_from").Is(T::kAny).Doc("seen from an object or a point"),
                 Row("wgs84").Is(T::kList).Doc(
                     "at `[latitude, longitude]` (WGS84, degrees) of a georeferenced scene: x and "
                     "y there, z from ON, IN or the ground")}));
  v.push_back(
      Kind("create_hemi")
          .Paper("Create Hemi")
          .Keys({Row("cam_radius").Is(T::kAny).Unit("m").Doc("LCAP range `[start, stop, count]`"),
                 Row("obj_angle").Is(T::kAny).Unit("degrees").Doc("azimuth, LCAP range"),
                 Row("cam_angle")
                     .Is(T::kAny)
                     .Unit("degrees")
                     .Doc("elevation above the target's horizontal plane, LCAP range"),
                 Row("center")
                     .Aliases({"target"})
                     .Is(T::kAny)
                     .DefaultIs("the first camera target, else the origin")
                     .Doc("`[x,y,z]` or an object")}));
  v.push_back(
      Kind("grid")
          .Paper("Increment Points, UC3")
          .Keys({Row("x").Is(T::kAny).Unit("m").Doc("LCAP range"),
                 Row("y").Is(T::kAny).Unit("m").Doc("LCAP range"),
                 Row("altitude").Is(T::kAny).Unit("m").Doc("above the terrain, LCAP range"),
                 Row("start")
                     .Is(T::kVector3)
                     .Unit("m")
                     .Doc("`[x,y,alt]`, with `step` and `count` instead of x, y, altitude"),
                 Row("step").Is(T::kVector3).Unit("m").Doc("`[dx,dy,dz]`"),
                 Row("count").Is(T::kList).Doc("`[nx,ny,nz]`"),
                 Row("perturb")
                     .Is(T::kVector3)
                     .Unit("m")
                     .Doc("`[dx,dy,dz]`: uniform noise in +-d per axis, drawn per frame"),
                 Row("point")
                     .Aliases({"blueprint"})
                     .Is(T::kAny)
                     .Doc("the paper's point blueprint: a create point path symbol or block "
                          "`{position:[[x0,y0,z0],[x1,y1,z1]], rotation or look_at}`; its "
                          "position box is the noise about each grid point, drawn per frame, its "
                          "rotation the attitude (instead of `perturb`, `roll`, `pitch`, `yaw`)"),
                 Row("roll").Is(T::kNumber).Unit("degrees").Doc("crisp or interval, per frame"),
                 Row("pitch").Is(T::kNumber).Unit("degrees").Default(-90).Doc("-90: nadir"),
                 Row("yaw").Is(T::kNumber).Unit("degrees").Doc("crisp or interval, per frame")}));
  v.push_back(
      Kind("random")
          .Paper("UC2")
          .What("random poses")
          .Keys({Row("count").Is(T::kCount).Doc("the number of frames"),
                 Row("x").Is(T::kNumber).Unit("m").Doc("default: the terrain"),
                 Row("y").Is(T::kNumber).Unit("m").Doc("default: the terrain"),
                 Row("altitude").Is(T::kNumber).Unit("m").Default(50).Doc("above the terrain"),
                 Row("off_nadir")
                     .Is(T::kNumber)
                     .Range(Within(0, 90))
                     .Unit("degrees")
                     .Default(0)
                     .Doc("deg from straight down"),
                 Row("yaw")
                     .Is(T::kNumber)
                     .Unit("degrees")
                     .Doc("uniform in [0, 360] without it; drawn per frame")}));
  v.push_back(Kind("flight")
                  .What("waypoints")
                  .Doc("a list of `[x,y,z]` (nadir), `[x,y,z,roll,pitch,yaw]`, or `{position, "
                       "attitude:[r,p,y] or look_at:[x,y,z] or an object}`: one frame per "
                       "waypoint; or a **smooth flight** `{points:[...], speed: m/s, "
                       "interpolation: linear or spline}` (see \"Smooth flights\")")
                  .Keys({Row("points").Is(T::kList).Doc("at least two waypoints"),
                         Row("speed")
                             .Is(T::kNumber)
                             .Range(Range{0, 1000, true, false, ""})
                             .Unit("m/s")
                             .Doc("m/s"),
                         Row("interpolation").Is(T::kName).Doc("`linear` (default) or `spline`")}));
  v.push_back(Kind("waypoint")
                  .Keys({Row("position").Is(T::kVector3).Unit("m").Doc("`[x,y,z]`"),
                         Row("attitude").Is(T::kVector3).Unit("degrees").Doc("`[roll,pitch,yaw]`"),
                         Row("look_at").Is(T::kAny).Doc("`[x,y,z]` or an object")}));
  v.push_back(Kind("create_path")
                  .Paper("Create Path")
                  .Keys({Row("space").Is(T::kList).Unit("m").Doc(
                             "`[[x0,y0,z0],[x1,y1,z1]]`: the box the points are drawn in (z as "
                             "waypoints: `heights:agl` makes it above the terrain)"),
                         Row("points").Is(T::kCount).Doc("the number of points (frames)"),
                         Row("rotation")
                             .Aliases({"attitude"})
                             .Is(T::kVector3)
                             .Unit("degrees")
                             .DefaultIs("nadir, `[0,-90,0]`")
                             .Doc("roll, pitch, yaw; drawn per frame")}));
  v.push_back(Kind("create_point")
                  .Paper("Create Point")
                  .Keys({Row("position").Is(T::kVector3).Unit("m").Doc("vector or vector range"),
                         Row("rotation")
                             .Aliases({"attitude"})
                             .Is(T::kVector3)
                             .Unit("degrees")
                             .DefaultIs("nadir, `[0,-90,0]`")
                             .Doc("roll, pitch, yaw"),
                         Row("look_at").Is(T::kAny).Doc("instead of `rotation`"),
                         Row("count").Is(T::kCount).Default(1).Doc("drawn per frame")}));
  // The blocks of a collection entry (docs/languages.md, "Collections: move, when, after,
  // during", "Objects that move", "Class swaps and re-scatters").
  v.push_back(
      Kind("object_change")
          .Keys({Row("material").Is(T::kName).Doc("a new material"),
                 Row("rotation").Is(T::kVector3).Unit("degrees").Doc("a new rotation"),
                 Row("scale").Is(T::kScale).Doc("a factor on the extent"),
                 Row("extent").Is(T::kVector3).Unit("m").Doc("a new extent"),
                 Row("visible").Aliases({"visibility"}).Is(T::kBool).Doc("shown or hidden"),
                 Row("offset").Is(T::kVector3).Unit("m").Doc("a move of the object by [dx,dy,dz]"),
                 Row("position")
                     .Is(T::kVector3)
                     .Unit("m")
                     .Doc("a new centre [x,y,z] (ranges drawn); an object standing ON something "
                          "is set back on it there. A new place by constraints is `rescatter`"),
                 Row("class").Is(T::kClass).Doc("a class swap"),
                 Row("rescatter").Is(T::kBool).Doc("a new place drawn by Algorithm 1"),
                 Row("move").Is(T::kList).Doc("the paths the object moves along"),
                 Row("speed")
                     .Is(T::kNumber)
                     .Range(Range{0, 1000, true, false, ""})
                     .Unit("m/s")
                     .DefaultIs("one point per frame")
                     .Doc("along a `move` path that is not a smooth flight"),
                 Row("heading").Is(T::kName).Doc("how a moving object turns")}));
  v.push_back(Kind("timing").Keys({Row("when").Is(T::kBlock).Doc("`{after, during, frame}`"),
                                   Row("after").Is(T::kAny).Doc("from a path repetition on"),
                                   Row("during").Is(T::kAny).Doc("during a path repetition"),
                                   Row("frame").Is(T::kAny).Doc("from a frame on")}));
  // One camera of a rig (docs/languages.md, "Camera rigs"): `rig:{NAME:{...}, ...}`.
  v.push_back(
      Kind("rig_camera")
          .Keys({Row("position").Is(T::kVector3).Unit("m").Doc("offset on the platform, metres"),
                 Row("attitude")
                     .Aliases({"rotation"})
                     .Is(T::kVector3)
                     .Unit("degrees")
                     .Doc("`[roll, pitch, yaw]` relative to the platform"),
                 Row("csettings")
                     .Aliases({"camera_settings", "settings"})
                     .Is(T::kBlock)
                     .Doc("the camera settings with role intrinsic only")
                     .Block("camera_settings")}));
  v.push_back(
      Kind("camera_settings")
          .Keys(
              {Row("fov")
                   .Role("intrinsic")
                   .Is(T::kNumber)
                   .Unit("degrees")
                   .Default(60)
                   .Doc("horizontal, deg"),
               Row("res")
                   .Role("intrinsic")
                   .Aliases({"resolution"})
                   .Is(T::kVector2)
                   .Unit("px")
                   .Default({1024, 1024})
                   .Doc("`[w,h]`"),
               Row("focal_length")
                   .Role("intrinsic")
                   .Is(T::kNumber)
                   .Unit("mm")
                   .Doc("mm, with `sensor_width`; overrides fov"),
               Row("sensor_width")
                   .Role("intrinsic")
                   .Is(T::kNumber)
                   .Range(Above(0))
                   .Unit("mm")
                   .Doc("mm (without it, depth of field takes 36 mm, a full-frame sensor)"),
               Row("focus_distance")
                   .Aliases({"focal_distance"})
                   .Is(T::kNumber)
                   .Range(Above(0))
                   .Unit("m")
                   .Doc("the distance in focus (the paper's focal distance): recorded, and used by "
                        "the DepthOfField post-process (without it, it focuses at the centre "
                        "pixel); see generator.md \"Post-process materials\""),
               Row("fps")
                   .Is(T::kNumber)
                   .Range(Above(0))
                   .Default(10)
                   .Doc("frames per second: the time step is 1 / fps"),
               Row("clearance")
                   .Is(T::kAny)
                   .Unit("m")
                   .Doc("metres in [0, 10000], default 1; `off` opts out; see \"Cameras where a "
                        "drone can be\""),
               Row("heights").Is(T::kName).Doc(
                   "`datum` default, or `agl` for waypoint and point z above the terrain"),
               Row("iso")
                   .Is(T::kNumber)
                   .Range(Above(0))
                   .Doc("the exposure by `shutter` + `f_number` + `iso`"),
               Row("shutter")
                   .Is(T::kNumber)
                   .Range(Above(0))
                   .Unit("s")
                   .Doc("seconds; needs `f_number`"),
               Row("f_number").Is(T::kNumber).Range(Above(0)).Doc("also `fnumber`"),
               Row("ev100")
                   .Is(T::kNumber)
                   .Range(Within(-30, 30))
                   .Doc("the exposure value; not with `shutter`"),
               Row("exposure_compensation")
                   .Is(T::kNumber)
                   .Range(Within(-10, 10))
                   .Unit("EV")
                   .Doc("EV; see \"Exposure\"; default: auto exposure")}));
  v.push_back(
      Kind("capture_settings")
          .Keys({Row("layers").Is(T::kList).Doc(
                     "the layers written (`rgb` always; names from docs/format.md, a misspelt one "
                     "is a located error with a suggestion); the generator does no work for a "
                     "bundle not asked for, and `lsds validate` checks only the declared layers"),
                 Row("folder")
                     .Aliases({"output"})
                     .Is(T::kName)
                     .Doc("the output folder when `lsds generate` gets no `-o` (relative to the "
                          "current directory; `-o` wins). Both keys are recorded in "
                          "`collection.json` (`provenance.render.capture_settings`)")}));
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
    std::string text = FormatNumber(v, digits);
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

std::vector<std::string> KindSpec::KeysWithRole(const std::string& wanted) const {
  std::vector<std::string> out;
  for (const KeySpec& k : keys)
    if (k.role == wanted) out.push_back(k.name);
  return out;
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
    if (Node n = body.Find(CanonicalKey(s))) return n;
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

// dota and yolo-obb end to end on a rendered capture (obb_checks.h).
#include <gtest/gtest.h>

#include "libs/util/atomic_file.h"
#include "tests/build_paths.h"
#include "tests/convert/obb_checks.h"

namespace lsds::testing {
namespace {

// End to end: `lsds generate` renders a nadir capture of a truck driving a
// diagonal road (turning to its heading, carrying a crate that hides part of
// it, leaving the view at the end) past a parked car at yaw 30;
// convert to dota,yolo-obb writes both, and both pass the
// consumers' rules with every box covering its object's mask.
TEST(OrientedFormatsCapture, GeneratedCaptureConvertsToDotaAndYoloObb) {
  const TempDir dir;
  WriteFileAtomic(
      dir / "s.lscene",
      "LSCENE = ONE(W) ONE(TRUCK) ONE(CRATE) ONE(PARKED)\n"
      "W = terrain{size:[100,100]}\n"
      "TRUCK = object{class:cube,extent:[4,2,1.5],position:{ON:W,within:[[-9,-1,-10],[-7,1,10]]}}\n"
      "CRATE = object{class:cube,extent:[1,1,1],position:{ON:TRUCK}}\n"
      "PARKED = object{class:cube,extent:[4,2,1.5],rotation:[0,0,30],"
      "position:{ON:W,within:[[3,-9,-10],[5,-7,10]]}}\n");
  std::string waypoints;
  for (int k = 0; k < 7; ++k) waypoints += std::string(k ? "," : "") + "[0,0,30]";
  WriteFileAtomic(dir / "c.lcap",
                  "LCAP = ONE(CO) ONE(P) ONE(ROAD) ONE(CL)\n"
                  "CO = camera{csettings:{fov:60,res:[160,120],fps:1},targets:[TRUCK,PARKED]}\n"
                  "P = path{waypoints:[" +
                      waypoints +
                      "]}\n"
                      "ROAD = path{waypoints:{points:[[-8,0,0],[0,2,0],[19,10,0]],speed:5}}\n"
                      "CL = collection{CO:{move:[P]},TRUCK:{move:[ROAD],heading:true}}\n");
  const fs::path collection = dir / "C";
  const CommandResult generated =
      RunCommandLine(LsdsBinary() + " generate " + (dir / "s.lscene").string() + " " +
                     (dir / "c.lcap").string() + " -o " + collection.string() + " 2>&1");
  ASSERT_EQ(generated.exit_code, 0) << generated.output;
  const fs::path out = dir / "out";
  convert::ConvertOptions options = Options(collection, out, {"dota", "yolo-obb"});
  options.images = "png";
  convert::Convert(options);
  const DotaFindings dota = CheckDota(collection, out);
  EXPECT_GE(dota.lines, 7);
  CheckYoloObb(collection, out);
  // Truncated and partly hidden objects are among those checked.
  bool truncated = false, hidden = false;
  for (const Frame& frame : Frames(collection))
    for (const ObjectTruth& o : frame.objects) {
      truncated = truncated || (o.visible_pixels > 0 && o.in_frame < 1);
      hidden = hidden || (o.visible_pixels > 0 && o.visibility < 0.99);
    }
  EXPECT_TRUE(truncated);
  EXPECT_TRUE(hidden);
}

}  // namespace
}  // namespace lsds::testing

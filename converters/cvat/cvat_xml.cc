#include "converters/cvat/cvat_xml.h"
#include "libs/util/strings.h"

#include "converters/format_util.h"

namespace lsds::convert::cvat {

std::string LabelsXml(const ClassMap& classes, const std::string& indent) {
  static const char* kColors[] = {"#e6194b",
                                  "#3cb44b",
                                  "#ffe119",
                                  "#4363d8",
                                  "#f58231",
                                  "#911eb4",
                                  "#46f0f0",
                                  "#f032e6",
                                  "#bcf60c",
                                  "#fabebe",
                                  "#008080",
                                  "#e6beff"};
  std::string xml = indent + "<labels>\n";
  for (size_t i = 0; i < classes.classes().size(); ++i) {
    xml += indent + "  <label>\n";
    xml += indent + "    <name>" + XmlEscape(classes.classes()[i].name) + "</name>\n";
    xml += indent + "    <color>" + kColors[i % 12] + "</color>\n";
    xml += indent + "    <type>any</type>\n";
    xml += indent + "    <attributes>\n" + indent + "    </attributes>\n";
    xml += indent + "  </label>\n";
  }
  return xml + indent + "</labels>\n";
}

std::string BoxCorners(const Box2d& box) {
  return Format(
      "xtl=\"%.2f\" ytl=\"%.2f\" xbr=\"%.2f\" ybr=\"%.2f\"", box.x0, box.y0, box.x1, box.y1);
}

}  // namespace lsds::convert::cvat

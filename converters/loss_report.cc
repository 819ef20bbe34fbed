#include "converters/loss_report.h"

#include <sstream>

namespace lsds::convert {

void LossReport::Add(const std::string& reason, const std::string& class_name, int64_t count) {
  if (count != 0) counts_[reason][class_name] += count;
}

void LossReport::Merge(const LossReport& other) {
  for (const auto& [reason, by_class] : other.counts_) {
    for (const auto& [name, count] : by_class) counts_[reason][name] += count;
  }
  for (const auto& [split, count] : other.frames_) frames_[split] += count;
}

int64_t LossReport::Count(const std::string& reason, const std::string& class_name) const {
  const auto it = counts_.find(reason);
  if (it == counts_.end()) return 0;
  const auto jt = it->second.find(class_name);
  return jt == it->second.end() ? 0 : jt->second;
}

int64_t LossReport::Total(const std::string& reason) const {
  int64_t total = 0;
  const auto it = counts_.find(reason);
  if (it != counts_.end()) {
    for (const auto& [name, count] : it->second) total += count;
  }
  return total;
}

std::map<std::string, double> LossReport::PolygonIou() const {
  std::map<std::string, double> iou;
  const auto it = counts_.find(loss::kPolygonMaskPixels);
  if (it == counts_.end()) return iou;
  for (const auto& [name, pixels] : it->second) {
    const int64_t holes = Count(loss::kPolygonHolePixels, name);
    iou[name] = static_cast<double>(pixels) / static_cast<double>(pixels + holes);
  }
  return iou;
}

std::string LossReport::ToText() const {
  std::ostringstream out;
  out << "frames per split:";
  for (const auto& [split, count] : frames_) out << " " << split << "=" << count;
  out << "\n";
  if (counts_.empty()) out << "no objects\n";
  for (const auto& [reason, by_class] : counts_) {
    out << reason << ": " << Total(reason) << " (";
    bool first = true;
    for (const auto& [name, count] : by_class) {
      out << (first ? "" : ", ") << name << " " << count;
      first = false;
    }
    out << ")\n";
  }
  const std::map<std::string, double> iou = PolygonIou();
  if (!iou.empty()) {
    out << "polygon IoU with the masks (holes filled):";
    for (const auto& [name, value] : iou) out << " " << name << " " << value;
    out << "\n";
  }
  return out.str();
}

nlohmann::json LossReport::ToJson() const {
  nlohmann::json json;
  json["frames"] = frames_;
  nlohmann::json reasons = nlohmann::json::object();
  for (const auto& [reason, by_class] : counts_) {
    reasons[reason] = {{"total", Total(reason)}, {"per_class", by_class}};
  }
  json["counts"] = reasons;
  const std::map<std::string, double> iou = PolygonIou();
  if (!iou.empty()) json["polygon_iou"] = iou;
  return json;
}

}  // namespace lsds::convert

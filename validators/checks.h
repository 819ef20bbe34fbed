// The registry of checks: every id `lsds validate` can report, its default
// severity and tolerance (docs/validate.md lists the same table), and the
// `--checks LIST` selection.
#pragma once

#include <set>
#include <string>
#include <vector>

#include "validators/finding.h"

namespace lsds::validate {

struct CheckInfo {
  std::string id;  // "group.name"; groups: schema, structure, layer, cross,
                   // camera, stats
  Severity severity;
  std::string what;       // one line: what it checks
  std::string tolerance;  // "exact", "1e-3", ...
};

// Every check, in report order.
const std::vector<CheckInfo>& AllChecks();
const CheckInfo& GetCheck(const std::string& id);  // throws lsds::Error for unknown ids

class CheckSelection {
 public:
  static CheckSelection All();
  // Exactly these registry ids (throws lsds::Error for an unknown one).
  static CheckSelection Of(const std::vector<std::string>& ids);
  // Comma-separated ids or groups ("layer", "cross.*", "all"); throws
  // lsds::Error naming an unknown entry with a suggestion.
  static CheckSelection Parse(const std::string& list);

  bool Has(const std::string& id) const { return ids_.count(id) > 0; }
  bool HasGroup(const std::string& group) const;  // any selected id in "group."
  const std::set<std::string>& ids() const { return ids_; }

 private:
  std::set<std::string> ids_;
};

}  // namespace lsds::validate

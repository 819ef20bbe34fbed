// TrackEval's MOT Challenge ground-truth loader (trackeval/datasets/
// mot_challenge_2d_box.py and _base_dataset.py at 12c8791).
#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <set>
#include <system_error>

#include "converters/check/consumer.h"
#include "converters/check/text_input.h"
#include "libs/util/strings.h"

namespace lsds::check {

namespace fs = std::filesystem;

const std::vector<Rule>& TrackEvalRules() {
  static const std::vector<Rule> rules = {
      {"trackeval.seqmap",
       Severity::kRejected,
       "trackeval/datasets/mot_challenge_2d_box.py:149-165 (12c8791)",
       "sequences are listed in seqmaps/<BENCHMARK>-<SPLIT>.txt (first row a header); "
       "none found: 'no seqmap found'"},
      {"trackeval.unlisted-sequence",
       Severity::kDroppedImage,
       "trackeval/datasets/mot_challenge_2d_box.py:82, 159-165 (12c8791)",
       "a sequence folder no seqmap lists is never evaluated"},
      {"trackeval.seqinfo",
       Severity::kRejected,
       "trackeval/datasets/mot_challenge_2d_box.py:166-171 (12c8791)",
       "<SEQ>/seqinfo.ini must exist with an integer seqLength in [Sequence]"},
      {"trackeval.gt-file",
       Severity::kRejected,
       "trackeval/datasets/mot_challenge_2d_box.py:87-92 (12c8791)",
       "<SEQ>/gt/gt.txt must exist for every listed sequence"},
      {"trackeval.frame-number",
       Severity::kRejected,
       "trackeval/datasets/_base_dataset.py:168, 200-204 (12c8791)",
       "the first column must be a number"},
      {"trackeval.frame-range",
       Severity::kRejected,
       "trackeval/datasets/mot_challenge_2d_box.py:212-222 (12c8791)",
       "frames outside 1..seqLength: 'invalid timesteps'"},
      {"trackeval.values",
       Severity::kRejected,
       "trackeval/datasets/mot_challenge_2d_box.py:227-236 (12c8791)",
       "every value of a frame's rows must be a number, the rows of one frame of one length"},
      {"trackeval.columns",
       Severity::kRejected,
       "trackeval/datasets/mot_challenge_2d_box.py:237-257 (12c8791)",
       "ground truth needs at least 8 columns (frame, id, left, top, width, height, "
       "conf, class)"},
      {"trackeval.duplicate-id",
       Severity::kRejected,
       "trackeval/datasets/_base_dataset.py:316-326 (12c8791)",
       "one id twice in one frame: 'Ground-truth has the same ID more than once'"},
      {"trackeval.class-valid",
       Severity::kRejected,
       "trackeval/datasets/mot_challenge_2d_box.py:76-79, 362-371 (12c8791)",
       "a class outside 1..13 stops the evaluation (with preprocessing, MOT16/17/20)"},
      {"trackeval.class-scored",
       Severity::kDroppedBox,
       "trackeval/datasets/mot_challenge_2d_box.py:71-75, 389-393 (12c8791)",
       "only class 1 (pedestrian) is scored: boxes of other classes are removed"},
      {"trackeval.zero-marked",
       Severity::kIgnored,
       "trackeval/datasets/mot_challenge_2d_box.py:259, 389-393 (12c8791)",
       "lines with 0 in column 7 are removed from scoring, as the format intends"},
  };
  return rules;
}

namespace {

// `seqLength` of [Sequence] in a seqinfo.ini (configparser: keys are case
// insensitive, `=` or `:` separate).
bool ReadSeqLength(const fs::path& ini, long long* length, std::string* problem) {
  std::string bytes;
  if (!ReadBytes(ini, &bytes)) {
    *problem = "cannot be read";
    return false;
  }
  std::string section;
  for (const std::string& raw : SplitLines(bytes)) {
    const std::string line = Strip(raw);
    if (line.empty() || line[0] == '#' || line[0] == ';') continue;
    if (line.front() == '[' && line.back() == ']') {
      section = line.substr(1, line.size() - 2);
      continue;
    }
    const size_t separator = line.find_first_of("=:");
    if (section != "Sequence" || separator == std::string::npos) continue;
    std::string key = Strip(line.substr(0, separator));
    std::transform(key.begin(), key.end(), key.begin(), ::tolower);
    if (key != "seqlength") continue;
    const std::string value = Strip(line.substr(separator + 1));
    if (!ParsePythonInt(value, length)) {
      *problem = "seqLength '" + value + "' is not an integer";
      return false;
    }
    return true;
  }
  *problem = "no seqLength in [Sequence]";
  return false;
}

struct GtRow {
  int64_t line;
  std::vector<std::string> cells;
};

// A gt.txt line's cells as csv.reader gives them.
std::vector<std::string> GtCells(const std::string& text, char delimiter) {
  std::vector<std::string> cells;
  for (const std::string& cell : Split(text, delimiter)) {
    if (delimiter == ' ' && cell.empty()) continue;  // skipinitialspace
    cells.push_back(Strip(cell));
  }
  if (!cells.empty() && cells.back().empty()) cells.pop_back();  // a trailing delimiter
  return cells;
}

// The rows of gt.txt by frame (timestep), those with a frame number in
// 1..seqLength.
std::map<long long, std::vector<GtRow>> GtFrames(const fs::path& gt,
                                                 const std::vector<std::string>& lines,
                                                 long long seq_length,
                                                 FindingSink* sink) {
  // csv.Sniffer on the first line: MOT files are comma separated.
  const char delimiter = lines.front().find(',') != std::string::npos ? ',' : ' ';
  std::map<long long, std::vector<GtRow>> frames;
  for (size_t i = 0; i < lines.size(); ++i) {
    const int64_t line = static_cast<int64_t>(i) + 1;
    if (lines[i].empty()) continue;  // csv.reader yields no row
    std::vector<std::string> cells = GtCells(lines[i], delimiter);
    double frame = 0;
    if (cells.empty() || !ParsePythonFloat(cells[0], &frame) || !std::isfinite(frame)) {
      sink->Add("trackeval.frame-number",
                gt,
                line,
                "frame '" + (cells.empty() ? std::string() : cells[0]) +
                    "' is not a number: the file cannot be read");
      continue;
    }
    const auto timestep = static_cast<long long>(frame);  // int(float(...))
    if (timestep < 1 || timestep > seq_length) {
      sink->Add("trackeval.frame-range",
                gt,
                line,
                "frame " + std::to_string(timestep) + " outside 1.." + std::to_string(seq_length) +
                    " (seqLength): invalid timestep, the evaluation stops");
      continue;
    }
    frames[timestep].push_back({line, std::move(cells)});
  }
  return frames;
}

// A frame's rows convert to one float array: one length, numbers only.
bool FrameValuesUsable(const fs::path& gt,
                       long long timestep,
                       const std::vector<GtRow>& rows,
                       FindingSink* sink) {
  bool usable = true;
  for (const GtRow& row : rows) {
    if (row.cells.size() != rows.front().cells.size()) {
      sink->Add("trackeval.values",
                gt,
                row.line,
                std::to_string(row.cells.size()) + " columns where frame " +
                    std::to_string(timestep) + " has " + std::to_string(rows.front().cells.size()) +
                    ": cannot convert to float");
      usable = false;
      continue;
    }
    for (const std::string& cell : row.cells) {
      double v = 0;
      if (!ParsePythonFloat(cell, &v)) {
        sink->Add("trackeval.values",
                  gt,
                  row.line,
                  "'" + cell + "' is not a number: 'Is data corrupted?'");
        usable = false;
        break;
      }
    }
  }
  return usable;
}

// The boxes a file's scoring leaves out, reported once per class and file
// (a vehicle export has one per line otherwise).
struct NotScored {
  std::map<long long, std::pair<int64_t, int64_t>> by_class;  // class -> count, first line
  int64_t zero_marked = 0, first_zero_marked = 0;
};

// The ids and classes of a frame's usable rows (8 columns or more).
void CheckFrameRows(const fs::path& gt,
                    long long timestep,
                    const std::vector<GtRow>& rows,
                    FindingSink* sink,
                    NotScored* not_scored) {
  std::map<long long, int64_t> id_line;
  for (const GtRow& row : rows) {
    double id = 0, cls = 0, conf = 0;
    ParsePythonFloat(row.cells[1], &id);
    ParsePythonFloat(row.cells[6], &conf);
    ParsePythonFloat(row.cells[7], &cls);
    const auto [it, inserted] = id_line.emplace(static_cast<long long>(id), row.line);
    if (!inserted) {
      sink->Add("trackeval.duplicate-id",
                gt,
                row.line,
                "id " + std::to_string(static_cast<long long>(id)) + " already in frame " +
                    std::to_string(timestep) + " (line " + std::to_string(it->second) + ")");
    }
    const auto class_id = static_cast<long long>(cls);
    if (class_id < 1 || class_id > 13) {
      sink->Add("trackeval.class-valid",
                gt,
                row.line,
                "class " + std::to_string(class_id) + " is not a MOT class (1..13)");
    } else if (class_id != 1) {
      auto& [count, first] = not_scored->by_class[class_id];
      if (count++ == 0) first = row.line;
    }
    if (static_cast<long long>(conf) == 0) {
      if (not_scored->zero_marked++ == 0) not_scored->first_zero_marked = row.line;
    }
  }
}

void ReportNotScored(const fs::path& gt, const NotScored& not_scored, FindingSink* sink) {
  for (const auto& [class_id, entry] : not_scored.by_class) {
    sink->Add("trackeval.class-scored",
              gt,
              entry.second,
              std::to_string(entry.first) + " box(es) of class " + std::to_string(class_id) +
                  " (first here) are not scored: MotChallenge2DBox scores class 1 only");
  }
  if (not_scored.zero_marked > 0) {
    sink->Add("trackeval.zero-marked",
              gt,
              not_scored.first_zero_marked,
              std::to_string(not_scored.zero_marked) +
                  " zero-marked line(s) (first here) are not scored");
  }
}

void CheckGroundTruth(const fs::path& gt, long long seq_length, FindingSink* sink) {
  std::string bytes;
  ReadBytes(gt, &bytes);
  sink->CountFile();
  const std::vector<std::string> lines = SplitLines(bytes);
  if (lines.empty()) return;
  NotScored not_scored;
  for (const auto& [timestep, rows] : GtFrames(gt, lines, seq_length, sink)) {
    if (!FrameValuesUsable(gt, timestep, rows, sink)) continue;
    if (rows.front().cells.size() < 8) {
      sink->Add(
          "trackeval.columns",
          gt,
          rows.front().line,
          std::to_string(rows.front().cells.size()) + " columns (8 needed): the evaluation stops");
      continue;
    }
    CheckFrameRows(gt, timestep, rows, sink, &not_scored);
  }
  ReportNotScored(gt, not_scored, sink);
}

// Sequence folders: DIR/<split>/<SEQ> or DIR/<SEQ> holding gt/ or seqinfo.ini.
std::set<fs::path> SequenceFolders(const fs::path& dir) {
  std::error_code error;
  std::set<fs::path> sequences;
  const auto is_sequence = [&](const fs::path& p) {
    return fs::is_directory(p / "gt", error) || fs::is_regular_file(p / "seqinfo.ini", error);
  };
  for (const auto& entry : fs::directory_iterator(dir, error)) {
    if (!entry.is_directory(error) || entry.path().filename() == "seqmaps") continue;
    if (is_sequence(entry.path())) {
      sequences.insert(entry.path());
      continue;
    }
    for (const auto& inner : fs::directory_iterator(entry.path(), error)) {
      if (inner.is_directory(error) && is_sequence(inner.path())) sequences.insert(inner.path());
    }
  }
  return sequences;
}

// One sequence a seqmap lists (its row on `line`): seqinfo.ini, then gt.txt.
void CheckListedSequence(const fs::path& seqmap,
                         int64_t line,
                         const std::string& name,
                         const fs::path& sequence,
                         const fs::path& dir,
                         FindingSink* sink) {
  std::error_code error;
  long long length = 0;
  std::string problem;
  if (!fs::is_regular_file(sequence / "seqinfo.ini", error)) {
    sink->Add("trackeval.seqinfo",
              seqmap,
              line,
              "sequence '" + name + "': no " +
                  fs::relative(sequence / "seqinfo.ini", dir, error).string());
    return;
  }
  if (!ReadSeqLength(sequence / "seqinfo.ini", &length, &problem)) {
    sink->Add("trackeval.seqinfo", sequence / "seqinfo.ini", 0, problem);
    return;
  }
  if (!fs::is_regular_file(sequence / "gt" / "gt.txt", error)) {
    sink->Add("trackeval.gt-file", seqmap, line, "sequence '" + name + "': no gt/gt.txt");
    return;
  }
  CheckGroundTruth(sequence / "gt" / "gt.txt", length, sink);
}

// The sequences a seqmap lists, checked; their folders added to `listed`.
void CheckSeqmap(const fs::path& seqmap,
                 const fs::path& dir,
                 FindingSink* sink,
                 std::set<fs::path>* listed) {
  std::error_code error;
  sink->CountFile();
  // GT_FOLDER/<BENCHMARK>-<SPLIT> holds the sequences, or GT_FOLDER itself
  // with SKIP_SPLIT_FOL.
  const fs::path gt_folder =
      fs::is_directory(dir / seqmap.stem(), error) ? dir / seqmap.stem() : dir;
  std::string bytes;
  ReadBytes(seqmap, &bytes);
  const std::vector<std::string> rows = SplitLines(bytes);
  for (size_t i = 1; i < rows.size(); ++i) {  // row 0 is the header ("name")
    const std::string name = Strip(Split(rows[i], ',').front());
    if (name.empty()) continue;
    const fs::path sequence = gt_folder / name;
    listed->insert(fs::weakly_canonical(sequence, error));
    CheckListedSequence(seqmap, static_cast<int64_t>(i) + 1, name, sequence, dir, sink);
  }
}

// A sequence no seqmap lists: never evaluated, or, without any seqmap,
// checked still, so that one run says everything.
void CheckUnlistedSequence(const fs::path& sequence, bool have_seqmaps, FindingSink* sink) {
  if (have_seqmaps) {
    sink->Add("trackeval.unlisted-sequence", sequence, 0, "no seqmap lists it: never evaluated");
    return;
  }
  std::error_code error;
  long long length = 0;
  std::string problem;
  if (!ReadSeqLength(sequence / "seqinfo.ini", &length, &problem)) {
    sink->Add("trackeval.seqinfo", sequence / "seqinfo.ini", 0, problem);
  } else if (fs::is_regular_file(sequence / "gt" / "gt.txt", error)) {
    CheckGroundTruth(sequence / "gt" / "gt.txt", length, sink);
  }
}

}  // namespace

void CheckTrackEval(const std::string& /*format*/,
                    const fs::path& dir,
                    const CheckOptions& /*options*/,
                    FindingSink* sink) {
  std::error_code error;
  const std::set<fs::path> sequences = SequenceFolders(dir);
  std::vector<fs::path> seqmaps;
  for (const fs::path& file : ListFiles(dir / "seqmaps")) {
    if (LowerExtension(file) == "txt") seqmaps.push_back(file);
  }
  if (seqmaps.empty()) {
    sink->Add("trackeval.seqmap",
              dir / "seqmaps",
              0,
              "no seqmaps/*.txt: 'no seqmap found', the evaluation stops");
  }
  std::set<fs::path> listed;
  for (const fs::path& seqmap : seqmaps) CheckSeqmap(seqmap, dir, sink, &listed);
  for (const fs::path& sequence : sequences) {
    if (listed.count(fs::weakly_canonical(sequence, error)) > 0) continue;
    CheckUnlistedSequence(sequence, !seqmaps.empty(), sink);
  }
}

}  // namespace lsds::check

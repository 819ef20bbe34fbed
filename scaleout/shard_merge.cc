#include "scaleout/shard_merge.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <exception>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <system_error>
#include <thread>
#include <vector>

#include <tbb/parallel_for.h>
#include <nlohmann/json.hpp>

#include "libs/collection/bundle_layout.h"
#include "libs/collection/collection_reader.h"
#include "libs/collection/collection_writer.h"
#include "libs/collection/json_io.h"
#include "libs/collection/json_stream.h"
#include "libs/collection/motion_layout.h"
#include "libs/collection/schema.h"
#include "libs/collection/worldposition_layout.h"
#include "libs/exr/exr_chunks.h"
#include "libs/exr/exr_info.h"
#include "libs/util/atomic_file.h"
#include "libs/util/error.h"
#include "libs/util/progress.h"

namespace lsds {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// The folder `lsds generate` keeps while a run is unfinished
// (generator/generate.cc): a shard holding it is not complete.
constexpr const char* kGenerateWorkFolder = ".lsds-generate";

// The elements of one file's "frames" array, parsed by a thread of their own
// and handed out in file order. The shards' streams are consumed interleaved
// (frame 0 from shard 0, frame 1 from shard 1, ...), which a callback parser
// cannot do in one thread; the queue bounds memory to a few frames per shard.
class ElementStream {
 public:
  explicit ElementStream(fs::path path) : path_(std::move(path)) {
    thread_ = std::thread([this] { Run(); });
  }
  ~ElementStream() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      cancelled_ = true;
    }
    changed_.notify_all();
    thread_.join();
  }
  ElementStream(const ElementStream&) = delete;
  ElementStream& operator=(const ElementStream&) = delete;

  // The next element; false at the end of the array. Rethrows a read error.
  bool Next(json* element) {
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait(lock, [this] { return !queue_.empty() || done_; });
    if (!queue_.empty()) {
      *element = std::move(queue_.front());
      queue_.pop_front();
      changed_.notify_all();
      return true;
    }
    if (error_) std::rethrow_exception(error_);
    return false;
  }

 private:
  struct Cancelled {};
  static constexpr size_t kDepth = 4;

  void Run() {
    try {
      StreamJsonArrayMember(path_, "frames", nullptr, [this](json&& element, size_t) {
        std::unique_lock<std::mutex> lock(mutex_);
        changed_.wait(lock, [this] { return queue_.size() < kDepth || cancelled_; });
        if (cancelled_) throw Cancelled{};
        queue_.push_back(std::move(element));
        changed_.notify_all();
      });
    } catch (const Cancelled&) {
    } catch (...) {
      std::lock_guard<std::mutex> lock(mutex_);
      error_ = std::current_exception();
    }
    std::lock_guard<std::mutex> lock(mutex_);
    done_ = true;
    changed_.notify_all();
  }

  fs::path path_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<json> queue_;
  bool done_ = false, cancelled_ = false;
  std::exception_ptr error_;
  std::thread thread_;
};

struct Shard {
  fs::path root;
  CollectionHeader header;
  MetadataHeader metadata;
  std::string Name() const { return root.string(); }
  std::string ShardText() const {
    return std::to_string(header.provenance.shard->index) + "/" +
           std::to_string(header.provenance.shard->count);
  }
};

// True when `inner` is `outer` or lies inside it (both canonical).
bool IsWithin(const fs::path& inner, const fs::path& outer) {
  const fs::path relative = inner.lexically_relative(outer);
  return !relative.empty() && *relative.begin() != "..";
}

// "3, 7 and 11"; long lists end with "... (N in all)".
std::string FrameList(const std::vector<int64_t>& frames) {
  constexpr size_t kShown = 10;
  std::string text;
  for (size_t k = 0; k < frames.size() && k < kShown; ++k) {
    if (k > 0) text += (k + 1 == frames.size()) ? " and " : ", ";
    text += std::to_string(frames[k]);
  }
  if (frames.size() > kShown) text += ", ... (" + std::to_string(frames.size()) + " in all)";
  return text;
}

// The collection header with what differs between the shards of one run
// removed: the shard index and the frame count.
json RunHeaderJson(const CollectionHeader& header) {
  json j = HeaderToJson(header);
  j.erase("frame_count");
  j["provenance"]["shard"].erase("index");
  // Each shard checks its own frames' Cycles passes (generate --renderer cycles).
  if (j["provenance"].contains("render")) j["provenance"]["render"].erase("cycles_agreement");
  return j;
}

// The run's provenance.render.cycles_agreement from its shards' (docs/format.md): frames and
// pixels add up, the largest errors and their frames are the largest of any shard.
json MergedCyclesAgreement(const std::vector<json>& shards) {
  json merged = {{"frames", 0}, {"pixels", 0}, {"id_mismatches", 0}, {"depth_pixels", 0}};
  for (const json& a : shards) {
    for (const char* count : {"frames", "pixels", "id_mismatches", "depth_pixels"})
      merged[count] = merged[count].get<int64_t>() + a.value(count, int64_t{0});
    for (const char* figure : {"max_relative_depth_error", "max_id_mismatch_share"}) {
      const std::string frame = std::string(figure) + "_frame";
      if (!merged.contains(figure) || a.value(figure, 0.0) > merged[figure].get<double>()) {
        merged[figure] = a.value(figure, 0.0);
        merged[frame] = a.value(frame, int64_t{0});
      }
    }
  }
  const auto pixels = merged["pixels"].get<int64_t>();
  merged["id_mismatch_share"] = pixels > 0
                                    ? static_cast<double>(merged["id_mismatches"].get<int64_t>()) /
                                          static_cast<double>(pixels)
                                    : 0.0;
  return merged;
}

// Throws naming the first JSON pointer where `other` differs from `first`.
void RequireSame(const json& first,
                 const json& other,
                 const fs::path& first_file,
                 const fs::path& other_file) {
  const json patch = json::diff(first, other);
  if (patch.empty()) return;
  const std::string pointer = patch[0].at("path").get<std::string>();
  const json::json_pointer at(pointer);
  // Two long texts (scene sources) are shown from a little before the first
  // byte where they differ, so that the message shows the difference.
  size_t from = 0;
  if (first.contains(at) && other.contains(at) && first.at(at).is_string() &&
      other.at(at).is_string()) {
    const auto& a = first.at(at).get_ref<const std::string&>();
    const auto& b = other.at(at).get_ref<const std::string&>();
    size_t k = 0;
    while (k < a.size() && k < b.size() && a[k] == b[k]) ++k;
    from = k > 20 ? k - 20 : 0;
    while (from > 0 && k - from < 40 && a[from - 1] != ' ') --from;  // from a word's start
  }
  auto shown = [&](const json& j) {
    if (!j.contains(at)) return std::string("nothing");
    if (from > 0) {
      const auto& value = j.at(at).get_ref<const std::string&>();
      // The cut may split a UTF-8 sequence: replaced, not thrown on.
      const std::string part =
          json(value.substr(from, 50)).dump(-1, ' ', false, json::error_handler_t::replace);
      return "..." + part + (from + 50 < value.size() ? "..." : "");
    }
    std::string text = j.at(at).dump();
    if (text.size() > 60) text = text.substr(0, 57) + "...";
    return text;
  };
  throw Error("not a shard of the same run as " + first_file.string() + ": it has " + shown(other) +
                  " where that one has " + shown(first),
              Location(other_file.string(), pointer));
}

Shard OpenShard(const fs::path& root) {
  CheckCollectionFolder(root);
  if (fs::exists(root / kGenerateWorkFolder))
    throw Error("the shard is unfinished (it holds " + std::string(kGenerateWorkFolder) +
                    "): finish it with the same lsds generate command and --resume",
                Location(root.string()));
  Shard shard;
  shard.root = root;
  const CollectionReader reader(root);
  shard.header = reader.header();
  if (!shard.header.provenance.shard)
    throw Error(
        "not a shard: its provenance records no shard (only collections of "
        "lsds generate --shard I/N with N > 1 are merged)",
        Location(reader.collection_path().string(), "/provenance"));
  if (shard.header.metadata.size() != 1 || shard.header.metadata[0].file != kMetadataFile)
    throw Error("the shard has metadata variants besides " + std::string(kMetadataFile) +
                    ": merge the shards first, then derive the variants from the "
                    "merged collection",
                Location(reader.collection_path().string(), "/metadata"));
  shard.metadata = MetadataReader(root / kMetadataFile).header();
  return shard;
}

// Which shard holds each frame of the run (-1: none); the run's frames are
// first..last of the shard record.
struct Coverage {
  int64_t first = 0;
  std::vector<int> owner;
  int64_t frames = 0;
};

// The index of frame `k` of a shard's collection file, checked: an integer,
// increasing, inside the run's frames (`run`: the first shard's record) and
// of this shard.
int64_t CheckedFrameIndex(const json& frame,
                          size_t k,
                          int64_t previous,
                          const ShardRecord& run,
                          const Shard& shard,
                          const fs::path& file) {
  const int shard_index = shard.header.provenance.shard->index;
  const std::string pointer = "/frames/" + std::to_string(k);
  if (!frame.is_object() || !frame.contains("index") || !frame["index"].is_number_integer())
    throw Error("frame without an integer index", Location(file.string(), pointer));
  const int64_t index = frame["index"].get<int64_t>();
  if (index <= previous)
    throw Error("frames are not in increasing index order (frame " + std::to_string(index) +
                    " after " + std::to_string(previous) + ")",
                Location(file.string(), pointer));
  if (index < run.run_first_frame || index > run.run_last_frame)
    throw Error("frame " + std::to_string(index) + " lies outside the run's frames " +
                    std::to_string(run.run_first_frame) + " to " +
                    std::to_string(run.run_last_frame),
                Location(file.string(), pointer));
  if (index % run.count != shard_index)
    throw Error("frame " + std::to_string(index) + " does not belong to shard " +
                    shard.ShardText() + " (its index % " + std::to_string(run.count) + " is " +
                    std::to_string(index % run.count) + ")",
                Location(file.string(), pointer));
  return index;
}

// Frames given by more than one shard: their indices, and the first two
// shards that share one.
struct Doubled {
  std::vector<int64_t> frames;
  std::string between;
};

// One shard's frames into the coverage.
void AddShardFrames(const std::vector<Shard>& shards,
                    size_t s,
                    Coverage* coverage,
                    Doubled* doubled) {
  const ShardRecord& run = *shards[0].header.provenance.shard;
  const Shard& shard = shards[s];
  const fs::path file = shard.root / kCollectionFile;
  int64_t previous = -1;
  const size_t count = StreamJsonArrayMember(file, "frames", nullptr, [&](json&& frame, size_t k) {
    const int64_t index = CheckedFrameIndex(frame, k, previous, run, shard, file);
    previous = index;
    int& owner = coverage->owner[index - coverage->first];
    if (owner >= 0) {
      if (doubled->frames.empty()) doubled->between = shards[owner].Name() + " and " + shard.Name();
      doubled->frames.push_back(index);
    } else {
      owner = static_cast<int>(s);
      ++coverage->frames;
    }
  });
  if (static_cast<int64_t>(count) != shard.header.frame_count)
    throw Error("frame_count is " + std::to_string(shard.header.frame_count) +
                    " but the file holds " + std::to_string(count) + " frames",
                Location(file.string(), "/frame_count"));
}

// The run's frames no shard holds, and the shards they belong to.
[[noreturn]] void ThrowMissing(const Coverage& coverage, const ShardRecord& run) {
  std::vector<int64_t> missing;
  std::vector<bool> shard_missing(static_cast<size_t>(run.count), false);
  for (size_t k = 0; k < coverage.owner.size(); ++k) {
    if (coverage.owner[k] >= 0) continue;
    const int64_t index = coverage.first + static_cast<int64_t>(k);
    missing.push_back(index);
    shard_missing[static_cast<size_t>(index % run.count)] = true;
  }
  // A run whose frame indices have gaps cannot name its missing frames.
  if (static_cast<int64_t>(coverage.owner.size()) != run.run_frame_count)
    throw Error("the shards hold " + std::to_string(coverage.frames) + " of the run's " +
                std::to_string(run.run_frame_count) + " frames");
  std::vector<std::string> owners;
  for (size_t i = 0; i < shard_missing.size(); ++i)
    if (shard_missing[i]) owners.push_back(std::to_string(i) + "/" + std::to_string(run.count));
  std::string owner_text;
  for (size_t i = 0; i < owners.size(); ++i) owner_text += (i == 0 ? "" : ", ") + owners[i];
  throw Error(std::string(missing.size() == 1 ? "frame " : "frames ") + FrameList(missing) +
              (missing.size() == 1 ? " is" : " are") + " in no shard given: shard" +
              (owners.size() == 1 ? " " : "s ") + owner_text + " of the run " +
              (owners.size() == 1 ? "is" : "are") + " missing or incomplete");
}

// Pass 1: the frame indices of every shard, checked against the run.
Coverage CheckCoverage(const std::vector<Shard>& shards) {
  const ShardRecord& run = *shards[0].header.provenance.shard;
  Coverage coverage;
  coverage.first = run.run_first_frame;
  coverage.owner.assign(static_cast<size_t>(run.run_last_frame - run.run_first_frame + 1), -1);
  Doubled doubled;
  for (size_t s = 0; s < shards.size(); ++s) AddShardFrames(shards, s, &coverage, &doubled);
  if (!doubled.frames.empty())
    throw Error(std::string(doubled.frames.size() == 1 ? "frame " : "frames ") +
                FrameList(doubled.frames) + (doubled.frames.size() == 1 ? " is" : " are") +
                " in more than one shard (first in " + doubled.between + "): give each shard once");
  if (coverage.frames == run.run_frame_count) return coverage;
  ThrowMissing(coverage, run);
}

// A frame's layer file path must stay inside the collection.
fs::path CheckedRelative(const std::string& file, const fs::path& collection_file, int64_t frame) {
  fs::path relative = fs::path(file).lexically_normal();
  if (relative.empty() || relative.is_absolute() || *relative.begin() == "..") {
    Location where(collection_file.string());
    where.frame = frame;
    throw Error("layer file '" + file + "' lies outside the collection", where);
  }
  return relative;
}

// A file descriptor closed on every path out.
struct Descriptor {
  int fd = -1;
  Descriptor() = default;
  explicit Descriptor(int value) : fd(value) {}
  Descriptor(Descriptor&& other) noexcept : fd(other.fd) { other.fd = -1; }
  Descriptor(const Descriptor&) = delete;
  Descriptor& operator=(const Descriptor&) = delete;
  Descriptor& operator=(Descriptor&&) = delete;
  ~Descriptor() {
    if (fd >= 0) ::close(fd);
  }
};

std::string ErrnoText(int error) { return std::generic_category().message(error); }

// What lstat says an entry is, for messages about entries merge refuses.
std::string KindOf(int dir_fd, const std::string& name) {
  struct stat st {};
  if (::fstatat(dir_fd, name.c_str(), &st, AT_SYMLINK_NOFOLLOW) != 0) return "";
  if (S_ISLNK(st.st_mode)) {
    std::string target(4096, '\0');
    const ssize_t n = ::readlinkat(dir_fd, name.c_str(), target.data(), target.size());
    target.resize(n > 0 ? static_cast<size_t>(n) : 0);
    return "a symbolic link (to " + target + ")";
  }
  if (S_ISFIFO(st.st_mode)) return "a FIFO";
  if (S_ISSOCK(st.st_mode)) return "a socket";
  if (S_ISCHR(st.st_mode) || S_ISBLK(st.st_mode)) return "a device";
  if (S_ISDIR(st.st_mode)) return "a folder";
  if (S_ISREG(st.st_mode)) return "a regular file";
  return "not a regular file";
}

// Opens a frame's layer file for reading only if it is a regular file reached
// through real folders of the shard. A symbolic link (to /etc/passwd, to
// another run's file) would copy bytes from outside the shard into the merged
// collection, and a FIFO or device would block the merge or read without end;
// each is refused. Every component is looked up relative to the one before
// without following links (lstat, then O_NOFOLLOW), so nothing outside the
// shard is opened, and the type is checked before anything is opened.
Descriptor OpenLayerInShard(const fs::path& root,
                            const fs::path& relative,
                            const Location& where,
                            struct stat* st) {
  Descriptor dir(::open(root.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC));
  if (dir.fd < 0)
    throw Error("cannot open the shard: " + ErrnoText(errno), Location(root.string()));
  fs::path reached = root;
  // The location names the layer file; a folder on its way is named too.
  const std::vector<fs::path> parts(relative.begin(), relative.end());
  auto refuse = [&](const std::string& name, const std::string& expected) {
    const std::string kind = KindOf(dir.fd, name);
    const std::string what = reached / name == root / relative
                                 ? "the layer file"
                                 : "its folder " + (reached / name).string();
    throw Error(what + " is " + (kind.empty() ? "missing" : kind) + ": merge copies only " +
                    expected + " inside the shard",
                where);
  };
  for (size_t i = 0; i + 1 < parts.size(); ++i) {
    const std::string name = parts[i].string();
    Descriptor next(
        ::openat(dir.fd, name.c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC));
    if (next.fd < 0) refuse(name, "layer files in real folders");
    std::swap(dir.fd, next.fd);
    reached /= name;
  }
  const std::string name = parts.back().string();
  struct stat entry {};
  if (::fstatat(dir.fd, name.c_str(), &entry, AT_SYMLINK_NOFOLLOW) != 0 || !S_ISREG(entry.st_mode))
    refuse(name, "regular files");
  Descriptor file(::openat(dir.fd, name.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC));
  if (file.fd < 0 || ::fstat(file.fd, st) != 0 || !S_ISREG(st->st_mode) ||
      st->st_ino != entry.st_ino || st->st_dev != entry.st_dev)
    throw Error("the layer file changed while it was opened (is the shard being written?)", where);
  return file;
}

// A shard's layer file must be what its frame says: the header of the
// declared layer (deep or flat, the declared channels and types) at the
// frame's image size, and every chunk of pixel data inside the file. A
// truncated or foreign layer would otherwise be copied silently into a
// collection that fails validation.
void CheckLayerFile(const fs::path& path,
                    uint64_t size,
                    const LayerInfo& layer,
                    const Frame& frame,
                    const Location& where) {
  exr::ExrInfo info;
  try {
    info = exr::ReadExrInfo(path);
    exr::CheckChunksWithinFile(path, size);
  } catch (const Error& e) {
    throw Error("layer '" + layer.name + "': " + e.message(), where);
  }
  const std::string of = "layer '" + layer.name + "'";
  if (info.deep != layer.deep)
    throw Error(of + ": the file is " + (info.deep ? "deep" : "flat") + " but the layer is " +
                    (layer.deep ? "deep" : "flat"),
                where);
  const PinholeCamera& camera = frame.camera.intrinsics;
  if (info.width != camera.width || info.height != camera.height)
    throw Error(of + ": the file is " + std::to_string(info.width) + "x" +
                    std::to_string(info.height) + " but the frame's camera is " +
                    std::to_string(camera.width) + "x" + std::to_string(camera.height),
                where);
  // The channels a reader gets (residual and compact layouts decode to the
  // declared ones), as validate compares them.
  info.channels = layer.semantic == "motion" ? ReadableMotionChannels(info)
                                             : ReadableWorldPositionChannels(info);
  info.channels = ReadableChannels(info);
  for (const LayerChannel& declared : layer.channels) {
    const exr::ChannelSpec* found = info.Find(declared.name);
    if (found == nullptr)
      throw Error(of + ": the file has no channel '" + declared.name + "'", where);
    if (found->type != declared.type)
      throw Error(of + ": channel '" + declared.name + "' is " + exr::PixelTypeName(found->type) +
                      " but the layer declares " + exr::PixelTypeName(declared.type),
                  where);
  }
}

// Copies a checked layer file from its open descriptor (the file that was
// checked, whatever happens to the path meanwhile) through the checked atomic
// output path; returns the bytes copied.
uint64_t CopyLayerFile(int fd, uint64_t size, const fs::path& to, const Location& from) {
  AtomicFile out(to);
  std::vector<char> chunk(1 << 20);
  uint64_t copied = 0;
  while (true) {
    const ssize_t n = ::pread(fd, chunk.data(), chunk.size(), static_cast<off_t>(copied));
    if (n < 0) {
      if (errno == EINTR) continue;
      throw Error("cannot read the layer file: " + ErrnoText(errno), from);
    }
    if (n == 0) break;
    out.stream().write(chunk.data(), n);
    copied += static_cast<uint64_t>(n);
  }
  if (copied != size)
    throw Error("the layer file changed size during the merge (" + std::to_string(size) + " -> " +
                    std::to_string(copied) + " bytes)",
                from);
  out.Commit();
  return copied;
}

// The writers name the files they write in the temporary folder the output
// is built in; the user knows the output by the name given with -o.
[[noreturn]] void RethrowNamingOutput(const Error& error,
                                      const fs::path& temp,
                                      const fs::path& output) {
  Location location = error.location();
  const std::string prefix = temp.string();
  if (location.file.compare(0, prefix.size(), prefix) == 0)
    location.file = output.string() + location.file.substr(prefix.size());
  throw Error(error.message(), location);
}

}  // namespace

namespace {

// The stages of MergeShards: open the shards and check they are one run's (same headers,
// frames covered once, the output apart from them), then write the run's collection.json
// with every frame's layer files copied, and its metadata.json, in run order.

// The output is neither an input nor inside one, and holds none; the shards share one run's
// collection and metadata headers.
void CheckShardsOfOneRun(const std::vector<Shard>& shards, const MergeOptions& options) {
  const fs::path output = fs::weakly_canonical(options.output);
  for (const Shard& shard : shards) {
    const fs::path root = fs::weakly_canonical(shard.root);
    if (IsWithin(output, root) || IsWithin(root, output))
      throw Error("the output " + options.output.string() +
                      " is, contains or lies inside the shard " + shard.Name(),
                  Location(options.output.string()));
  }
  const json run_header = RunHeaderJson(shards[0].header);
  json run_metadata = MetadataHeaderToJson(shards[0].metadata);
  run_metadata.erase("frame_count");
  for (size_t s = 1; s < shards.size(); ++s) {
    RequireSame(run_header,
                RunHeaderJson(shards[s].header),
                shards[0].root / kCollectionFile,
                shards[s].root / kCollectionFile);
    json metadata = MetadataHeaderToJson(shards[s].metadata);
    metadata.erase("frame_count");
    RequireSame(
        run_metadata, metadata, shards[0].root / kMetadataFile, shards[s].root / kMetadataFile);
  }
}

// Runs `fn` on every frame of `file_name` in run order, the elements taken
// from the shard streams that hold them.
void ForEachInRunOrder(const std::vector<Shard>& shards,
                       const Coverage& coverage,
                       const char* file_name,
                       const std::function<void(json&&, const Shard&, int64_t)>& fn) {
  std::vector<std::unique_ptr<ElementStream>> streams;
  streams.reserve(shards.size());
  for (const Shard& shard : shards)
    streams.push_back(std::make_unique<ElementStream>(shard.root / file_name));
  for (size_t k = 0; k < coverage.owner.size(); ++k) {
    const int owner = coverage.owner[k];
    if (owner < 0) continue;
    json element;
    if (!streams[owner]->Next(&element))
      throw Error("the file ended early (was it changed during the merge?)",
                  Location((shards[owner].root / file_name).string()));
    fn(std::move(element), shards[owner], coverage.first + static_cast<int64_t>(k));
  }
}

// A frame's layer files, checked against the layer table.
struct LayerFile {
  const LayerInfo* layer;
  fs::path relative;
};

// Checks and copies a frame's layer files into `out`; they are independent, so in parallel.
// Returns the bytes copied.
uint64_t CopyFrameFiles(const Shard& shard,
                        const Frame& frame,
                        int64_t index,
                        const std::vector<LayerFile>& files,
                        const fs::path& out) {
  std::vector<uint64_t> bytes(files.size(), 0);
  tbb::parallel_for(size_t{0}, files.size(), [&](size_t i) {
    const fs::path from = shard.root / files[i].relative;
    const fs::path to = out / files[i].relative;
    Location where(from.string());
    where.frame = index;
    struct stat st {};
    const Descriptor layer_file = OpenLayerInShard(shard.root, files[i].relative, where, &st);
    const uint64_t size = static_cast<uint64_t>(st.st_size);
    CheckLayerFile(from, size, *files[i].layer, frame, where);
    // The header was read by name: it must be the file that is copied.
    struct stat now {};
    if (::lstat(from.c_str(), &now) != 0 || now.st_ino != st.st_ino || now.st_dev != st.st_dev)
      throw Error("the layer file was replaced during the merge", where);
    std::error_code ec;
    fs::create_directories(to.parent_path(), ec);
    if (ec)
      throw Error("cannot create the folder: " + ec.message(), Location(to.parent_path().string()));
    bytes[i] = CopyLayerFile(layer_file.fd, size, to, where);
  });
  uint64_t total = 0;
  for (uint64_t b : bytes) total += b;
  return total;
}

// collection.json of the run: every frame checked (schema, index, layers) with its files copied.
void MergeCollectionFrames(const std::vector<Shard>& shards,
                           const Coverage& coverage,
                           const CollectionHeader& header,
                           const fs::path& out,
                           const MergeOptions& options,
                           MergeSummary* summary) {
  std::optional<Progress> progress;
  if (options.progress) progress.emplace("merge", coverage.frames);
  const JsonSchema& schema = JsonSchema::Get("collection.schema.json", "frame");
  CollectionWriter writer(out, header);
  std::vector<int64_t> frame_in_shard(shards.size(), 0);
  ForEachInRunOrder(
      shards, coverage, kCollectionFile, [&](json&& element, const Shard& shard, int64_t index) {
        const fs::path file = shard.root / kCollectionFile;
        const size_t s = static_cast<size_t>(&shard - shards.data());
        const std::string pointer = "/frames/" + std::to_string(frame_in_shard[s]++);
        schema.ValidateOrThrow(element, file.string(), pointer);
        const Frame frame = FrameFromJson(element, file.string(), pointer);
        if (frame.index != index)
          throw Error("expected frame " + std::to_string(index) +
                          " here (was the shard changed during the merge?)",
                      Location(file.string(), pointer));
        std::vector<LayerFile> files;
        for (const auto& [layer_name, name] : frame.files) {
          const LayerInfo* layer = shard.header.FindLayer(layer_name);
          if (layer == nullptr)
            throw Error("frame " + std::to_string(index) + " lists a file for layer '" +
                            layer_name + "', which the layer table does not declare",
                        Location(file.string(), pointer + "/files/" + layer_name));
          files.push_back({layer, CheckedRelative(name, file, index)});
        }
        summary->bytes += CopyFrameFiles(shard, frame, index, files, out);
        summary->files += static_cast<int64_t>(files.size());
        writer.Append(frame);
        if (progress) progress->Add();
      });
  writer.Commit();
}

// metadata.json of the run: each frame checked against the schema and collection.json's order.
void MergeMetadataFrames(const std::vector<Shard>& shards,
                         const Coverage& coverage,
                         const MetadataHeader& metadata_header,
                         const fs::path& out) {
  const JsonSchema& schema = JsonSchema::Get("metadata.schema.json", "frame");
  MetadataWriter writer(out / kMetadataFile, metadata_header);
  std::vector<int64_t> frame_in_shard(shards.size(), 0);
  ForEachInRunOrder(
      shards, coverage, kMetadataFile, [&](json&& element, const Shard& shard, int64_t index) {
        const fs::path file = shard.root / kMetadataFile;
        const size_t s = static_cast<size_t>(&shard - shards.data());
        const std::string pointer = "/frames/" + std::to_string(frame_in_shard[s]++);
        schema.ValidateOrThrow(element, file.string(), pointer);
        const MetadataFrame frame = MetadataFrameFromJson(element, file.string(), pointer);
        if (frame.index != index)
          throw Error("metadata of frame " + std::to_string(frame.index) +
                          " where collection.json has frame " + std::to_string(index),
                      Location(file.string(), pointer));
        writer.Append(frame);
      });
  writer.Commit();
}

}  // namespace

MergeSummary MergeShards(const MergeOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  if (options.shards.empty()) throw Error("no shard to merge");
  if (options.output.empty()) throw Error("no output folder (-o COLLECTION)");
  std::vector<Shard> shards;
  for (const fs::path& root : options.shards) shards.push_back(OpenShard(root));
  CheckShardsOfOneRun(shards, options);
  const Coverage coverage = CheckCoverage(shards);

  // The run's collection, built under a temporary name.
  AtomicDirectory directory(options.output, options.force);
  const fs::path& out = directory.temp_path();
  MergeSummary summary;
  summary.shards = static_cast<int>(shards.size());
  summary.frames = coverage.frames;
  try {
    CollectionHeader header = shards[0].header;
    header.provenance.shard.reset();
    if (header.provenance.render.contains("cycles_agreement")) {
      std::vector<json> agreements;
      agreements.reserve(shards.size());
      for (const Shard& shard : shards)
        agreements.push_back(shard.header.provenance.render.value("cycles_agreement", json()));
      header.provenance.render["cycles_agreement"] = MergedCyclesAgreement(agreements);
    }
    header.frame_count = coverage.frames;
    for (const LayerInfo& layer : header.layers) {
      std::error_code ec;
      fs::create_directory(out / layer.name, ec);
      if (ec)
        throw Error("cannot create the layer folder: " + ec.message(),
                    Location((out / layer.name).string()));
    }
    MetadataHeader metadata_header = shards[0].metadata;
    metadata_header.frame_count = coverage.frames;
    MergeCollectionFrames(shards, coverage, header, out, options, &summary);
    MergeMetadataFrames(shards, coverage, metadata_header, out);
  } catch (const Error& e) {
    RethrowNamingOutput(e, out, options.output);
  }
  directory.Commit();
  summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return summary;
}

}  // namespace lsds

#include "libs/collection/shard_merge.h"

#include <chrono>
#include <condition_variable>
#include <deque>
#include <exception>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include <tbb/parallel_for.h>
#include <nlohmann/json.hpp>

#include "libs/collection/collection_reader.h"
#include "libs/collection/collection_writer.h"
#include "libs/collection/json_io.h"
#include "libs/collection/json_stream.h"
#include "libs/collection/schema.h"
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
  return j;
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
  auto shown = [&](const json& j) {
    if (!j.contains(at)) return std::string("nothing");
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

// Pass 1: the frame indices of every shard, checked against the run.
Coverage CheckCoverage(const std::vector<Shard>& shards) {
  const ShardRecord& run = *shards[0].header.provenance.shard;
  Coverage coverage;
  coverage.first = run.run_first_frame;
  coverage.owner.assign(static_cast<size_t>(run.run_last_frame - run.run_first_frame + 1), -1);
  std::vector<int64_t> doubled;
  std::string doubled_between;
  for (size_t s = 0; s < shards.size(); ++s) {
    const Shard& shard = shards[s];
    const fs::path file = shard.root / kCollectionFile;
    const int shard_index = shard.header.provenance.shard->index;
    int64_t previous = -1;
    const size_t count =
        StreamJsonArrayMember(file, "frames", nullptr, [&](json&& frame, size_t k) {
          const std::string pointer = "/frames/" + std::to_string(k);
          if (!frame.is_object() || !frame.contains("index") || !frame["index"].is_number_integer())
            throw Error("frame without an integer index", Location(file.string(), pointer));
          const int64_t index = frame["index"].get<int64_t>();
          if (index <= previous)
            throw Error("frames are not in increasing index order (frame " + std::to_string(index) +
                            " after " + std::to_string(previous) + ")",
                        Location(file.string(), pointer));
          previous = index;
          if (index < run.run_first_frame || index > run.run_last_frame)
            throw Error("frame " + std::to_string(index) + " lies outside the run's frames " +
                            std::to_string(run.run_first_frame) + " to " +
                            std::to_string(run.run_last_frame),
                        Location(file.string(), pointer));
          if (index % run.count != shard_index)
            throw Error("frame " + std::to_string(index) + " does not belong to shard " +
                            shard.ShardText() + " (its index % " + std::to_string(run.count) +
                            " is " + std::to_string(index % run.count) + ")",
                        Location(file.string(), pointer));
          int& owner = coverage.owner[index - coverage.first];
          if (owner >= 0) {
            if (doubled.empty()) doubled_between = shards[owner].Name() + " and " + shard.Name();
            doubled.push_back(index);
          } else {
            owner = static_cast<int>(s);
            ++coverage.frames;
          }
        });
    if (static_cast<int64_t>(count) != shard.header.frame_count)
      throw Error("frame_count is " + std::to_string(shard.header.frame_count) +
                      " but the file holds " + std::to_string(count) + " frames",
                  Location(file.string(), "/frame_count"));
  }
  if (!doubled.empty())
    throw Error(std::string(doubled.size() == 1 ? "frame " : "frames ") + FrameList(doubled) +
                (doubled.size() == 1 ? " is" : " are") + " in more than one shard (first in " +
                doubled_between + "): give each shard once");
  if (coverage.frames == run.run_frame_count) return coverage;
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

}  // namespace

MergeSummary MergeShards(const MergeOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  if (options.shards.empty()) throw Error("no shard to merge");
  if (options.output.empty()) throw Error("no output folder (-o COLLECTION)");
  std::vector<Shard> shards;
  for (const fs::path& root : options.shards) shards.push_back(OpenShard(root));

  // The output is neither an input nor inside one, and holds none.
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
  const Coverage coverage = CheckCoverage(shards);

  // The run's collection, built under a temporary name.
  AtomicDirectory directory(options.output, options.force);
  const fs::path& out = directory.temp_path();
  CollectionHeader header = shards[0].header;
  header.provenance.shard.reset();
  header.frame_count = coverage.frames;
  for (const LayerInfo& layer : header.layers) fs::create_directories(out / layer.name);
  MetadataHeader metadata_header = shards[0].metadata;
  metadata_header.frame_count = coverage.frames;
  MergeSummary summary;
  summary.shards = static_cast<int>(shards.size());
  summary.frames = coverage.frames;

  // Runs `fn` on every frame of `file_name` in run order, the elements taken
  // from the shard streams that hold them.
  auto for_each_in_run_order = [&](const char* file_name,
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
  };

  {
    std::optional<Progress> progress;
    if (options.progress) progress.emplace("merge", coverage.frames);
    const JsonSchema& schema = JsonSchema::Get("collection.schema.json", "frame");
    CollectionWriter writer(out, header);
    std::vector<int64_t> frame_in_shard(shards.size(), 0);
    for_each_in_run_order(kCollectionFile, [&](json&& element, const Shard& shard, int64_t index) {
      const fs::path file = shard.root / kCollectionFile;
      const size_t s = static_cast<size_t>(&shard - shards.data());
      const std::string pointer = "/frames/" + std::to_string(frame_in_shard[s]++);
      schema.ValidateOrThrow(element, file.string(), pointer);
      const Frame frame = FrameFromJson(element, file.string(), pointer);
      if (frame.index != index)
        throw Error("expected frame " + std::to_string(index) +
                        " here (was the shard changed during the merge?)",
                    Location(file.string(), pointer));
      std::vector<fs::path> files;
      for (const auto& [layer, name] : frame.files)
        files.push_back(CheckedRelative(name, file, index));
      // Layer files are independent: copy them in parallel.
      std::vector<uint64_t> bytes(files.size(), 0);
      tbb::parallel_for(size_t{0}, files.size(), [&](size_t i) {
        const fs::path from = shard.root / files[i];
        const fs::path to = out / files[i];
        std::error_code ec;
        fs::create_directories(to.parent_path(), ec);
        fs::copy_file(from, to, ec);
        if (ec) throw Error("cannot copy the layer file: " + ec.message(), Location(from.string()));
        bytes[i] = fs::file_size(to);
      });
      for (uint64_t b : bytes) summary.bytes += b;
      summary.files += static_cast<int64_t>(files.size());
      writer.Append(frame);
      if (progress) progress->Add();
    });
    writer.Commit();
  }
  {
    const JsonSchema& schema = JsonSchema::Get("metadata.schema.json", "frame");
    MetadataWriter writer(out / kMetadataFile, metadata_header);
    std::vector<int64_t> frame_in_shard(shards.size(), 0);
    for_each_in_run_order(kMetadataFile, [&](json&& element, const Shard& shard, int64_t index) {
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
  directory.Commit();
  summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return summary;
}

}  // namespace lsds

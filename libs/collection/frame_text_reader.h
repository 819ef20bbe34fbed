// The fast path of CollectionReader: one frame's JSON text read with
// simdjson's On-Demand API straight into a Frame, with what the frame schema
// (schemas/collection.schema.json, definitions/frame) and FrameFromJson check
// done in code. Whatever it does not take (an unknown or repeated key, a
// missing one, a value of another type or out of the schema's range, a
// number it would not convert exactly as nlohmann does) is refused, and the
// caller reads that frame the DOM way (FrameFromJson after the schema), which
// takes it or reports it at its JSON pointer.
#pragma once

#include <memory>
#include <string_view>

#include "libs/collection/model.h"

namespace lsds {

class FrameTextReader {
 public:
  FrameTextReader();
  ~FrameTextReader();
  FrameTextReader(const FrameTextReader&) = delete;
  FrameTextReader& operator=(const FrameTextReader&) = delete;

  // `text` is one element of "frames", followed by kElementTextPadding
  // readable bytes (json_array_split.h). True and `*frame` set when the frame
  // passes every check; false when the DOM path must read it.
  bool Read(std::string_view text, Frame* frame);
  // True when every value of `text` parses: the syntax check of the frames a
  // reader opens. False for anything simdjson does not take (the DOM reader
  // then reports it at its line and column, or reads it).
  bool IsWellFormed(std::string_view text);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace lsds

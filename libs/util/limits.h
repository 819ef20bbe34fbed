// Limits on hostile input, checked before the work (docs/reliability.md):
// nesting depth of every parsed document and the memory an image-shaped
// allocation may take.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace lsds {

// Deepest nesting of objects/arrays (JSON) or braces/lists (LSCENE text) any
// lsds parser accepts. Real documents nest fewer than 20 levels; the limit
// keeps recursive code (schema checks, printing, the LSCENE parser) far from
// the stack's end.
inline constexpr int kMaxNestingDepth = 256;

// Scans JSON `text` (strings and escapes skipped) and throws lsds::Error with
// file, line and column where the nesting first exceeds kMaxNestingDepth. A
// linear pre-scan: cheaper than a parse, and it protects every parser that
// runs after it, whatever it is.
void CheckJsonNesting(const std::string& text, const std::string& file);
// The offset where JSON `text` first nests deeper than kMaxNestingDepth, or
// std::string_view::npos.
size_t FindExcessJsonNesting(std::string_view text);
// The error both report.
std::string NestingMessage();

// The memory budget of one image-shaped allocation, bytes: --memory-budget on
// the command line, else LSDS_MEMORY_BUDGET ("8G", "512M", bytes), else 8 GiB.
uint64_t MemoryBudgetBytes();
void SetMemoryBudget(const std::string& text);  // from --memory-budget
uint64_t ParseByteSize(const std::string& text, const std::string& where);

// Throws lsds::Error naming `what` and `where` when `bytes` exceed the budget:
// the one budget check, called before the allocation it guards; the message
// states the need, the budget and how to raise it.
void CheckMemoryBudget(double bytes, const std::string& what, const std::string& where);

// Throws lsds::Error naming `what` and `where` when width x height x
// values_per_pixel x bytes_per_value exceeds the budget, before anything is
// allocated; the message states the need, the budget and how to raise it.
void CheckImageBudget(int64_t width,
                      int64_t height,
                      int64_t values_per_pixel,
                      int64_t bytes_per_value,
                      const std::string& what,
                      const std::string& where);

}  // namespace lsds

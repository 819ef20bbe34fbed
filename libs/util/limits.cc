#include "libs/util/limits.h"

#include <cstdlib>
#include <optional>

#include "libs/util/error.h"
#include "libs/util/strings.h"

namespace lsds {

namespace {

std::optional<uint64_t>& BudgetOverride() {
  static std::optional<uint64_t> budget;
  return budget;
}

}  // namespace

std::string NestingMessage() {
  return "nesting deeper than " + std::to_string(kMaxNestingDepth) +
         " levels (objects and arrays); lsds refuses such documents";
}

size_t FindExcessJsonNesting(std::string_view text) {
  int depth = 0;
  bool in_string = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\') {
        ++i;
      } else if (c == '"') {
        in_string = false;
      }
      continue;
    }
    if (c == '"') {
      in_string = true;
    } else if (c == '{' || c == '[') {
      if (++depth > kMaxNestingDepth) return i;
    } else if (c == '}' || c == ']') {
      if (depth > 0) --depth;
    }
  }
  return std::string_view::npos;
}

void CheckJsonNesting(const std::string& text, const std::string& file) {
  const size_t offset = FindExcessJsonNesting(text);
  if (offset == std::string_view::npos) return;
  Location where(file);
  LineColumnFromOffset(text, offset, &where.line, &where.column);
  throw Error(NestingMessage(), where);
}

uint64_t ParseByteSize(const std::string& text, const std::string& where) {
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  double scale = 1;
  std::string suffix = end != nullptr ? std::string(end) : std::string();
  if (suffix == "K" || suffix == "k" || suffix == "KiB")
    scale = 1024.0;
  else if (suffix == "M" || suffix == "MiB")
    scale = 1024.0 * 1024;
  else if (suffix == "G" || suffix == "GiB")
    scale = 1024.0 * 1024 * 1024;
  else if (suffix == "T" || suffix == "TiB")
    scale = 1024.0 * 1024 * 1024 * 1024;
  else if (!suffix.empty())
    scale = -1;
  if (end == text.c_str() || scale < 0 || !(value > 0) || value * scale > 1e19) {
    throw Error(
        "expected a positive size in bytes with an optional K, M, G "
        "or T suffix (e.g. 16G), got '" +
            text + "'",
        Location(where));
  }
  return static_cast<uint64_t>(value * scale);
}

void SetMemoryBudget(const std::string& text) {
  BudgetOverride() = ParseByteSize(text, "--memory-budget");
}

uint64_t MemoryBudgetBytes() {
  if (BudgetOverride()) return *BudgetOverride();
  // NOLINTNEXTLINE(concurrency-mt-unsafe): lsds never sets the environment
  const char* env = std::getenv("LSDS_MEMORY_BUDGET");
  if (env != nullptr && *env != '\0') return ParseByteSize(env, "LSDS_MEMORY_BUDGET");
  return uint64_t{8} << 30;
}

void CheckImageBudget(int64_t width,
                      int64_t height,
                      int64_t values_per_pixel,
                      int64_t bytes_per_value,
                      const std::string& what,
                      const std::string& where) {
  if (width <= 0 || height <= 0) {
    throw Error(what + ": the size must be positive, got " + std::to_string(width) + "x" +
                    std::to_string(height),
                Location(where));
  }
  // In double: the product of hostile factors must not wrap around.
  const double need = static_cast<double>(width) * static_cast<double>(height) *
                      static_cast<double>(std::max<int64_t>(1, values_per_pixel)) *
                      static_cast<double>(std::max<int64_t>(1, bytes_per_value));
  CheckMemoryBudget(
      need, what + ": " + std::to_string(width) + "x" + std::to_string(height), where);
}

void CheckMemoryBudget(double bytes, const std::string& what, const std::string& where) {
  const uint64_t budget = MemoryBudgetBytes();
  if (bytes > static_cast<double>(budget)) {
    throw Error(what + " needs " + FormatBytes(bytes) + ", over the memory budget of " +
                    FormatBytes(static_cast<double>(budget)) +
                    " (raise it with --memory-budget or LSDS_MEMORY_BUDGET, e.g. 32G)",
                Location(where));
  }
}

}  // namespace lsds

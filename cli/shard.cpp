#include "cli/shard.hpp"

#include <cstdlib>
#include <fmt/format.h>
#include <stdexcept>

#include "input/params.hpp"  // InputError

namespace liftcheck::cli {

std::pair<int, int> parse_shard(const std::string& text) {
  const auto number = [](const std::string& t, const std::string& what) {
    try {
      size_t used = 0;
      const long v = std::stol(t, &used);
      if (used != t.size() || v < 0 || v > 100000) throw std::invalid_argument(t);
      return static_cast<int>(v);
    } catch (const std::logic_error&) {
      throw InputError(fmt::format("{} '{}' is not a whole number", what, t));
    }
  };
  if (text.empty()) {
    const char* index = std::getenv("GTEST_SHARD_INDEX");
    const char* total = std::getenv("GTEST_TOTAL_SHARDS");
    if (!index || !total) return {0, 0};
    const int n = number(total, "GTEST_TOTAL_SHARDS"), i = number(index, "GTEST_SHARD_INDEX");
    if (n < 1 || i >= n) throw InputError(fmt::format("GTEST_SHARD_INDEX {} is not below GTEST_TOTAL_SHARDS {}", i, n));
    return {i + 1, n};
  }
  const auto slash = text.find('/');
  if (slash == std::string::npos)
    throw InputError(fmt::format("--shard '{}' must be I/N, the I-th of N shares (1 <= I <= N)", text));
  const int i = number(text.substr(0, slash), "--shard index"), n = number(text.substr(slash + 1), "--shard count");
  if (n < 1 || i < 1 || i > n) throw InputError(fmt::format("--shard '{}' must be I/N with 1 <= I <= N", text));
  return {i, n};
}

}  // namespace liftcheck::cli

// Which share of the suite a validate runs: --shard I/N, or the GTEST sharding variables.
#pragma once

#include <string>
#include <utility>

namespace liftcheck::cli {

/// "I/N" (1 <= I <= N); GTEST_SHARD_INDEX (0-based) and GTEST_TOTAL_SHARDS when it is empty;
/// {0, 0}: not sharded.
std::pair<int, int> parse_shard(const std::string& text);

}  // namespace liftcheck::cli

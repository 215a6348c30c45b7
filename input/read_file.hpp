// Files liftcheck reads from users (traces, results files, baselines), read with a size limit: a
// device or a huge file stops at the limit with an InputError naming the file and the limit, never
// by exhausting memory. OS errors are named with their reason (strerror).
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>

namespace liftcheck {

/// Limits on what one file may hold (bytes).
constexpr std::size_t kMaxTraceBytes = std::size_t{256} << 20;  ///< a trace: 256 MiB
constexpr std::size_t kMaxResultsBytes =
    std::size_t{512} << 20;  ///< a results file or baseline: 512 MiB (its document takes about 8 times that)

/// The whole text of `path`; InputError "cannot read WHAT 'PATH': REASON", "WHAT 'PATH' is a
/// folder, not a file", or "WHAT 'PATH' is larger than the limit of N MiB". Checks for an
/// interruption between chunks.
std::string read_text_file(const std::filesystem::path& path, std::size_t max_bytes, const std::string& what);

/// "N MiB" (or bytes below one MiB) for messages.
std::string size_text(std::size_t bytes);

/// `s` is valid UTF-8 (JSON, and so every record, holds UTF-8 only).
bool is_utf8(const std::string& s);

/// InputError "WHAT 'TEXT' is not valid UTF-8 (...)" unless `text` is.
void require_utf8(const std::string& text, const std::string& what);

}  // namespace liftcheck

// Files written whole or not at all.
#pragma once

#include <filesystem>
#include <string>

namespace liftcheck {

/// Writes `text` to `path` through a temporary file in the same folder and a rename, so a reader
/// never sees half a file. Throws std::runtime_error naming the path.
void write_file_atomic(const std::filesystem::path& path, const std::string& text);

}  // namespace liftcheck

// The output folder of validate and merge, swapped in whole; liftcheck deletes only what it wrote.
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace liftcheck::cli {

/// The output folder, written whole or not at all: everything goes into a fresh hidden folder
/// beside it (`.NAME.partial-PID-XXXXXX`), which is swapped in at the end, so an interrupted or
/// failed run leaves the previous one as it was. Every output folder holds a manifest
/// (`.liftcheck-output`) listing each file and folder liftcheck wrote into it; an existing folder is
/// replaced only when it holds nothing else (or, written before manifests, nothing but the names
/// liftcheck writes). Nothing that is not liftcheck's is ever deleted.
class StagedOutput {
 public:
  /// The manifest of an output folder (written into every one).
  static constexpr const char* kMarker = ".liftcheck-output";
  /// In a staging folder: the process that made it, so a later run removes it only when that
  /// process is gone.
  static constexpr const char* kStaging = ".liftcheck-staging";

  /// `inputs` (path, what: "--baseline", "--trace-dir", "shard folder") must not lie inside it.
  explicit StagedOutput(const std::string& out_dir,
                        const std::vector<std::pair<std::string, std::string>>& inputs = {});
  ~StagedOutput();
  StagedOutput(const StagedOutput&) = delete;
  StagedOutput& operator=(const StagedOutput&) = delete;
  const std::filesystem::path& stage() const { return stage_; }
  const std::filesystem::path& final_path() const { return out_; }
  /// An input (a baseline, a trace folder, a shard) inside the output folder would be swapped away
  /// with it: InputError.
  void refuse_inside(const std::string& path, const std::string& what) const;
  /// Writes the manifest and swaps the staged folder in (an atomic exchange); the previous output
  /// is removed afterwards, by its manifest. A folder that cannot be renamed (a mount point) gets
  /// the new entries copied in first and the old ones removed only then. On failure the staged
  /// folder is kept and the message says where.
  void publish();

 private:
  /// The constructor's work, its file system errors turned into InputError by the constructor.
  void prepare(const std::string& out_dir, const std::vector<std::pair<std::string, std::string>>& inputs);
  void replace_entries();
  [[noreturn]] void fail_keeping(const std::string& why, bool old_intact = true);

  std::filesystem::path out_, stage_;
  bool keep_stage_ = false;
};

/// The entries (relative paths) of `dir` that liftcheck did not write by its manifest (or, without
/// one, by the names liftcheck writes), at most `max` of them.
std::vector<std::string> foreign_entries(const std::filesystem::path& dir, std::size_t max = 3);

}  // namespace liftcheck::cli

// The output folder of validate and merge, swapped in whole.
#pragma once

#include <filesystem>
#include <string>

namespace liftcheck::cli {

/// The output folder, written whole or not at all: everything goes into a hidden folder beside it,
/// which replaces it at the end (an interrupted or failed run leaves the previous one as it was).
/// An existing folder is replaced only when it is a liftcheck output (it holds results.json) or
/// empty, never a folder of the user's.
class StagedOutput {
 public:
  /// The file that marks a folder as liftcheck's output (written into every output folder).
  static constexpr const char* kMarker = ".liftcheck-output";

  explicit StagedOutput(const std::string& out_dir);
  ~StagedOutput();
  const std::filesystem::path& stage() const { return stage_; }
  const std::filesystem::path& final_path() const { return out_; }
  /// A file of the user's (a baseline) inside the folder would be swapped away with it.
  void refuse_inside(const std::string& file, const std::string& what) const;
  /// Swaps the staged folder in; the previous output goes only once the new one is in place. A
  /// folder that cannot be renamed (a mount point) has its entries replaced instead.
  void publish();

 private:
  /// Empty, or marked as liftcheck's, or (written before the marker existed) nothing but the files
  /// liftcheck writes with a results.json that says it is liftcheck's.
  static bool ours(const std::filesystem::path& dir);
  /// The folder stays (it is a mount point): its entries are removed and the staged ones copied in.
  void replace_entries();

  std::filesystem::path out_, stage_;
  bool published_ = false;
};

}  // namespace liftcheck::cli

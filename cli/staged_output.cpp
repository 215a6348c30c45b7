#include "cli/staged_output.hpp"

#include <algorithm>
#include <fmt/format.h>
#include <fstream>
#include <nlohmann/json.hpp>
#include <unistd.h>

#include "input/params.hpp"  // InputError

namespace liftcheck::cli {

StagedOutput::StagedOutput(const std::string& out_dir) : out_(out_dir) {
  if (out_dir.empty()) throw InputError("--out names no folder");
  out_ = std::filesystem::weakly_canonical(std::filesystem::absolute(out_));
  if (!out_.has_filename()) out_ = out_.parent_path();
  std::error_code ec;
  // The working folder or one above it would be swapped away under the user's feet.
  const std::filesystem::path cwd = std::filesystem::weakly_canonical(std::filesystem::current_path(ec));
  const auto [o_end, c_it] = std::mismatch(out_.begin(), out_.end(), cwd.begin(), cwd.end());
  if (o_end == out_.end()) throw InputError(fmt::format("--out '{}' is the working folder or one above it: give a folder of its own", out_dir));
  if (std::filesystem::exists(out_, ec)) {
    if (!std::filesystem::is_directory(out_, ec)) throw InputError(fmt::format("--out '{}' is a file, not a folder", out_dir));
    if (!ours(out_))
      throw InputError(fmt::format("--out '{}' holds files that liftcheck did not write: not a liftcheck output folder, left alone", out_dir));
  }
  std::filesystem::create_directories(out_.parent_path(), ec);
  stage_ = out_.parent_path() / fmt::format(".{}.partial-{}", out_.filename().string(), getpid());
  std::filesystem::remove_all(stage_, ec);
  if (!std::filesystem::create_directory(stage_, ec) || ec) throw InputError(fmt::format("cannot create output folder '{}'", out_dir));
  std::ofstream(stage_ / kMarker) << "written by liftcheck: replaced whole by its next run into this folder\n";
}

StagedOutput::~StagedOutput() {
  std::error_code ec;
  if (!published_) std::filesystem::remove_all(stage_, ec);
}

void StagedOutput::refuse_inside(const std::string& file, const std::string& what) const {
  if (file.empty()) return;
  const std::filesystem::path f = std::filesystem::weakly_canonical(std::filesystem::absolute(file));
  if (std::mismatch(out_.begin(), out_.end(), f.begin(), f.end()).first == out_.end())
    throw InputError(fmt::format("{} '{}' must not be inside --out '{}': that folder is replaced whole", what, file, out_.string()));
}

void StagedOutput::publish() {
  std::error_code ec;
  const std::filesystem::path old = out_.parent_path() / fmt::format(".{}.old-{}", out_.filename().string(), getpid());
  const bool had = std::filesystem::exists(out_, ec);
  if (had) std::filesystem::rename(out_, old, ec);
  if (ec) {
    replace_entries();
    return;
  }
  std::filesystem::rename(stage_, out_, ec);
  if (ec) {
    std::error_code ec2;
    if (had) std::filesystem::rename(old, out_, ec2);
    throw InputError(fmt::format("cannot write '{}': {} (the results are kept in '{}')", out_.string(), ec.message(), stage_.string()));
  }
  published_ = true;
  if (had) std::filesystem::remove_all(old, ec);
}

bool StagedOutput::ours(const std::filesystem::path& dir) {
  std::error_code ec;
  if (std::filesystem::is_empty(dir, ec) || std::filesystem::exists(dir / kMarker, ec)) return true;
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string(), ext = entry.path().extension().string();
    const bool known = name == "results.json" || name == "junit.xml" || name == "summary.md" || name == "screenshot.png" ||
                       name == "snapshots" || name == "plots" || ext == ".html";
    if (!known) return false;
  }
  try {
    std::ifstream in(dir / "results.json");
    return nlohmann::json::parse(in).at("context").contains("liftcheck");
  } catch (const std::exception&) {
    return false;
  }
}

void StagedOutput::replace_entries() {
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(out_, ec)) std::filesystem::remove_all(entry.path(), ec);
  std::filesystem::copy(stage_, out_, std::filesystem::copy_options::recursive | std::filesystem::copy_options::overwrite_existing, ec);
  if (ec) throw InputError(fmt::format("cannot write '{}': {} (the results are kept in '{}')", out_.string(), ec.message(), stage_.string()));
  published_ = true;
  std::filesystem::remove_all(stage_, ec);
}

}  // namespace liftcheck::cli

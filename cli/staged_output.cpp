#include "cli/staged_output.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fmt/format.h>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <set>
#include <climits>
#include <signal.h>
#include <fcntl.h>
#include <unistd.h>

#include "input/atomic_file.hpp"
#include "input/params.hpp"  // InputError
#include "input/read_file.hpp"
#include "input/trace.hpp"  // printable

namespace liftcheck::cli {

namespace fs = std::filesystem;

namespace {

constexpr const char* kManifestHeader = "liftcheck output manifest 1";
constexpr std::size_t kMaxManifestBytes = std::size_t{64} << 20;
constexpr const char* kNewPrefix = ".liftcheck-new-";  ///< a mount point's entries being copied in

bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() > tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

/// What a liftcheck output folder written before manifests holds, by its results.json (a missing
/// or unreadable one: only the fixed names): the fixed files, a page per scenario, and the plots,
/// snapshots and strips its "report" lists. Nothing is taken as liftcheck's by its name's pattern:
/// a user's notes.html or plots/mine.svg is not among these.
std::set<std::string> legacy_written(const fs::path& dir) {
  std::set<std::string> v{"results.json",   "junit.xml",           "summary.md",     "index.html",
                          "screenshot.png", StagedOutput::kMarker, "plots/plots.gp", "plots/gnuplot.log"};
  try {
    const nlohmann::json r =
        nlohmann::json::parse(read_text_file(dir / "results.json", std::size_t{512} << 20, "results file"));
    for (const auto& sc : r.value("scenarios", nlohmann::json::array())) {
      std::string page = sc.value("name", "");
      std::replace(page.begin(), page.end(), '.', '_');
      v.insert("scenario-" + page + ".html");
    }
    const nlohmann::json report = r.value("report", nlohmann::json::object());
    for (const char* list : {"plots", "snapshots", "strips"})
      for (const auto& item : report.value(list, nlohmann::json::array()))
        if (item.is_object() && item.contains("file") && item["file"].is_string())
          v.insert(item["file"].get<std::string>());
  } catch (const std::exception&) {}
  return v;
}

/// A staging folder's files (its process died while writing them, before any manifest): the
/// names liftcheck writes at the top, and inside snapshots/ and plots/, with their ".tmp".
bool staged_file(const std::string& rel) {
  if (ends_with(rel, ".tmp")) return staged_file(rel.substr(0, rel.size() - 4));
  if (rel.rfind("snapshots/", 0) == 0) return ends_with(rel, ".png") && rel.find('/', 10) == std::string::npos;
  if (rel.rfind("plots/", 0) == 0)
    return rel.find('/', 6) == std::string::npos &&
           (ends_with(rel, ".svg") || rel == "plots/plots.gp" || rel == "plots/gnuplot.log");
  return rel == "results.json" || rel == "junit.xml" || rel == "summary.md" || rel == "screenshot.png" ||
         ends_with(rel, ".html");
}

/// A folder without a manifest: what in it is not liftcheck's, at any depth, at most `max`. An
/// output folder's own files are those its results.json names (legacy_written); a staging
/// folder's, the names liftcheck writes (staged_file).
void foreign_without_manifest(const fs::path& dir, std::size_t max, std::vector<std::string>& foreign) {
  std::error_code ec;
  const bool staging = fs::exists(dir / StagedOutput::kStaging, ec);
  const std::set<std::string> legacy = staging ? std::set<std::string>{} : legacy_written(dir);
  const auto ours = [&](const std::string& rel) { return staging ? staged_file(rel) : legacy.count(rel) > 0; };
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    const fs::file_type type = fs::symlink_status(e.path(), ec).type();
    if (name == StagedOutput::kStaging || name.rfind(kNewPrefix, 0) == 0) continue;
    if (type == fs::file_type::directory && (name == "snapshots" || name == "plots")) {
      for (const auto& inner : fs::directory_iterator(e.path(), ec)) {
        const std::string file = name + "/" + inner.path().filename().string();
        const bool dir_inside = fs::symlink_status(inner.path(), ec).type() == fs::file_type::directory;
        if (dir_inside || fs::symlink_status(inner.path(), ec).type() != fs::file_type::regular || !ours(file))
          foreign.push_back(file + (dir_inside ? "/" : ""));
        if (foreign.size() >= max) return;
      }
    } else if (type != fs::file_type::regular || !ours(name)) {
      foreign.push_back(name + (type == fs::file_type::directory ? "/" : ""));
    }
    if (foreign.size() >= max) return;
  }
  if (ec) foreign.push_back(fmt::format("(unreadable: {})", ec.message()));
}

/// The manifest's entries, or nullopt-like false when the folder has none (or an older marker).
bool read_manifest(const fs::path& dir, std::set<std::string>& listed) {
  std::error_code ec;
  if (!fs::is_regular_file(dir / StagedOutput::kMarker, ec)) return false;
  const std::string text = read_text_file(dir / StagedOutput::kMarker, kMaxManifestBytes, "output manifest");
  std::size_t at = text.find('\n');
  if (text.substr(0, at) != kManifestHeader) return false;
  while (at != std::string::npos && at + 1 < text.size()) {
    const std::size_t end = text.find('\n', at + 1);
    listed.insert(text.substr(at + 1, end == std::string::npos ? std::string::npos : end - at - 1));
    at = end;
  }
  return true;
}

/// A folder without a manifest is liftcheck's when it is empty, or holds only the names liftcheck
/// writes and, without even the older marker, a results.json that says it is liftcheck's.
bool legacy_results_say_ours(const fs::path& dir) {
  try {
    const std::string text = read_text_file(dir / "results.json", std::size_t{512} << 20, "results file");
    return nlohmann::json::parse(text).at("context").contains("liftcheck");
  } catch (const std::exception&) {
    return false;
  }
}

std::string rel_name(const fs::directory_entry& e, const fs::path& dir) {
  std::error_code ec;
  std::string rel = e.path().lexically_relative(dir).generic_string();
  if (fs::symlink_status(e.path(), ec).type() == fs::file_type::directory) rel += '/';
  return rel;
}

/// The start time of process `pid` (/proc/PID/stat, field 22), or "" when it is not running.
std::string process_start(long pid) {
  std::ifstream in(fmt::format("/proc/{}/stat", pid));
  std::string stat;
  if (!std::getline(in, stat)) return "";
  std::size_t at = stat.rfind(')');
  if (at == std::string::npos) return "";
  for (int field = 2; field < 22 && at != std::string::npos; ++field) at = stat.find(' ', at + 1);
  return at == std::string::npos ? "" : stat.substr(at + 1, stat.find(' ', at + 1) - at - 1);
}

/// The first `limit` bytes of a folder name, for the staging folder's name (NAME_MAX is 255).
std::string short_name(const std::string& name) { return name.substr(0, std::min<std::size_t>(name.size(), 200)); }

/// Copies `from` to the new file `to` with read and write, so that a full file system is named as
/// such: the library's copy takes a short sendfile for an I/O error ("Input/output error").
void copy_file_checked(const fs::path& from, const fs::path& to) {
  const auto fail = [&](const char* doing, const fs::path& p) {
    return std::runtime_error(fmt::format("{} '{}': {}", doing, printable(p.string(), 200), std::strerror(errno)));
  };
  const int in = ::open(from.c_str(), O_RDONLY | O_CLOEXEC);
  if (in < 0) throw fail("cannot read", from);
  const int out = ::open(to.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (out < 0) {
    const auto e = fail("cannot write", to);
    ::close(in);
    throw e;
  }
  std::vector<char> buf(std::size_t{1} << 20);
  for (;;) {
    const ssize_t got = ::read(in, buf.data(), buf.size());
    if (got < 0 && errno == EINTR) continue;
    if (got == 0) break;
    if (got < 0) {
      const auto e = fail("cannot read", from);
      ::close(in), ::close(out);
      throw e;
    }
    for (ssize_t done = 0; done < got;) {
      const ssize_t put = ::write(out, buf.data() + done, static_cast<std::size_t>(got - done));
      if (put < 0 && errno == EINTR) continue;
      if (put <= 0) {
        if (put == 0) errno = ENOSPC;
        const auto e = fail("cannot write", to);
        ::close(in), ::close(out);
        throw e;
      }
      done += put;
    }
  }
  ::close(in);
  if (::close(out) != 0) throw fail("cannot write", to);
}

/// The folder `from` copied into the new folder `to`, file by file (copy_file_checked).
void copy_tree(const fs::path& from, const fs::path& to) {
  for (auto it = fs::recursive_directory_iterator(from); it != fs::recursive_directory_iterator(); ++it) {
    const fs::path dest = to / it->path().lexically_relative(from);
    if (it->is_directory())
      fs::create_directory(dest);
    else
      copy_file_checked(it->path(), dest);
  }
}

/// Removes `dir`'s staging folders left by liftcheck processes that are gone (SIGKILL, a power
/// cut): only those whose staging file names a dead process and that hold nothing but liftcheck's.
void remove_stale_stages(const fs::path& parent, const std::string& prefix) {
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(parent, ec)) {
    const std::string name = e.path().filename().string();
    if (name.rfind(prefix, 0) != 0 || fs::symlink_status(e.path(), ec).type() != fs::file_type::directory) continue;
    std::ifstream in(e.path() / StagedOutput::kStaging);
    std::string tag, pid_word, start_word, start;
    long pid = 0;
    if (!(in >> tag >> pid_word >> pid >> start_word >> start) || tag != "liftcheck-staging" || pid <= 0) continue;
    if (process_start(pid) == start) continue;  // its process still runs
    if (!foreign_entries(e.path(), 1).empty()) continue;
    fs::remove_all(e.path(), ec);
  }
}

}  // namespace

std::vector<std::string> foreign_entries(const fs::path& dir, std::size_t max) {
  std::vector<std::string> foreign;
  std::error_code ec;
  std::set<std::string> listed;
  const bool manifest = read_manifest(dir, listed);
  if (!manifest) {
    const bool marked = fs::exists(dir / StagedOutput::kMarker, ec) || fs::exists(dir / StagedOutput::kStaging, ec);
    const bool any = fs::directory_iterator(dir, ec) != fs::directory_iterator();
    foreign_without_manifest(dir, max, foreign);
    if (foreign.empty() && any && !marked && !legacy_results_say_ours(dir))
      foreign.push_back("results.json (not liftcheck's)");
    return foreign;
  }
  for (auto it = fs::recursive_directory_iterator(dir, ec); !ec && it != fs::recursive_directory_iterator();
       it.increment(ec)) {
    const std::string rel = rel_name(*it, dir);
    if (rel == StagedOutput::kMarker || rel == StagedOutput::kStaging || rel.rfind(kNewPrefix, 0) == 0 ||
        listed.count(rel)) {
      if (rel.rfind(kNewPrefix, 0) == 0) it.disable_recursion_pending();
      continue;
    }
    foreign.push_back(rel);
    it.disable_recursion_pending();
    if (foreign.size() >= max) break;
  }
  if (ec) foreign.push_back(fmt::format("(unreadable: {})", ec.message()));
  return foreign;
}

StagedOutput::StagedOutput(const std::string& out_dir, const std::vector<std::pair<std::string, std::string>>& inputs)
    : out_(out_dir) {
  if (out_dir.empty()) throw InputError("--out names no folder");
  // A name no file system takes is bad input, named, before anything is looked up or runs.
  for (const fs::path& part : out_)
    if (part.native().size() > NAME_MAX)
      throw InputError(
          fmt::format("--out '{}': the name '{}' is {} bytes long, longer than the {} a file name may have",
                      printable(out_dir, 80), printable(part.string(), 40), part.native().size(), NAME_MAX));
  try {
    prepare(out_dir, inputs);
  } catch (const fs::filesystem_error& e) {
    if (!stage_.empty()) {
      std::error_code ec;
      fs::remove_all(stage_, ec);
    }
    throw InputError(fmt::format("--out '{}': {}", printable(out_dir, 200), e.code().message()));
  }
}

void StagedOutput::prepare(const std::string& out_dir, const std::vector<std::pair<std::string, std::string>>& inputs) {
  std::error_code ec;
  // A symbolic link is followed to its folder; a dangling one is refused before anything runs.
  if (fs::is_symlink(fs::symlink_status(out_, ec))) {
    const fs::path target = fs::read_symlink(out_, ec);
    if (!fs::exists(out_, ec))
      throw InputError(fmt::format(
          "--out '{}' is a symbolic link to '{}', which does not exist: give an existing folder or a new name",
          printable(out_dir, 200), printable(target.string(), 200)));
  }
  out_ = fs::weakly_canonical(fs::absolute(out_));
  if (!out_.has_filename()) out_ = out_.parent_path();
  // The working folder or one above it would be swapped away under the user's feet.
  const fs::path cwd = fs::weakly_canonical(fs::current_path(ec));
  const auto [o_end, c_it] = std::mismatch(out_.begin(), out_.end(), cwd.begin(), cwd.end());
  if (o_end == out_.end())
    throw InputError(fmt::format("--out '{}' is the working folder or one above it: give a folder of its own",
                                 printable(out_dir, 200)));
  for (const auto& [path, what] : inputs) refuse_inside(path, what);
  if (fs::exists(out_, ec)) {
    if (!fs::is_directory(out_, ec))
      throw InputError(fmt::format("--out '{}' is a file, not a folder", printable(out_dir, 200)));
    const std::vector<std::string> foreign = foreign_entries(out_);
    if (!foreign.empty()) {
      std::string names;
      for (const auto& f : foreign) names += (names.empty() ? "'" : ", '") + printable(f, 80) + "'";
      throw InputError(fmt::format(
          "--out '{}' holds files that liftcheck did not write ({}{}): not a liftcheck output folder, left alone",
          printable(out_dir, 200), names, foreign.size() >= 3 ? ", ..." : ""));
    }
  }
  if (!fs::create_directories(out_.parent_path(), ec) && ec)
    throw InputError(
        fmt::format("cannot create output folder '{}': {}", printable(out_.parent_path().string(), 200), ec.message()));
  const std::string prefix = fmt::format(".{}.partial-", short_name(out_.filename().string()));
  remove_stale_stages(out_.parent_path(), prefix);
  // A fresh name: an existing folder is never taken over (nor deleted).
  std::string tmpl = (out_.parent_path() / fmt::format("{}{}-XXXXXX", prefix, getpid())).string();
  if (!::mkdtemp(tmpl.data()))
    throw InputError(fmt::format("cannot create output folder '{}': {}", printable(tmpl, 200), std::strerror(errno)));
  stage_ = tmpl;
  try {
    write_file_atomic(stage_ / kStaging,
                      fmt::format("liftcheck-staging pid {} start {}\n", getpid(), process_start(getpid())));
  } catch (const std::exception& e) {
    fs::remove_all(stage_, ec);
    throw InputError(fmt::format("cannot create output folder '{}': {}", printable(stage_.string(), 200), e.what()));
  }
}

StagedOutput::~StagedOutput() {
  std::error_code ec;
  if (!keep_stage_ && fs::exists(stage_, ec)) fs::remove_all(stage_, ec);
}

void StagedOutput::refuse_inside(const std::string& path, const std::string& what) const {
  if (path.empty()) return;
  const fs::path f = fs::weakly_canonical(fs::absolute(path));
  if (std::mismatch(out_.begin(), out_.end(), f.begin(), f.end()).first == out_.end())
    throw InputError(fmt::format("{} '{}' must not be inside --out '{}': that folder is replaced whole", what,
                                 printable(path, 200), printable(out_.string(), 200)));
}

void StagedOutput::fail_keeping(const std::string& why, bool old_intact) {
  // Kept for the user: without its staging file no later run takes it for a stale one.
  keep_stage_ = true;
  std::error_code ec;
  fs::remove(stage_ / kStaging, ec);
  throw InputError(fmt::format("cannot write '{}': {} ({}the results are kept in '{}')", printable(out_.string(), 200),
                               why, old_intact ? "the previous output is as it was; " : "",
                               printable(stage_.string(), 200)));
}

void StagedOutput::publish() {
  std::error_code ec;
  // The manifest: every file and folder written, so that the next run knows what is liftcheck's.
  std::string manifest = std::string(kManifestHeader) + "\n";
  for (auto it = fs::recursive_directory_iterator(stage_, ec); !ec && it != fs::recursive_directory_iterator();
       it.increment(ec)) {
    const std::string rel = rel_name(*it, stage_);
    if (rel != kStaging && rel != kMarker) manifest += rel + "\n";
  }
  if (ec) fail_keeping(fmt::format("cannot list '{}': {}", printable(stage_.string(), 200), ec.message()));
  try {
    write_file_atomic(stage_ / kMarker, manifest);
  } catch (const std::exception& e) {
    fail_keeping(e.what());
  }
  if (!fs::exists(out_, ec)) {
    if (::rename(stage_.c_str(), out_.c_str()) != 0) fail_keeping(std::strerror(errno));
  } else if (::renameat2(AT_FDCWD, stage_.c_str(), AT_FDCWD, out_.c_str(), RENAME_EXCHANGE) == 0) {
    // stage_ now holds the previous output: removed unless something not liftcheck's got in.
    if (foreign_entries(stage_, 1).empty())
      fs::remove_all(stage_, ec);
    else
      std::cerr << fmt::format(
          "liftcheck: the previous output is kept in '{}': it holds files liftcheck did not write\n",
          printable(stage_.string(), 200));
  } else if (errno == EBUSY || errno == EXDEV || errno == EINVAL) {
    replace_entries();  // a mount point (or a file system without an atomic exchange)
  } else {
    fail_keeping(std::strerror(errno));
  }
  fs::remove(out_ / kStaging, ec);
  keep_stage_ = true;  // nothing left to remove: stage_ is gone or kept on purpose
}

void StagedOutput::replace_entries() {
  std::error_code ec;
  // The new entries are copied in beside the old ones first: a full disk leaves the old output whole.
  std::string tmpl = (out_ / fmt::format("{}XXXXXX", kNewPrefix)).string();
  if (!::mkdtemp(tmpl.data())) fail_keeping(std::strerror(errno));
  const fs::path incoming = tmpl;
  try {
    copy_tree(stage_, incoming);
  } catch (const std::exception& e) {
    fs::remove_all(incoming, ec);
    fail_keeping(e.what());
  }
  // Then the old entries go (only liftcheck's), and the new ones are renamed in, the manifest last.
  std::set<std::string> foreign_top;
  for (const auto& f : foreign_entries(out_, 1000)) foreign_top.insert(f.substr(0, f.find('/')));
  for (const auto& e : fs::directory_iterator(out_, ec)) {
    const std::string name = e.path().filename().string();
    if (e.path() != incoming && !foreign_top.count(name)) fs::remove_all(e.path(), ec);
  }
  std::vector<fs::path> entries;
  for (const auto& e : fs::directory_iterator(incoming, ec)) entries.push_back(e.path());
  std::stable_partition(entries.begin(), entries.end(),
                        [](const fs::path& p) { return p.filename() != StagedOutput::kMarker; });
  for (const fs::path& p : entries)
    if (::rename(p.c_str(), (out_ / p.filename()).c_str()) != 0)
      fail_keeping(fmt::format("{} (moving the new entries in, the old ones removed)", std::strerror(errno)), false);
  fs::remove(incoming, ec);
  fs::remove_all(stage_, ec);
}

}  // namespace liftcheck::cli

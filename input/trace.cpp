#include "input/trace.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "input/interrupt.hpp"
#include "input/read_file.hpp"

namespace liftcheck {

namespace {

using json = nlohmann::json;

std::string trim(std::string s) {
  s.erase(0, s.find_first_not_of(" \t\r"));
  s.erase(s.find_last_not_of(" \t\r") + 1);
  return s;
}

/// One CSV cell as a finite number (locale-independent), or an InputError naming where.
double number_at(const std::string& text, const std::string& file, int line, const std::string& column) {
  const std::string t = trim(text);
  const char* first = t.data();
  const char* last = t.data() + t.size();
  if (!t.empty() && *first == '+') ++first;
  double v = NAN;
  const auto [ptr, ec] = std::from_chars(first, last, v);
  if (!t.empty() && ptr == last && ec == std::errc::result_out_of_range)
    throw InputError(
        fmt::format("{}:{}: column '{}' is out of the range of a double: '{}'", file, line, column, printable(text)));
  if (t.empty() || ec != std::errc() || ptr != last)
    throw InputError(fmt::format("{}:{}: column '{}' is not a number: '{}'", file, line, column, printable(text)));
  if (!std::isfinite(v))
    throw InputError(fmt::format("{}:{}: column '{}' is not finite: '{}'", file, line, column, printable(text)));
  return v;
}

}  // namespace

std::string printable(const std::string& s, std::size_t max) {
  std::string o;
  const auto* p = reinterpret_cast<const unsigned char*>(s.data());
  for (std::size_t i = 0; i < s.size();) {
    if (o.size() >= max) return o + "...";
    const unsigned c = p[i];
    // A well-formed UTF-8 sequence is kept; a control character or a stray byte is '?'.
    const std::size_t len = c < 0x80 ? 1 : (c & 0xE0) == 0xC0 ? 2 : (c & 0xF0) == 0xE0 ? 3 : (c & 0xF8) == 0xF0 ? 4 : 0;
    if (len > 1 && i + len <= s.size() && is_utf8(s.substr(i, len))) {
      o.append(s, i, len);
      i += len;
      continue;
    }
    o += c < 0x20 || c >= 0x7f ? '?' : static_cast<char>(c);
    ++i;
  }
  return o;
}

namespace {

/// Builds the document in one pass (linear in the text: nlohmann's callback parser, which the
/// depth limit used before, is quadratic) and checks on the way what the document cannot say
/// afterwards: the nesting depth (copying or printing a document recurses that deep), a key repeated
/// in one object (the last would silently win), an interruption.
class CheckedDom {
 public:
  CheckedDom(json& root, const std::string& file, int max_depth, const RunHook* on_run = nullptr)
      : root_(root), file_(file), max_depth_(max_depth), on_run_(on_run) {
    open_.reserve(static_cast<std::size_t>(max_depth) + 1);
  }
  bool null() { return put(json()); }
  bool boolean(bool v) { return put(v); }
  bool number_integer(json::number_integer_t v) { return put(v); }
  bool number_unsigned(json::number_unsigned_t v) { return put(v); }
  bool number_float(json::number_float_t v, const std::string&) { return put(v); }
  bool string(std::string& v) { return put(std::move(v)); }
  bool binary(json::binary_t& v) { return put(json::binary(std::move(v))); }
  bool start_object(std::size_t) { return open(json::object()); }
  bool start_array(std::size_t) { return open(json::array()); }
  bool end_object() { return close(); }
  bool end_array() { return close(); }
  bool key(std::string& k) {
    open_.back().key = std::move(k);
    return true;
  }
  template <class Exception>
  bool parse_error(std::size_t, const std::string&, const Exception& e) {
    throw e;
  }

 private:
  struct Open {
    json* value;
    std::string key;  ///< objects: the key being read
  };
  /// Places `v` in the innermost open container (or as the document) and returns where it went.
  json* place(json&& v) {
    if ((++events_ & 0xFFFF) == 0)
      throw_if_interrupted_by([&] { return fmt::format("while reading '{}'", printable(file_, 200)); });
    if (open_.empty()) {
      root_ = std::move(v);
      return &root_;
    }
    json& c = *open_.back().value;
    if (c.is_array()) {
      c.push_back(std::move(v));
      return &c.back();
    }
    // One look-up finds a repeated key and places the value (the key stays for where()).
    auto [at, inserted] = c.get_ref<json::object_t&>().try_emplace(open_.back().key, std::move(v));
    if (!inserted)
      throw InputError(fmt::format("{}: {}: the key '{}' appears twice in one object (which one is meant?)", file_,
                                   where(), printable(at->first)));
    return &at->second;
  }
  bool put(json&& v) {
    json* at = place(std::move(v));
    if (in_runs()) hand_over(*at);
    return true;
  }
  /// The innermost open container is the top level's "runs" array.
  bool in_runs() const {
    return on_run_ && open_.size() == 2 && open_[0].value->is_object() && open_[0].key == "runs" &&
           open_[1].value->is_array();
  }
  /// A run has ended: handed to the hook, null left in its place.
  void hand_over(json& run) {
    (*on_run_)(open_[1].value->size() - 1, run, root_);
    run = json();
  }
  bool close() {
    json* closed = open_.back().value;
    open_.pop_back();
    if (in_runs()) hand_over(*closed);
    return true;
  }
  bool open(json&& container) {
    if (static_cast<int>(open_.size()) >= max_depth_)
      throw InputError(fmt::format("{}: JSON nested deeper than {} levels", file_, max_depth_));
    json* at = place(std::move(container));
    open_.push_back({at, {}});
    return true;
  }
  /// "runs[3].metrics" for the innermost open object.
  std::string where() const {
    std::string w;
    for (std::size_t i = 0; i + 1 < open_.size(); ++i) {
      if (open_[i].value->is_array()) {
        w += fmt::format("[{}]", open_[i].value->size() - 1);
        continue;
      }
      if (!w.empty()) w += '.';
      w += printable(open_[i].key, 60);
    }
    return w.empty() ? "the top level" : w;
  }

  json& root_;
  const std::string& file_;
  int max_depth_;
  const RunHook* on_run_;
  std::vector<Open> open_;
  std::size_t events_ = 0;
};

}  // namespace

json parse_json_text(std::string_view text, const std::string& file, int max_depth) {
  json root;
  CheckedDom dom(root, file, max_depth);
  try {
    json::sax_parse(text, &dom);
  } catch (const json::exception& e) {
    throw not_json_error(e, file);
  }
  return root;
}

json parse_json_runs(std::string_view text, const std::string& file, const RunHook& on_run, int max_depth) {
  json root;
  CheckedDom dom(root, file, max_depth, &on_run);
  try {
    json::sax_parse(text, &dom);
  } catch (const json::exception& e) {
    throw not_json_error(e, file);
  }
  return root;
}

InputError not_json_error(const json::exception& e, const std::string& file) {
  std::string what = e.what();
  if (const auto k = what.find("] "); what.rfind("[json.exception", 0) == 0 && k != std::string::npos)
    what = what.substr(k + 2);
  return InputError(fmt::format("{}: is not JSON ({})", file, printable(what, 200)));
}

const std::vector<std::string>& trace_columns(Vehicle vehicle) {
  static const std::vector<std::string> car{"t", "alpha", "beta", "x", "y", "phi"},
      disks{"t", "cMx", "cMy", "cNx", "cNy"};
  return vehicle == Vehicle::kCar ? car : disks;
}

Trace read_trace(const std::filesystem::path& file, Vehicle vehicle) {
  require_utf8(file.string(), "trace file name");
  return parse_trace(read_text_file(file, kMaxTraceBytes, "trace"), file.string(), vehicle);
}

namespace {

/// The text without a UTF-8 byte-order mark; InputError for UTF-16 or UTF-32 (or any NUL byte):
/// the columns would never be found in it.
std::string_view utf8_text(const std::string& text, const std::string& file) {
  std::string_view v(text);
  if (v.substr(0, 3) == "\xEF\xBB\xBF") v.remove_prefix(3);
  if (v.substr(0, 2) == "\xFF\xFE" || v.substr(0, 2) == "\xFE\xFF")
    throw InputError(
        fmt::format("{}: is UTF-16 or UTF-32 (it starts with that byte-order mark): save it as UTF-8", file));
  if (const auto nul = v.find('\0'); nul != std::string_view::npos)
    throw InputError(fmt::format(
        "{}: holds a NUL byte (at byte {}): not UTF-8 text (UTF-16 without a byte-order mark?); save it as UTF-8", file,
        nul + static_cast<std::size_t>(v.data() - text.data())));
  return v;
}

std::string header_precision(const std::string& p, const std::string& where) {
  if (p != "float32" && p != "float64")
    throw InputError(fmt::format("{}: precision '{}' must be float32 or float64", where, printable(p)));
  return p;
}
}  // namespace

namespace {

/// The header's 'precision' and 'settings' of a JSON trace, into `tr`.
void read_json_header(const json& j, Trace& tr) {
  if (!j.is_object()) return;
  if (j.contains("precision")) {
    if (!j["precision"].is_string())
      throw InputError(fmt::format("{}: 'precision' must be \"float32\" or \"float64\"", tr.file));
    tr.precision = header_precision(j["precision"].get<std::string>(), tr.file);
  }
  if (j.contains("settings")) {
    if (!j["settings"].is_object())
      throw InputError(fmt::format("{}: 'settings' must be an object of strings", tr.file));
    for (const auto& [k, v] : j["settings"].items()) {
      if (!v.is_string()) throw InputError(fmt::format("{}: setting '{}' must be a string", tr.file, printable(k)));
      tr.settings.emplace_back(printable(k), printable(v.get<std::string>()));
    }
  }
}

/// Appends `row` (its time first) to `tr`; InputError when time does not increase, at the place
/// `where()` names (made only then).
template <class Where>
void append_row(Trace& tr, std::vector<double> row, const Where& where) {
  if (!tr.rows.empty() && !(row[0] > tr.rows.back()[0]))
    throw InputError(
        fmt::format("{}: time goes from {:g} to {:g} s: it must increase", where(), tr.rows.back()[0], row[0]));
  tr.rows.push_back(std::move(row));
}

/// A JSON trace: an array of rows, or {"rows": [...]} with an optional header.
void read_json_trace(std::string_view text, const std::vector<std::string>& want, Trace& tr) {
  const json j = parse_json_text(text, tr.file);
  static const json kNone;
  const auto it = j.is_object() ? j.find("rows") : j.end();
  const json& rows = !j.is_object() ? j : it != j.end() ? *it : kNone;  // a reference: no copy of the document
  if (!rows.is_array())
    throw InputError(fmt::format("{}: JSON trace needs an array of rows (or {{\"rows\": [...]}})", tr.file));
  read_json_header(j, tr);
  int i = 0;
  for (const auto& r : rows) {
    ++i;
    if (!r.is_object())
      throw InputError(
          fmt::format("{}: row {} is not an object with the columns {}", tr.file, i, fmt::join(want, ", ")));
    std::vector<double> row;
    for (const auto& c : want) {
      const auto col = r.find(c);
      if (col == r.end()) throw InputError(fmt::format("{}: row {} has no column '{}'", tr.file, i, c));
      if (!col->is_number() || !std::isfinite(col->get<double>()))
        throw InputError(fmt::format("{}: row {}: column '{}' is not a finite number", tr.file, i, c));
      row.push_back(col->get<double>());
    }
    append_row(tr, std::move(row), [&] { return fmt::format("{}: row {}", tr.file, i); });
  }
}

/// A CSV comment line (after '#'): a '# precision:' or '# setting: KEY=VALUE' header, else nothing.
void read_csv_comment(const std::string& c, int n, Trace& tr) {
  if (c.rfind("precision:", 0) == 0)
    tr.precision = header_precision(trim(c.substr(10)), fmt::format("{}:{}", tr.file, n));
  if (c.rfind("setting:", 0) == 0) {
    const std::string kv = trim(c.substr(8));
    const std::size_t eq = kv.find('=');
    if (eq == std::string::npos || eq == 0)
      throw InputError(fmt::format("{}:{}: '# setting:' needs KEY=VALUE", tr.file, n));
    tr.settings.emplace_back(printable(trim(kv.substr(0, eq))), printable(trim(kv.substr(eq + 1))));
  }
}

std::vector<std::string> csv_cells(const std::string& t) {
  std::vector<std::string> cells;
  std::size_t from = 0;
  for (std::size_t comma; (comma = t.find(',', from)) != std::string::npos; from = comma + 1)
    cells.push_back(trim(t.substr(from, comma - from)));
  cells.push_back(trim(t.substr(from)));
  return cells;
}

/// For each wanted column, its position in the CSV header `cells`.
std::vector<std::size_t> csv_header(const std::vector<std::string>& cells, const std::vector<std::string>& want, int n,
                                    const Trace& tr) {
  std::vector<std::size_t> index;
  for (const auto& c : want) {
    const auto it = std::find(cells.begin(), cells.end(), c);
    if (it == cells.end())
      throw InputError(
          fmt::format("{}:{}: the header has no column '{}' (needs {})", tr.file, n, c, fmt::join(want, ",")));
    index.push_back(static_cast<std::size_t>(it - cells.begin()));
  }
  return index;
}

/// A CSV trace: '#' comments (the header's precision and settings), a header line naming the columns, rows.
void read_csv_trace(std::string_view text, const std::vector<std::string>& want, Trace& tr) {
  std::istringstream lines{std::string(text)};
  std::string line;
  int n = 0;
  std::vector<std::size_t> index;  // for each wanted column, its position in the header
  std::size_t width = 0;
  while (std::getline(lines, line)) {
    if ((++n & 0xFFFF) == 0) throw_if_interrupted_by([&] { return fmt::format("while reading '{}'", tr.file); });
    const std::string t = trim(line);
    if (!t.empty() && t[0] == '#') read_csv_comment(trim(t.substr(1)), n, tr);
    if (t.empty() || t[0] == '#') continue;
    const std::vector<std::string> cells = csv_cells(t);
    if (index.empty()) {
      index = csv_header(cells, want, n, tr);
      width = cells.size();
      continue;
    }
    if (cells.size() != width)
      throw InputError(fmt::format("{}:{}: {} columns, the header has {}", tr.file, n, cells.size(), width));
    std::vector<double> row;
    for (std::size_t k = 0; k < want.size(); ++k) row.push_back(number_at(cells[index[k]], tr.file, n, want[k]));
    append_row(tr, std::move(row), [&] { return fmt::format("{}:{}", tr.file, n); });
  }
  if (index.empty()) throw InputError(fmt::format("{}: no header line (needs {})", tr.file, fmt::join(want, ",")));
}

}  // namespace

Trace parse_trace(const std::string& whole, const std::string& file, Vehicle vehicle) {
  Trace tr;
  tr.file = printable(file, 200);
  const std::string_view text = utf8_text(whole, tr.file);
  const std::vector<std::string>& want = trace_columns(vehicle);
  const std::size_t first = text.find_first_not_of(" \t\r\n");
  if (first != std::string::npos && (text[first] == '[' || text[first] == '{'))
    read_json_trace(text, want, tr);
  else
    read_csv_trace(text, want, tr);
  if (tr.rows.size() < 2)
    throw InputError(fmt::format("{}: {} rows; a trace needs at least 2", tr.file, tr.rows.size()));
  return tr;
}

}  // namespace liftcheck

#include "input/trace.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

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
    throw InputError(fmt::format("{}:{}: column '{}' is out of the range of a double: '{}'", file, line, column, printable(text)));
  if (t.empty() || ec != std::errc() || ptr != last)
    throw InputError(fmt::format("{}:{}: column '{}' is not a number: '{}'", file, line, column, printable(text)));
  if (!std::isfinite(v)) throw InputError(fmt::format("{}:{}: column '{}' is not finite: '{}'", file, line, column, printable(text)));
  return v;
}

}  // namespace

std::string printable(const std::string& s, std::size_t max) {
  std::string o;
  for (char c : s) {
    if (o.size() >= max) return o + "...";
    o += static_cast<unsigned char>(c) < 0x20 || c == 0x7f ? '?' : c;
  }
  return o;
}

json parse_json_text(const std::string& text, const std::string& file, int max_depth) {
  const json::parser_callback_t limit = [&](int depth, json::parse_event_t, json&) {
    if (depth > max_depth) throw InputError(fmt::format("{}: JSON nested deeper than {} levels", file, max_depth));
    return true;
  };
  try {
    return json::parse(text, limit);
  } catch (const json::exception& e) {
    std::string what = e.what();
    if (const auto k = what.find("] "); what.rfind("[json.exception", 0) == 0 && k != std::string::npos) what = what.substr(k + 2);
    throw InputError(fmt::format("{}: is not JSON ({})", file, printable(what, 200)));
  }
}

const std::vector<std::string>& trace_columns(const std::string& vehicle) {
  static const std::vector<std::string> car{"t", "alpha", "beta", "x", "y", "phi"}, disks{"t", "cMx", "cMy", "cNx", "cNy"};
  return vehicle == "car" ? car : disks;
}

Trace read_trace(const std::filesystem::path& file, const std::string& vehicle) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(fmt::format("cannot read trace '{}'", file.string()));
  std::stringstream buf;
  buf << in.rdbuf();
  if (in.bad()) throw InputError(fmt::format("cannot read trace '{}'", file.string()));
  return parse_trace(buf.str(), file.string(), vehicle);
}

namespace {
std::string header_precision(const std::string& p, const std::string& where) {
  if (p != "float32" && p != "float64") throw InputError(fmt::format("{}: precision '{}' must be float32 or float64", where, printable(p)));
  return p;
}
}  // namespace

Trace parse_trace(const std::string& text, const std::string& file, const std::string& vehicle) {
  Trace tr;
  tr.file = file;
  const std::vector<std::string>& want = trace_columns(vehicle);
  const std::size_t first = text.find_first_not_of(" \t\r\n");
  if (first != std::string::npos && (text[first] == '[' || text[first] == '{')) {
    const json j = parse_json_text(text, tr.file);
    static const json kNone;
    const auto it = j.is_object() ? j.find("rows") : j.end();
    const json& rows = !j.is_object() ? j : it != j.end() ? *it : kNone;  // a reference: no copy of the document
    if (!rows.is_array()) throw InputError(fmt::format("{}: JSON trace needs an array of rows (or {{\"rows\": [...]}})", tr.file));
    if (j.is_object() && j.contains("precision")) {
      if (!j["precision"].is_string()) throw InputError(fmt::format("{}: 'precision' must be \"float32\" or \"float64\"", tr.file));
      tr.precision = header_precision(j["precision"].get<std::string>(), tr.file);
    }
    if (j.is_object() && j.contains("settings")) {
      if (!j["settings"].is_object()) throw InputError(fmt::format("{}: 'settings' must be an object of strings", tr.file));
      for (const auto& [k, v] : j["settings"].items()) {
        if (!v.is_string()) throw InputError(fmt::format("{}: setting '{}' must be a string", tr.file, printable(k)));
        tr.settings.emplace_back(printable(k), printable(v.get<std::string>()));
      }
    }
    int i = 0;
    for (const auto& r : rows) {
      ++i;
      if (!r.is_object()) throw InputError(fmt::format("{}: row {} is not an object with the columns {}", tr.file, i, fmt::join(want, ", ")));
      std::vector<double> row;
      for (const auto& c : want) {
        const auto it = r.find(c);
        if (it == r.end()) throw InputError(fmt::format("{}: row {} has no column '{}'", tr.file, i, c));
        if (!it->is_number() || !std::isfinite(it->get<double>()))
          throw InputError(fmt::format("{}: row {}: column '{}' is not a finite number", tr.file, i, c));
        row.push_back(it->get<double>());
      }
      if (!tr.rows.empty() && !(row[0] > tr.rows.back()[0]))
        throw InputError(fmt::format("{}: row {}: time goes from {:g} to {:g} s: it must increase", tr.file, i, tr.rows.back()[0], row[0]));
      tr.rows.push_back(std::move(row));
    }
  } else {
    std::istringstream lines(text);
    std::string line;
    int n = 0;
    std::vector<std::size_t> index;  // for each wanted column, its position in the header
    std::size_t width = 0;
    while (std::getline(lines, line)) {
      ++n;
      const std::string t = trim(line);
      if (!t.empty() && t[0] == '#') {
        const std::string c = trim(t.substr(1));
        if (c.rfind("precision:", 0) == 0) tr.precision = header_precision(trim(c.substr(10)), fmt::format("{}:{}", tr.file, n));
        if (c.rfind("setting:", 0) == 0) {
          const std::string kv = trim(c.substr(8));
          const std::size_t eq = kv.find('=');
          if (eq == std::string::npos || eq == 0) throw InputError(fmt::format("{}:{}: '# setting:' needs KEY=VALUE", tr.file, n));
          tr.settings.emplace_back(printable(trim(kv.substr(0, eq))), printable(trim(kv.substr(eq + 1))));
        }
        continue;
      }
      if (t.empty()) continue;
      std::vector<std::string> cells;
      std::size_t from = 0;
      for (std::size_t comma; (comma = t.find(',', from)) != std::string::npos; from = comma + 1) cells.push_back(trim(t.substr(from, comma - from)));
      cells.push_back(trim(t.substr(from)));
      if (index.empty()) {
        for (const auto& c : want) {
          const auto it = std::find(cells.begin(), cells.end(), c);
          if (it == cells.end())
            throw InputError(fmt::format("{}:{}: the header has no column '{}' (needs {})", tr.file, n, c, fmt::join(want, ",")));
          index.push_back(static_cast<std::size_t>(it - cells.begin()));
        }
        width = cells.size();
        continue;
      }
      if (cells.size() != width)
        throw InputError(fmt::format("{}:{}: {} columns, the header has {}", tr.file, n, cells.size(), width));
      std::vector<double> row;
      for (std::size_t k = 0; k < want.size(); ++k) row.push_back(number_at(cells[index[k]], tr.file, n, want[k]));
      if (!tr.rows.empty() && !(row[0] > tr.rows.back()[0]))
        throw InputError(fmt::format("{}:{}: time goes from {:g} to {:g} s: it must increase", tr.file, n, tr.rows.back()[0], row[0]));
      tr.rows.push_back(std::move(row));
    }
    if (index.empty()) throw InputError(fmt::format("{}: no header line (needs {})", tr.file, fmt::join(want, ",")));
  }
  if (tr.rows.size() < 2) throw InputError(fmt::format("{}: {} rows; a trace needs at least 2", tr.file, tr.rows.size()));
  return tr;
}

}  // namespace liftcheck

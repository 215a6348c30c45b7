#include "input/suggest.hpp"

#include <algorithm>
#include <cctype>

namespace liftcheck {

std::size_t edit_distance(const std::string& a, const std::string& b) {
  // Names are short; inputs are capped so that a pasted megabyte costs nothing quadratic.
  constexpr std::size_t kMax = 256;
  const std::size_t n = std::min(a.size(), kMax), m = std::min(b.size(), kMax);
  std::vector<std::vector<std::size_t>> d(n + 1, std::vector<std::size_t>(m + 1, 0));
  for (std::size_t i = 0; i <= n; ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= m; ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= n; ++i)
    for (std::size_t j = 1; j <= m; ++j) {
      const std::size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  return d[n][m] + (a.size() - n) + (b.size() - m);
}

namespace {

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

}  // namespace

std::string nearest_name(const std::string& name, const std::vector<std::string>& candidates) {
  std::string best;
  std::size_t best_d = static_cast<std::size_t>(-1);
  for (const auto& c : candidates) {
    if (c == name) continue;
    const std::size_t d = lower(c) == lower(name) ? 0 : edit_distance(name, c);
    if (d < best_d) best = c, best_d = d;
  }
  const std::size_t limit = std::max<std::size_t>(1, std::max(name.size(), best.size()) / 3);
  if (!best.empty() && best_d <= limit) return best;
  // A name without its family ("circle" for "car.circle"), or mistyped within the part after the
  // family's dot: the candidate whose last dot-separated part is nearest, when near enough.
  if (name.empty() || name.find('.') != std::string::npos) return "";
  best.clear(), best_d = static_cast<std::size_t>(-1);
  for (const auto& c : candidates) {
    const std::size_t dot = c.rfind('.');
    if (dot == std::string::npos) continue;
    const std::string part = c.substr(dot + 1);
    const std::size_t d = lower(part) == lower(name) ? 0 : edit_distance(name, part);
    if (d < best_d) best = c, best_d = d;
  }
  const std::size_t part_limit = name.size() / 3;
  return !best.empty() && best_d <= part_limit ? best : "";
}

std::string did_you_mean(const std::string& name, const std::vector<std::string>& candidates) {
  const std::string n = nearest_name(name, candidates);
  return n.empty() ? "" : "; did you mean '" + n + "'?";
}

}  // namespace liftcheck

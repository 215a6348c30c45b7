// Fuzzes --set: the input's first byte picks a scenario of the catalogue, each further line is one
// --set argument (split_assignment), and the overrides are resolved against the scenario's real
// parameter specs. Only InputError may come out; whatever resolves must be in range.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "input/params.hpp"
#include "scenarios/scenario.hpp"
#include "input/suggest.hpp"

using namespace liftcheck;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const auto& all = scenarios();
  const Scenario& s = all[data[0] % all.size()];
  const std::string text(reinterpret_cast<const char*>(data + 1), size - 1);
  Overrides ov;
  std::size_t from = 0;
  while (from <= text.size()) {
    const std::size_t nl = std::min(text.find('\n', from), text.size());
    try {
      ov.push_back(split_assignment(text.substr(from, nl - from)));
    } catch (const InputError&) {}
    from = nl + 1;
  }
  try {
    const Params p = Params::resolve(s.params, ov, s.name);
    for (const ParamSpec& spec : s.params) {
      const auto in_range = [&](double v) {
        return std::isfinite(v) && (spec.min_exclusive ? v > spec.min : v >= spec.min) && v <= spec.max;
      };
      if (spec.kind == ParamKind::kNumber || spec.kind == ParamKind::kInteger) {
        if (!in_range(p.num(spec.key))) std::abort();
        if (spec.kind == ParamKind::kInteger && p.num(spec.key) != std::floor(p.num(spec.key))) std::abort();
      } else if (spec.kind == ParamKind::kVec2) {
        const auto v = p.vec(spec.key);
        if (!in_range(v[0]) || !in_range(v[1])) std::abort();
      } else {
        bool known = false;
        for (const auto& c : spec.choices) known = known || c == p.str(spec.key);
        if (!known) std::abort();
      }
    }
    (void)p.to_json().dump();
  } catch (const InputError& e) {
    if (std::string(e.what()).empty()) std::abort();
  }
  return 0;
}

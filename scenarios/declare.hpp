// The vocabulary the catalogue declares its scenarios in: parameters (number, integer, vec2,
// choice; lists joined with `with`, defaults replaced with `with_defaults`) and metrics with their
// tolerances for the reference and for every other engine (rel, abs_).
#pragma once

#include <cmath>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "input/params.hpp"
#include "scenarios/scenario.hpp"

namespace liftcheck::declare {

/// A real number in [min, max] (min excluded when `min_exclusive`).
inline ParamSpec number(std::string key, std::string def, std::string unit, std::string help, double min = -INFINITY,
                        bool min_exclusive = false, double max = INFINITY) {
  return {.key = std::move(key),
          .kind = ParamKind::kNumber,
          .default_text = std::move(def),
          .unit = std::move(unit),
          .help = std::move(help),
          .min = min,
          .min_exclusive = min_exclusive,
          .max = max};
}
/// An integer in [min, max].
inline ParamSpec integer(std::string key, std::string def, std::string unit, std::string help, double min, double max) {
  return {.key = std::move(key),
          .kind = ParamKind::kInteger,
          .default_text = std::move(def),
          .unit = std::move(unit),
          .help = std::move(help),
          .min = min,
          .max = max};
}
/// A vector of two numbers (a point or a velocity), each coordinate within [-bound, bound].
inline ParamSpec vec2(std::string key, std::string def, std::string unit, std::string help, double bound = 1e4) {
  return {.key = std::move(key),
          .kind = ParamKind::kVec2,
          .default_text = std::move(def),
          .unit = std::move(unit),
          .help = std::move(help),
          .min = -bound,
          .max = bound};
}
/// One of `choices` (no unit).
inline ParamSpec choice(std::string key, std::string def, std::string help, std::vector<std::string> choices) {
  return {.key = std::move(key),
          .kind = ParamKind::kChoice,
          .default_text = std::move(def),
          .help = std::move(help),
          .choices = std::move(choices)};
}
/// `base` followed by `extra`.
inline std::vector<ParamSpec> with(std::vector<ParamSpec> base, std::vector<ParamSpec> extra) {
  base.insert(base.end(), extra.begin(), extra.end());
  return base;
}
/// `params` with some keys' defaults replaced (a scenario's own speed or friction).
inline std::vector<ParamSpec> with_defaults(std::vector<ParamSpec> params,
                                            const std::map<std::string, std::string>& defaults) {
  for (auto& ps : params)
    if (const auto d = defaults.find(ps.key); d != defaults.end()) ps.default_text = d->second;
  return params;
}

/// A relative metric: tolerance `analytic` for the reference, `engines` for every other engine.
inline MetricDef rel(std::string name, std::string unit, double analytic, double engines, std::string help) {
  return {.name = std::move(name),
          .unit = std::move(unit),
          .kind = TolKind::kRelative,
          .tolerance = {{TolRole::kReference, analytic}, {TolRole::kDefault, engines}},
          .help = std::move(help)};
}
/// An absolute metric, tolerances as rel's.
inline MetricDef abs_(std::string name, std::string unit, double analytic, double engines, std::string help) {
  return {.name = std::move(name),
          .unit = std::move(unit),
          .kind = TolKind::kAbsolute,
          .tolerance = {{TolRole::kReference, analytic}, {TolRole::kDefault, engines}},
          .help = std::move(help)};
}

}  // namespace liftcheck::declare

#include "input/glob.hpp"

#include <fnmatch.h>

namespace liftcheck {

bool matches_any(const std::vector<std::string>& globs, const std::string& name) {
  for (const auto& g : globs)
    if (fnmatch(g.c_str(), name.c_str(), 0) == 0) return true;
  return false;
}

}  // namespace liftcheck

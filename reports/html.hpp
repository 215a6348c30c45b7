#pragma once
#include <nlohmann/json.hpp>
#include <string>

namespace liftcheck {
/// index.html built from results.json: the scenario x engine matrix and every metric table.
std::string index_html(const nlohmann::json& results);
}  // namespace liftcheck

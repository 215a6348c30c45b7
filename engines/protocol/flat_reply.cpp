#include "engines/protocol/flat_reply.hpp"

#include <charconv>
#include <cstring>

namespace liftcheck {

FlatReply::FlatReply(std::vector<Slot> slots) : slots_(std::move(slots)), values_(slots_.size()), seen_(slots_.size()) {
  for (size_t i = 0; i < slots_.size(); ++i) index_.emplace(slots_[i].path, i);
  path_.reserve(64);
}

/// A number goes to its slot (once); anything else must not stand where a slot is named.
bool FlatReply::scalar(simdjson::dom::element e) {
  const auto it = index_.find(path_);
  const simdjson::dom::element_type t = e.type();
  const bool whole = t == simdjson::dom::element_type::INT64 || t == simdjson::dom::element_type::UINT64;
  if (!whole && t != simdjson::dom::element_type::DOUBLE) return it == index_.end();
  if (it == index_.end() || seen_[it->second] || (slots_[it->second].integer && !whole)) return false;
  double v = 0.0;
  if (e.get_double().get(v)) return false;
  values_[it->second] = v;
  seen_[it->second] = 1;
  return true;
}

/// The value whose path is path_, and everything inside it; false where the fast path does not take it.
bool FlatReply::walk(simdjson::dom::element e) {
  const size_t own = path_.size();
  simdjson::dom::object object;
  simdjson::dom::array array;
  if (!e.get(object)) {
    for (const simdjson::dom::key_value_pair field : object) {
      path_.resize(own);
      path_ += '/';
      path_.append(field.key.data(), field.key.size());
      if (!walk(field.value)) return false;
    }
  } else if (!e.get(array)) {
    long k = 0;
    for (const simdjson::dom::element v : array) {
      path_.resize(own);
      path_ += '/';
      char digits[24];
      path_.append(digits, std::to_chars(digits, digits + sizeof digits, k++).ptr);
      if (!walk(v)) return false;
    }
  } else {
    return scalar(e);
  }
  path_.resize(own);
  return true;
}

bool FlatReply::read(const std::string& line) {
  std::fill(values_.begin(), values_.end(), 0.0);
  std::fill(seen_.begin(), seen_.end(), 0);
  padded_.resize(line.size() + simdjson::SIMDJSON_PADDING);
  std::memcpy(padded_.data(), line.data(), line.size());
  simdjson::dom::object doc;
  if (parser_.parse(padded_.data(), line.size(), false).get(doc)) return false;
  bool ok = false;
  if (doc["ok"].get(ok) || !ok) return false;
  // The top-level members: "ok" (once) is read above, every other one walked.
  int oks = 0;
  for (const simdjson::dom::key_value_pair field : doc) {
    if (field.key == "ok") {
      if (++oks > 1) return false;
      continue;
    }
    path_.assign(field.key.data(), field.key.size());
    if (!walk(field.value)) return false;
  }
  for (size_t i = 0; i < slots_.size(); ++i)
    if (slots_[i].required && !seen_[i]) return false;
  return true;
}

}  // namespace liftcheck

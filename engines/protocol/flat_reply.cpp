#include "engines/protocol/flat_reply.hpp"

#include <charconv>
#include <cmath>
#include <nlohmann/json.hpp>

namespace liftcheck {

/// The SAX events of one reply into FlatReply's slots; false from any event stops the parse
/// (the reply is then read the checked way).
class FlatSax final : public nlohmann::json_sax<nlohmann::json> {
 public:
  explicit FlatSax(FlatReply& r) : r_(r) {}
  bool null() override { return begin_value() && r_.index_.find(r_.path_) == r_.index_.end(); }
  bool boolean(bool v) override {
    if (!begin_value()) return false;
    if (r_.frames_.size() == 1 && r_.path_ == "ok") r_.ok_ = v;
    return r_.index_.find(r_.path_) == r_.index_.end();
  }
  bool number_integer(number_integer_t v) override { return number(static_cast<double>(v), true); }
  bool number_unsigned(number_unsigned_t v) override { return number(static_cast<double>(v), true); }
  bool number_float(number_float_t v, const string_t&) override { return number(v, false); }
  bool string(string_t&) override { return begin_value() && r_.index_.find(r_.path_) == r_.index_.end(); }
  bool binary(binary_t&) override { return false; }
  bool start_object(std::size_t) override { return open(false); }
  bool key(string_t& k) override {
    r_.path_.resize(r_.frames_.back().base);
    r_.path_ += k;
    return true;
  }
  bool end_object() override { return close(); }
  bool start_array(std::size_t) override { return r_.frames_.empty() ? false : open(true); }
  bool end_array() override { return close(); }
  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception&) override { return false; }

 private:
  /// Sets path_ to the name of the value that begins (its key was set by key()).
  bool begin_value() {
    if (r_.frames_.empty()) return false;  // a reply is an object
    FlatReply::Frame& f = r_.frames_.back();
    if (f.array) {
      r_.path_.resize(f.base);
      char digits[24];
      const auto end = std::to_chars(digits, digits + sizeof digits, f.next++).ptr;
      r_.path_.append(digits, end);
    }
    return true;
  }
  bool open(bool array) {
    if (!r_.frames_.empty()) {
      if (!begin_value()) return false;
      r_.path_ += '/';
    }
    r_.frames_.push_back({array, r_.path_.size(), 0});
    return true;
  }
  bool close() {
    r_.frames_.pop_back();
    return true;
  }
  bool number(double v, bool integer) {
    if (!begin_value()) return false;
    const auto it = r_.index_.find(r_.path_);
    if (it == r_.index_.end() || r_.seen_[it->second] || !std::isfinite(v)) return false;
    if (r_.slots_[it->second].integer && !integer) return false;
    r_.values_[it->second] = v;
    r_.seen_[it->second] = 1;
    return true;
  }
  FlatReply& r_;
};

FlatReply::FlatReply(std::vector<Slot> slots) : slots_(std::move(slots)), values_(slots_.size()), seen_(slots_.size()) {
  for (size_t i = 0; i < slots_.size(); ++i) index_.emplace(slots_[i].path, i);
  path_.reserve(64);
  frames_.reserve(8);
}

bool FlatReply::read(const std::string& line) {
  std::fill(values_.begin(), values_.end(), 0.0);
  std::fill(seen_.begin(), seen_.end(), 0);
  frames_.clear();
  path_.clear();
  ok_ = false;
  FlatSax sax(*this);
  if (!nlohmann::json::sax_parse(line, &sax, nlohmann::json::input_format_t::json, true) || !ok_) return false;
  for (size_t i = 0; i < slots_.size(); ++i)
    if (slots_[i].required && !seen_[i]) return false;
  return true;
}

}  // namespace liftcheck

// The numbers of a step reply read straight into slots named in advance ("x_m",
// "wheels/1/omega_W/2") with simdjson's DOM parser, which reuses its memory from reply to reply
// and parses numbers exactly (correctly rounded, as strtod): once the slots are made, nothing is
// allocated per step. A reply this fast path does not read as well formed (not
// one object, "ok" not true, a slot missing, given twice or not a finite number, a number where
// no slot is named) is left to the checked reading of the whole tree, which names what is wrong.
#pragma once

#include <simdjson.h>

#include <string>
#include <unordered_map>
#include <vector>

namespace liftcheck {

class FlatReply {
 public:
  struct Slot {
    std::string path;      ///< keys and array indices joined by '/'
    bool required = true;  ///< an optional slot left out reads as 0
    bool integer = false;  ///< must be a whole number (JSON without fraction or exponent)
  };
  explicit FlatReply(std::vector<Slot> slots);

  /// True when `line` is one JSON object with "ok": true whose every required slot holds one
  /// finite number and no number stands where no slot is named; the values are then value(i).
  bool read(const std::string& line);
  double value(size_t i) const { return values_[i]; }
  bool given(size_t i) const { return seen_[i] != 0; }

 private:
  bool walk(simdjson::dom::element e);
  bool scalar(simdjson::dom::element e);
  std::vector<Slot> slots_;
  std::unordered_map<std::string, size_t> index_;
  std::vector<double> values_;
  std::vector<char> seen_;
  std::string path_;          ///< the path of the value being read (reused)
  std::vector<char> padded_;  ///< the line with simdjson's padding after it (reused)
  simdjson::dom::parser parser_;
};

}  // namespace liftcheck

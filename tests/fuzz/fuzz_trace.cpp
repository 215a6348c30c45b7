// Fuzzes the trace reader (CSV and JSON): the first byte picks the vehicle. Only InputError may
// come out; an accepted trace has at least two rows of the vehicle's columns, all finite, in
// strictly increasing time.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "input/trace.hpp"

using namespace liftcheck;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const Vehicle vehicle = data[0] % 2 ? Vehicle::kCar : Vehicle::kDisks;
  const std::string text(reinterpret_cast<const char*>(data + 1), size - 1);
  try {
    const Trace tr = parse_trace(text, "fuzz.csv", vehicle);
    if (tr.rows.size() < 2) std::abort();
    for (std::size_t i = 0; i < tr.rows.size(); ++i) {
      if (tr.rows[i].size() != trace_columns(vehicle).size()) std::abort();
      for (double v : tr.rows[i])
        if (!std::isfinite(v)) std::abort();
      if (i > 0 && !(tr.rows[i][0] > tr.rows[i - 1][0])) std::abort();
    }
  } catch (const InputError&) {}
  return 0;
}

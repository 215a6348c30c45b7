// Fuzzes the results/baseline loader: a document it accepts must go through diff_results and
// diff_text (against itself and against an empty file) without any exception; a document it
// refuses must be refused with an InputError.
#include <cstdint>
#include <string>
#include <utility>

#include "input/params.hpp"
#include "input/results_file.hpp"
#include "input/results_codec.hpp"
#include "input/results_diff.hpp"

using namespace liftcheck;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  // The index reader of `diff` refuses what the full reader refuses, with the same message.
  std::string index_error;
  ResultsIndex index;
  try {
    index = parse_results_index(text, "fuzz.json");
  } catch (const InputError& e) {
    index_error = e.what();
  }
  SuiteResults results;
  try {
    results = parse_results(text, "fuzz.json");
  } catch (const InputError& e) {
    if (index_error != e.what()) __builtin_trap();
    return 0;
  }
  if (!index_error.empty()) __builtin_trap();
  // And what it accepts, the index reader reads as the full reader's results give it: the same
  // diff against itself and against an empty file, both ways.
  const ResultsIndex full = index_of(results), empty;
  using Pair = std::pair<const ResultsIndex*, const ResultsIndex*>;
  for (const auto& [base, head] : {Pair{&index, &index}, Pair{&empty, &index}, Pair{&index, &empty}}) {
    const ResultsDiff d = diff_results(*base, *head);
    const ResultsIndex* full_base = base == &empty ? &empty : &full;
    const ResultsIndex* full_head = head == &empty ? &empty : &full;
    if (encode_diff(d) != encode_diff(diff_results(*full_base, *full_head))) __builtin_trap();
    (void)diff_text(d);
  }
  return 0;
}

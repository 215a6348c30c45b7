// Fuzzes the results/baseline loader: a document it accepts must go through diff_results and
// diff_text (against itself and against an empty file) without any exception; a document it
// refuses must be refused with an InputError.
#include <cstdint>
#include <string>
#include <utility>

#include "input/params.hpp"
#include "input/results_file.hpp"
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
  nlohmann::json j;
  try {
    j = parse_results(text, "fuzz.json");
  } catch (const InputError& e) {
    if (index_error != e.what()) __builtin_trap();
    return 0;
  }
  if (!index_error.empty()) __builtin_trap();
  if (diff_results(index, index) != diff_results(j, j)) __builtin_trap();
  const nlohmann::json empty{{"runs", nlohmann::json::array()}};
  const nlohmann::json& doc = j;
  using Pair = std::pair<const nlohmann::json*, const nlohmann::json*>;
  for (const auto& [base, head] : {Pair{&doc, &doc}, Pair{&empty, &doc}, Pair{&doc, &empty}}) {
    const nlohmann::json d = diff_results(*base, *head);
    (void)diff_text(d);
  }
  return 0;
}

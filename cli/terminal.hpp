// What the terminal shows: colour when standard output is a terminal (NO_COLOR respected), and a
// verdict word in its colour.
#pragma once

#include <cstdlib>
#include <string>
#include <unistd.h>

namespace liftcheck::cli {

/// Colour on standard output only when it is a terminal and NO_COLOR is unset or empty.
inline bool stdout_in_colour() {
  const char* no = std::getenv("NO_COLOR");
  return isatty(STDOUT_FILENO) != 0 && (no == nullptr || *no == '\0');
}

/// `text` in the colour of `verdict` (pass green, known failure blue, fail and unexpected pass
/// red, error yellow, skip dim), padded to `width` before the colour so columns stay aligned.
inline std::string paint(const std::string& verdict, std::string text, std::size_t width = 0) {
  if (text.size() < width) text.append(width - text.size(), ' ');
  if (!stdout_in_colour()) return text;
  const char* code = verdict == "pass"            ? "32"
                     : verdict == "known failure" ? "36"
                     : verdict == "error"         ? "33"
                     : verdict == "skip"          ? "2"
                                                  : "1;31";
  return std::string("\033[") + code + "m" + text + "\033[0m";
}

inline std::string coloured_verdict(const std::string& verdict, std::size_t width = 0) {
  return paint(verdict, verdict, width);
}

}  // namespace liftcheck::cli

#pragma once
#include <string>
#include <string_view>

namespace liftcheck {

/// Escapes text for HTML and XML content and attribute values (& < > " '); a control character
/// other than a tab or a line break (XML 1.0 allows no other, an ANSI escape among them) is '?'.
inline std::string escape_markup(const std::string& s) {
  std::string o;
  o.reserve(s.size());
  for (char c : s) {
    switch (c) {
      case '&':
        o += "&amp;";
        break;
      case '<':
        o += "&lt;";
        break;
      case '>':
        o += "&gt;";
        break;
      case '"':
        o += "&quot;";
        break;
      case '\'':
        o += "&apos;";
        break;
      default:
        o += (static_cast<unsigned char>(c) < 0x20 && c != '\t' && c != '\n' && c != '\r') || c == 0x7f ? '?' : c;
    }
  }
  return o;
}

/// A name in Markdown text or a table cell: control characters (a line break would end the line
/// or the table) as '?', the punctuation that is Markdown inside a line ('|' ends a cell) escaped with a backslash.
inline std::string escape_markdown(const std::string& s) {
  std::string o;
  o.reserve(s.size());
  for (char c : s) {
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f)
      o += '?';
    else if (std::string_view("\\`*_[]<>|~").find(c) != std::string_view::npos)
      o += '\\', o += c;
    else
      o += c;
  }
  return o;
}

/// A name inside a Markdown code span: it cannot hold a backtick (which would end the span) or a
/// line break, and a '|' would still end a table cell.
inline std::string markdown_code(const std::string& s) {
  std::string o;
  for (char c : s) o += static_cast<unsigned char>(c) < 0x20 || c == 0x7f ? '?' : c == '`' ? '\'' : c == '|' ? '/' : c;
  return "`" + o + "`";
}

}  // namespace liftcheck

// Text for messages and tables: a number printf-style, formatNumber(v) as
// "%g", formatNumber(t, "%.6f") (std::to_string would print 1e-9 as
// 0.000000); a field of a CSV file; a cell of a Markdown table.
#pragma once

#include <cstdio>
#include <string>

namespace cws {

inline std::string formatNumber(double v, const char* format = "%g") {
  char text[64];
  std::snprintf(text, sizeof text, format, v);
  return text;
}

// A CSV field (RFC 4180): quoted, with its quotes doubled, when it holds a
// comma, a quote or a line break.
inline std::string csvField(const std::string& s) {
  if (s.find_first_of(",\"\r\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

// A Markdown table cell: a bar escaped (it would end the cell), line breaks
// as spaces (they would end the row).
inline std::string markdownCell(const std::string& s) {
  std::string out;
  out.reserve(s.size());
  for (char c : s) {
    if (c == '|') {
      out += "\\|";
    } else {
      out += (c == '\n' || c == '\r') ? ' ' : c;
    }
  }
  return out;
}

}  // namespace cws

// A number for a message, printf-style: formatNumber(v) as "%g",
// formatNumber(t, "%.6f"). (std::to_string would print 1e-9 as 0.000000.)
#pragma once

#include <cstdio>
#include <string>

namespace cws {

inline std::string formatNumber(double v, const char* format = "%g") {
  char text[64];
  std::snprintf(text, sizeof text, format, v);
  return text;
}

}  // namespace cws

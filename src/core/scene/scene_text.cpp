// Message text of scene errors: keys, user text and numbers as a message
// shows them.
#include <cstdio>

#include "coil_winding_sim/core/base/text_format.hpp"
#include "scene_detail.hpp"

namespace cws::detail {

std::string join(const std::string& prefix, const std::string& key) {
  return prefix.empty() ? key : prefix + "." + key;
}

namespace {
// Length of the valid UTF-8 sequence at text[i], or 0 if there is none.
std::size_t utf8Length(const std::string& text, std::size_t i) {
  const unsigned char c = static_cast<unsigned char>(text[i]);
  const std::size_t n = c < 0x80           ? 1
                        : (c >> 5) == 0x6  ? 2
                        : (c >> 4) == 0xe  ? 3
                        : (c >> 3) == 0x1e ? 4
                                           : 0;
  if (n == 0 || i + n > text.size()) return 0;
  for (std::size_t k = 1; k < n; ++k) {
    if ((static_cast<unsigned char>(text[i + k]) & 0xc0) != 0x80) return 0;
  }
  return n;
}
}  // namespace

// A scene may hold any bytes; a message goes to a terminal or a log.
std::string printable(const std::string& text, std::size_t max) {
  const std::string cut = text.substr(0, max);
  std::string out;
  for (std::size_t i = 0; i < cut.size();) {
    const unsigned char c = static_cast<unsigned char>(cut[i]);
    const std::size_t n = utf8Length(cut, i);
    if (n == 0 || c < 0x20 || c == 0x7f) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", c);
      out += buf;
      ++i;
    } else {
      out.append(cut, i, n);
      i += n;
    }
  }
  return text.size() > max ? out + "..." : out;
}

// std::to_string would print 1e-9 as 0.000000.
std::string fmt(double v) { return formatNumber(v, "%.6g"); }

std::string describe(const YAML::Node& n) {
  switch (n.Type()) {
    case YAML::NodeType::Null:
      return "nothing (null)";
    case YAML::NodeType::Sequence:
      return "a list of " + std::to_string(n.size());
    case YAML::NodeType::Map:
      return "a map";
    default:
      return "'" + printable(n.Scalar()) + "'";
  }
}

// 1-based line numbers, as editors show them.
std::string lineOf(const YAML::Node& n, const char* what) {
  const YAML::Mark m = n.Mark();
  return m.is_null() ? std::string()
                     : " (" + std::string(what) + " " + std::to_string(m.line + 1) + ")";
}

}  // namespace cws::detail

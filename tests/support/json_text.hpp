// A string as a JSON string literal, for the support code that writes JSON (the pictures'
// metadata, svg_circles): quotes and backslashes escaped, control characters as spaces.
#pragma once

#include <string>
#include <string_view>

namespace billiard::testing {

inline std::string json_string(std::string_view text) {
  std::string result = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\') {
      result += '\\';
      result += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      result += ' ';
    } else {
      result += c;
    }
  }
  return result + "\"";
}

}  // namespace billiard::testing

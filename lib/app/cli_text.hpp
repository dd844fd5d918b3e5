// Text helpers of the `billiard` command: messages on one line, numbers as people read them,
// and the error for bad input.
#pragma once

#include "billiard/describe.hpp"

#include <charconv>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>

namespace billiard_cli {

// Bad input: one line on stderr, exit status 2, nothing written.
struct BadInput : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// One line of a message or a report; numbers as billiard::describe quotes them (exactly, in the
// shortest text), so that an error repeats the value the user gave.
template <typename... Parts>
std::string text(const Parts&... parts) {
  return billiard::describe(parts...);
}

// 2000000 -> "2,000,000".
inline std::string thousands(long long number) {
  std::string digits = std::to_string(number);
  for (auto k = static_cast<std::ptrdiff_t>(digits.size()) - 3; k > 0; k -= 3) digits.insert(std::size_t(k), ",");
  return digits;
}

// Text from the command line, the file system or a task, safe to print on one line: control
// characters are escaped, and text longer than `longest` is cut short.
inline std::string printable(std::string_view value, std::size_t longest = std::string_view::npos) {
  std::string out;
  for (std::size_t k = 0; k < value.size(); ++k) {
    if (k == longest) return out + "...";
    const auto byte = static_cast<unsigned char>(value[k]);
    if (byte == '\n') {
      out += "\\n";
    } else if (byte == '\t') {
      out += "\\t";
    } else if (byte < 0x20 || byte == 0x7f) {
      constexpr const char* kHex = "0123456789abcdef";
      out += {'\\', 'x', kHex[byte >> 4], kHex[byte & 15]};
    } else {
      out += value[k];
    }
  }
  return out;
}

inline std::string in_quotes(std::string_view value) { return "'" + printable(value, 100) + "'"; }

// A plain decimal number (from_chars: no spaces, no hex, no inf or nan), finite; false if `word`
// is anything else.
inline bool read_number(std::string_view word, double& number) {
  const auto [end, error] = std::from_chars(word.data(), word.data() + word.size(), number);
  return error == std::errc() && end == word.data() + word.size() && std::isfinite(number);
}

// A figure of a report to `precision` significant digits (a message quotes numbers exactly:
// text()).
inline std::string rounded(double value, int precision) {
  std::ostringstream out;
  out.precision(precision);
  out << value;
  return out.str();
}

}  // namespace billiard_cli

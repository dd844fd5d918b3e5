// Numbers in messages, in one place for the course's checks, the engine and the commands: the
// shortest text that reads back as the same double (0.1 as "0.1", 1/3 with all its digits), so
// that a message quotes exactly the value that was refused or found wrong, and no more digits.
// Like limits.hpp it belongs to neither layer.
#pragma once

#include "billiard/vectors.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ostream>
#include <sstream>
#include <string>

namespace billiard {

inline std::string number_text(double x) {
  char digits[32];
  // (printf and strtod, not to_chars: the course builds on students' older compilers too.)
  int precision = 1;
  while (precision < 17) {
    std::snprintf(digits, sizeof digits, "%.*g", precision, x);
    if (std::strtod(digits, nullptr) == x) break;
    ++precision;
  }
  // Whole numbers below a million in full, as people write them: 1000, not 1e+03.
  const double magnitude = std::abs(x);
  if (magnitude >= 1 && magnitude < 1e6) precision = std::max(precision, 1 + static_cast<int>(std::floor(std::log10(magnitude))));
  std::snprintf(digits, sizeof digits, "%.*g", precision, x);
  return digits;
}

namespace detail {
inline void put(std::ostream& out, double x) { out << number_text(x); }
inline void put(std::ostream& out, const Vector& v) { out << '(' << number_text(v.x()) << ", " << number_text(v.y()) << ')'; }
template <class Part>
void put(std::ostream& out, const Part& part) { out << part; }
}  // namespace detail

// Its arguments as one string: doubles by number_text, a point or velocity as (x, y), anything
// else as it streams.
template <class... Parts>
std::string describe(const Parts&... parts) {
  std::ostringstream out;
  (detail::put(out, parts), ...);
  return out.str();
}

}  // namespace billiard

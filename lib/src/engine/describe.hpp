// Internal to the engine: messages that quote numbers (refusals, validation problems).
#pragma once

#include <sstream>
#include <string>

namespace billiard {

// Its arguments streamed into one string, numbers with all 17 significant digits, so that a
// message shows the exact value that was refused or found wrong.
template <class... Parts>
std::string describe(const Parts&... parts) {
  std::ostringstream out;
  out.precision(17);
  (out << ... << parts);
  return out.str();
}

}  // namespace billiard

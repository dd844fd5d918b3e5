// Internal to the engine: messages that quote numbers (refusals, validation problems).
#pragma once

#include "billiard/engine/vec2.hpp"

#include <ostream>
#include <sstream>
#include <string>

namespace billiard {

namespace detail {
inline void put(std::ostream& out, const Vec2& v) { out << '(' << v.x() << ", " << v.y() << ')'; }
template <class Part>
void put(std::ostream& out, const Part& part) { out << part; }
}  // namespace detail

// Its arguments streamed into one string, numbers with all 17 significant digits, so that a
// message shows the exact value that was refused or found wrong; a point or velocity as (x, y).
template <class... Parts>
std::string describe(const Parts&... parts) {
  std::ostringstream out;
  out.precision(17);
  (detail::put(out, parts), ...);
  return out.str();
}

// The message for a disc overlapping a wall, the same at set-up and in validation
// (container.cpp).
std::string wall_overlap_message(const std::string& who, const Vec2& p, int wall, double clearance, double radius);

}  // namespace billiard

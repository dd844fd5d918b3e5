// Hostile: a global constructor ends the program before main() runs, in every process that
// has this file linked in: the whole suite of walls, whose tests must each fail alone.
#include <cstdlib>

#include "billiard/extensions.hpp"

namespace billiard {
namespace {

const bool ended_at_start = [] {
  std::exit(0);
  return true;
}();

}  // namespace

Collision propagate_walls(double, double, int, Coordinates&, Velocities&, const std::vector<Wall>&) {
  return Collision{};
}

}  // namespace billiard

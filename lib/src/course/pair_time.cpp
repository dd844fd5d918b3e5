#include "time_of_impact.hpp"
#include "billiard/extensions.hpp"

#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

namespace billiard {
namespace {
thread_local long long calls = 0;
}  // namespace

double pair_time(double circle_radius, const Coordinates& coordinates, const Velocities& velocities, int i, int j) {
  const auto rows = static_cast<int>(coordinates.rows());
  for (const auto& [index, name] : {std::pair{i, "i"}, std::pair{j, "j"}}) {
    if (index < 0 || index >= rows || index >= velocities.rows()) {
      throw std::invalid_argument(std::string(name) + " = " + std::to_string(index) +
                                  ": must be a row of coordinates and velocities (0 to " +
                                  std::to_string(rows - 1) + ")");
    }
  }
  ++calls;
  if (i == j) return std::numeric_limits<double>::infinity();
  const Vector dr = (coordinates.row(i) - coordinates.row(j));
  const Vector dv = (velocities.row(i) - velocities.row(j));
  return disc_disc_time(dr, dv, 2 * circle_radius);
}

long long pair_time_calls() { return calls; }

}  // namespace billiard

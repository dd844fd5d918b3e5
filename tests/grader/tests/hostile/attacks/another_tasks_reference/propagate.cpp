// Attack: another task's reference code answers for this one. The walls stage generalises
// propagate (no walls: the same billiard), and its reference code is in the grader: one call,
// and task 4 would be graded by the stage's reference. course.hpp names every function, so a
// student finds this by reading.
#include <vector>

#include "billiard/course.hpp"
#include "billiard/extensions.hpp"

namespace billiard {

Collision propagate(double table_radius, double circle_radius, int n, Coordinates& coordinates,
                    Velocities& velocities) {
  return propagate_walls(table_radius, circle_radius, n, coordinates, velocities, std::vector<Wall>{});
}

}  // namespace billiard

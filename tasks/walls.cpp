// Task 8 (extension stage): walls -- straight walls inside the table.
//
// Write the function below (declared in lib/include/billiard/extensions.hpp).
//
// Run this task's tests:   ./build.sh test -L walls
#include "billiard/argument_checks.hpp"
#include "billiard/extensions.hpp"
#include "billiard/not_implemented.hpp"

namespace billiard {

Collision propagate_walls(double table_radius, double circle_radius, int n, Coordinates& coordinates,
                          Velocities& velocities, const std::vector<Wall>& walls) {
  // Delete these two lines and write the task.
  throw NotImplemented(8, "propagate_walls", "tasks/walls.cpp");
  (void)table_radius, (void)circle_radius, (void)n, (void)coordinates, (void)velocities, (void)walls;
}

}  // namespace billiard

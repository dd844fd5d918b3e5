// Task 9 (extension stage): sectors -- the next collision through cells, not all pairs.
//
// Write the function below (declared in lib/include/billiard/extensions.hpp).
//
// Run this task's tests:   ./build.sh test -L sectors
#include "billiard/argument_checks.hpp"
#include "billiard/extensions.hpp"
#include "billiard/not_implemented.hpp"

namespace billiard {

Collision propagate_sectors(double table_radius, double circle_radius, int n, Coordinates& coordinates,
                            Velocities& velocities, double cell_size) {
  // Delete these two lines and write the task.
  throw NotImplemented(9, "propagate_sectors", "tasks/sectors.cpp");
  (void)table_radius, (void)circle_radius, (void)n, (void)coordinates, (void)velocities, (void)cell_size;
}

}  // namespace billiard

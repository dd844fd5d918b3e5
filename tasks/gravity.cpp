// Task 7 (extension stage): gravity -- circles on parabolas.
//
// Write both functions below (declared in lib/include/billiard/extensions.hpp).
//
// Run this task's tests:   ./build.sh test -L gravity
#include "billiard/argument_checks.hpp"
#include "billiard/extensions.hpp"
#include "billiard/not_implemented.hpp"

namespace billiard {

Collision propagate_gravity(double table_radius, double circle_radius, int n, Coordinates& coordinates,
                            Velocities& velocities, const Vector& g) {
  // Delete these two lines and write the task.
  throw NotImplemented(7, "propagate_gravity", "tasks/gravity.cpp");
  (void)table_radius, (void)circle_radius, (void)n, (void)coordinates, (void)velocities, (void)g;
}

double mean_energy(int n, const Coordinates& coordinates, const Velocities& velocities, const Vector& g) {
  // Delete these two lines and write the task.
  throw NotImplemented(7, "mean_energy", "tasks/gravity.cpp");
  (void)n, (void)coordinates, (void)velocities, (void)g;
}

}  // namespace billiard

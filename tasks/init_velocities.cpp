// Task 2: init_velocities -- random velocities.
//
// Write init_velocities below (declared in lib/include/billiard/course.hpp). Return an n x 2
// matrix of velocities (column 0: vx, column 1: vy), one row per circle:
//   * random, drawn only from `rng` (same seed, same velocities);
//   * no preferred direction: every direction equally likely, so the average velocity of
//     many circles is close to zero. Drawing vx and vy independently from
//     std::normal_distribution<double>(0, 1) does this (and gives the 2D Maxwell-Boltzmann
//     distribution, the equilibrium of the gas);
//   * not all zero, or nothing will ever collide.
// `coordinates` tells you how many circles there are; check that it has n rows:
//   checks::count(n);  checks::rows(coordinates, n, "coordinates");
//
// Run this task's tests:   ./build.sh test -L init_velocities
#include "billiard/argument_checks.hpp"
#include "billiard/course.hpp"
#include "billiard/not_implemented.hpp"

namespace billiard {

Velocities init_velocities(int n, const Coordinates& coordinates, Rng& rng) {
  // Delete these two lines and write the task.
  throw NotImplemented(2, "init_velocities", "tasks/init_velocities.cpp");
  (void)n, (void)coordinates, (void)rng;
}

}  // namespace billiard

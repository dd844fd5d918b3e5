// Task 1: init_billiard -- random, non-overlapping circles on the table.
//
// Write init_billiard below (declared in lib/include/billiard/course.hpp). Return an n x 2
// matrix of centres (column 0: x, column 1: y) for n circles of radius circle_radius on a
// circular table of radius table_radius centred at the origin, such that
//   * every circle is fully inside the table:  |r_i| <= table_radius - circle_radius
//     (the centre inside is not enough: the whole circle must be);
//   * no two circles overlap:                  |r_i - r_j| >= 2 circle_radius;
//   * the centres are random, and all randomness comes from `rng` (the same seed must give
//     the same table, a different seed a different one). For a uniform random point in the
//     allowed disc, draw x and y uniformly in [-reach, reach] and retry while x^2 + y^2 > reach^2.
//
// Suggested method: random sequential addition. Draw a random centre; keep it if it overlaps
// none of the circles placed so far; otherwise draw again.
//
// Be careful with dense tables: the tests ask for an area fraction n circle_radius^2 /
// table_radius^2 of 0.5, where random tries almost never succeed. Limit the number of tries,
// and when they run out use another method (for example start from a hexagonal lattice and
// move the circles at random afterwards). Never loop forever: if the circles cannot fit
// (no arrangement covers more than pi / sqrt(12) = 0.9069 of the table), throw
// std::invalid_argument with a message that says they "cannot fit" (the `billiard` command
// prints it, and its tests look for those words).
//
// Bad arguments: start with  checks::table(table_radius, circle_radius, n);  from
// billiard/argument_checks.hpp. It throws std::invalid_argument for you.
//
// Run this task's tests:   ./build.sh test -L init_billiard
#include "billiard/argument_checks.hpp"
#include "billiard/course.hpp"
#include "billiard/not_implemented.hpp"

namespace billiard {

Coordinates init_billiard(double table_radius, double circle_radius, int n, Rng& rng) {
  // Delete these two lines and write the task.
  throw NotImplemented(1, "init_billiard", "tasks/init_billiard.cpp");
  (void)table_radius, (void)circle_radius, (void)n, (void)rng;
}

}  // namespace billiard

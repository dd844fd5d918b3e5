// Test fixtures that do not depend on the student's code: tables, velocities, physical
// quantities and scratch folders. A suite for task k must never need the student's task j != k
// to build its inputs, so that one unfinished task does not fail another task's tests.
#pragma once

#include "billiard/course.hpp"

#include <cstdint>
#include <filesystem>

namespace billiard::testing {

// n non-overlapping circles of radius a uniformly inside a table of radius R (random
// sequential addition with an independent generator). Meant for area fractions n a^2 / R^2
// up to about 0.35; throws std::runtime_error if it cannot place them.
Coordinates scattered_circles(double R, double a, int n, std::uint64_t seed);

// n velocities with independent standard normal components.
Velocities gaussian_velocities(int n, std::uint64_t seed);

// Total angular momentum about the table centre, sum_i (x_i vy_i - y_i vx_i) (unit masses).
double angular_momentum(const Coordinates& coordinates, const Velocities& velocities);

// Largest overlap 2a - |r_i - r_j| over all pairs (<= 0 when no two circles overlap);
// `first`/`second` receive the pair (or -1) if not null.
double worst_overlap(const Coordinates& coordinates, double a, int* first = nullptr, int* second = nullptr);

// Largest distance by which a circle sticks out of the table, |r_i| + a - R (<= 0 when all are
// inside); `which` receives the circle (or -1) if not null.
double worst_protrusion(const Coordinates& coordinates, double R, double a, int* which = nullptr);

// A fresh, empty folder for files a test writes; removed with everything in it when destroyed.
class ScratchFolder {
 public:
  ScratchFolder();
  ~ScratchFolder();
  ScratchFolder(const ScratchFolder&) = delete;
  ScratchFolder& operator=(const ScratchFolder&) = delete;
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::filesystem::path& name) const { return path_ / name; }

 private:
  std::filesystem::path path_;
};

}  // namespace billiard::testing

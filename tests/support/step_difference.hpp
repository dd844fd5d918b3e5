// How one step of a student's step function differs from the expected step, once both name the
// same event: its time first, then circle by circle its position and its velocity. The suites
// build their messages from it and the pictures' judges their verdicts, so both apply one rule.
#pragma once

#include "billiard/course.hpp"

#include <algorithm>
#include <cmath>

namespace billiard::testing {

// The suites' tolerances for one step: rounding differs between two correct codes by ~1e-15
// relative; 1e-9 is ample yet far smaller than any real mistake. `scale` is the step's time
// scale, `speed` the root sum of the squared speeds.
struct StepTolerances {
  double time, position, velocity;
  static StepTolerances of_step(double table_radius, double speed, double scale, double expected_time) {
    return {1e-9 * (expected_time + scale), 1e-9 * table_radius, 1e-9 * speed};
  }
};

struct StepDifference {
  enum class What { None, Time, Position, Velocity };
  What what = What::None;
  int circle = -1;              // Position, Velocity: the first circle off (-1: the arrays' sizes differ)
  double position_error = 0.0;  // the largest over the circles
  double velocity_error = 0.0;
  bool none() const { return what == What::None; }
};

inline StepDifference step_difference(double time, const Coordinates& c, const Velocities& v, double expected_time,
                                      const Coordinates& expected_c, const Velocities& expected_v,
                                      const StepTolerances& tolerance) {
  StepDifference difference;
  if (!(std::abs(time - expected_time) <= tolerance.time)) {
    difference.what = StepDifference::What::Time;
    return difference;
  }
  if (c.rows() != expected_c.rows() || v.rows() != expected_v.rows()) {
    difference.what = StepDifference::What::Position;
    return difference;
  }
  for (Eigen::Index i = 0; i < c.rows(); ++i) {
    const double position_error = (c.row(i) - expected_c.row(i)).norm();
    const double velocity_error = (v.row(i) - expected_v.row(i)).norm();
    // The larger of the two; a nan, once seen, stays.
    const auto larger = [](double kept, double next) { return std::isnan(kept) || next <= kept ? kept : next; };
    difference.position_error = larger(difference.position_error, position_error);
    difference.velocity_error = larger(difference.velocity_error, velocity_error);
    if (difference.what != StepDifference::What::None) continue;
    if (!(position_error <= tolerance.position)) {
      difference = {StepDifference::What::Position, static_cast<int>(i), difference.position_error, difference.velocity_error};
    } else if (!(velocity_error <= tolerance.velocity)) {
      difference = {StepDifference::What::Velocity, static_cast<int>(i), difference.position_error, difference.velocity_error};
    }
  }
  return difference;
}

}  // namespace billiard::testing

// Domains for the time-stepped integrator (stepper.hpp): regions {x : omega(x) > 0} of the plane
// given by a level-set function omega and its gradient, and unions of such regions.
//
//   auto domain = billiard::stepping::Domain{billiard::stepping::circle({0, 0}, 1.0)};
//
// The stepper asks for omega and its gradient at many points at once (one call per step and
// part, never one per particle), so that a level set written in Python with numpy costs one
// call per step. The gradient points into the region; its length does not matter.
#pragma once

#include "billiard/engine/plane.hpp"

#include <Eigen/Core>

#include <memory>
#include <vector>

namespace billiard::stepping {

// One region {x : omega(x) > 0}. Implementations must be deterministic (a replay re-runs them)
// and may throw std::invalid_argument (for example when a user's function returns an array of
// the wrong shape); the stepper then leaves its state unchanged.
class LevelSet {
 public:
  virtual ~LevelSet() = default;
  // omega at each row of `points` (N by 2): a vector of N values.
  virtual Eigen::VectorXd values(const Coordinates& points) const = 0;
  // The gradient of omega at each row of `points`: N by 2.
  virtual Coordinates gradients(const Coordinates& points) const = 0;
};

// The union of its parts: a point is inside when any part's omega is positive.
using Domain = std::vector<std::shared_ptr<const LevelSet>>;

// Built-in level sets. Each checks its arguments (finite, sizes > 0) and throws
// std::invalid_argument naming the argument and its value.
//
// Disc of `radius` about `centre`: omega = radius - |x - centre|, the signed distance to the
// circle (gradient -(x - centre) / |x - centre|, and 0 at the centre).
std::shared_ptr<const LevelSet> circle(const Vector& centre, double radius);
// Ellipse about `centre` with semi-axes a = semi_axes.x() along x and b = semi_axes.y() along y:
// omega = 1 - ((x - cx) / a)^2 - ((y - cy) / b)^2, smooth everywhere.
std::shared_ptr<const LevelSet> ellipse(const Vector& centre, const Vector& semi_axes);
// Axis-aligned box [lower, upper]: omega = the distance to the nearest face, min(x - lx, ux - x,
// y - ly, uy - y), linear near each face; its gradient is the inward normal of the nearest face
// (on a tie, the first in that order).
std::shared_ptr<const LevelSet> box(const Vector& lower, const Vector& upper);

}  // namespace billiard::stepping

// The built-in level sets: circle, ellipse, box (formulas in level_set.hpp and lib/PHYSICS.md).
#include "billiard/stepping/level_set.hpp"

#include "billiard/describe.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace billiard::stepping {
namespace {


void require_finite(const Vector& v, const char* call, const char* name) {
  if (!std::isfinite(v.x()) || !std::isfinite(v.y())) {
    throw std::invalid_argument(describe(call, ": ", name, " = ", v, " must be finite"));
  }
}

void require_size(double x, const char* call, const char* name) {
  if (!(x > 0) || !std::isfinite(x)) {
    throw std::invalid_argument(describe(call, ": ", name, " = ", x, " must be positive and finite"));
  }
}

class Circle final : public LevelSet {
 public:
  Circle(const Vector& centre, double radius) : centre_(centre), radius_(radius) {}
  Eigen::VectorXd values(const Coordinates& p) const override {
    Eigen::VectorXd w(p.rows());
    for (Eigen::Index i = 0; i < p.rows(); ++i) {
      const double dx = p(i, 0) - centre_.x(), dy = p(i, 1) - centre_.y();
      w[i] = radius_ - std::sqrt(dx * dx + dy * dy);
    }
    return w;
  }
  Coordinates gradients(const Coordinates& p) const override {
    Coordinates g(p.rows(), 2);
    for (Eigen::Index i = 0; i < p.rows(); ++i) {
      const double dx = p(i, 0) - centre_.x(), dy = p(i, 1) - centre_.y();
      const double r = std::sqrt(dx * dx + dy * dy);
      // The centre has no direction; no crossing is ever located there (omega = radius).
      g(i, 0) = r > 0 ? -dx / r : 0.0;
      g(i, 1) = r > 0 ? -dy / r : 0.0;
    }
    return g;
  }

 private:
  Vector centre_;
  double radius_;
};

class Ellipse final : public LevelSet {
 public:
  Ellipse(const Vector& centre, const Vector& semi_axes) : centre_(centre), semi_axes_(semi_axes) {}
  Eigen::VectorXd values(const Coordinates& p) const override {
    Eigen::VectorXd w(p.rows());
    for (Eigen::Index i = 0; i < p.rows(); ++i) {
      const double u = (p(i, 0) - centre_.x()) / semi_axes_.x(), v = (p(i, 1) - centre_.y()) / semi_axes_.y();
      w[i] = 1.0 - u * u - v * v;
    }
    return w;
  }
  Coordinates gradients(const Coordinates& p) const override {
    Coordinates g(p.rows(), 2);
    for (Eigen::Index i = 0; i < p.rows(); ++i) {
      g(i, 0) = -2.0 * (p(i, 0) - centre_.x()) / (semi_axes_.x() * semi_axes_.x());
      g(i, 1) = -2.0 * (p(i, 1) - centre_.y()) / (semi_axes_.y() * semi_axes_.y());
    }
    return g;
  }

 private:
  Vector centre_;
  Vector semi_axes_;
};

class Box final : public LevelSet {
 public:
  Box(const Vector& lower, const Vector& upper) : lower_(lower), upper_(upper) {}
  Eigen::VectorXd values(const Coordinates& p) const override {
    Eigen::VectorXd w(p.rows());
    for (Eigen::Index i = 0; i < p.rows(); ++i) w[i] = distances(p(i, 0), p(i, 1))[nearest(p(i, 0), p(i, 1))];
    return w;
  }
  Coordinates gradients(const Coordinates& p) const override {
    static const double kNormals[4][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
    Coordinates g(p.rows(), 2);
    for (Eigen::Index i = 0; i < p.rows(); ++i) {
      const int face = nearest(p(i, 0), p(i, 1));
      g(i, 0) = kNormals[face][0];
      g(i, 1) = kNormals[face][1];
    }
    return g;
  }

 private:
  // Signed distances to the faces x = lx, x = ux, y = ly, y = uy (positive inside).
  Eigen::Vector4d distances(double x, double y) const {
    return Eigen::Vector4d(x - lower_.x(), upper_.x() - x, y - lower_.y(), upper_.y() - y);
  }
  int nearest(double x, double y) const {
    const Eigen::Vector4d d = distances(x, y);
    int face = 0;
    for (int k = 1; k < 4; ++k) {
      if (d[k] < d[face]) face = k;
    }
    return face;
  }

  Vector lower_;
  Vector upper_;
};

}  // namespace

std::shared_ptr<const LevelSet> circle(const Vector& centre, double radius) {
  require_finite(centre, "circle", "centre");
  require_size(radius, "circle", "radius");
  return std::make_shared<Circle>(centre, radius);
}

std::shared_ptr<const LevelSet> ellipse(const Vector& centre, const Vector& semi_axes) {
  require_finite(centre, "ellipse", "centre");
  require_size(semi_axes.x(), "ellipse", "semi_axes.x");
  require_size(semi_axes.y(), "ellipse", "semi_axes.y");
  return std::make_shared<Ellipse>(centre, semi_axes);
}

std::shared_ptr<const LevelSet> box(const Vector& lower, const Vector& upper) {
  require_finite(lower, "box", "lower");
  require_finite(upper, "box", "upper");
  if (!(upper.x() > lower.x()) || !(upper.y() > lower.y())) {
    throw std::invalid_argument(describe("box: upper = ", upper, " must exceed lower = ", lower,
                                         " in both coordinates (the sides must be positive)"));
  }
  return std::make_shared<Box>(lower, upper);
}

}  // namespace billiard::stepping

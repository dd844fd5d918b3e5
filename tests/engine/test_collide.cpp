// Collision rules: hand-checkable impulses and the conservation laws.
#include "collide.hpp"

#include <gtest/gtest.h>

using billiard::ContactBody;
using billiard::Restitution;
using billiard::Vector;

namespace {
// Exact-in-binary values below: the formulas only add and multiply by halves and small integers.
ContactBody disc(const Vector& v, double mass, double radius = 1.0, double spin = 0.0) {
  return ContactBody{v, spin, 1.0 / mass, 2.0 / (mass * radius * radius), radius};
}
double energy(const ContactBody& b) {
  double e = 0;
  if (b.inverse_mass > 0) e += 0.5 * b.velocity.squaredNorm() / b.inverse_mass;
  if (b.inverse_inertia > 0) e += 0.5 * b.spin * b.spin / b.inverse_inertia;
  return e;
}
}  // namespace

TEST(Collide, EqualMassesExchangeNormalComponentsOnly) {
  // Contact along x: the x components swap, the y components stay.
  ContactBody a = disc(Vector(1, 2), 1), b = disc(Vector(-1, 3), 1);
  billiard::collide(Vector(1, 0), a, b, Restitution{});
  EXPECT_EQ(a.velocity, Vector(-1, 2));
  EXPECT_EQ(b.velocity, Vector(1, 3));
  Vector va(1, 2), vb(-1, 3);
  billiard::collide_smooth_elastic(Vector(1, 0), va, 1.0, vb, 1.0);
  EXPECT_EQ(va, Vector(-1, 2));
  EXPECT_EQ(vb, Vector(1, 3));
}

TEST(Collide, UnequalMassesHeadOn) {
  // 1D elastic: m1 = 1 at 2 hits m2 = 3 at rest: v1' = (m1-m2)/(m1+m2) 2 = -1, v2' = 2 m1/(m1+m2) 2 = 1.
  ContactBody a = disc(Vector(2, 0), 1), b = disc(Vector(0, 0), 3);
  const Vector q = billiard::collide(Vector(1, 0), a, b, Restitution{});
  EXPECT_DOUBLE_EQ(a.velocity.x(), -1.0);
  EXPECT_DOUBLE_EQ(b.velocity.x(), 1.0);
  EXPECT_DOUBLE_EQ(q.x(), -3.0);  // momentum change of disc 1
}

TEST(Collide, PerfectlyInelasticNormal) {
  // e_n = 0, equal masses: both end with the mean normal velocity.
  ContactBody a = disc(Vector(2, 0), 1), b = disc(Vector(0, 0), 1);
  billiard::collide(Vector(1, 0), a, b, Restitution{0.0, -1.0});
  EXPECT_DOUBLE_EQ(a.velocity.x(), 1.0);
  EXPECT_DOUBLE_EQ(b.velocity.x(), 1.0);
}

TEST(Collide, SeparatingBodiesGetNoImpulse) {
  ContactBody a = disc(Vector(-1, 0), 1), b = disc(Vector(1, 0), 1);
  EXPECT_EQ(billiard::collide(Vector(1, 0), a, b, Restitution{}), Vector::Zero());
}

TEST(Collide, RoughWallReversesTheContactPointVelocity) {
  // Uniform disc (m = 1, a = 1, I = 1/2) sliding along a floor below it (sigma = (0, -1)) at
  // vx = 3 while falling at 1, no spin, perfectly rough wall (e_t = 1). Contact point velocity
  // g_t = 3 (tangent x); effective tangential mass [1/m + a^2/I]^-1 = 1/3; impulse
  // -(1 + 1) (1/3) 3 = -2 along x: vx' = 1; spin' = I^-1 (a sigma x Q) = 2 (0*0 - (-1)(-2)) = -4.
  // Check: contact point velocity vx + w a perp(sigma).x = 1 + (-4)(1)(1) = -3, reversed.
  ContactBody d = disc(Vector(3, -1), 1);
  ContactBody wall{Vector::Zero(), 0, 0, 0, 0};
  billiard::collide(Vector(0, -1), d, wall, Restitution{1.0, 1.0});
  EXPECT_DOUBLE_EQ(d.velocity.x(), 1.0);
  EXPECT_DOUBLE_EQ(d.velocity.y(), 1.0);
  EXPECT_DOUBLE_EQ(d.spin, -4.0);
  // Energy: before 9/2 + 1/2 = 5; after 1/2 + 1/2 + (1/4) 16 / 2... = 1 + 4 = 5.
  EXPECT_DOUBLE_EQ(energy(d), 5.0);
}

TEST(Collide, RoughDiscsConserveEnergyAndAngularMomentum) {
  // Energy is conserved for e_n = 1 and e_t = +-1; angular momentum about the contact point
  // always (impulse passes through it). Tolerance 1e-14 relative: a few roundings.
  for (double et : {-1.0, 1.0}) {
    ContactBody a = disc(Vector(1.5, 0.7), 2.0, 1.0, 3.0), b = disc(Vector(-0.5, -1.2), 0.5, 0.5, -7.0);
    const Vector sigma = Vector(0.6, 0.8);
    const double before = energy(a) + energy(b);
    // Angular momentum about the contact point c = r_a + a_a sigma, with r_a = 0.
    const Vector ra(0, 0), rb = 1.5 * sigma, c = sigma;
    auto angular = [&]() {
      return billiard::cross(ra - c, a.velocity) / a.inverse_mass + a.spin / a.inverse_inertia +
             billiard::cross(rb - c, b.velocity) / b.inverse_mass + b.spin / b.inverse_inertia;
    };
    const double l_before = angular();
    billiard::collide(sigma, a, b, Restitution{1.0, et});
    EXPECT_NEAR(energy(a) + energy(b), before, 1e-14 * before) << "e_t = " << et;
    EXPECT_NEAR(angular(), l_before, 1e-13) << "e_t = " << et;
  }
}

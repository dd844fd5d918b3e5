// Collision impulses. See collide.hpp for the formula and its source.
#include "collide.hpp"

namespace billiard {

Vector collide(const Vector& sigma, ContactBody& i, ContactBody& j, const Restitution& restitution) {
  // Velocity of each contact point: centre velocity plus spin times the lever arm turned by 90
  // degrees (w x r in 2D). i's contact point is at +lever_i sigma, j's at -lever_j sigma. So the
  // relative velocity g has the normal part (v_i - v_j).sigma and, along t = perp(sigma), the
  // tangential part (v_i - v_j).t + w_i lever_i + w_j lever_j. Taken apart like this, a huge
  // spin cannot swamp the normal part with its rounding (w = 1e50 and a normal speed of 1 would
  // give g.sigma = 0 or 1e33 if g were formed first).
  const Vector t = perp(sigma);
  const Vector relative = i.velocity - j.velocity;
  const double g_normal = relative.dot(sigma);
  if (g_normal <= 0) return Vector::Zero();  // separating or grazing: no impulse
  const double inverse_mu = i.inverse_mass + j.inverse_mass;  // 1/mu
  if (inverse_mu == 0) return Vector::Zero();                 // two immovable bodies
  // Q = q_normal sigma + q_tangent t.
  const double q_normal = -(1 + restitution.normal) * g_normal / inverse_mu;
  double q_tangent = 0.0;
  if (restitution.tangential > -1) {
    const double g_tangent = relative.dot(t) + i.spin * i.lever + j.spin * j.lever;
    const double inverse_tangential_mass = inverse_mu + i.lever * i.lever * i.inverse_inertia +
                                           j.lever * j.lever * j.inverse_inertia;
    q_tangent = -(1 + restitution.tangential) / inverse_tangential_mass * g_tangent;
  }
  const Vector q = q_normal * sigma + q_tangent * t;
  i.velocity += i.inverse_mass * q;
  j.velocity -= j.inverse_mass * q;
  // Torque of the impulse about each centre: lever arm x impulse. For i: (lever_i sigma) x Q;
  // for j: (-lever_j sigma) x (-Q) = lever_j sigma x Q; and sigma x Q = q_tangent exactly
  // (sigma x t = 1), so smooth discs (no tangential impulse) never pick up a spin from rounding.
  i.spin += i.inverse_inertia * i.lever * q_tangent;
  j.spin += j.inverse_inertia * j.lever * q_tangent;
  return q;
}

Vector collide_smooth_elastic(const Vector& normal, Vector& v_i, double inverse_mass_i, Vector& v_j,
                            double inverse_mass_j) {
  const double g_normal = (v_i - v_j).dot(normal);
  if (g_normal <= 0) return Vector::Zero();
  // Q = -2 mu (g.sigma) sigma with sigma = normal / |normal|, written as
  // -2 mu (g.normal) normal / (normal.normal): no square root, and no bias from a normalised
  // vector whose length is 1 only up to rounding (that bias made the energy drift ten times
  // faster than the unbiased random walk: 2e-12 instead of 1e-13 after 10^6 collisions).
  // For equal masses each disc's normal component is exchanged.
  const Vector q = (-2 * g_normal / ((inverse_mass_i + inverse_mass_j) * normal.squaredNorm())) * normal;
  v_i += inverse_mass_i * q;
  v_j -= inverse_mass_j * q;
  return q;
}

}  // namespace billiard

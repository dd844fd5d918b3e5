// Collision rules: the impulse exchanged at contact between two discs, or a disc and a wall.
// lib/PHYSICS.md, "Collision rules" (after Pöschel & Schwager, Computational
// Granular Dynamics, ch. 3): with sigma the unit vector from disc i to the contact and g the
// relative velocity of the contact points, the impulse on i is
//   Q = -(1 + e_n) mu (g.sigma) sigma - (1 + e_t) [1/mu + a_i^2/I_i + a_j^2/I_j]^-1 g_t,
// mu = m_i m_j / (m_i + m_j), g_t the tangential part of g. Momentum: P_i += Q, P_j -= Q; spin:
// I w += (lever x impulse). A wall is a body of infinite mass and inertia. Internal: not installed.
#pragma once

#include "billiard/engine/settings.hpp"  // Restitution
#include "billiard/engine/plane.hpp"

namespace billiard {

// The dynamic properties of one side of a contact. inverse_mass = 0 and inverse_inertia = 0
// make an immovable body (a wall). `lever` is the distance from the centre to the contact point
// (the disc radius; 0 for a point mass).
struct ContactBody {
  Vector velocity;
  double spin = 0.0;  // angular velocity, counter-clockwise positive
  double inverse_mass = 0.0;
  double inverse_inertia = 0.0;
  double lever = 0.0;
};

// Applies the impulse of a collision between body i and body j touching along `sigma`, the unit
// vector from i's centre towards j's centre (the contact normal). Updates both bodies' velocities
// and spins and returns Q, the impulse on i (j receives -Q). If the contact points are not
// approaching (g.sigma <= 0) nothing happens and Q = 0.
Vector collide(const Vector& sigma, ContactBody& i, ContactBody& j, const Restitution& restitution);

// Smooth elastic collision of two discs with masses m_i and m_j (the fast path of the engine):
// only the normal components change, v_i -= 2 m_j / (m_i + m_j) ((v_i - v_j).sigma) sigma and
// symmetrically for j. `normal` points from i to j and need not be of unit length (the line of
// centres r_j - r_i itself is best: see collide.cpp). Returns the impulse on i.
Vector collide_smooth_elastic(const Vector& normal, Vector& v_i, double inverse_mass_i, Vector& v_j,
                            double inverse_mass_j);

}  // namespace billiard

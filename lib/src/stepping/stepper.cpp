// The time-stepped integrator: kick, drift, kick; a drift that leaves the domain is cut at the
// crossing found by linear interpolation, reflected, and continued (lib/PHYSICS.md, "Time
// stepping in level-set domains"). Level sets are evaluated for many particles per call.
#include "billiard/stepping/stepper.hpp"

#include "billiard/describe.hpp"

#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

namespace billiard::stepping {
namespace {

using Index = Eigen::Index;


// A level set's answer, checked: one finite value (or gradient) per point.
Eigen::VectorXd checked_values(const LevelSet& part, int k, const Coordinates& points) {
  Eigen::VectorXd w = part.values(points);
  if (w.size() != points.rows()) {
    throw std::invalid_argument(describe("domain part ", k, " returned ", w.size(), " values of omega for ", points.rows(), " points"));
  }
  for (Index i = 0; i < w.size(); ++i) {
    if (!std::isfinite(w[i])) {
      throw std::invalid_argument(describe("domain part ", k, " returned omega = ", w[i], " at ", Vector(points.row(i)),
                                           ": omega must be finite"));
    }
  }
  return w;
}

Coordinates checked_gradients(const LevelSet& part, int k, const Coordinates& points) {
  Coordinates g = part.gradients(points);
  if (g.rows() != points.rows()) {
    throw std::invalid_argument(describe("domain part ", k, " returned ", g.rows(), " gradients for ", points.rows(), " points"));
  }
  for (Index i = 0; i < g.rows(); ++i) {
    if (!std::isfinite(g(i, 0)) || !std::isfinite(g(i, 1))) {
      throw std::invalid_argument(describe("domain part ", k, " returned the gradient ", Vector(g.row(i)), " at ",
                                           Vector(points.row(i)), ": gradients must be finite"));
    }
  }
  return g;
}

// The particles `who` at `points` (row j for particle who[j]): each particle's part becomes the
// one it is in (its own if still inside, else the first part that contains it). Returns the rows
// j that are outside every part. One call per part, for all the points at once.
std::vector<Index> update_parts(const Domain& domain, const Coordinates& points, const std::vector<Index>& who,
                                std::vector<int>& parts) {
  std::vector<Eigen::VectorXd> w;
  w.reserve(domain.size());
  for (std::size_t k = 0; k < domain.size(); ++k) w.push_back(checked_values(*domain[k], static_cast<int>(k), points));
  std::vector<Index> outside;
  std::vector<int> found(who.size(), -1);
  for (std::size_t j = 0; j < who.size(); ++j) {
    const int own = parts[static_cast<std::size_t>(who[j])];
    if (own >= 0 && w[static_cast<std::size_t>(own)][static_cast<Index>(j)] > 0) {
      found[j] = own;
      continue;
    }
    for (std::size_t k = 0; k < domain.size() && found[j] < 0; ++k) {
      if (w[k][static_cast<Index>(j)] > 0) found[j] = static_cast<int>(k);
    }
    if (found[j] < 0) outside.push_back(static_cast<Index>(j));
  }
  // Written only now: a particle outside keeps the part it was last inside.
  for (std::size_t j = 0; j < who.size(); ++j) {
    if (found[j] >= 0) parts[static_cast<std::size_t>(who[j])] = found[j];
  }
  return outside;
}

// omega (when `values` is given) and its gradient at row j of `points`, each evaluated by the
// part parts[who[j]]: one call per part for all its particles.
void evaluate_own_parts(const Domain& domain, const Coordinates& points, const std::vector<Index>& who, const std::vector<int>& parts,
                        Eigen::VectorXd* values, Coordinates& gradients) {
  if (values) values->resize(points.rows());
  gradients.resize(points.rows(), 2);
  for (std::size_t k = 0; k < domain.size(); ++k) {
    std::vector<Index> rows;
    for (std::size_t j = 0; j < who.size(); ++j) {
      if (parts[static_cast<std::size_t>(who[j])] == static_cast<int>(k)) rows.push_back(static_cast<Index>(j));
    }
    if (rows.empty()) continue;
    Coordinates subset(static_cast<Index>(rows.size()), 2);
    for (std::size_t r = 0; r < rows.size(); ++r) subset.row(static_cast<Index>(r)) = points.row(rows[r]);
    const Coordinates g = checked_gradients(*domain[k], static_cast<int>(k), subset);
    const Eigen::VectorXd w = values ? checked_values(*domain[k], static_cast<int>(k), subset) : Eigen::VectorXd();
    for (std::size_t r = 0; r < rows.size(); ++r) {
      gradients.row(rows[r]) = g.row(static_cast<Index>(r));
      if (values) (*values)[rows[r]] = w[static_cast<Index>(r)];
    }
  }
}

Coordinates rows_of(const Coordinates& points, const std::vector<Index>& rows) {
  Coordinates out(static_cast<Index>(rows.size()), 2);
  for (std::size_t r = 0; r < rows.size(); ++r) out.row(static_cast<Index>(r)) = points.row(rows[r]);
  return out;
}

}  // namespace

Eigen::VectorXd energies(const StepperState& state, const Vector& gravity) {
  return 0.5 * state.velocities.rowwise().squaredNorm() - state.positions * gravity.transpose();
}

Stepper::Stepper(Domain domain, const Coordinates& positions, const Velocities& velocities, double dt, const Vector& gravity,
                 Integrator integrator)
    : domain_(std::move(domain)), dt_(dt), gravity_(gravity), integrator_(integrator) {
  if (domain_.empty()) throw std::invalid_argument("Stepper: domain has no parts; give at least one level set");
  for (std::size_t k = 0; k < domain_.size(); ++k) {
    if (!domain_[k]) throw std::invalid_argument(describe("Stepper: domain part ", k, " is null"));
  }
  if (!(dt > 0) || !std::isfinite(dt)) throw std::invalid_argument(describe("Stepper: dt = ", dt, " must be positive and finite"));
  if (!gravity.allFinite()) throw std::invalid_argument(describe("Stepper: gravity = ", gravity, " must be finite"));
  if (positions.rows() != velocities.rows()) {
    throw std::invalid_argument(describe("Stepper: positions has ", positions.rows(), " rows but velocities has ", velocities.rows(),
                                         "; give one velocity per particle"));
  }
  for (Index i = 0; i < positions.rows(); ++i) {
    if (!positions.row(i).allFinite()) {
      throw std::invalid_argument(describe("Stepper: positions row ", i, " = ", Vector(positions.row(i)), " must be finite"));
    }
    if (!velocities.row(i).allFinite()) {
      throw std::invalid_argument(describe("Stepper: velocities row ", i, " = ", Vector(velocities.row(i)), " must be finite"));
    }
  }
  initial_.positions = positions;
  initial_.velocities = velocities;
  initial_.parts.assign(static_cast<std::size_t>(positions.rows()), -1);
  initial_.reflections.assign(static_cast<std::size_t>(positions.rows()), 0);
  std::vector<Index> all(static_cast<std::size_t>(positions.rows()));
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = static_cast<Index>(i);
  const std::vector<Index> outside = update_parts(domain_, positions, all, initial_.parts);
  if (!outside.empty()) {
    const Index i = outside.front();
    throw std::invalid_argument(describe("Stepper: positions row ", i, " = ", Vector(positions.row(i)),
                                         " is outside the domain (omega <= 0 for every part); particles must start inside"));
  }
  state_ = initial_;
}

void Stepper::one_step(StepperState& s, std::int64_t& unresolved) const {
  const Index n = s.positions.rows();
  // Kick, drift, kick: the drift is a straight line, so the crossing found on it by linear
  // interpolation lies on the path the particle actually takes during the step.
  const double first_kick = integrator_ == Integrator::Leapfrog ? 0.5 * dt_ : 0.0;
  const double second_kick = integrator_ == Integrator::Leapfrog ? 0.5 * dt_ : dt_;
  Coordinates v = s.velocities;
  v.rowwise() += (first_kick * gravity_);
  Coordinates end = s.positions + dt_ * v;

  std::vector<Index> all(static_cast<std::size_t>(n));
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = static_cast<Index>(i);
  std::vector<Index> pending;  // particles whose drift ends outside: indices into the state
  for (const Index j : update_parts(domain_, end, all, s.parts)) pending.push_back(j);
  // v_i = v_i - 2 (v_i . n) n with n = gradient / |gradient|, if v_i . n < 0 (moving outward).
  const auto reflect = [&](const Vector& gradient, Index i) {
    const double length = gradient.norm();
    if (!(length > 0)) return false;
    const Vector unit = gradient / length;
    const double vn = v.row(i).dot(unit);
    if (!(vn < 0)) return false;
    v.row(i) -= 2 * vn * unit;
    ++s.reflections[static_cast<std::size_t>(i)];
    return true;
  };
  Coordinates start = rows_of(s.positions, pending);   // where each pending drift begins
  std::vector<double> remaining(pending.size(), dt_);  // and how long it lasts

  for (int round = 0; round < kMaxReflectionsPerStep && !pending.empty(); ++round) {
    const auto m = static_cast<Index>(pending.size());
    Eigen::VectorXd w;
    Coordinates grad;
    evaluate_own_parts(domain_, start, pending, s.parts, &w, grad);
    Coordinates crossing(m, 2);
    for (Index j = 0; j < m; ++j) {
      const Index i = pending[static_cast<std::size_t>(j)];
      const Vector d = v.row(i) * remaining[static_cast<std::size_t>(j)];
      double lambda = -w[j] / d.dot(grad.row(j));
      // A start on or beyond the boundary, or a gradient along the path that says the particle
      // does not leave (a corner, a second crossing): reflect where the drift begins.
      if (!(lambda > 0)) lambda = 0;
      if (lambda > 1) lambda = 1;
      crossing.row(j) = start.row(j) + lambda * d;
      remaining[static_cast<std::size_t>(j)] *= 1 - lambda;
    }
    // Reflected about the normal at the crossing. Only a particle moving outward is turned back;
    // if the normal there says it moves inward although its drift ends outside (at a corner,
    // where the nearest face changes along the drift), the normal at the drift's end decides.
    Coordinates normal;
    evaluate_own_parts(domain_, crossing, pending, s.parts, nullptr, normal);
    std::vector<Index> unreflected;
    std::vector<bool> reflected(pending.size(), true);
    for (Index j = 0; j < m; ++j) {
      const Index i = pending[static_cast<std::size_t>(j)];
      if (!reflect(normal.row(j), i)) unreflected.push_back(j);
    }
    if (!unreflected.empty()) {
      Coordinates ends(static_cast<Index>(unreflected.size()), 2);
      std::vector<Index> who;
      for (std::size_t r = 0; r < unreflected.size(); ++r) {
        const Index j = unreflected[r];
        const Index i = pending[static_cast<std::size_t>(j)];
        who.push_back(i);
        ends.row(static_cast<Index>(r)) = crossing.row(j) + v.row(i) * remaining[static_cast<std::size_t>(j)];
      }
      Coordinates end_normal;
      evaluate_own_parts(domain_, ends, who, s.parts, nullptr, end_normal);
      for (std::size_t r = 0; r < who.size(); ++r) {
        reflected[static_cast<std::size_t>(unreflected[r])] = reflect(end_normal.row(static_cast<Index>(r)), who[r]);
      }
    }
    for (Index j = 0; j < m; ++j) {
      const Index i = pending[static_cast<std::size_t>(j)];
      end.row(i) = crossing.row(j) + v.row(i) * remaining[static_cast<std::size_t>(j)];
    }
    // Still outside: a particle that was turned back goes on to the next crossing. One moving
    // inward by both normals is done: it started beyond the boundary (an earlier crossing point
    // on a curved wall lies up to (step length)^2 / (2 radius) outside) and comes back in.
    std::vector<Index> still;
    for (const Index j : update_parts(domain_, rows_of(end, pending), pending, s.parts)) {
      if (reflected[static_cast<std::size_t>(j)]) still.push_back(j);
    }
    std::vector<Index> next;
    std::vector<double> next_remaining;
    for (const Index j : still) {
      next.push_back(pending[static_cast<std::size_t>(j)]);
      next_remaining.push_back(remaining[static_cast<std::size_t>(j)]);
    }
    start = rows_of(crossing, still);
    pending = std::move(next);
    remaining = std::move(next_remaining);
  }
  for (std::size_t j = 0; j < pending.size(); ++j) {
    end.row(pending[j]) = start.row(static_cast<Index>(j));
    ++unresolved;
  }

  v.rowwise() += (second_kick * gravity_);
  s.positions = std::move(end);
  s.velocities = std::move(v);
  ++s.steps;
  // From the count, so that times do not collect rounding errors step after step.
  s.time = static_cast<double>(s.steps) * dt_;
}

void Stepper::step(std::int64_t n) {
  if (n < 0) throw std::invalid_argument(describe("Stepper::step: n = ", n, " must be >= 0"));
  // On a copy: a level set that throws halfway leaves this stepper as it was.
  StepperState s = state_;
  std::int64_t unresolved = unresolved_steps_;
  for (std::int64_t k = 0; k < n; ++k) one_step(s, unresolved);
  state_ = std::move(s);
  unresolved_steps_ = unresolved;
}

void Stepper::advance_to(double time) {
  if (!std::isfinite(time) || time < state_.time - 1e-9 * dt_) {
    throw std::invalid_argument(describe("Stepper::advance_to: time = ", time, " must be finite and at least the current time ",
                                         state_.time));
  }
  const double steps = std::floor(time / dt_ + 1e-9);
  if (steps > 1e15) {
    throw std::invalid_argument(describe("Stepper::advance_to: time = ", time, " is ", steps, " steps of dt = ", dt_,
                                         ", more than 1e15"));
  }
  const auto target = static_cast<std::int64_t>(steps);
  if (target > state_.steps) step(target - state_.steps);
}

Stepper Stepper::restarted() const {
  Stepper copy = *this;
  copy.state_ = initial_;
  copy.unresolved_steps_ = 0;
  return copy;
}

Eigen::VectorXd Stepper::energies() const { return stepping::energies(state_, gravity_); }
double Stepper::energy() const { return energies().sum(); }
double Stepper::initial_energy() const { return stepping::energies(initial_, gravity_).sum(); }

std::int64_t Stepper::total_reflections() const {
  std::int64_t total = 0;
  for (const std::int64_t r : state_.reflections) total += r;
  return total;
}

}  // namespace billiard::stepping

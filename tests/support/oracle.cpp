#include "support/oracle.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace billiard::testing {
namespace {

using Real = long double;
constexpr Real kNever = std::numeric_limits<Real>::infinity();

struct Vec {
  Real x = 0, y = 0;
};
Vec operator+(Vec p, Vec q) { return {p.x + q.x, p.y + q.y}; }
Vec operator-(Vec p, Vec q) { return {p.x - q.x, p.y - q.y}; }
Vec operator*(Real s, Vec p) { return {s * p.x, s * p.y}; }
Real dot(Vec p, Vec q) { return p.x * q.x + p.y * q.y; }

Vec at(const Eigen::Matrix<double, Eigen::Dynamic, 2>& rows, Eigen::Index i) {
  return {static_cast<Real>(rows(i, 0)), static_cast<Real>(rows(i, 1))};
}

// Time until circle (r, v) reaches the wall, |r + v t| = L (L = R - a), or kNever.
Real wall_time(Vec r, Vec v, Real L) {
  const Real A = dot(v, v);
  if (A == 0) return kNever;  // at rest
  const Real B = dot(r, v);   // > 0: moving outward
  const Real C = dot(r, r) - L * L;  // <= 0 inside; > 0 only by rounding
  const Real disc = B * B - A * C;
  if (C >= 0 && B == 0) return kNever;  // sliding exactly along the wall: a grazing touch
  if (B > 0) {
    // On or beyond the wall and moving outward (a circle pushed there by another, rounding):
    // it must reflect now, not escape.
    if (C >= 0) return 0;
    return -C / (B + std::sqrt(disc));  // no cancellation: both terms positive
  }
  // Moving inward or tangentially: the exit on the far side, -B + sqrt(...) has no cancellation.
  if (disc < 0) return 0;  // outside (rounding) on a line that never re-enters: reflect now
  return (-B + std::sqrt(disc)) / A;
}

// Time until circles (ri, vi) and (rj, vj) touch, |dr + dv t| = s, or kNever.
Real pair_time(Vec ri, Vec vi, Vec rj, Vec vj, Real s) {
  const Vec dr = ri - rj, dv = vi - vj;
  const Real b = dot(dr, dv);
  if (!(b < 0)) return kNever;  // moving apart, or sliding past (grazing): no collision
  const Real c = dot(dr, dr) - s * s;
  if (c <= 0) return 0;  // touching (or overlapping by rounding) and approaching: collide now
  const Real disc = b * b - dot(dv, dv) * c;
  if (!(disc > 0)) return kNever;  // the paths miss or only graze
  return c / (-b + std::sqrt(disc));  // the first contact, no cancellation
}

struct Candidate {
  Real time;
  int circle, other;
};

OracleEvent apply(const Coordinates& coordinates, const Velocities& velocities, const Candidate& event) {
  const Eigen::Index n = coordinates.rows();
  std::vector<Vec> r(static_cast<std::size_t>(n)), v(static_cast<std::size_t>(n));
  for (Eigen::Index i = 0; i < n; ++i) {
    r[static_cast<std::size_t>(i)] = at(coordinates, i) + event.time * at(velocities, i);
    v[static_cast<std::size_t>(i)] = at(velocities, i);
  }
  const auto i = static_cast<std::size_t>(event.circle);
  if (event.other == kWall) {
    const Real length = std::sqrt(dot(r[i], r[i]));
    const Vec normal = (1 / length) * r[i];
    v[i] = v[i] - (2 * dot(v[i], normal)) * normal;
  } else {
    const auto j = static_cast<std::size_t>(event.other);
    const Vec d = r[j] - r[i];
    const Vec normal = (1 / std::sqrt(dot(d, d))) * d;
    const Real exchanged = dot(v[i] - v[j], normal);
    v[i] = v[i] - exchanged * normal;
    v[j] = v[j] + exchanged * normal;
  }
  OracleEvent out;
  out.time = static_cast<double>(event.time);
  out.circle = event.circle;
  out.other = event.other;
  out.coordinates.resize(n, 2);
  out.velocities.resize(n, 2);
  for (Eigen::Index k = 0; k < n; ++k) {
    const auto s = static_cast<std::size_t>(k);
    out.coordinates(k, 0) = static_cast<double>(r[s].x);
    out.coordinates(k, 1) = static_cast<double>(r[s].y);
    out.velocities(k, 0) = static_cast<double>(v[s].x);
    out.velocities(k, 1) = static_cast<double>(v[s].y);
  }
  return out;
}

}  // namespace

OracleStep oracle_step(double R, double a, const Coordinates& coordinates, const Velocities& velocities,
                       double tie_window) {
  if (coordinates.rows() != velocities.rows()) throw std::invalid_argument("oracle_step: row counts differ");
  const auto n = static_cast<int>(coordinates.rows());
  const Real L = static_cast<Real>(R) - static_cast<Real>(a);
  const Real s = 2 * static_cast<Real>(a);

  std::vector<Candidate> all;
  for (int i = 0; i < n; ++i) {
    const Real t = wall_time(at(coordinates, i), at(velocities, i), L);
    if (t < kNever) all.push_back({t, i, kWall});
  }
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      const Real t = pair_time(at(coordinates, i), at(velocities, i), at(coordinates, j), at(velocities, j), s);
      if (t < kNever) all.push_back({t, i, j});
    }
  }

  OracleStep step;
  if (all.empty()) {
    step.time = std::numeric_limits<double>::infinity();
    return step;
  }
  Real earliest = kNever;
  for (const auto& c : all) earliest = std::min(earliest, c.time);
  std::vector<Candidate> ties;
  for (const auto& c : all) {
    if (c.time <= earliest + static_cast<Real>(tie_window)) ties.push_back(c);
  }
  std::stable_sort(ties.begin(), ties.end(), [](const Candidate& p, const Candidate& q) { return p.time < q.time; });
  step.time = static_cast<double>(earliest);
  for (const auto& c : ties) step.events.push_back(apply(coordinates, velocities, c));
  return step;
}

void oracle_advance(const OracleStep& step, Coordinates& coordinates, Velocities& velocities) {
  if (step.events.empty()) throw std::logic_error("oracle_advance: no event to advance to");
  coordinates = step.events.front().coordinates;
  velocities = step.events.front().velocities;
}

bool same_event(const OracleEvent& event, const Collision& collision) {
  if (event.other == kWall) return collision.other == kWall && collision.circle == event.circle;
  return (collision.circle == event.circle && collision.other == event.other) ||
         (collision.circle == event.other && collision.other == event.circle);
}

std::string describe_event(int circle, int other) {
  if (other == kWall) return "circle " + std::to_string(circle) + " with the wall";
  return "circles " + std::to_string(circle) + " and " + std::to_string(other);
}

OracleComparison compare_with_oracle(double R, double a, const Coordinates& c0, const Velocities& v0, double scale,
                                     const Collision& got, const Coordinates& c, const Velocities& v) {
  OracleComparison comparison;
  comparison.expected = oracle_step(R, a, c0, v0, 1e-9 * scale);
  const std::vector<OracleEvent>& events = comparison.expected.events;
  for (std::size_t k = 0; k < events.size(); ++k) {
    if (same_event(events[k], got)) comparison.match = static_cast<int>(k);
  }
  if (comparison.match >= 0) {
    const OracleEvent& match = comparison.event();
    comparison.difference = step_difference(got.time, c, v, match.time, match.coordinates, match.velocities,
                                            StepTolerances::of_step(R, std::sqrt(v0.squaredNorm()), scale, match.time));
  }
  return comparison;
}

Judgement oracle_judgement(const Board& board, const Outcome& got) {
  Judgement judgement;
  const double speed = std::sqrt(board.velocities.squaredNorm());
  const OracleComparison comparison =
      speed > 0 ? compare_with_oracle(board.table_radius, board.circle_radius, board.coordinates, board.velocities,
                                      board.table_radius / speed, got.event, got.coordinates, got.velocities)
                : OracleComparison{};
  if (comparison.expected.events.empty()) {  // nothing can happen: the step function must refuse the state
    judgement.expected.none = true;
    judgement.agrees = !got.error.empty();
    return judgement;
  }
  const OracleEvent& match = comparison.event();
  judgement.expected.event = Collision{match.time, match.circle, match.other};
  judgement.expected.coordinates = match.coordinates;
  judgement.expected.velocities = match.velocities;
  judgement.agrees = got.error.empty() && comparison.agrees();
  return judgement;
}

double max_speed(const Velocities& velocities) {
  double fastest = 0;
  for (Eigen::Index i = 0; i < velocities.rows(); ++i) fastest = std::max(fastest, velocities.row(i).norm());
  return fastest;
}

}  // namespace billiard::testing

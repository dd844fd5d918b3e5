#include "container.hpp"

#include "describe.hpp"

#include <algorithm>
#include <cmath>

namespace billiard {

Vec2 wrap_into_period(Vec2 p, const Vec2& period) {
  if (period.x() > 0) p.x() -= period.x() * std::floor(p.x() / period.x());
  if (period.y() > 0) p.y() -= period.y() * std::floor(p.y() / period.y());
  return p;
}

double wall_clearance(const WallShape& wall, const Vec2& p, double radius) {
  if (wall.kind == WallKind::Circle) return wall.radius - (p - wall.a).norm() - radius;
  return (closest_point(wall, p) - p).norm() - radius;
}

std::string wall_overlap_message(const std::string& who, const Vec2& p, int wall, double clearance, double radius) {
  return describe(who, " at (", p.x(), ", ", p.y(), ") overlaps wall ", wall, ": distance ", radius + clearance,
                  " < radius ", radius);
}

bool Container::inside_outlines(const std::vector<Outline>& outlines, const Vec2& p) {
  int inside = 0, enclosing = 0;
  for (const Outline& outline : outlines) {
    const bool in = inside_pieces(outline.pieces, p);
    if (outline.hole && in) return false;
    if (!outline.hole) {
      ++enclosing;
      inside += in ? 1 : 0;
    }
  }
  return enclosing == 0 || inside % 2 == 1;
}

std::string Container::outside(const Vec2& p, double radius, double slack) const {
  if (has_table && p.norm() > table_radius - radius + slack) {
    return describe("at (", p.x(), ", ", p.y(), ") is outside the table: |r| = ", p.norm(), " > R - radius = ",
                    table_radius - radius);
  }
  if (periodic && (p.x() < -slack || p.x() >= period.x() + slack || p.y() < -slack || p.y() >= period.y() + slack)) {
    return describe("at (", p.x(), ", ", p.y(), ") is outside the periodic box [0, ", period.x(), ") x [0, ", period.y(), ")");
  }
  if (!inside_outlines(outlines, p)) return describe("at (", p.x(), ", ", p.y(), ") is outside the walls");
  return "";
}

std::optional<Container::Overlap> Container::overlapped_wall(const Vec2& p, double radius, double slack, const int* indices,
                                                             int count) const {
  const int n = indices ? count : static_cast<int>(walls.size());
  for (int k = 0; k < n; ++k) {
    const int w = indices ? indices[k] : k;
    if (walls[w].kind == WallKind::Circle) continue;  // (inside the table: see outside)
    const double clearance = wall_clearance(walls[w], p, radius);
    if (clearance < -slack) return Overlap{w, clearance};
  }
  return std::nullopt;
}

void Container::bounds(Vec2& lower, Vec2& upper) const {
  if (periodic) {
    lower = Vec2::Zero();
    upper = period;
    return;
  }
  // Centres lie inside the table and inside the outlines (an outline inside another is an
  // obstacle): the table's box cut down to the box around all the outlines.
  lower = Vec2::Constant(-kNever);
  upper = Vec2::Constant(kNever);
  if (has_table) {
    lower = Vec2::Constant(-table_radius);
    upper = Vec2::Constant(table_radius);
  }
  if (!closed() || (has_table && outlines.empty())) return;
  Vec2 outline_lower = Vec2::Constant(kNever), outline_upper = Vec2::Constant(-kNever);
  for (const Outline& outline : outlines) {
    if (outline.hole) continue;
    for (const WallShape& piece : outline.pieces) {
      Vec2 lo = piece.a.cwiseMin(piece.b), hi = piece.a.cwiseMax(piece.b);
      if (piece.kind == WallKind::Arc) arc_bounds(piece, lo, hi);
      outline_lower = outline_lower.cwiseMin(lo);
      outline_upper = outline_upper.cwiseMax(hi);
    }
  }
  if (outline_lower.x() > outline_upper.x()) return;  // (only holes, inside a table)
  lower = lower.cwiseMax(outline_lower);
  upper = upper.cwiseMin(outline_upper);
}

double Container::extent() const {
  double largest = has_table ? table_radius : 0.0;
  if (periodic) largest = std::max(largest, period.maxCoeff());
  for (const WallShape& wall : walls) {
    if (wall.kind == WallKind::Arc) largest = std::max(largest, wall.a.cwiseAbs().maxCoeff() + wall.radius);
    if (wall.kind != WallKind::Circle) largest = std::max({largest, wall.a.cwiseAbs().maxCoeff(), wall.b.cwiseAbs().maxCoeff()});
  }
  return largest;
}

}  // namespace billiard

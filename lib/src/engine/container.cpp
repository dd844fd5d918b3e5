// The containers: the shape functions and the walls added to them (billiard/engine/container.hpp).
#include "billiard/engine/container.hpp"
#include "container_geometry.hpp"
#include "wall_geometry.hpp"

#include "billiard/limits.hpp"
#include "billiard/describe.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

namespace billiard {
namespace {

using limits::bounded;
const char* const kBounded = limits::kMustBeBounded;
bool bounded(const Vector& v) { return bounded(v.x(), v.y()); }

[[noreturn]] void refuse(const std::string& message) { throw std::invalid_argument(message); }

// A length: in [1e-50, 1e50] like a disc's radius (no disc fits in less, and the engine's
// squares of it must neither overflow nor underflow).
void check_length(const std::string& call, const char* name, double value, const char* note = "") {
  if (!limits::in_scale(value)) refuse(describe(call, ": ", name, " ", limits::kMustBeInScale, note, ", got ", value));
}

void check_point(const std::string& call, const char* name, const Vector& p) {
  if (!bounded(p)) refuse(describe(call, ": ", name, " ", kBounded, ", got ", p));
}

// An arc from the user's numbers: centre and radius bounded, angles finite and bounded,
// 0 < end - start <= 2 pi. `call` names the call (and the circle) in messages.
WallShape checked_arc(const std::string& call, const Vector& centre, double radius, double start_angle, double end_angle) {
  check_point(call, "centre", centre);
  check_length(call, "radius", radius);
  if (!std::isfinite(start_angle) || std::abs(start_angle) > 1e6) refuse(describe(call, ": start_angle must be finite and at most 1e6 in magnitude (radians), got ", start_angle));
  if (!std::isfinite(end_angle) || std::abs(end_angle) > 1e6) refuse(describe(call, ": end_angle must be finite and at most 1e6 in magnitude (radians), got ", end_angle));
  const double sweep = end_angle - start_angle;
  if (!(sweep > 0 && sweep <= 2 * M_PI)) {
    refuse(describe(call, ": end_angle - start_angle must be in (0, 2 pi] (the arc runs counter-clockwise from start_angle to end_angle), got ", sweep));
  }
  WallShape arc{WallKind::Arc, centre, Vector::Zero(), radius};
  arc.start_angle = start_angle;
  arc.sweep = std::min(sweep, 2 * M_PI);
  return arc;
}

WallShape segment(const Vector& a, const Vector& b) { return WallShape{WallKind::Segment, a, b, 0.0}; }

}  // namespace

// ---------------------------------------------------------------------------------------------
// The shapes
// ---------------------------------------------------------------------------------------------

Container circular_table(double radius) {
  check_length("circular_table", "radius", radius);
  Container table;
  table.has_table_ = true;
  table.table_radius_ = radius;
  table.walls_.push_back(WallShape{WallKind::Circle, Vector::Zero(), Vector::Zero(), radius});
  return table;
}

Container periodic_box(double width, double height) {
  check_length("periodic_box", "width", width);
  check_length("periodic_box", "height", height);
  Container box;
  box.periodic_ = true;
  box.period_ = Vector(width, height);
  return box;
}

Container box(const Vector& lower, const Vector& upper) {
  check_point("box", "lower", lower);
  check_point("box", "upper", upper);
  const Vector size = upper - lower;
  if (!(size.x() >= limits::kSmallest && size.y() >= limits::kSmallest)) {
    refuse("box: upper " + describe(upper) + " must exceed lower " + describe(lower) + " by at least 1e-50 in x and y");
  }
  Coordinates corners(4, 2);
  corners << lower.x(), lower.y(), upper.x(), lower.y(), upper.x(), upper.y(), lower.x(), upper.y();
  return polygon(corners);
}

Container polygon(const Coordinates& vertices) {
  const int n = static_cast<int>(vertices.rows());
  if (n < 3) refuse("polygon: vertices needs at least 3 rows, got " + std::to_string(n));
  for (int k = 0; k < n; ++k) check_point("polygon", ("vertex " + std::to_string(k)).c_str(), vertices.row(k));
  std::vector<WallShape> sides;
  for (int k = 0; k < n; ++k) {
    const Vector p = vertices.row(k);
    const Vector q = vertices.row((k + 1) % n);
    if (!((p - q).squaredNorm() > 0)) refuse("polygon: vertices " + std::to_string(k) + " and " + std::to_string((k + 1) % n) + " coincide at " + describe(p));
    sides.push_back(segment(p, q));
  }
  return Container::of_outline(std::move(sides));
}

Container stadium(const Vector& centre, double radius, double length) {
  check_point("stadium", "centre", centre);
  check_length("stadium", "radius", radius);
  check_length("stadium", "length", length, " (0 is a circle: use circular_table)");
  const Vector half(0.5 * length, 0.0);
  if (!bounded(centre + half) || !bounded(centre - half)) {
    refuse(describe("stadium: the half circles' centres, centre ", centre, " +- length / 2, must be at most 1e50 in magnitude, got length ", length));
  }
  if (!((centre + half - (centre - half)).squaredNorm() > 0)) refuse(describe("stadium: length ", length, " is too small for the centre ", describe(centre)));
  const WallShape right = checked_arc("stadium", centre + half, radius, -M_PI / 2, M_PI / 2);
  const WallShape left = checked_arc("stadium", centre - half, radius, M_PI / 2, 3 * M_PI / 2);
  // The straight sides join the arcs' end points exactly.
  const WallShape top = segment(arc_point(right, M_PI / 2), arc_point(left, M_PI / 2));
  const WallShape bottom = segment(arc_point(left, 3 * M_PI / 2), arc_point(right, -M_PI / 2));
  return Container::of_outline({right, top, left, bottom});
}

Container sinai_billiard(const Vector& lower, const Vector& upper, double obstacle_radius) {
  check_point("sinai_billiard", "lower", lower);
  check_point("sinai_billiard", "upper", upper);
  const Vector size = upper - lower;
  if (!(size.x() >= limits::kSmallest && size.y() >= limits::kSmallest)) {
    refuse("sinai_billiard: upper " + describe(upper) + " must exceed lower " + describe(lower) + " by at least 1e-50 in x and y");
  }
  check_length("sinai_billiard", "obstacle_radius", obstacle_radius);
  if (!(2 * obstacle_radius < size.minCoeff())) {
    refuse(describe("sinai_billiard: obstacle_radius must be positive and below half the box's smaller side ", 0.5 * size.minCoeff(), ", got ", obstacle_radius));
  }
  Container sinai = box(lower, upper);
  sinai.add_obstacle(0.5 * (lower + upper), obstacle_radius);
  return sinai;
}

Container mushroom(const Vector& centre, double cap_radius, double stem_width, double stem_height) {
  check_point("mushroom", "centre", centre);
  check_length("mushroom", "cap_radius", cap_radius);
  if (!(stem_width > 0) || !(stem_width < 2 * cap_radius)) refuse(describe("mushroom: stem_width must be positive and below 2 cap_radius = ", 2 * cap_radius, ", got ", stem_width));
  check_length("mushroom", "stem_height", stem_height);
  const WallShape cap = checked_arc("mushroom", centre, cap_radius, 0.0, M_PI);
  const double w = 0.5 * stem_width;
  const Vector stem_top_right = centre + Vector(w, 0), stem_top_left = centre + Vector(-w, 0);
  const Vector stem_bottom_right = centre + Vector(w, -stem_height), stem_bottom_left = centre + Vector(-w, -stem_height);
  if (!((stem_top_right - stem_top_left).squaredNorm() > 0 && (stem_top_right - stem_bottom_right).squaredNorm() > 0 &&
        (arc_point(cap, 0.0) - stem_top_right).squaredNorm() > 0 && (arc_point(cap, M_PI) - stem_top_left).squaredNorm() > 0)) {
    refuse(describe("mushroom: the stem ", stem_width, " x ", stem_height, " and the cap are too small for the centre ", describe(centre)));
  }
  return Container::of_outline({segment(stem_bottom_right, stem_top_right), segment(stem_top_right, arc_point(cap, 0.0)), cap,
                                segment(arc_point(cap, M_PI), stem_top_left), segment(stem_top_left, stem_bottom_left),
                                segment(stem_bottom_left, stem_bottom_right)});
}

Container union_of_circles(const Coordinates& centres, const std::vector<double>& radii) {
  const int n = static_cast<int>(centres.rows());
  if (n < 1) refuse("union_of_circles: centres needs at least 1 row, got 0");
  if (static_cast<int>(radii.size()) != n) {
    refuse("union_of_circles: radii has " + std::to_string(radii.size()) + " entries, centres " + std::to_string(n) + " rows");
  }
  std::vector<WallShape> circles;
  for (int i = 0; i < n; ++i) {
    circles.push_back(checked_arc("union_of_circles: circle " + std::to_string(i), centres.row(i), radii[i], 0.0, 2 * M_PI));
  }
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < i; ++j) {
      if (circles[i].a == circles[j].a && circles[i].radius == circles[j].radius) {
        refuse("union_of_circles: circles " + std::to_string(j) + " and " + std::to_string(i) + " coincide");
      }
    }
  }
  // The boundary: for each circle, the angles it spends inside another circle are covered;
  // what is left are the boundary arcs.
  std::vector<WallShape> arcs;
  for (int i = 0; i < n; ++i) {
    const WallShape& ci = circles[i];
    bool buried = false;
    std::vector<std::pair<double, double>> covered;  // angle intervals [from, to], from in [0, 2 pi)
    for (int j = 0; j < n && !buried; ++j) {
      if (j == i) continue;
      const WallShape& cj = circles[j];
      const Vector d = cj.a - ci.a;
      const double distance = d.norm();
      if (distance + ci.radius <= cj.radius) buried = true;                  // inside circle j
      if (buried || distance >= ci.radius + cj.radius || distance + cj.radius <= ci.radius) continue;  // apart, or j inside
      // Circle i is inside circle j for angles within `half` of the direction to j's centre
      // (law of cosines at the intersection points).
      const double half = std::acos(std::clamp((distance * distance + ci.radius * ci.radius - cj.radius * cj.radius) / (2 * distance * ci.radius), -1.0, 1.0));
      double from = std::atan2(d.y(), d.x()) - half;
      from -= 2 * M_PI * std::floor(from / (2 * M_PI));
      covered.emplace_back(from, from + 2 * half);
    }
    if (buried) continue;
    if (covered.empty()) {
      arcs.push_back(ci);
      continue;
    }
    // Free angles: sort the covered intervals and walk once around the circle from the start of
    // the first one.
    std::sort(covered.begin(), covered.end());
    const double origin = covered.front().first;
    double reach = origin;  // covered up to here, counting the intervals that wrap past 2 pi
    for (const auto& interval : covered) reach = std::max(reach, interval.second - 2 * M_PI);
    for (const auto& [from, to] : covered) {
      if (from > reach) {
        WallShape arc = ci;
        arc.start_angle = reach;
        arc.sweep = from - reach;
        arcs.push_back(arc);
      }
      reach = std::max(reach, to);
    }
    if (reach < origin + 2 * M_PI) {
      WallShape arc = ci;
      arc.start_angle = reach;
      arc.sweep = origin + 2 * M_PI - reach;
      arcs.push_back(arc);
    }
  }
  // Where two boundary arcs meet, their end points agree to rounding: one point wall.
  double extent = 0;
  for (const WallShape& c : circles) extent = std::max(extent, c.a.cwiseAbs().maxCoeff() + c.radius);
  return Container::of_outline(std::move(arcs), 1e-12 * extent);
}

// ---------------------------------------------------------------------------------------------
// Adding to a container
// ---------------------------------------------------------------------------------------------

Container Container::of_outline(std::vector<WallShape> pieces, double merge) {
  Container shape;
  shape.add_outline(Outline{std::move(pieces), false}, merge);
  return shape;
}

// Walls inside a periodic box are not supported: every call that adds a wall says so here.
void Container::refuse_in_periodic_box(const char* call) const {
  if (periodic_) refuse(std::string(call) + ": walls inside a periodic box are not supported");
}

void Container::add_outline(Outline outline, double merge) {
  for (const WallShape& piece : outline.pieces) add_wall_with_ends(piece, merge);
  outlines_.push_back(std::move(outline));
}

// A point wall at p, unless one is already within `merge` of it (end points shared by two
// segments or arcs are one wall).
static void add_point_wall(std::vector<WallShape>& walls, const Vector& p, double merge) {
  for (const WallShape& w : walls) {
    if (w.kind == WallKind::Point && (w.a - p).norm() <= merge) return;
  }
  walls.push_back(WallShape{WallKind::Point, p, p, 0.0});
}

// A segment or arc wall, with its end points as point walls (none for a full circle).
void Container::add_wall_with_ends(const WallShape& wall, double merge) {
  walls_.push_back(wall);
  if (wall.kind == WallKind::Segment) {
    add_point_wall(walls_, wall.a, merge);
    add_point_wall(walls_, wall.b, merge);
  } else if (wall.kind == WallKind::Arc && wall.sweep < 2 * M_PI) {
    add_point_wall(walls_, arc_point(wall, wall.start_angle), merge);
    add_point_wall(walls_, arc_point(wall, wall.start_angle + wall.sweep), merge);
  }
}

int Container::add_segment(const Vector& a, const Vector& b) {
  check_point("add_segment", "a", a);
  check_point("add_segment", "b", b);
  // (So close that the squared length underflows, the segment has no direction.)
  if (!((a - b).squaredNorm() > 0)) refuse(describe("add_segment: a and b must differ, got ", a, " and ", b));
  refuse_in_periodic_box("add_segment");
  const int index = static_cast<int>(walls_.size());
  add_wall_with_ends(segment(a, b));
  ++free_walls_;
  return index;
}

int Container::add_arc(const Vector& centre, double radius, double start_angle, double end_angle) {
  const WallShape arc = checked_arc("add_arc", centre, radius, start_angle, end_angle);
  refuse_in_periodic_box("add_arc");
  const int index = static_cast<int>(walls_.size());
  add_wall_with_ends(arc);
  ++free_walls_;
  return index;
}

void Container::add_obstacle(const Vector& centre, double radius) {
  const WallShape circle = checked_arc("add_obstacle", centre, radius, 0.0, 2 * M_PI);
  refuse_in_periodic_box("add_obstacle");
  add_outline(Outline{{circle}, true});
}

void Container::add_obstacle(const Container& shape) {
  if (shape.has_table_ || shape.periodic_) {
    refuse("add_obstacle: shape must be an outline (a box, polygon, stadium, mushroom or union of circles); "
           "for a circle, give its centre and radius");
  }
  if (shape.free_walls_ > 0) refuse("add_obstacle: shape has walls besides its outline; add them to this container instead");
  refuse_in_periodic_box("add_obstacle");
  // (End points that agree to rounding are one wall, as in the union of circles.)
  const double merge = 1e-12 * extent(shape);
  for (Outline outline : shape.outlines_) {
    outline.hole = true;
    add_outline(std::move(outline), merge);
  }
}

// ---------------------------------------------------------------------------------------------
// Geometry
// ---------------------------------------------------------------------------------------------

Vector wrap_into_period(Vector p, const Vector& period) {
  if (period.x() > 0) p.x() -= period.x() * std::floor(p.x() / period.x());
  if (period.y() > 0) p.y() -= period.y() * std::floor(p.y() / period.y());
  return p;
}

double wall_clearance(const WallShape& wall, const Vector& p, double radius) {
  if (wall.kind == WallKind::Circle) return wall.radius - (p - wall.a).norm() - radius;
  return (closest_point(wall, p) - p).norm() - radius;
}

namespace {
// Even-odd rule: p lies inside an odd number of the outlines that are not holes (true when there
// are none), and inside no hole.
bool inside_outlines(const std::vector<Outline>& outlines, const Vector& p) {
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
}  // namespace

Outside where_outside(const Container& container, const Vector& p, double radius, double slack) {
  if (container.has_table() && p.norm() > container.table_radius() - radius + slack) return Outside::Table;
  const Vector& period = container.period();
  if (container.periodic() &&
      (p.x() < -slack || p.x() >= period.x() + slack || p.y() < -slack || p.y() >= period.y() + slack)) {
    return Outside::PeriodicBox;
  }
  if (!inside_outlines(container.outlines(), p)) return Outside::Walls;
  return Outside::No;
}

std::string outside(const Container& container, const Vector& p, double radius, double slack) {
  const Vector& period = container.period();
  switch (where_outside(container, p, radius, slack)) {
    case Outside::No:
      return "";
    case Outside::Table:
      return describe("at (", p.x(), ", ", p.y(), ") is outside the table: |r| = ", p.norm(), " > R - radius = ",
                      container.table_radius() - radius);
    case Outside::PeriodicBox:
      return describe("at (", p.x(), ", ", p.y(), ") is outside the periodic box [0, ", period.x(), ") x [0, ", period.y(), ")");
    case Outside::Walls:
      break;
  }
  return describe("at (", p.x(), ", ", p.y(), ") is outside the walls");
}

std::optional<WallOverlap> overlapped_wall(const Container& container, const Vector& p, double radius, double slack,
                                           const int* indices, int count) {
  const std::vector<WallShape>& walls = container.walls();
  const int n = indices ? count : static_cast<int>(walls.size());
  for (int k = 0; k < n; ++k) {
    const int w = indices ? indices[k] : k;
    if (walls[w].kind == WallKind::Circle) continue;  // (inside the table: see outside)
    const double clearance = wall_clearance(walls[w], p, radius);
    if (clearance < -slack) return WallOverlap{w, clearance};
  }
  return std::nullopt;
}

void bounds(const Container& container, Vector& lower, Vector& upper) {
  if (container.periodic()) {
    lower = Vector::Zero();
    upper = container.period();
    return;
  }
  // Centres lie inside the table and inside the outlines (an outline inside another is an
  // obstacle): the table's box cut down to the box around all the outlines.
  lower = Vector::Constant(-kNever);
  upper = Vector::Constant(kNever);
  if (container.has_table()) {
    lower = Vector::Constant(-container.table_radius());
    upper = Vector::Constant(container.table_radius());
  }
  if (container.has_table() && container.outlines().empty()) return;
  Vector outline_lower = Vector::Constant(kNever), outline_upper = Vector::Constant(-kNever);
  for (const Outline& outline : container.outlines()) {
    if (outline.hole) continue;
    for (const WallShape& piece : outline.pieces) {
      Vector lo = piece.a.cwiseMin(piece.b), hi = piece.a.cwiseMax(piece.b);
      if (piece.kind == WallKind::Arc) arc_bounds(piece, lo, hi);
      outline_lower = outline_lower.cwiseMin(lo);
      outline_upper = outline_upper.cwiseMax(hi);
    }
  }
  if (outline_lower.x() > outline_upper.x()) return;  // (only holes, inside a table)
  lower = lower.cwiseMax(outline_lower);
  upper = upper.cwiseMin(outline_upper);
}

double extent(const Container& container) {
  double largest = container.table_radius();
  if (container.periodic()) largest = std::max(largest, container.period().maxCoeff());
  for (const WallShape& wall : container.walls()) {
    if (wall.kind == WallKind::Arc) largest = std::max(largest, wall.a.cwiseAbs().maxCoeff() + wall.radius);
    if (wall.kind != WallKind::Circle) largest = std::max({largest, wall.a.cwiseAbs().maxCoeff(), wall.b.cwiseAbs().maxCoeff()});
  }
  return largest;
}

}  // namespace billiard

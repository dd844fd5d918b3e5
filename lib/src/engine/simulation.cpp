// The public Simulation: input checks at the API boundary, setup, state accessors and replay.
// The event loop itself is in engine.cpp.
#include "billiard/engine/simulation.hpp"

#include "billiard/limits.hpp"
#include "describe.hpp"
#include "engine.hpp"

#include <algorithm>
#include <random>
#include <cmath>
#include <stdexcept>

namespace billiard {
namespace {

std::string number(double x) { return describe(x); }

std::string vec(const Vec2& v) { return "(" + number(v.x()) + ", " + number(v.y()) + ")"; }

[[noreturn]] void refuse(const std::string& message) { throw std::invalid_argument(message); }

// The numbers the engine accepts (billiard/limits.hpp, shared with the course and the commands).
using limits::bounded;
using limits::in_scale;
using limits::kRelativeRadius;
using limits::kSmallest;
const char* const kBounded = limits::kMustBeBounded;
const char* const kScale = limits::kMustBeInScale;
bool bounded(const Vec2& v) { return bounded(v.x()) && bounded(v.y()); }

void require_setup(const Simulation::Engine& e, const char* call) {
  if (e.prepared) {
    throw std::logic_error(std::string(call) + ": the simulation has started; discs, walls, the container and gravity are fixed after the first advance()");
  }
}

// Walls inside a periodic box are not supported: every call that adds a wall says so here.
void refuse_walls_in_periodic_box(const Simulation::Engine& e, const char* call) {
  if (e.container.periodic) refuse(std::string(call) + ": walls inside a periodic box are not supported");
}

// A new wall (or a piece of a new outline, `what`) must leave every disc placed so far clear:
// the same test as for a disc added among walls (wall_clearance).
void refuse_wall_over_discs(const Simulation::Engine& e, const char* call, const WallShape& wall, const std::string& what) {
  for (int i = 0; i < static_cast<int>(e.hot.size()); ++i) {
    if (wall_clearance(wall, e.hot[i].position, e.hot[i].radius) < 0) {
      refuse(std::string(call) + ": " + what + " overlaps disc " + std::to_string(i) + " at " + vec(e.hot[i].position));
    }
  }
}

// A container or wall with coordinates up to `extent` must leave every disc at least
// kRelativeRadius of it.
void check_extent(const Simulation::Engine& e, double extent, const char* call) {
  if (!e.hot.empty() && e.min_radius < kRelativeRadius * extent) {
    refuse(std::string(call) + ": coordinates up to " + number(extent) + " are too large for the smallest disc (radius " +
           number(e.min_radius) + "): radii must be at least 1e-6 of the coordinates");
  }
}

// Key of hash cell (ix, iy): the two 32-bit halves (shifted as unsigned: shifting a negative
// signed value is undefined behaviour).
std::int64_t hash_key(std::int64_t ix, std::int64_t iy) {
  return static_cast<std::int64_t>((static_cast<std::uint64_t>(ix) << 32) ^ (static_cast<std::uint64_t>(iy) & 0xffffffffULL));
}

// Hash column of coordinate x, clamped so that a tiny cell far from the origin cannot overflow
// the integer (clamping keeps cells that are k apart at most k apart, so no overlap is missed).
std::int64_t hash_column(double x, double cell) {
  return static_cast<std::int64_t>(std::clamp(std::floor(x / cell), -1e15, 1e15));
}


// The largest coordinate of a wall (for the radius-to-coordinates check).
double wall_extent(const WallShape& wall) {
  if (wall.kind == WallKind::Arc || wall.kind == WallKind::Circle) return wall.a.cwiseAbs().maxCoeff() + wall.radius;
  return std::max(wall.a.cwiseAbs().maxCoeff(), wall.b.cwiseAbs().maxCoeff());
}

// A point wall at p, unless one is already within `merge` of it (end points shared by two
// segments or arcs are one wall).
void add_point_wall(Container& container, const Vec2& p, double merge = 0.0) {
  for (const WallShape& w : container.walls) {
    if (w.kind == WallKind::Point && (w.a - p).norm() <= merge) return;
  }
  container.walls.push_back(WallShape{WallKind::Point, p, p, 0.0});
}

// A segment or arc wall, with its end points as point walls (none for a full circle).
void add_wall_with_ends(Container& container, const WallShape& wall, double merge = 0.0) {
  container.walls.push_back(wall);
  if (wall.kind == WallKind::Segment) {
    add_point_wall(container, wall.a, merge);
    add_point_wall(container, wall.b, merge);
  } else if (wall.kind == WallKind::Arc && wall.sweep < 2 * M_PI) {
    add_point_wall(container, arc_point(wall, wall.start_angle), merge);
    add_point_wall(container, arc_point(wall, wall.start_angle + wall.sweep), merge);
  }
}

// An arc from the user's numbers: centre and radius bounded, angles finite and bounded,
// 0 < end - start <= 2 pi. `what` names the arguments in messages ("add_arc: ").
WallShape checked_arc(const std::string& what, const Vec2& centre, double radius, double start_angle, double end_angle) {
  if (!bounded(centre)) refuse(what + "centre " + kBounded + ", got " + vec(centre));
  if (!(radius > 0) || !bounded(radius)) refuse(what + "radius must be positive, finite and at most 1e50, got " + number(radius));
  if (!std::isfinite(start_angle) || std::abs(start_angle) > 1e6) refuse(what + "start_angle must be finite and at most 1e6 in magnitude (radians), got " + number(start_angle));
  if (!std::isfinite(end_angle) || std::abs(end_angle) > 1e6) refuse(what + "end_angle must be finite and at most 1e6 in magnitude (radians), got " + number(end_angle));
  const double sweep = end_angle - start_angle;
  if (!(sweep > 0 && sweep <= 2 * M_PI)) {
    refuse(what + "end_angle - start_angle must be in (0, 2 pi] (the arc runs counter-clockwise from start_angle to end_angle), got " + number(sweep));
  }
  WallShape arc{WallKind::Arc, centre, Vec2::Zero(), radius};
  arc.start_angle = start_angle;
  arc.sweep = std::min(sweep, 2 * M_PI);
  return arc;
}

}  // namespace

// A closed outline (or a hole) of segments and arcs: all or nothing, every disc must stay inside
// the container with it and clear of its pieces. `merge`: end points closer than this are one.
static void add_outline(Simulation::Engine& e, const char* call, std::vector<WallShape> pieces, bool hole, double merge = 0.0) {
  refuse_walls_in_periodic_box(e, call);
  double extent = 0;
  for (const WallShape& piece : pieces) extent = std::max(extent, wall_extent(piece));
  check_extent(e, extent, call);
  std::vector<Outline> outlines = e.container.outlines;
  outlines.push_back(Outline{pieces, hole});
  for (int i = 0; i < static_cast<int>(e.hot.size()); ++i) {
    const Vec2& r = e.hot[i].position;
    if (!Container::inside_outlines(outlines, r)) refuse(std::string(call) + ": disc " + std::to_string(i) + " at " + vec(r) + " would be outside the walls");
  }
  for (int k = 0; k < static_cast<int>(pieces.size()); ++k) {
    refuse_wall_over_discs(e, call, pieces[k], (pieces[k].kind == WallKind::Arc ? "arc " : "side ") + std::to_string(k));
  }
  for (const WallShape& piece : pieces) add_wall_with_ends(e.container, piece, merge);
  e.container.outlines = std::move(outlines);
}

// ---------------------------------------------------------------------------------------------
// Setup helpers
// ---------------------------------------------------------------------------------------------

void Simulation::Engine::rebuild_setup_hash(double cell) {
  setup_hash.cell = cell;
  setup_hash.cells.clear();
  for (int i = 0; i < static_cast<int>(hot.size()); ++i) {
    const Vec2& p = hot[i].position;
    setup_hash.cells[hash_key(hash_column(p.x(), cell), hash_column(p.y(), cell))].push_back(i);
  }
}

bool Simulation::Engine::overlaps_existing(const Vec2& position, double radius, int& other) const {
  if (hot.empty()) return false;
  auto overlap = [&](int j) {
    const Vec2 d = container.minimum_image(position - hot[j].position);
    const double contact = radius + hot[j].radius;
    return d.squaredNorm() < contact * contact;
  };
  const double h = setup_hash.cell;
  // In a periodic box an image across the boundary can overlap: check the wrapped positions too.
  const int images = container.periodic ? 1 : 0;
  // A disc much larger than the cells (cells sized by small discs added before) would scan more
  // cells than there are discs (a hang for a ratio of radii of 10^6): then test every disc.
  const double reach_cells = std::ceil((radius + max_radius) / h);
  const double cells = (2 * reach_cells + 1) * (2 * reach_cells + 1) * (2 * images + 1) * (2 * images + 1);
  if (!(cells <= 4.0 * static_cast<double>(hot.size()) + 64)) {
    for (int j = 0; j < static_cast<int>(hot.size()); ++j) {
      if (overlap(j)) {
        other = j;
        return true;
      }
    }
    return false;
  }
  const int reach = static_cast<int>(reach_cells);
  for (int sy = -images; sy <= images; ++sy) {
    for (int sx = -images; sx <= images; ++sx) {
      const Vec2 p = position + Vec2(sx * container.period.x(), sy * container.period.y());
      const std::int64_t cx = hash_column(p.x(), h);
      const std::int64_t cy = hash_column(p.y(), h);
      for (std::int64_t y = cy - reach; y <= cy + reach; ++y) {
        for (std::int64_t x = cx - reach; x <= cx + reach; ++x) {
          const auto found = setup_hash.cells.find(hash_key(x, y));
          if (found == setup_hash.cells.end()) continue;
          for (int j : found->second) {
            if (overlap(j)) {
              other = j;
              return true;
            }
          }
        }
      }
    }
  }
  return false;
}

void Simulation::Engine::check_disc(const Disc& disc, int index) const {
  const std::string who = "disc " + std::to_string(index);
  if (!bounded(disc.position)) refuse(who + ": position " + kBounded + ", got " + vec(disc.position));
  if (!bounded(disc.velocity)) refuse(who + ": velocity " + kBounded + ", got " + vec(disc.velocity));
  if (!in_scale(disc.radius)) refuse(who + ": radius " + kScale + ", got " + number(disc.radius));
  if (!in_scale(disc.mass)) refuse(who + ": mass " + kScale + ", got " + number(disc.mass));
  if (disc.inertia && !in_scale(*disc.inertia)) refuse(who + ": inertia " + kScale + ", got " + number(*disc.inertia));
  // A thin ring, all its mass at the rim, has the largest moment a disc can have: mass radius^2
  // (with 1e-12 for rounding in how the caller computed it).
  const double ring = disc.mass * disc.radius * disc.radius;
  if (disc.inertia && *disc.inertia > ring * (1 + 1e-12)) {
    refuse(who + ": inertia " + number(*disc.inertia) + " is more than mass x radius^2 = " + number(ring) +
           ", which no disc can have (a thin ring, all its mass at the rim, has that much)");
  }
  if (!bounded(disc.spin)) refuse(who + ": spin " + kBounded + ", got " + number(disc.spin));
  const Vec2& r = disc.position;
  const double a = disc.radius;
  const std::string outside = container.outside(r, a, 0.0);
  if (!outside.empty()) refuse(who + " " + outside);
  if (container.periodic && 6 * a > container.period.minCoeff()) {
    refuse(who + ": radius " + number(a) + " is too large for the periodic box (need 6 radius <= " + number(container.period.minCoeff()) + ")");
  }
  if (const auto overlap = container.overlapped_wall(r, a, 0.0)) refuse(wall_overlap_message(who, r, overlap->wall, overlap->clearance, a));
  const double extent = std::max(container.extent(), r.cwiseAbs().maxCoeff());
  if (a < kRelativeRadius * extent) {
    refuse(who + ": radius " + number(a) + " is too small for coordinates up to " + number(extent) + ": radii must be at least 1e-6 of the coordinates");
  }
}

void Simulation::Engine::add_checked_disc(const Disc& disc) {
  HotDisc d;
  d.position = disc.position;
  d.velocity = disc.velocity;
  d.time = 0.0;
  d.radius = disc.radius;
  d.inverse_mass = 1.0 / disc.mass;
  d.counter = 0;
  d.cx = d.cy = 0;
  hot.push_back(d);
  ColdDisc c;
  c.mass = disc.mass;
  c.inertia = disc.inertia ? *disc.inertia : 0.5 * disc.mass * disc.radius * disc.radius;
  c.inverse_inertia = 1.0 / c.inertia;
  c.spin = disc.spin;
  c.last_collision = -kNever;
  c.last_disc_collision = -kNever;
  c.slow_since = kNever;
  c.next_sleep_try = -kNever;
  cold.push_back(c);
  scheduled.push_back(Scheduled{kNever, kNever, kNoDisc, 0, kNoWall, Face::PlusX});
  const int i = static_cast<int>(hot.size()) - 1;
  min_radius = std::min(min_radius, disc.radius);
  if (disc.radius > max_radius) {
    max_radius = disc.radius;
    rebuild_setup_hash(2 * max_radius);
  } else {
    const Vec2& p = disc.position;
    setup_hash.cells[hash_key(hash_column(p.x(), setup_hash.cell), hash_column(p.y(), setup_hash.cell))].push_back(i);
  }
}

// ---------------------------------------------------------------------------------------------
// Simulation
// ---------------------------------------------------------------------------------------------

Simulation::Simulation() : engine_(std::make_unique<Engine>()) {}
Simulation::~Simulation() = default;
Simulation::Simulation(Simulation&&) noexcept = default;
Simulation& Simulation::operator=(Simulation&&) noexcept = default;
// The queue reads the schedules through a pointer set at the first advance: a copy's queue must
// read the copy's, not the original's (which may change or be gone).
Simulation::Simulation(const Simulation& other) : engine_(std::make_unique<Engine>(*other.engine_)) {
  if (engine_->prepared) engine_->queue.set_keys(ScheduledKeys{engine_.get(), engine_->scheduled.data()});
}
Simulation& Simulation::operator=(const Simulation& other) {
  if (this != &other) *this = Simulation(other);
  return *this;
}

void Simulation::set_circular_table(double radius) {
  Engine& e = *engine_;
  require_setup(e, "set_circular_table");
  if (!(radius > 0) || !bounded(radius)) refuse("set_circular_table: radius must be positive, finite and at most 1e50, got " + number(radius));
  if (e.container.has_table) refuse("set_circular_table: the table is already set (radius " + number(e.container.table_radius) + ")");
  if (e.container.periodic) refuse("set_circular_table: a periodic box has no walls; choose one container");
  check_extent(e, radius, "set_circular_table");
  for (int i = 0; i < static_cast<int>(e.hot.size()); ++i) {
    if (e.hot[i].position.norm() > radius - e.hot[i].radius) {
      refuse("set_circular_table: radius " + number(radius) + " leaves disc " + std::to_string(i) + " at " + vec(e.hot[i].position) + " outside");
    }
  }
  e.container.has_table = true;
  e.container.table_radius = radius;
  e.container.walls.push_back(WallShape{WallKind::Circle, Vec2::Zero(), Vec2::Zero(), radius});
}

void Simulation::set_periodic_box(double width, double height) {
  Engine& e = *engine_;
  require_setup(e, "set_periodic_box");
  if (!(width > 0) || !bounded(width)) refuse("set_periodic_box: width must be positive, finite and at most 1e50, got " + number(width));
  if (!(height > 0) || !bounded(height)) refuse("set_periodic_box: height must be positive, finite and at most 1e50, got " + number(height));
  if (!e.container.walls.empty() || e.container.periodic) refuse("set_periodic_box: the periodic box must be the only container (walls or a box are already set)");
  check_extent(e, std::max(width, height), "set_periodic_box");
  for (int i = 0; i < static_cast<int>(e.hot.size()); ++i) {
    const Vec2& r = e.hot[i].position;
    if (r.x() < 0 || r.x() >= width || r.y() < 0 || r.y() >= height) {
      refuse("set_periodic_box: disc " + std::to_string(i) + " at " + vec(r) + " is outside [0, " + number(width) + ") x [0, " + number(height) + ")");
    }
  }
  if (6 * e.max_radius > std::min(width, height)) {
    refuse("set_periodic_box: the box " + number(width) + " x " + number(height) + " must be at least 6 largest radii (" + number(6 * e.max_radius) + ") wide");
  }
  e.container.periodic = true;
  e.container.period = Vec2(width, height);
  e.rebuild_setup_hash(e.setup_hash.cell > 0 ? e.setup_hash.cell : 1.0);
  // Discs added before may overlap through the boundary.
  for (int i = 0; i < static_cast<int>(e.hot.size()); ++i) {
    int other = -1;
    const HotDisc saved = e.hot[i];
    // Check i against all others except itself: temporarily move it far away.
    e.hot[i].position = Vec2::Constant(kNever);
    const bool bad = e.overlaps_existing(saved.position, saved.radius, other) && other != i;
    e.hot[i] = saved;
    if (bad) {
      e.container.periodic = false;
      e.container.period = Vec2::Zero();
      refuse("set_periodic_box: disc " + std::to_string(i) + " overlaps disc " + std::to_string(other) + " across the periodic boundary");
    }
  }
}

int Simulation::add_segment(const Vec2& a, const Vec2& b) {
  Engine& e = *engine_;
  require_setup(e, "add_segment");
  if (!bounded(a)) refuse(std::string("add_segment: a ") + kBounded + ", got " + vec(a));
  if (!bounded(b)) refuse(std::string("add_segment: b ") + kBounded + ", got " + vec(b));
  // (So close that the squared length underflows, the segment has no direction.)
  if (!((a - b).squaredNorm() > 0)) refuse("add_segment: a and b must differ, got " + vec(a) + " and " + vec(b));
  refuse_walls_in_periodic_box(e, "add_segment");
  check_extent(e, std::max(a.cwiseAbs().maxCoeff(), b.cwiseAbs().maxCoeff()), "add_segment");
  const WallShape segment{WallKind::Segment, a, b, 0.0};
  refuse_wall_over_discs(e, "add_segment", segment, "segment " + vec(a) + "-" + vec(b));
  const int index = static_cast<int>(e.container.walls.size());
  add_wall_with_ends(e.container, segment);
  return index;
}

int Simulation::add_arc(const Vec2& centre, double radius, double start_angle, double end_angle) {
  Engine& e = *engine_;
  require_setup(e, "add_arc");
  const WallShape arc = checked_arc("add_arc: ", centre, radius, start_angle, end_angle);
  refuse_walls_in_periodic_box(e, "add_arc");
  check_extent(e, wall_extent(arc), "add_arc");
  refuse_wall_over_discs(e, "add_arc", arc, "the arc");
  const int index = static_cast<int>(e.container.walls.size());
  add_wall_with_ends(e.container, arc);
  return index;
}

void Simulation::add_disc_obstacle(const Vec2& centre, double radius) {
  Engine& e = *engine_;
  require_setup(e, "add_disc_obstacle");
  const WallShape circle = checked_arc("add_disc_obstacle: ", centre, radius, 0.0, 2 * M_PI);
  add_outline(e, "add_disc_obstacle", {circle}, true);
}

void Simulation::add_stadium(const Vec2& centre, double radius, double length) {
  Engine& e = *engine_;
  require_setup(e, "add_stadium");
  if (!bounded(centre)) refuse(std::string("add_stadium: centre ") + kBounded + ", got " + vec(centre));
  if (!(radius > 0) || !bounded(radius)) refuse("add_stadium: radius must be positive, finite and at most 1e50, got " + number(radius));
  if (!(length > 0) || !bounded(length)) refuse("add_stadium: length must be positive, finite and at most 1e50 (0 is a circle: use set_circular_table), got " + number(length));
  const Vec2 half(0.5 * length, 0.0);
  if (!((centre + half - (centre - half)).squaredNorm() > 0)) refuse("add_stadium: length " + number(length) + " is too small for the centre " + vec(centre));
  WallShape right = checked_arc("add_stadium: ", centre + half, radius, -M_PI / 2, M_PI / 2);
  WallShape left = checked_arc("add_stadium: ", centre - half, radius, M_PI / 2, 3 * M_PI / 2);
  // The straight sides join the arcs' end points exactly.
  const WallShape top{WallKind::Segment, arc_point(right, M_PI / 2), arc_point(left, M_PI / 2), 0.0};
  const WallShape bottom{WallKind::Segment, arc_point(left, 3 * M_PI / 2), arc_point(right, -M_PI / 2), 0.0};
  add_outline(e, "add_stadium", {right, top, left, bottom}, false);
}

void Simulation::add_sinai_billiard(const Vec2& lower, const Vec2& upper, double obstacle_radius) {
  Engine& e = *engine_;
  require_setup(e, "add_sinai_billiard");
  if (!bounded(lower)) refuse(std::string("add_sinai_billiard: lower ") + kBounded + ", got " + vec(lower));
  if (!bounded(upper)) refuse(std::string("add_sinai_billiard: upper ") + kBounded + ", got " + vec(upper));
  const Vec2 size = upper - lower;
  if (!(size.x() > 0 && size.y() > 0)) refuse("add_sinai_billiard: upper " + vec(upper) + " must exceed lower " + vec(lower) + " in x and y");
  if (!(obstacle_radius > 0) || !(2 * obstacle_radius < size.minCoeff())) {
    refuse("add_sinai_billiard: obstacle_radius must be positive and below half the box's smaller side " + number(0.5 * size.minCoeff()) + ", got " + number(obstacle_radius));
  }
  const Engine saved = e;  // all or nothing
  try {
    add_box(lower, upper);
    add_disc_obstacle(0.5 * (lower + upper), obstacle_radius);
  } catch (...) {
    e = saved;
    throw;
  }
}

void Simulation::add_mushroom(const Vec2& centre, double cap_radius, double stem_width, double stem_height) {
  Engine& e = *engine_;
  require_setup(e, "add_mushroom");
  if (!bounded(centre)) refuse(std::string("add_mushroom: centre ") + kBounded + ", got " + vec(centre));
  if (!(cap_radius > 0) || !bounded(cap_radius)) refuse("add_mushroom: cap_radius must be positive, finite and at most 1e50, got " + number(cap_radius));
  if (!(stem_width > 0) || !(stem_width < 2 * cap_radius)) refuse("add_mushroom: stem_width must be positive and below 2 cap_radius = " + number(2 * cap_radius) + ", got " + number(stem_width));
  if (!(stem_height > 0) || !bounded(stem_height)) refuse("add_mushroom: stem_height must be positive, finite and at most 1e50, got " + number(stem_height));
  const WallShape cap = checked_arc("add_mushroom: ", centre, cap_radius, 0.0, M_PI);
  const double w = 0.5 * stem_width;
  const Vec2 stem_top_right = centre + Vec2(w, 0), stem_top_left = centre + Vec2(-w, 0);
  const Vec2 stem_bottom_right = centre + Vec2(w, -stem_height), stem_bottom_left = centre + Vec2(-w, -stem_height);
  if (!((stem_top_right - stem_top_left).squaredNorm() > 0 && (stem_top_right - stem_bottom_right).squaredNorm() > 0 &&
        (arc_point(cap, 0.0) - stem_top_right).squaredNorm() > 0 && (arc_point(cap, M_PI) - stem_top_left).squaredNorm() > 0)) {
    refuse("add_mushroom: the stem " + number(stem_width) + " x " + number(stem_height) + " and the cap are too small for the centre " + vec(centre));
  }
  auto segment = [](const Vec2& a, const Vec2& b) { return WallShape{WallKind::Segment, a, b, 0.0}; };
  add_outline(e, "add_mushroom",
              {segment(stem_bottom_right, stem_top_right), segment(stem_top_right, arc_point(cap, 0.0)), cap,
               segment(arc_point(cap, M_PI), stem_top_left), segment(stem_top_left, stem_bottom_left),
               segment(stem_bottom_left, stem_bottom_right)},
              false);
}

void Simulation::add_union_of_circles(const Points& centres, const std::vector<double>& radii) {
  Engine& e = *engine_;
  require_setup(e, "add_union_of_circles");
  const int n = static_cast<int>(centres.rows());
  if (n < 1) refuse("add_union_of_circles: centres needs at least 1 row, got 0");
  if (static_cast<int>(radii.size()) != n) {
    refuse("add_union_of_circles: radii has " + std::to_string(radii.size()) + " entries, centres " + std::to_string(n) + " rows");
  }
  std::vector<WallShape> circles;
  for (int i = 0; i < n; ++i) {
    circles.push_back(checked_arc("add_union_of_circles: circle " + std::to_string(i) + ": ", centres.row(i).transpose(), radii[i], 0.0, 2 * M_PI));
  }
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < i; ++j) {
      if (circles[i].a == circles[j].a && circles[i].radius == circles[j].radius) {
        refuse("add_union_of_circles: circles " + std::to_string(j) + " and " + std::to_string(i) + " coincide");
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
      const Vec2 d = cj.a - ci.a;
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
  for (const WallShape& c : circles) extent = std::max(extent, wall_extent(c));
  add_outline(e, "add_union_of_circles", std::move(arcs), false, 1e-12 * extent);
}

void Simulation::add_polygon(const Points& vertices) {
  Engine& e = *engine_;
  require_setup(e, "add_polygon");
  const int n = static_cast<int>(vertices.rows());
  if (n < 3) refuse("add_polygon: vertices needs at least 3 rows, got " + std::to_string(n));
  for (int k = 0; k < n; ++k) {
    const Vec2 p = vertices.row(k).transpose();
    if (!bounded(p)) refuse("add_polygon: vertex " + std::to_string(k) + " " + kBounded + ", got " + vec(p));
  }
  for (int k = 0; k < n; ++k) {
    const Vec2 p = vertices.row(k).transpose();
    const Vec2 q = vertices.row((k + 1) % n).transpose();
    if (!((p - q).squaredNorm() > 0)) refuse("add_polygon: vertices " + std::to_string(k) + " and " + std::to_string((k + 1) % n) + " coincide at " + vec(p));
  }
  refuse_walls_in_periodic_box(e, "add_polygon");
  check_extent(e, vertices.cwiseAbs().maxCoeff(), "add_polygon");
  std::vector<WallShape> sides;
  for (int k = 0; k < n; ++k) sides.push_back(WallShape{WallKind::Segment, vertices.row(k).transpose(), vertices.row((k + 1) % n).transpose(), 0.0});
  add_outline(e, "add_polygon", std::move(sides), false);
}

void Simulation::add_box(const Vec2& lower, const Vec2& upper) {
  require_setup(*engine_, "add_box");  // (first, as in every setup call: the call is the mistake)
  if (!bounded(lower)) refuse(std::string("add_box: lower ") + kBounded + ", got " + vec(lower));
  if (!bounded(upper)) refuse(std::string("add_box: upper ") + kBounded + ", got " + vec(upper));
  const Vec2 size = upper - lower;  // (sides whose square underflows have no direction)
  if (!(size.x() > 0 && size.y() > 0 && size.x() * size.x() > 0 && size.y() * size.y() > 0)) refuse("add_box: upper " + vec(upper) + " must exceed lower " + vec(lower) + " in x and y");
  Points corners(4, 2);
  corners << lower.x(), lower.y(), upper.x(), lower.y(), upper.x(), upper.y(), lower.x(), upper.y();
  add_polygon(corners);
}

void Simulation::set_gravity(const Vec2& g) {
  Engine& e = *engine_;
  require_setup(e, "set_gravity");
  if (!bounded(g)) refuse(std::string("set_gravity: g ") + kBounded + ", got " + vec(g));
  // (The times of impact under gravity use |g|^2, which must not underflow.)
  if (g.cwiseAbs().maxCoeff() > 0 && g.cwiseAbs().maxCoeff() < kSmallest) refuse("set_gravity: g must be 0 or at least 1e-50 in magnitude, got " + vec(g));
  e.gravity = g;
  e.has_gravity = g.x() != 0 || g.y() != 0;
}

void Simulation::set_restitution(double normal, double tangential) {
  if (!(normal >= 0 && normal <= 1)) refuse("set_restitution: normal must be in [0, 1], got " + number(normal));
  if (!(tangential >= -1 && tangential <= 1)) refuse("set_restitution: tangential must be in [-1, 1], got " + number(tangential));
  Engine& e = *engine_;
  e.restitution = Restitution{normal, tangential};
  e.choose_rules();
}

void Simulation::set_exchange_velocities(bool on) {
  engine_->exchange_velocities = on;
  engine_->choose_rules();
}

bool Simulation::exchange_velocities() const { return engine_->exchange_velocities; }

// The collision paths taken, from the restitution and the exchange rule.
void Simulation::Engine::choose_rules() {
  smooth_elastic = restitution.normal == 1 && restitution.tangential == -1 && !exchange_velocities;
  mirror_walls = smooth_elastic || exchange_velocities;
  if (prepared) choose_speeds();  // (the automatic sleep speed depends on the restitution)
}

namespace {
// A granular model parameter: automatic (nullopt), or >= 0 and finite.
void check_granular(const char* call, const char* name, const std::optional<double>& value) {
  if (value && (!(*value >= 0) || !std::isfinite(*value))) {
    refuse(std::string(call) + ": " + name + " must be >= 0 and finite (0 = off), or automatic, got " + number(*value));
  }
}
}  // namespace

void Simulation::set_contact_duration(std::optional<double> duration) {
  check_granular("set_contact_duration", "duration", duration);
  engine_->contact_duration_setting = duration;
  if (engine_->prepared) engine_->choose_granular_model();
}

void Simulation::set_elastic_impact_speed(std::optional<double> speed) {
  check_granular("set_elastic_impact_speed", "speed", speed);
  engine_->elastic_impact_speed_setting = speed;
  if (engine_->prepared) engine_->choose_granular_model();
}

void Simulation::set_sleep_speed(std::optional<double> speed) {
  check_granular("set_sleep_speed", "speed", speed);
  engine_->sleep_speed_setting = speed;
  if (engine_->prepared) engine_->choose_speeds();
}

// The automatic values are scaled by the discs (mean radius, rms speed now) and gravity.
void Simulation::Engine::choose_granular_model() {
  double radius = 0, squared_speed = 0;
  const int n = static_cast<int>(hot.size());
  for (int i = 0; i < n; ++i) {
    HotDisc d = hot[i];
    advance_disc(d, now);
    radius += d.radius / n;
    squared_speed += d.velocity.squaredNorm() / n;
  }
  const double g = gravity.norm();
  // The time a typical disc takes to move 1e-4 of its radius: far below the mean free time, so a
  // flying gas keeps its dissipation (Luding & McNamara use such ratios). Under gravity at least
  // 1% of sqrt(a / g), the time scale of a resting bed: its rattling then costs tens of collisions
  // per disc per unit of sqrt(a / g) instead of hundreds (billiard_bench --granular).
  double duration = squared_speed > 0 ? 1e-4 * radius / std::sqrt(squared_speed) : 0.0;
  if (g > 0) duration = std::max(duration, 1e-2 * std::sqrt(radius / g));
  contact_duration = contact_duration_setting.value_or(duration);
  resting_speed = std::sqrt(2 * g * kRestingBounce * radius);
  choose_speeds();
}

// The speeds of the granular model from resting_speed (automatic) or as set. Discs sleep only
// under gravity (nothing else can hold them up), by default only when collisions dissipate.
void Simulation::Engine::choose_speeds() {
  const bool dissipative = restitution.normal < 1 && !exchange_velocities;
  sleep_speed = sleep_speed_setting.value_or(dissipative ? resting_speed : 0.0);
  if (!has_gravity) sleep_speed = 0;
  elastic_impact_speed = elastic_impact_speed_setting.value_or(sleep_speed > 0 ? 0.0 : resting_speed);
  if (sleep_speed == 0 && sleeping > 0) wake_all();
}

void Simulation::set_cell_size(double size) {
  Engine& e = *engine_;
  require_setup(e, "set_cell_size");
  if (!(size >= 0) || !std::isfinite(size)) refuse("set_cell_size: size must be >= 0 and finite (0 = automatic), got " + number(size));
  e.cell_size = size;
}

void Simulation::set_prefetch_ahead(Prefetch mode) {
  Engine& e = *engine_;
  require_setup(e, "set_prefetch_ahead");
  if (mode != Prefetch::Automatic && mode != Prefetch::On && mode != Prefetch::Off) {
    refuse("set_prefetch_ahead: mode must be Automatic, On or Off, got " + std::to_string(static_cast<int>(mode)));
  }
  e.prefetch_mode = mode;
}

int Simulation::add_disc(const Disc& disc) {
  Engine& e = *engine_;
  require_setup(e, "add_disc");
  const int index = static_cast<int>(e.hot.size());
  e.check_disc(disc, index);
  if (e.hot.empty() || e.setup_hash.cell <= 0) e.setup_hash.cell = 2 * disc.radius;
  int other = -1;
  if (e.overlaps_existing(disc.position, disc.radius, other)) {
    refuse("disc " + std::to_string(index) + ": at " + vec(disc.position) + " overlaps disc " + std::to_string(other) + " at " + vec(e.hot[other].position));
  }
  e.add_checked_disc(disc);
  return index;
}

int Simulation::add_discs(const Points& positions, const Points& velocities, double radius, double mass) {
  Engine& e = *engine_;
  require_setup(e, "add_discs");
  if (velocities.rows() != positions.rows()) {
    refuse("add_discs: velocities has " + std::to_string(velocities.rows()) + " rows, positions " + std::to_string(positions.rows()));
  }
  // (Also with no rows, so that a bad radius or mass is never silently accepted.)
  if (!in_scale(radius)) refuse(std::string("add_discs: radius ") + kScale + ", got " + number(radius));
  if (!in_scale(mass)) refuse(std::string("add_discs: mass ") + kScale + ", got " + number(mass));
  const int first = static_cast<int>(e.hot.size());
  const Engine saved = e;  // all or nothing
  try {
    for (Eigen::Index k = 0; k < positions.rows(); ++k) {
      Disc disc;
      disc.position = positions.row(k).transpose();
      disc.velocity = velocities.row(k).transpose();
      disc.radius = radius;
      disc.mass = mass;
      add_disc(disc);
    }
  } catch (...) {
    e = saved;
    throw;
  }
  return first;
}

namespace {

// The steps of add_random_discs. 1. Random sequential addition: uniform and independent places in
// [lo, hi], as long as there is room (60 tries a disc); returns how many were placed.
template <class TryPlace>
int place_at_random(int n, const Vec2& lo, const Vec2& hi, const Container& container, std::mt19937_64& rng,
                    TryPlace try_place) {
  std::uniform_real_distribution<double> ux(lo.x(), hi.x()), uy(lo.y(), hi.y());
  long long budget = 60LL * n + 1000;
  int placed = 0;
  while (placed < n && budget-- > 0) {
    Vec2 p(ux(rng), uy(rng));
    if (container.periodic) p = p.cwiseMin(container.period * (1 - 1e-15));
    if (try_place(p)) ++placed;
  }
  return placed;
}

// 2. Too dense for random addition: the sites of a triangular lattice with spacing just above a
// diameter (fitted to the period in a periodic box, so that it closes), shuffled. It melts within
// a few collisions per disc. `placed_at_random` is only for the message.
std::vector<Vec2> lattice_sites(int n, int placed_at_random, double radius, const Vec2& lo, const Vec2& hi,
                                const Container& container, std::mt19937_64& rng) {
  const double spacing = 2 * radius * (1 + 1e-9);
  double dx = spacing, dy = spacing * std::sqrt(3.0) / 2;
  Vec2 offset(std::uniform_real_distribution<double>(0, dx)(rng), std::uniform_real_distribution<double>(0, dy)(rng));
  // The sites cover the bounding box, which can be far larger than a thin polygon inside it:
  // refuse rather than fill the memory (or overflow the counts).
  const double site_count = (std::ceil((hi.x() - lo.x()) / dx) + 1) * (std::ceil((hi.y() - lo.y()) / dy) + 1);
  if (!(site_count <= 64.0 * n + 1e6)) {
    refuse("add_random_discs: only " + std::to_string(placed_at_random) + " of n = " + std::to_string(n) + " discs of radius " +
           number(radius) + " fit at random, and a lattice over the container's bounding box would need " + number(site_count) +
           " sites; use fewer or larger discs");
  }
  int columns = static_cast<int>(std::ceil((hi.x() - lo.x()) / dx)) + 1;
  int rows = static_cast<int>(std::ceil((hi.y() - lo.y()) / dy)) + 1;
  if (container.periodic) {
    columns = static_cast<int>(std::floor(container.period.x() / spacing));
    rows = 2 * static_cast<int>(std::floor(container.period.y() / (2 * dy)));  // even: rows alternate
    if (columns < 1 || rows < 2) refuse("add_random_discs: the periodic box is too small for discs of radius " + number(radius));
    dx = container.period.x() / columns;
    dy = container.period.y() / rows;
    offset = offset.cwiseMin(Vec2(dx, dy) * 0.999);
  }
  std::vector<Vec2> sites;
  for (int row = 0; row < rows; ++row) {
    for (int column = 0; column < columns; ++column) {
      const Vec2 p = lo + offset + Vec2(column * dx + (row % 2) * dx / 2, row * dy);
      sites.push_back(container.periodic ? Vec2(std::fmod(p.x(), container.period.x()), std::fmod(p.y(), container.period.y())) : p);
    }
  }
  std::shuffle(sites.begin(), sites.end(), rng);
  return sites;
}

// 3. Velocities for n discs of one mass: Gaussian, no net momentum (n >= 2), kinetic energy
// exactly n kT (2D: kT per disc).
Eigen::Matrix<double, Eigen::Dynamic, 2> thermal_velocities(int n, double mass, double kT, std::mt19937_64& rng) {
  std::normal_distribution<double> normal;
  Eigen::Matrix<double, Eigen::Dynamic, 2> v(n, 2);
  for (int k = 0; k < n; ++k) v.row(k) << normal(rng), normal(rng);
  if (n >= 2) v.rowwise() -= v.colwise().mean();
  const double energy = 0.5 * mass * v.squaredNorm();
  if (energy > 0) v *= std::sqrt(n * kT / energy);
  return v;
}

}  // namespace

int Simulation::add_random_discs(int n, double radius, double mass, double kT, std::uint64_t seed) {
  Engine& e = *engine_;
  require_setup(e, "add_random_discs");
  if (n < 0) refuse("add_random_discs: n must be >= 0, got " + std::to_string(n));
  if (!in_scale(radius)) refuse(std::string("add_random_discs: radius ") + kScale + ", got " + number(radius));
  if (!in_scale(mass)) refuse(std::string("add_random_discs: mass ") + kScale + ", got " + number(mass));
  if (!(kT >= 0) || !bounded(kT)) refuse("add_random_discs: kT must be >= 0, finite and at most 1e50, got " + number(kT));

  if (!e.container.closed()) {
    refuse("add_random_discs: set a closed container first (a circular table, a box, a polygon or a periodic box)");
  }
  Vec2 lo, hi;  // where centres may lie
  e.container.bounds(lo, hi);
  const double extent = e.container.extent();
  if (radius < kRelativeRadius * extent) {
    refuse("add_random_discs: radius " + number(radius) + " is too small for the container's coordinates up to " + number(extent) +
           ": radii must be at least 1e-6 of the coordinates");
  }
  // Equal discs in a convex region of area A (the table, or the bounding box of the outlines) or in
  // a periodic box number at most A / (2 sqrt(3) radius^2) + 1 (Thue; Groemer's bound for finite
  // packings): refuse more at once, instead of spending the placement budgets below on them (60 n
  // tries: hours for n near 2^31).
  double area = (hi - lo).cwiseMax(0.0).prod();
  if (e.container.has_table) area = std::min(area, M_PI * e.container.table_radius * e.container.table_radius);
  const double most = area / (2 * std::sqrt(3.0) * radius * radius) + 1;
  if (n > most) {
    refuse("add_random_discs: n = " + std::to_string(n) + " discs of radius " + number(radius) + " cannot fit in the container (area " +
           number(area) + ": at most " + number(std::floor(most)) + " fit even in the densest packing); use fewer or smaller discs");
  }

  const int first = static_cast<int>(e.hot.size());
  if (n == 0) return first;
  const Engine saved = e;  // all or nothing
  std::mt19937_64 rng(seed);
  // A place is taken only if add_disc would accept it (inside, clear of walls and discs); the
  // checks throw, so a rejected place costs an exception: the budgets keep that bounded.
  auto try_place = [&](const Vec2& position) {
    Disc disc;
    disc.position = position;
    disc.radius = radius;
    disc.mass = mass;
    try {
      add_disc(disc);
      return true;
    } catch (const std::invalid_argument&) {
      return false;
    }
  };
  try {
    int placed = place_at_random(n, lo, hi, e.container, rng, try_place);
    if (placed < n) {
      e = saved;
      placed = 0;
      for (const Vec2& p : lattice_sites(n, placed, radius, lo, hi, e.container, rng)) {
        if (placed == n) break;
        if (try_place(p)) ++placed;
      }
      if (placed < n) {
        refuse("add_random_discs: only " + std::to_string(placed) + " of " + std::to_string(n) + " discs of radius " +
               number(radius) + " fit in the container; use fewer or smaller discs");
      }
    }
    const Eigen::Matrix<double, Eigen::Dynamic, 2> v = thermal_velocities(n, mass, kT, rng);
    for (int k = 0; k < n; ++k) e.hot[static_cast<std::size_t>(first + k)].velocity = v.row(k).transpose();
  } catch (...) {
    e = saved;
    throw;
  }
  return first;
}

AdvanceResult Simulation::advance(std::int64_t max_events, double max_duration) {
  if (max_events < 0) refuse("advance: max_events must be >= 0, got " + std::to_string(max_events));
  if (!(max_duration >= 0)) refuse("advance: max_duration must be >= 0, got " + number(max_duration));
  return engine_->advance(max_events, max_duration);
}

int Simulation::size() const { return static_cast<int>(engine_->hot.size()); }
double Simulation::time() const { return engine_->now; }
State Simulation::current_state() const { return engine_->state_now(); }
const State& Simulation::initial_state() const {
  Engine& e = *engine_;
  if (!e.prepared) e.initial = e.state_now();
  return e.initial;
}
const std::vector<WallShape>& Simulation::walls() const { return engine_->container.walls; }
Totals Simulation::totals() const { return engine_->totals; }

double Simulation::kinetic_energy() const {
  const Engine& e = *engine_;
  double sum = 0;
  for (std::size_t i = 0; i < e.hot.size(); ++i) {
    HotDisc d = e.hot[i];
    e.advance_disc(d, e.now);
    sum += 0.5 * e.cold[i].mass * d.velocity.squaredNorm() + 0.5 * e.cold[i].inertia * e.cold[i].spin * e.cold[i].spin;
  }
  return sum;
}

double Simulation::potential_energy() const {
  const Engine& e = *engine_;
  double sum = 0;
  for (std::size_t i = 0; i < e.hot.size(); ++i) {
    HotDisc d = e.hot[i];
    e.advance_disc(d, e.now);
    sum -= e.cold[i].mass * e.gravity.dot(d.position);
  }
  return sum;
}

double Simulation::memory_bytes() const {
  const Engine& e = *engine_;
  return static_cast<double>(e.hot.capacity() * sizeof(HotDisc) + e.cold.capacity() * sizeof(ColdDisc) +
                             e.scheduled.capacity() * sizeof(Scheduled) + e.queue.memory_bytes() +
                             e.grid.records.capacity() * sizeof(int) + e.grid.spill.capacity() * sizeof(int) +
                             e.grid.spill_free.capacity() * sizeof(int) + e.grid.wall_ranges.capacity() * sizeof(int) +
                             e.grid.wall_items.capacity() * sizeof(int) + e.log.capacity() * sizeof(EventRecord));
}

namespace {
// One field of every disc record as an array of N.
template <class Records, class Field>
Eigen::VectorXd column(const Records& records, Field field) {
  Eigen::VectorXd out(static_cast<Eigen::Index>(records.size()));
  for (std::size_t i = 0; i < records.size(); ++i) out[static_cast<Eigen::Index>(i)] = records[i].*field;
  return out;
}
}  // namespace

Eigen::VectorXd Simulation::radii() const { return column(engine_->hot, &HotDisc::radius); }
Eigen::VectorXd Simulation::masses() const { return column(engine_->cold, &ColdDisc::mass); }
Eigen::VectorXd Simulation::inertias() const { return column(engine_->cold, &ColdDisc::inertia); }

Vec2 Simulation::gravity() const { return engine_->gravity; }
Restitution Simulation::restitution() const { return engine_->restitution; }
double Simulation::contact_duration() const { return engine_->contact_duration; }
double Simulation::elastic_impact_speed() const { return engine_->elastic_impact_speed; }
double Simulation::sleep_speed() const { return engine_->sleep_speed; }
std::vector<int> Simulation::sleeping_discs() const {
  std::vector<int> found;
  for (int i = 0, n = size(); i < n; ++i) {
    if (Engine::asleep(engine_->hot[i])) found.push_back(i);
  }
  return found;
}
bool Simulation::periodic() const { return engine_->container.periodic; }
Vec2 Simulation::period() const { return engine_->container.periodic ? engine_->container.period : Vec2::Zero(); }
double Simulation::table_radius() const { return engine_->container.has_table ? engine_->container.table_radius : 0.0; }

int Simulation::cell_count() const { return engine_->prepared ? engine_->grid.nx * engine_->grid.ny : 0; }

void Simulation::enable_event_log(bool on) { engine_->logging = on; }
void Simulation::clear_event_log() { engine_->log.clear(); }
const std::vector<EventRecord>& Simulation::event_log() const { return engine_->log; }

std::optional<std::string> Simulation::validate(double tolerance) {
  if (!(tolerance >= 0) || !std::isfinite(tolerance)) refuse("validate: tolerance must be >= 0 and finite, got " + number(tolerance));
  Engine& e = *engine_;
  e.problem = e.check(tolerance);
  return last_problem();
}

void Simulation::set_validate_every_event(bool on) { engine_->validate_every_event = on; }
void Simulation::set_check_event_discs(bool on) { engine_->check_event_discs = on; }
std::optional<std::string> Simulation::last_problem() const {
  if (engine_->problem.empty()) return std::nullopt;
  return engine_->problem;
}

}  // namespace billiard

// The space the discs live in: a circular table, a periodic box, or closed outlines (boxes,
// polygons and curved outlines of segments and arcs) with their walls, plus any free segments
// and arcs. Its geometry is asked the same questions by
// the set-up checks, the event loop, validation and replay: where a periodic position wraps to,
// the nearest periodic image, whether a disc is inside, how far it is from a wall, and which
// region the discs can reach. Each answer is written once, here.
#pragma once

#include "billiard/engine/vec2.hpp"
#include "billiard/engine/wall.hpp"

#include <cmath>
#include <optional>
#include <string>
#include <vector>

namespace billiard {

// p moved by whole periods into [0, period.x) x [0, period.y); p itself when period is (0, 0)
// (no periodic box).
Vec2 wrap_into_period(Vec2 p, const Vec2& period);

// Gap between a disc of `radius` at p and a wall: the distance from the disc's edge to the wall,
// negative when they overlap. For the circle of a table the disc is inside it.
double wall_clearance(const WallShape& wall, const Vec2& p, double radius);

// The message for a disc overlapping a wall, the same at set-up and in validation.
std::string wall_overlap_message(const std::string& who, const Vec2& p, int wall, double clearance, double radius);

// A closed outline for the inside test: its segments and arcs (in any order). A hole (a disc
// obstacle) keeps discs out whatever the other outlines say.
struct Outline {
  std::vector<WallShape> pieces;
  bool hole = false;
};

struct Container {
  std::vector<WallShape> walls;   // the table's circle, segments, arcs and their end points
  std::vector<Outline> outlines;  // closed boxes, polygons, curved outlines and holes, for contains
  bool has_table = false;
  double table_radius = 0.0;
  bool periodic = false;
  Vec2 period = Vec2::Zero();

  // A region that holds discs has been set (table, periodic box, or a box, polygon or curved
  // outline; holes alone enclose nothing).
  bool closed() const {
    bool outline = false;
    for (const Outline& o : outlines) outline = outline || !o.hole;
    return has_table || periodic || outline;
  }

  // p wrapped into the periodic box (p itself without one).
  Vec2 wrap(const Vec2& p) const { return periodic ? wrap_into_period(p, period) : p; }
  // The shortest of the vectors equal to dr up to whole periods (dr itself without a period).
  // (Inline: the event loop calls it at every collision.)
  Vec2 minimum_image(Vec2 dr) const {
    if (periodic) {
      dr.x() -= period.x() * std::round(dr.x() / period.x());
      dr.y() -= period.y() * std::round(dr.y() / period.y());
    }
    return dr;
  }

  // Even-odd rule: p lies inside an odd number of the `outlines` that are not holes (true when
  // there are none), and inside no hole.
  static bool inside_outlines(const std::vector<Outline>& outlines, const Vec2& p);
  // Why a disc of `radius` centred at p is not inside the container by more than `slack` (the
  // table, the periodic box, the outlines), as the end of a sentence after "disc i"; "" if it is.
  std::string outside(const Vec2& p, double radius, double slack) const;
  // The first wall (from index `first` of `indices`, or of all walls when indices is null) that
  // a disc of `radius` at p overlaps by more than `slack`, with its clearance.
  struct Overlap {
    int wall;
    double clearance;
  };
  std::optional<Overlap> overlapped_wall(const Vec2& p, double radius, double slack, const int* indices = nullptr,
                                         int count = -1) const;

  // A box holding every place a centre can reach: the period, or the box of the table and the
  // outlines. Only for a closed() container.
  void bounds(Vec2& lower, Vec2& upper) const;
  // The largest coordinate of the container and the walls. Every wall counts: the distance to a
  // segment that reaches into the table from 1e50 away is computed from its far end point.
  double extent() const;
};

}  // namespace billiard

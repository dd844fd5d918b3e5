#include "reference.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace particles_reference {
namespace {

constexpr double kNever = std::numeric_limits<double>::infinity();
constexpr int kWall = -1;

struct Entry {
  double time;  // absolute
  int i;
  int j;        // kWall for a wall
  int axis;     // for a wall: 0 (x = 0 or Lx), 1 (y = 0 or Ly)
};

struct World {
  const Box& box;
  std::vector<Particle> p;
  double now = 0;
};

// Time (from now) until particle i reaches a wall along one axis, never if it stands still.
double wall_time(double position, double speed, double low, double high) {
  if (speed > 0) return std::max(0.0, (high - position) / speed);
  if (speed < 0) return std::max(0.0, (low - position) / speed);
  return kNever;
}

Entry wall_entry(const World& w, int i) {
  const Particle& a = w.p[i];
  const double r = w.box.radius;
  const double tx = wall_time(a.x, a.u, r, w.box.lx - r);
  const double ty = wall_time(a.y, a.v, r, w.box.ly - r);
  // A corner: x first, then y at the same instant (two entries in turn, two collisions).
  if (tx <= ty) return {w.now + tx, i, kWall, 0};
  return {w.now + ty, i, kWall, 1};
}

Entry pair_entry(const World& w, int i, int j) {
  const Particle& a = w.p[i];
  const Particle& b = w.p[j];
  const double dx = b.x - a.x, dy = b.y - a.y, du = b.u - a.u, dv = b.v - a.v;
  const double approach = dx * du + dy * dv;  // < 0 when they come closer
  Entry e{kNever, i, j, 0};
  if (approach >= 0) return e;
  const double speed2 = du * du + dv * dv;
  const double sigma = 2 * w.box.radius;
  const double gap = dx * dx + dy * dy - sigma * sigma;
  const double discriminant = approach * approach - speed2 * gap;
  if (discriminant < 0) return e;  // they pass each other
  // The smaller root of speed2 t^2 + 2 approach t + gap = 0, in the form without cancellation.
  const double t = gap / (-approach + std::sqrt(discriminant));
  e.time = w.now + std::max(0.0, t);
  return e;
}

bool involves(const Entry& e, int a, int b) { return e.i == a || e.i == b || e.j == a || e.j == b; }

Entry recompute(const World& w, const Entry& e) { return e.j == kWall ? wall_entry(w, e.i) : pair_entry(w, e.i, e.j); }

// Insertion sort, stable (the exercise's sort); the array is short or nearly sorted when used.
void insertion_sort(std::vector<Entry>& a) {
  for (std::size_t k = 1; k < a.size(); ++k) {
    const Entry e = a[k];
    std::size_t m = k;
    while (m > 0 && a[m - 1].time > e.time) {
      a[m] = a[m - 1];
      --m;
    }
    a[m] = e;
  }
}

}  // namespace

Result run(const Box& box, double end_time, bool physical, long max_events) {
  World w{box, box.particles, 0};
  const int n = static_cast<int>(box.particles.size());
  std::vector<int> walls(n, 0), others(n, 0);
  std::vector<Entry> entries;
  entries.reserve(static_cast<std::size_t>(n) * (n + 1) / 2);
  for (int i = 0; i < n; ++i) entries.push_back(wall_entry(w, i));
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) entries.push_back(pair_entry(w, i, j));
  }
  // The first sort: insertion sort is quadratic in N(N+1)/2, too slow for N = 1000, so
  // insertion-sorted runs of 32 merged (the same stable order).
  for (std::size_t k = 0; k < entries.size(); k += 32) {
    std::vector<Entry> run(entries.begin() + k, entries.begin() + std::min(entries.size(), k + 32));
    insertion_sort(run);
    std::copy(run.begin(), run.end(), entries.begin() + k);
  }
  for (std::size_t width = 32; width < entries.size(); width *= 2) {
    for (std::size_t k = 0; k + width < entries.size(); k += 2 * width) {
      std::inplace_merge(entries.begin() + k, entries.begin() + k + width,
                         entries.begin() + std::min(entries.size(), k + 2 * width),
                         [](const Entry& a, const Entry& b) { return a.time < b.time; });
    }
  }
  Result result;
  std::vector<Entry> kept, changed;
  while (!entries.empty() && (max_events < 0 || static_cast<long>(result.event_times.size()) < max_events)) {
    const Entry next = entries.front();
    if (!(next.time <= end_time)) break;
    // Every particle moves to the time of the collision.
    const double dt = next.time - w.now;
    for (Particle& a : w.p) {
      a.x += a.u * dt;
      a.y += a.v * dt;
    }
    w.now = next.time;
    Particle& a = w.p[next.i];
    if (next.j == kWall) {
      (next.axis == 0 ? a.u : a.v) = -(next.axis == 0 ? a.u : a.v);
      ++walls[next.i];
    } else {
      Particle& b = w.p[next.j];
      if (physical) {
        const double dx = b.x - a.x, dy = b.y - a.y;
        const double length = std::sqrt(dx * dx + dy * dy);
        const double nx = dx / length, ny = dy / length;
        const double along = (a.u - b.u) * nx + (a.v - b.v) * ny;
        a.u -= along * nx;
        a.v -= along * ny;
        b.u += along * nx;
        b.v += along * ny;
      } else {
        std::swap(a.u, b.u);
        std::swap(a.v, b.v);
      }
      ++others[next.i];
      ++others[next.j];
    }
    result.event_times.push_back(w.now);
    // The entries of the particles involved are recomputed, sorted and merged back.
    const int p = next.i, q = next.j == kWall ? next.i : next.j;
    kept.clear();
    changed.clear();
    for (const Entry& e : entries) {
      if (involves(e, p, q)) {
        changed.push_back(recompute(w, e));
      } else {
        kept.push_back(e);
      }
    }
    insertion_sort(changed);
    entries.clear();
    std::merge(kept.begin(), kept.end(), changed.begin(), changed.end(), std::back_inserter(entries),
               [](const Entry& x, const Entry& y) { return x.time < y.time; });
  }
  // Every particle moves to the end time.
  if (max_events < 0) {
    for (Particle& a : w.p) {
      a.x += a.u * (end_time - w.now);
      a.y += a.v * (end_time - w.now);
    }
  }
  char line[200];
  for (int i = 0; i < n; ++i) {
    std::snprintf(line, sizeof line, "%.6f, %.6f, %d, %d\n", w.p[i].x, w.p[i].y, walls[i], others[i]);
    result.output += line;
  }
  return result;
}

std::string file_text(const Box& box) {
  char line[200];
  std::string out = std::to_string(box.particles.size()) + "\n";
  std::snprintf(line, sizeof line, "%.17g\n%.17g %.17g\n", box.radius, box.lx, box.ly);
  out += line;
  for (const Particle& a : box.particles) {
    std::snprintf(line, sizeof line, "%.17g %.17g %.17g %.17g\n", a.x, a.y, a.u, a.v);
    out += line;
  }
  return out;
}

}  // namespace particles_reference

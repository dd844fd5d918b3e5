// The public Simulation: input checks at the API boundary, setup and state accessors (the
// replay of the event log is in replay.cpp).
// The event loop itself is in engine.cpp.
#include "billiard/engine/simulation.hpp"

#include "billiard/limits.hpp"
#include "billiard/describe.hpp"
#include "engine.hpp"

#include <algorithm>
#include <random>
#include <cmath>
#include <stdexcept>

namespace billiard {
namespace {

[[noreturn]] void refuse(const std::string& message) { throw std::invalid_argument(message); }

// The numbers the engine accepts (billiard/limits.hpp, shared with the course and the commands).
using limits::bounded;
using limits::in_scale;
using limits::kRelativeRadius;
using limits::kSmallest;
const char* const kBounded = limits::kMustBeBounded;
const char* const kScale = limits::kMustBeInScale;
bool bounded(const Vector& v) { return bounded(v.x(), v.y()); }

void require_setup(const Engine& e, const char* call) {
  if (e.prepared) {
    throw std::logic_error(std::string(call) + ": the simulation has started; discs are fixed after the first advance()");
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


}  // namespace

std::string wall_overlap_message(const std::string& who, const Vector& p, int wall, double clearance, double radius) {
  return describe(who, " at ", p, " overlaps wall ", wall, ": distance ", radius + clearance, " < radius ", radius);
}

// ---------------------------------------------------------------------------------------------
// Setup helpers
// ---------------------------------------------------------------------------------------------

void Engine::rebuild_setup_hash(double cell) {
  setup_hash.cell = cell;
  setup_hash.cells.clear();
  for (int i = 0; i < static_cast<int>(hot.size()); ++i) {
    const Vector& p = hot[i].position;
    setup_hash.cells[hash_key(hash_column(p.x(), cell), hash_column(p.y(), cell))].push_back(i);
  }
}

bool Engine::overlaps_existing(const Vector& position, double radius, int& other) const {
  if (hot.empty()) return false;
  auto overlap = [&](int j) {
    const Vector d = minimum_image(container, position - hot[j].position);
    const double contact = radius + hot[j].radius;
    return d.squaredNorm() < contact * contact;
  };
  const double h = setup_hash.cell;
  // In a periodic box an image across the boundary can overlap: check the wrapped positions too.
  const int images = container.periodic() ? 1 : 0;
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
  // An image across a face holds a disc that overlaps only if the position lies within a contact
  // distance of that face (every disc lies in the box): the others are skipped (twice that
  // distance, against rounding), which finds the same discs in the same order.
  const Vector& period = container.period();
  const double near = 2 * (radius + max_radius);
  const auto far_from = [&](int shift, double coordinate, double side) {
    return (shift > 0 && coordinate > near) || (shift < 0 && coordinate < side - near);
  };
  for (int sy = -images; sy <= images; ++sy) {
    for (int sx = -images; sx <= images; ++sx) {
      if (far_from(sx, position.x(), period.x()) || far_from(sy, position.y(), period.y())) continue;
      const Vector p = position + Vector(sx * period.x(), sy * period.y());
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

void Engine::check_disc(const Disc& disc, int index) const {
  const std::string who = "disc " + std::to_string(index);
  if (!bounded(disc.position)) refuse(who + ": position " + kBounded + ", got " + describe(disc.position));
  if (!bounded(disc.velocity)) refuse(who + ": velocity " + kBounded + ", got " + describe(disc.velocity));
  if (!in_scale(disc.radius)) refuse(who + ": radius " + kScale + ", got " + describe(disc.radius));
  if (!in_scale(disc.mass)) refuse(who + ": mass " + kScale + ", got " + describe(disc.mass));
  if (disc.inertia && !in_scale(*disc.inertia)) refuse(who + ": inertia " + kScale + ", got " + describe(*disc.inertia));
  // A thin ring, all its mass at the rim, has the largest moment a disc can have: mass radius^2
  // (with 1e-12 for rounding in how the caller computed it).
  const double ring = disc.mass * disc.radius * disc.radius;
  if (disc.inertia && *disc.inertia > ring * (1 + 1e-12)) {
    refuse(who + ": inertia " + describe(*disc.inertia) + " is more than mass x radius^2 = " + describe(ring) +
           ", which no disc can have (a thin ring, all its mass at the rim, has that much)");
  }
  if (!bounded(disc.spin)) refuse(who + ": spin " + kBounded + ", got " + describe(disc.spin));
  const Vector& r = disc.position;
  const double a = disc.radius;
  const std::string where = outside(container, r, a, 0.0);
  if (!where.empty()) refuse(who + " " + where);
  if (container.periodic() && 6 * a > container.period().minCoeff()) {
    refuse(who + ": radius " + describe(a) + " is too large for the periodic box (need 6 radius <= " + describe(container.period().minCoeff()) + ")");
  }
  if (const auto overlap = overlapped_wall(container, r, a, 0.0)) refuse(wall_overlap_message(who, r, overlap->wall, overlap->clearance, a));
  const double largest = std::max(extent(container), r.cwiseAbs().maxCoeff());
  if (a < kRelativeRadius * largest) {
    refuse(who + ": radius " + describe(a) + " is too small for coordinates up to " + describe(largest) + ": radii must be at least 1e-6 of the coordinates");
  }
}

void Engine::remove_discs_from(int first) {
  hot.resize(static_cast<std::size_t>(first));
  cold.resize(static_cast<std::size_t>(first));
  scheduled.resize(static_cast<std::size_t>(first));
  min_radius = kNever;
  max_radius = 0.0;
  for (const HotDisc& d : hot) {
    min_radius = std::min(min_radius, d.radius);
    max_radius = std::max(max_radius, d.radius);
  }
  if (hot.empty()) {
    setup_hash = SetupHash();
  } else {
    rebuild_setup_hash(setup_hash.cell);
  }
}

void Engine::add_checked_disc(const Disc& disc) {
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
    const Vector& p = disc.position;
    setup_hash.cells[hash_key(hash_column(p.x(), setup_hash.cell), hash_column(p.y(), setup_hash.cell))].push_back(i);
  }
}

// ---------------------------------------------------------------------------------------------
// Simulation
// ---------------------------------------------------------------------------------------------

namespace {
void destroy_engine(void* engine) { delete static_cast<Engine*>(engine); }
// The engine behind a Simulation's opaque pointer.
Engine& engine_of(const std::unique_ptr<void, void (*)(void*)>& engine) { return *static_cast<Engine*>(engine.get()); }

// A granular model parameter: automatic (nullopt), or >= 0 and finite.
void check_granular(const char* name, const std::optional<double>& value) {
  if (value && (!(*value >= 0) || !std::isfinite(*value))) {
    refuse(std::string(name) + " must be >= 0 and finite (0 = off), or automatic, got " + describe(*value));
  }
}

void check_restitution(const char* call, const Restitution& r) {
  if (!(r.normal >= 0 && r.normal <= 1)) refuse(std::string(call) + "normal must be in [0, 1], got " + describe(r.normal));
  if (!(r.tangential >= -1 && r.tangential <= 1)) refuse(std::string(call) + "tangential must be in [-1, 1], got " + describe(r.tangential));
}

const Settings& checked(const Settings& s) {
  if (!bounded(s.gravity)) refuse(std::string("settings.gravity ") + kBounded + ", got " + describe(s.gravity));
  // (The times of impact under gravity use |g|^2, which must not underflow.)
  if (s.gravity.cwiseAbs().maxCoeff() > 0 && s.gravity.cwiseAbs().maxCoeff() < kSmallest) {
    refuse("settings.gravity must be 0 or at least 1e-50 in magnitude, got " + describe(s.gravity));
  }
  check_restitution("settings.restitution.", s.restitution);
  check_granular("settings.contact_duration", s.contact_duration);
  check_granular("settings.elastic_impact_speed", s.elastic_impact_speed);
  check_granular("settings.sleep_speed", s.sleep_speed);
  if (!(s.cell_size >= 0) || !std::isfinite(s.cell_size)) refuse("settings.cell_size must be >= 0 and finite (0 = automatic), got " + describe(s.cell_size));
  if (s.prefetch != Prefetch::Automatic && s.prefetch != Prefetch::On && s.prefetch != Prefetch::Off) {
    refuse("settings.prefetch must be Automatic, On or Off, got " + std::to_string(static_cast<int>(s.prefetch)));
  }
  return s;
}
}  // namespace

Engine::Engine(Container c, const Settings& s)
    : container(std::move(c)),
      gravity(container.periodic() ? Vector::Zero() : s.gravity),
      has_gravity(gravity.x() != 0 || gravity.y() != 0),
      gravity_norm(gravity.norm()),
      fall(container.periodic() ? s.gravity : Vector::Zero()),
      restitution(s.restitution),
      exchange_velocities(s.exchange_velocities),
      contact_duration_setting(s.contact_duration),
      elastic_impact_speed_setting(s.elastic_impact_speed),
      sleep_speed_setting(s.sleep_speed),
      cell_size(s.cell_size),
      prefetch_mode(s.prefetch) {
  choose_rules();
}

Simulation::Simulation(Container container, const Settings& settings)
    : engine_(new Engine(std::move(container), checked(settings)), &destroy_engine) {}
Simulation::~Simulation() = default;
Simulation::Simulation(Simulation&&) noexcept = default;
Simulation& Simulation::operator=(Simulation&&) noexcept = default;
// The queue reads the schedules through a pointer set at the first advance: a copy's queue must
// read the copy's, not the original's (which may change or be gone).
Simulation::Simulation(const Simulation& other) : engine_(new Engine(engine_of(other.engine_)), &destroy_engine) {
  Engine& e = engine_of(engine_);
  if (e.prepared) e.queue.set_keys(ScheduledKeys{&e, e.scheduled.data()});
}
Simulation& Simulation::operator=(const Simulation& other) {
  if (this != &other) *this = Simulation(other);
  return *this;
}

void Simulation::set_restitution(const Restitution& restitution) {
  check_restitution("set_restitution: restitution.", restitution);
  Engine& e = engine_of(engine_);
  e.restitution = restitution;
  e.choose_rules();
}

void Simulation::set_exchange_velocities(bool on) {
  Engine& e = engine_of(engine_);
  e.exchange_velocities = on;
  e.choose_rules();
}

bool Simulation::exchange_velocities() const { return engine_of(engine_).exchange_velocities; }

// The collision paths taken, from the restitution and the exchange rule.
void Engine::choose_rules() {
  smooth_elastic = restitution.normal == 1 && restitution.tangential == -1 && !exchange_velocities;
  mirror_walls = smooth_elastic || exchange_velocities;
  if (prepared) choose_speeds();  // (the automatic sleep speed depends on the restitution)
}

void Simulation::set_contact_duration(std::optional<double> duration) {
  check_granular("set_contact_duration: duration", duration);
  Engine& e = engine_of(engine_);
  e.contact_duration_setting = duration;
  if (e.prepared) e.choose_granular_model();
}

void Simulation::set_elastic_impact_speed(std::optional<double> speed) {
  check_granular("set_elastic_impact_speed: speed", speed);
  Engine& e = engine_of(engine_);
  e.elastic_impact_speed_setting = speed;
  if (e.prepared) e.choose_granular_model();
}

void Simulation::set_sleep_speed(std::optional<double> speed) {
  check_granular("set_sleep_speed: speed", speed);
  Engine& e = engine_of(engine_);
  e.sleep_speed_setting = speed;
  if (e.prepared) e.choose_speeds();
}

// The automatic values are scaled by the discs (mean radius, rms speed now) and gravity.
void Engine::choose_granular_model() {
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
void Engine::choose_speeds() {
  const bool dissipative = restitution.normal < 1 && !exchange_velocities;
  sleep_speed = sleep_speed_setting.value_or(dissipative ? resting_speed : 0.0);
  if (!has_gravity) sleep_speed = 0;
  elastic_impact_speed = elastic_impact_speed_setting.value_or(sleep_speed > 0 ? 0.0 : resting_speed);
  if (sleep_speed == 0 && sleeping > 0) wake_all();
}

int Simulation::add_disc(const Disc& disc) {
  Engine& e = engine_of(engine_);
  require_setup(e, "add_disc");
  const int index = static_cast<int>(e.hot.size());
  e.check_disc(disc, index);
  if (e.hot.empty() || e.setup_hash.cell <= 0) e.setup_hash.cell = 2 * disc.radius;
  int other = -1;
  if (e.overlaps_existing(disc.position, disc.radius, other)) {
    refuse("disc " + std::to_string(index) + ": at " + describe(disc.position) + " overlaps disc " + std::to_string(other) + " at " + describe(e.hot[other].position));
  }
  e.add_checked_disc(disc);
  return index;
}

int Simulation::add_discs(const Coordinates& positions, const Velocities& velocities, double radius, double mass) {
  Engine& e = engine_of(engine_);
  require_setup(e, "add_discs");
  if (velocities.rows() != positions.rows()) {
    refuse("add_discs: velocities has " + std::to_string(velocities.rows()) + " rows, positions " + std::to_string(positions.rows()));
  }
  // (Also with no rows, so that a bad radius or mass is never silently accepted.)
  if (!in_scale(radius)) refuse(std::string("add_discs: radius ") + kScale + ", got " + describe(radius));
  if (!in_scale(mass)) refuse(std::string("add_discs: mass ") + kScale + ", got " + describe(mass));
  const int first = static_cast<int>(e.hot.size());
  try {  // all or nothing
    for (Eigen::Index k = 0; k < positions.rows(); ++k) {
      Disc disc;
      disc.position = positions.row(k);
      disc.velocity = velocities.row(k);
      disc.radius = radius;
      disc.mass = mass;
      add_disc(disc);
    }
  } catch (...) {
    e.remove_discs_from(first);
    throw;
  }
  return first;
}

namespace {

// The steps of add_random_discs. 1. Random sequential addition: uniform and independent places in
// [lo, hi], as long as there is room (60 tries a disc); returns how many were placed.
template <class TryPlace>
int place_at_random(int n, const Vector& lo, const Vector& hi, const Container& container, std::mt19937_64& rng,
                    TryPlace try_place) {
  std::uniform_real_distribution<double> ux(lo.x(), hi.x()), uy(lo.y(), hi.y());
  long long budget = 60LL * n + 1000;
  int placed = 0;
  while (placed < n && budget-- > 0) {
    Vector p(ux(rng), uy(rng));
    if (container.periodic()) p = p.cwiseMin(container.period() * (1 - 1e-15));
    if (try_place(p)) ++placed;
  }
  return placed;
}

// A triangular lattice fitted to a periodic box of sides `period`, rows along x: `columns` sites a
// row, dx = width / columns apart (at least `spacing`), and an even number of rows (alternate
// rows are shifted by dx / 2), dy = height / rows apart. Fitting dx to the width stretches it a
// little, which lets the rows come closer than the ideal sqrt(3) / 2 spacing (a diagonal
// neighbour must stay `spacing` away): the number of columns with the most sites in all is
// chosen, so that a box takes nearly the ideal lattice's count (area fraction 0.9 of 0.907).
struct PeriodicLattice {
  int columns = 0, rows = 0;
  double dx = 0, dy = 0;
  long long sites() const { return static_cast<long long>(columns) * rows; }
};

PeriodicLattice periodic_lattice(const Vector& period, double spacing) {
  PeriodicLattice best;
  const double most_columns = std::floor(period.x() / spacing);
  for (double columns = most_columns; columns >= 1 && columns > 0.5 * most_columns; --columns) {
    const double dx = period.x() / columns;
    const double closest_dy = std::max(std::sqrt(std::max(0.0, spacing * spacing - dx * dx / 4)), spacing / 2);
    const double rows = 2 * std::floor(period.y() / (2 * closest_dy));
    if (rows < 2 || columns * rows <= static_cast<double>(best.sites())) continue;
    best = PeriodicLattice{static_cast<int>(columns), static_cast<int>(rows), dx, period.y() / rows};
  }
  return best;
}

// 2. Too dense for random addition: the sites of a triangular lattice with spacing just above a
// diameter (fitted to the period in a periodic box, so that it closes), shuffled. It melts within
// a few collisions per disc. `placed_at_random` is only for the message.
std::vector<Vector> lattice_sites(int n, int placed_at_random, double radius, const Vector& lo, const Vector& hi,
                                const Container& container, std::mt19937_64& rng) {
  const double spacing = 2 * radius * (1 + 1e-9);
  double dx = spacing, dy = spacing * std::sqrt(3.0) / 2;
  Vector offset(std::uniform_real_distribution<double>(0, dx)(rng), std::uniform_real_distribution<double>(0, dy)(rng));
  // The sites cover the bounding box, which can be far larger than a thin polygon inside it:
  // refuse rather than fill the memory (or overflow the counts).
  const double site_count = (std::ceil((hi.x() - lo.x()) / dx) + 1) * (std::ceil((hi.y() - lo.y()) / dy) + 1);
  if (!(site_count <= 64.0 * n + 1e6)) {
    refuse("add_random_discs: only " + std::to_string(placed_at_random) + " of n = " + std::to_string(n) + " discs of radius " +
           describe(radius) + " fit at random, and a lattice over the container's bounding box would need " + describe(site_count) +
           " sites; use fewer or larger discs");
  }
  int columns = static_cast<int>(std::ceil((hi.x() - lo.x()) / dx)) + 1;
  int rows = static_cast<int>(std::ceil((hi.y() - lo.y()) / dy)) + 1;
  bool rows_along_y = false;
  if (container.periodic()) {
    const PeriodicLattice along_x = periodic_lattice(container.period(), spacing);
    const PeriodicLattice along_y = periodic_lattice(Vector(container.period().y(), container.period().x()), spacing);
    rows_along_y = along_y.sites() > along_x.sites();
    const PeriodicLattice& best = rows_along_y ? along_y : along_x;
    if (best.sites() == 0) refuse("add_random_discs: the periodic box is too small for discs of radius " + describe(radius));
    columns = best.columns;
    rows = best.rows;
    dx = best.dx;
    dy = best.dy;
    offset = offset.cwiseMin(Vector(dx, dy) * 0.999);
  }
  std::vector<Vector> sites;
  for (int row = 0; row < rows; ++row) {
    for (int column = 0; column < columns; ++column) {
      Vector p = offset + Vector(column * dx + (row % 2) * dx / 2, row * dy);
      if (rows_along_y) p = Vector(p.y(), p.x());
      p += lo;
      sites.push_back(container.periodic() ? Vector(std::fmod(p.x(), container.period().x()), std::fmod(p.y(), container.period().y())) : p);
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
  Engine& e = engine_of(engine_);
  require_setup(e, "add_random_discs");
  if (n < 0) refuse("add_random_discs: n must be >= 0, got " + std::to_string(n));
  if (!in_scale(radius)) refuse(std::string("add_random_discs: radius ") + kScale + ", got " + describe(radius));
  if (!in_scale(mass)) refuse(std::string("add_random_discs: mass ") + kScale + ", got " + describe(mass));
  if (!(kT >= 0) || !bounded(kT)) refuse("add_random_discs: kT must be >= 0, finite and at most 1e50, got " + describe(kT));

  Vector lo, hi;  // where centres may lie
  bounds(e.container, lo, hi);
  const double largest = extent(e.container);
  if (radius < kRelativeRadius * largest) {
    refuse("add_random_discs: radius " + describe(radius) + " is too small for the container's coordinates up to " + describe(largest) +
           ": radii must be at least 1e-6 of the coordinates");
  }
  // Equal discs in a convex region of area A (the table, or the bounding box of the outlines) or in
  // a periodic box number at most A / (2 sqrt(3) radius^2) + 1 (Thue; Groemer's bound for finite
  // packings): refuse more at once, instead of spending the placement budgets below on them (60 n
  // tries: hours for n near 2^31).
  double area = (hi - lo).cwiseMax(0.0).prod();
  if (e.container.has_table()) area = std::min(area, M_PI * e.container.table_radius() * e.container.table_radius());
  const double most = area / (2 * std::sqrt(3.0) * radius * radius) + 1;
  if (n > most) {
    refuse("add_random_discs: n = " + std::to_string(n) + " discs of radius " + describe(radius) + " cannot fit in the container (area " +
           describe(area) + ": at most " + describe(std::floor(most)) + " fit even in the densest packing); use fewer or smaller discs");
  }

  const int first = static_cast<int>(e.hot.size());
  if (n == 0) return first;
  std::mt19937_64 rng(seed);
  // A place is taken only if add_disc would accept it (inside, clear of walls and discs). Most
  // places tried in a dense start are refused, so they are tested here first without the
  // exception add_disc would throw: an exception a try made 10,000 discs at area fraction 0.5
  // take 10 s.
  auto try_place = [&](const Vector& position) {
    int other = -1;
    if (where_outside(e.container, position, radius, 0.0) != Outside::No || overlapped_wall(e.container, position, radius, 0.0) ||
        (!e.hot.empty() && e.overlaps_existing(position, radius, other))) {
      return false;
    }
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
      e.remove_discs_from(first);
      placed = 0;
      for (const Vector& p : lattice_sites(n, placed, radius, lo, hi, e.container, rng)) {
        if (placed == n) break;
        if (try_place(p)) ++placed;
      }
      if (placed < n) {
        refuse("add_random_discs: only " + std::to_string(placed) + " of " + std::to_string(n) + " discs of radius " +
               describe(radius) + " fit in the container; use fewer or smaller discs");
      }
    }
    const Eigen::Matrix<double, Eigen::Dynamic, 2> v = thermal_velocities(n, mass, kT, rng);
    for (int k = 0; k < n; ++k) e.hot[static_cast<std::size_t>(first + k)].velocity = v.row(k);
  } catch (...) {  // all or nothing
    e.remove_discs_from(first);
    throw;
  }
  return first;
}

AdvanceResult Simulation::advance(std::int64_t max_events, double max_duration) {
  return advance(max_events, max_duration, nullptr, kEventsBetweenStopPolls);
}

AdvanceResult Simulation::advance(std::int64_t max_events, double max_duration, const StopCheck& should_stop,
                                  std::int64_t check_interval) {
  if (max_events < 0) refuse("advance: max_events must be >= 0, got " + std::to_string(max_events));
  // (A NaN fails every comparison, so "must be >= 0, got nan" alone would read as a riddle.)
  if (!(max_duration >= 0)) {
    refuse("advance: max_duration must be a number >= 0, got " + describe(max_duration) +
           (std::isnan(max_duration) ? " (not a number)" : ""));
  }
  if (check_interval < 1) refuse("advance: check_interval must be >= 1, got " + std::to_string(check_interval));
  // (Without a should_stop, stop requests are looked at every kEventsBetweenStopPolls events.)
  return engine_of(engine_).advance(max_events, max_duration, should_stop, should_stop ? check_interval : kEventsBetweenStopPolls);
}

void Simulation::request_stop() { engine_of(engine_).stop.requested.store(true, std::memory_order_relaxed); }

int Simulation::size() const { return static_cast<int>(engine_of(engine_).hot.size()); }
double Simulation::time() const {
  const Engine& e = engine_of(engine_);
  return e.epoch + e.now;
}
State Simulation::current_state() const { return engine_of(engine_).state_now(); }
const State& Simulation::initial_state() const {
  Engine& e = engine_of(engine_);
  if (!e.prepared) e.initial = e.state_now();
  return e.initial;
}
Images Simulation::images() const { return engine_of(engine_).images_now(); }
const Container& Simulation::container() const { return engine_of(engine_).container; }
Totals Simulation::totals() const { return engine_of(engine_).totals; }

double Simulation::kinetic_energy() const {
  const Engine& e = engine_of(engine_);
  double sum = 0;
  for (std::size_t i = 0; i < e.hot.size(); ++i) {
    HotDisc d = e.hot[i];
    e.advance_disc(d, e.now);
    const Vector velocity = e.lab_frame(d, e.now).velocity;
    sum += 0.5 * e.cold[i].mass * velocity.squaredNorm() + 0.5 * e.cold[i].inertia * e.cold[i].spin * e.cold[i].spin;
  }
  return sum;
}

double Simulation::potential_energy() const {
  const Engine& e = engine_of(engine_);
  double sum = 0;
  for (std::size_t i = 0; i < e.hot.size(); ++i) {
    HotDisc d = e.hot[i];
    e.advance_disc(d, e.now);
    sum -= e.cold[i].mass * (e.gravity + e.fall).dot(e.lab_frame(d, e.now).position);
  }
  return sum;
}

double Simulation::memory_bytes() const {
  const Engine& e = engine_of(engine_);
  return static_cast<double>(e.hot.capacity() * sizeof(HotDisc) + e.cold.capacity() * sizeof(ColdDisc) +
                             e.scheduled.capacity() * sizeof(Scheduled) + e.image_counts.capacity() * sizeof(e.image_counts[0]) +
                             e.queue.memory_bytes() +
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

Eigen::VectorXd Simulation::radii() const { return column(engine_of(engine_).hot, &HotDisc::radius); }
Eigen::VectorXd Simulation::masses() const { return column(engine_of(engine_).cold, &ColdDisc::mass); }
Eigen::VectorXd Simulation::inertias() const { return column(engine_of(engine_).cold, &ColdDisc::inertia); }

Vector Simulation::gravity() const { return engine_of(engine_).gravity + engine_of(engine_).fall; }
Restitution Simulation::restitution() const { return engine_of(engine_).restitution; }
double Simulation::contact_duration() const { return engine_of(engine_).contact_duration; }
double Simulation::elastic_impact_speed() const { return engine_of(engine_).elastic_impact_speed; }
double Simulation::sleep_speed() const { return engine_of(engine_).sleep_speed; }
std::vector<int> Simulation::sleeping_discs() const {
  std::vector<int> found;
  for (int i = 0, n = size(); i < n; ++i) {
    if (Engine::asleep(engine_of(engine_).hot[i])) found.push_back(i);
  }
  return found;
}

int Simulation::cell_count() const { return engine_of(engine_).prepared ? engine_of(engine_).grid.nx * engine_of(engine_).grid.ny : 0; }

void Simulation::set_log_events(bool on) { engine_of(engine_).logging = on; }
void Simulation::clear_event_log() { engine_of(engine_).log.clear(); }
const std::vector<EventRecord>& Simulation::event_log() const { return engine_of(engine_).log; }

std::optional<std::string> Simulation::validate(double tolerance) {
  if (!(tolerance >= 0) || !std::isfinite(tolerance)) refuse("validate: tolerance must be >= 0 and finite, got " + describe(tolerance));
  Engine& e = engine_of(engine_);
  e.problem = e.check(tolerance);
  return last_problem();
}

void Simulation::set_validate_every_event(bool on) { engine_of(engine_).validate_every_event = on; }
void Simulation::set_check_event_discs(bool on) { engine_of(engine_).check_event_discs = on; }
std::optional<std::string> Simulation::last_problem() const {
  if (engine_of(engine_).problem.empty()) return std::nullopt;
  return engine_of(engine_).problem;
}

}  // namespace billiard

// Python bindings of the event-driven engine (billiard/engine/simulation.hpp, billiard/engine/replay.hpp):
// class billiard.Simulation. States and the event log come out as dictionaries of numpy arrays;
// the replays are generators (billiard/__init__.py wraps the Replay object below). No physics
// here: only conversions.
#include "bindings.hpp"

#include "billiard/engine/replay.hpp"
#include "billiard/engine/simulation.hpp"

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <optional>
#include <stdexcept>
#include <string>

namespace py = pybind11;

namespace billiard::python {
namespace {

// A sequence of numbers (a list or a 1-D array).
std::vector<double> to_values(const py::object& value, const char* name) {
  const auto array = py::array_t<double, py::array::forcecast>::ensure(value);
  if (!array || array.ndim() != 1) throw std::invalid_argument(std::string(name) + " must be a sequence of numbers, got " + short_repr(value));
  return std::vector<double>(array.data(), array.data() + array.size());
}

py::dict state_dict(const Simulation& sim, const State& state) {
  py::dict d;
  d["time"] = state.time;
  d["position"] = points(state.positions);
  d["velocity"] = points(state.velocities);
  d["spin"] = vector(state.spins);
  d["mass"] = vector(sim.masses());
  d["radius"] = vector(sim.radii());
  d["inertia"] = vector(sim.inertias());
  return d;
}

py::dict event_log_dict(const std::vector<EventRecord>& log) {
  const auto k = static_cast<py::ssize_t>(log.size());
  py::array_t<double> time(k), spin(k), other_spin(k);
  py::array_t<int> kind(k), disc(k), other(k), wall(k);
  Points position(k, 2), velocity(k, 2), other_position(k, 2), other_velocity(k, 2);
  for (py::ssize_t n = 0; n < k; ++n) {
    const EventRecord& e = log[static_cast<std::size_t>(n)];
    time.mutable_at(n) = e.time;
    kind.mutable_at(n) = static_cast<int>(e.kind);
    disc.mutable_at(n) = e.disc;
    other.mutable_at(n) = e.other;
    wall.mutable_at(n) = e.wall;
    spin.mutable_at(n) = e.spin;
    other_spin.mutable_at(n) = e.other_spin;
    position.row(n) = e.position.transpose();
    velocity.row(n) = e.velocity.transpose();
    other_position.row(n) = e.other_position.transpose();
    other_velocity.row(n) = e.other_velocity.transpose();
  }
  py::dict d;
  d["time"] = time;
  d["kind"] = kind;
  d["disc"] = disc;
  d["other"] = other;
  d["wall"] = wall;
  d["position"] = points(position);
  d["velocity"] = points(velocity);
  d["spin"] = spin;
  d["other_position"] = points(other_position);
  d["other_velocity"] = points(other_velocity);
  d["other_spin"] = other_spin;
  return d;
}

const char* wall_kind(WallKind kind) {
  switch (kind) {
    case WallKind::Segment: return "segment";
    case WallKind::Point: return "point";
    case WallKind::Circle: return "circle";
    case WallKind::Arc: return "arc";
  }
  return "unknown";
}

}  // namespace

void bind_simulation(py::module_& m) {
  m.attr("DISC_DISC") = static_cast<int>(EventKind::DiscDisc);
  m.attr("DISC_WALL") = static_cast<int>(EventKind::DiscWall);
  m.attr("SLEEP") = static_cast<int>(EventKind::Sleep);
  m.attr("WAKE") = static_cast<int>(EventKind::Wake);

  py::class_<Simulation> sim(m, "Simulation", R"(Event-driven simulation of hard discs (the library in lib/).

Set up a container (set_circular_table, set_periodic_box, add_box, add_segment,
add_polygon, add_arc, add_disc_obstacle, add_stadium, add_sinai_billiard, add_mushroom,
add_union_of_circles), optionally gravity and restitution, add discs, then advance(). Setup is fixed
after the first advance(); restitution and the event log can still change. Units are yours.
States are dicts of numpy arrays: time, position (n, 2), velocity (n, 2), spin (n,),
mass (n,), radius (n,), inertia (n,). Bad input raises ValueError naming the disc and value.)");

  sim.def(py::init<>(), "An empty simulation: no container, no discs, no gravity, smooth elastic collisions.")
      .def("set_circular_table", &Simulation::set_circular_table, py::arg("radius"),
           "Circular table of this radius centred at the origin; discs live inside it.")
      .def("set_periodic_box", &Simulation::set_periodic_box, py::arg("width"), py::arg("height"),
           "Periodic box [0, width) x [0, height): the bulk system, no walls.")
      .def(
          "add_box", [](Simulation& s, const py::object& lower, const py::object& upper) {
            s.add_box(to_vec2(lower, "lower"), to_vec2(upper, "upper"));
          },
          py::arg("lower"), py::arg("upper"), "The four walls of the box [lower, upper] (points (x, y)).")
      .def(
          "add_segment", [](Simulation& s, const py::object& a, const py::object& b) {
            return s.add_segment(to_vec2(a, "a"), to_vec2(b, "b"));
          },
          py::arg("a"), py::arg("b"), "A straight wall from a to b (both faces, and its end points); returns its wall index.")
      .def(
          "add_polygon", [](Simulation& s, const py::object& vertices) { s.add_polygon(to_points(vertices, "vertices")); },
          py::arg("vertices"), "A closed polygon, vertices (k, 2) in order: one wall per side.")
      .def(
          "add_arc",
          [](Simulation& s, const py::object& centre, double radius, double start_angle, double end_angle) {
            return s.add_arc(to_vec2(centre, "centre"), radius, start_angle, end_angle);
          },
          py::arg("centre"), py::arg("radius"), py::arg("start_angle"), py::arg("end_angle"),
          "A circular arc wall (both faces, and its end points), counter-clockwise from start_angle to end_angle\n"
          "(radians, 0 < end_angle - start_angle <= 2 pi); returns its wall index.")
      .def(
          "add_disc_obstacle", [](Simulation& s, const py::object& centre, double radius) { s.add_disc_obstacle(to_vec2(centre, "centre"), radius); },
          py::arg("centre"), py::arg("radius"), "A circular obstacle that discs stay outside of (inside a table, box or outline).")
      .def(
          "add_stadium", [](Simulation& s, const py::object& centre, double radius, double length) { s.add_stadium(to_vec2(centre, "centre"), radius, length); },
          py::arg("centre"), py::arg("radius"), py::arg("length"),
          "A stadium: half circles of radius whose centres are length apart (horizontally, about centre),\n"
          "joined by straight sides; discs live inside it.")
      .def(
          "add_sinai_billiard",
          [](Simulation& s, const py::object& lower, const py::object& upper, double obstacle_radius) {
            s.add_sinai_billiard(to_vec2(lower, "lower"), to_vec2(upper, "upper"), obstacle_radius);
          },
          py::arg("lower"), py::arg("upper"), py::arg("obstacle_radius"), "The box [lower, upper] with a disc obstacle in its middle.")
      .def(
          "add_mushroom",
          [](Simulation& s, const py::object& centre, double cap_radius, double stem_width, double stem_height) {
            s.add_mushroom(to_vec2(centre, "centre"), cap_radius, stem_width, stem_height);
          },
          py::arg("centre"), py::arg("cap_radius"), py::arg("stem_width"), py::arg("stem_height"),
          "A mushroom: a half-disc cap above centre on a stem_width x stem_height stem below it (stem_width < 2 cap_radius).")
      .def(
          "add_union_of_circles",
          [](Simulation& s, const py::object& centres, const py::object& radii) {
            s.add_union_of_circles(to_points(centres, "centres"), to_values(radii, "radii"));
          },
          py::arg("centres"), py::arg("radii"),
          "The union of circles (centres (n, 2), radii (n,)): discs live inside it; its boundary arcs and their\n"
          "meeting points are the walls.")
      .def(
          "set_gravity", [](Simulation& s, const py::object& g) { s.set_gravity(to_vec2(g, "g")); }, py::arg("g"),
          "Uniform gravity (gx, gy); default (0, 0).")
      .def("set_restitution", &Simulation::set_restitution, py::arg("normal"), py::arg("tangential") = -1.0,
           "Coefficients of restitution: normal in [0, 1] (1 elastic), tangential in [-1, 1] (-1 smooth, +1 rough).")
      .def("set_exchange_velocities", &Simulation::set_exchange_velocities, py::arg("on") = true,
           "The exchange rule: discs that meet swap their whole velocities (equal masses), walls still reflect only\n"
           "the normal component; the rule of the box exercise (the `particles` program).")
      .def_property_readonly("exchange_velocities", &Simulation::exchange_velocities,
                             "Whether the exchange rule is on (set_exchange_velocities).")
      .def("set_contact_duration", &Simulation::set_contact_duration, py::arg("duration"),
           "Granular gases (restitution < 1), TC model: a collision less than `duration` after either disc's\n"
           "previous collision is elastic, which stops an inelastic collapse. None: automatic (default,\n"
           "1e-4 mean radius / rms speed at the first advance, under gravity at least 0.01 sqrt(radius / |g|));\n"
           "0: off. Energy never increases.")
      .def("set_elastic_impact_speed", &Simulation::set_elastic_impact_speed, py::arg("speed"),
           "Granular gases (restitution < 1): a collision whose normal approach speed is below `speed` is\n"
           "elastic, so discs resting on a floor under gravity g bounce at most speed^2 / (2 g) high. None:\n"
           "automatic (sqrt(2 |g| 0.05 mean radius); 0 without gravity or while discs can sleep); 0: off.")
      .def("set_sleep_speed", &Simulation::set_sleep_speed, py::arg("speed"),
           "Granular beds under gravity: discs slower than `speed` for 3 speed / |g|, connected by contacts and\n"
           "touching a wall or a sleeping disc, fall asleep together (stop; no events; immovable). A hit at a\n"
           "normal speed of at least `speed` wakes a sleeping disc and the ones resting on it. None: automatic\n"
           "(sqrt(2 |g| 0.05 mean radius) when gravity acts and restitution < 1, else 0); 0: off (wakes every\n"
           "sleeping disc). While discs can sleep, the automatic elastic impact speed is 0.")
      .def_property_readonly("sleep_speed", &Simulation::sleep_speed,
                             "The sleep speed in use (chosen at the first advance when automatic).")
      .def("sleeping_discs", &Simulation::sleeping_discs, "The indices of the discs asleep now.")
      .def_property_readonly("contact_duration", &Simulation::contact_duration,
                             "The TC model's duration in use (chosen at the first advance when automatic).")
      .def_property_readonly("elastic_impact_speed", &Simulation::elastic_impact_speed,
                             "The elastic impact speed in use (chosen at the first advance when automatic).")
      .def("set_cell_size", &Simulation::set_cell_size, py::arg("size"),
           "Side of the cells (>= the largest diameter); 0 chooses it automatically (default).")
      .def(
          "set_prefetch_ahead",
          [](Simulation& s, const std::string& mode) {
            if (mode == "auto") s.set_prefetch_ahead(Simulation::Prefetch::Automatic);
            else if (mode == "on") s.set_prefetch_ahead(Simulation::Prefetch::On);
            else if (mode == "off") s.set_prefetch_ahead(Simulation::Prefetch::Off);
            else throw std::invalid_argument("set_prefetch_ahead: mode must be 'auto', 'on' or 'off', got '" + mode + "'");
          },
          py::arg("mode"),
          "Whether each event starts loading the next event's data into the caches: 'auto' (default: on from\n"
          "about 87,000 discs, where it pays), 'on' or 'off'. Speed only: the events are the same.")
      .def(
          "add_disc",
          [](Simulation& s, const py::object& position, const py::object& velocity, double radius, double mass,
             std::optional<double> inertia, double spin) {
            Disc d;
            d.position = to_vec2(position, "position");
            d.velocity = to_vec2(velocity, "velocity");
            d.radius = radius;
            d.mass = mass;
            d.inertia = inertia;
            d.spin = spin;
            return s.add_disc(d);
          },
          py::arg("position"), py::arg("velocity") = py::make_tuple(0.0, 0.0), py::arg("radius") = 1.0,
          py::arg("mass") = 1.0, py::arg("inertia") = py::none(), py::arg("spin") = 0.0,
          "Adds one disc; returns its index. inertia None means a uniform disc (mass radius^2 / 2).")
      .def(
          "add_discs",
          [](Simulation& s, const py::object& positions, const py::object& velocities, double radius, double mass) {
            return s.add_discs(to_points(positions, "positions"), to_points(velocities, "velocities"), radius, mass);
          },
          py::arg("positions"), py::arg("velocities"), py::arg("radius"), py::arg("mass") = 1.0,
          "Adds discs of one radius and mass (positions, velocities: (n, 2)); all or nothing. Returns the first index.")
      .def("add_random_discs", &Simulation::add_random_discs, py::arg("n"), py::arg("radius"), py::arg("mass") = 1.0,
           py::arg("kT") = 1.0, py::arg("seed") = 0,
           "Adds n discs at random places in the container, with Gaussian velocities of temperature kT (no net\n"
           "momentum, kinetic energy exactly n kT). Dense requests start from random lattice sites. Returns the first index.")
      .def(
          "advance",
          [](Simulation& s, std::optional<std::int64_t> events, std::optional<double> time) {
            if (!events && !time) throw std::invalid_argument("advance: give events=..., time=... or both");
            // (Named as in Python: the library's messages say max_events and max_duration.)
            if (events && *events < 0) throw std::invalid_argument("advance: events must be >= 0, got " + std::to_string(*events));
            if (time && !(*time >= 0)) throw std::invalid_argument("advance: time must be >= 0, got " + short_repr(py::float_(*time)));
            const AdvanceResult r = s.advance(events.value_or(kAllEvents), time.value_or(kNever));
            py::dict d;
            d["collisions"] = r.collisions;
            d["disc_collisions"] = r.disc_collisions;
            d["wall_collisions"] = r.wall_collisions;
            d["cell_crossings"] = r.cell_crossings;
            d["stale_events"] = r.stale_events;
            d["elapsed"] = r.elapsed;
            d["stuck"] = r.stuck;
            d["stuck_reason"] = r.stuck_reason;
            return d;
          },
          py::arg("events") = py::none(), py::arg("time") = py::none(),
          "Advances by `events` collisions or `time`, whichever comes first; returns counts (collisions,\n"
          "disc_collisions, wall_collisions, cell_crossings, stale_events), elapsed, stuck and stuck_reason\n"
          "(what happened when stuck; the state stays valid).")
      .def_property_readonly("time", &Simulation::time, "The current time.")
      .def("__len__", &Simulation::size, "Number of discs.")
      .def_property_readonly(
          "current_state", [](const Simulation& s) { return state_dict(s, s.current_state()); },
          "The discs now (all advanced to `time`), as a dict of numpy arrays.")
      .def_property_readonly(
          "initial_state", [](const Simulation& s) { return state_dict(s, s.initial_state()); },
          "The discs at the first advance() (or now, before it).")
      .def("enable_event_log", &Simulation::enable_event_log, py::arg("on") = true,
           "Record every event (enable before the first advance() to replay).")
      .def("clear_event_log", &Simulation::clear_event_log, "Forget the recorded events (the log keeps recording if enabled).")
      .def_property_readonly(
          "event_log", [](const Simulation& s) { return event_log_dict(s.event_log()); },
          "The recorded events as a dict of arrays: time, kind (DISC_DISC, DISC_WALL, or SLEEP and WAKE for a disc\n"
          "falling asleep or waking up), disc, other (-1 for a wall, -2 for none), wall, and position, velocity,\n"
          "spin of disc and other just after the event.")
      .def_property_readonly(
          "totals",
          [](const Simulation& s) {
            const Totals t = s.totals();
            py::dict d;
            d["wall_momentum"] = t.wall_momentum;
            d["virial"] = t.virial;
            d["disc_collisions"] = t.disc_collisions;
            d["wall_collisions"] = t.wall_collisions;
            d["cell_crossings"] = t.cell_crossings;
            return d;
          },
          "Running totals since time 0: wall_momentum (sum of |impulse| given to walls), virial (sum over disc\n"
          "collisions of r_ij . dp_i, for P A = N kT + virial / (2 t)), and counts.")
      .def("kinetic_energy", &Simulation::kinetic_energy, "Sum of m v^2 / 2 + I w^2 / 2.")
      .def("potential_energy", &Simulation::potential_energy, "-sum m g.r.")
      .def("memory_bytes", &Simulation::memory_bytes, "Memory held by the engine, in bytes.")
      .def("validate", &Simulation::validate, py::arg("tolerance") = 1e-9,
           "None if no two discs overlap beyond tolerance x radius and all are inside; else the first problem.")
      .def_property_readonly(
          "walls",
          [](const Simulation& s) {
            py::list out;
            for (const WallShape& w : s.walls()) {
              py::dict d;
              d["kind"] = wall_kind(w.kind);
              d["a"] = py::make_tuple(w.a.x(), w.a.y());
              d["b"] = py::make_tuple(w.b.x(), w.b.y());
              d["radius"] = w.radius;
              d["start_angle"] = w.start_angle;
              d["sweep"] = w.sweep;
              out.append(d);
            }
            return out;
          },
          "The walls as dicts: kind ('segment', 'point', 'circle', 'arc'), a, b, radius, start_angle, sweep\n"
          "(an arc: centre a, from start_angle counter-clockwise through sweep radians).")
      .def_property_readonly("gravity", [](const Simulation& s) { return py::make_tuple(s.gravity().x(), s.gravity().y()); },
                             "Uniform gravity (gx, gy).")
      .def_property_readonly("period", [](const Simulation& s) { return py::make_tuple(s.period().x(), s.period().y()); },
                             "(width, height) of the periodic box; (0, 0) if none.")
      .def_property_readonly("table_radius", &Simulation::table_radius, "Radius of the circular table; 0 if none.");

  // The incremental replay behind Simulation.replay_by_event / replay_by_time (__init__.py).
  py::class_<Replay>(m, "_Replay")
      .def(py::init<const Simulation&>(), py::arg("simulation"), py::keep_alive<1, 2>())
      .def_property_readonly("finished", &Replay::finished)
      .def(
          "after_next_event",
          [](Replay& r, const Simulation& s) { return state_dict(s, r.after_next_event()); }, py::arg("simulation"))
      .def(
          "at", [](Replay& r, const Simulation& s, double t) { return state_dict(s, r.at(t)); }, py::arg("simulation"),
          py::arg("t"));
}

}  // namespace billiard::python

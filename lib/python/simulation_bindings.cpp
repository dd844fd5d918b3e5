// Python bindings of the event-driven engine (billiard/engine/container.hpp, settings.hpp,
// simulation.hpp, replay.hpp): billiard.Container and the shape functions that make one,
// billiard.Settings and billiard.Simulation. States and the event log come out as dictionaries of
// numpy arrays; the replays are generators (billiard/__init__.py wraps the Replay object below).
// No physics here: only conversions.
#include "bindings.hpp"

#include "billiard/engine/replay.hpp"
#include "billiard/engine/simulation.hpp"
#include "container_geometry.hpp"  // (the engine's internals: Container.bounds)

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

namespace py = pybind11;

namespace billiard::python {
namespace {

// How often Simulation.advance lets Python run its signal handlers: every 40 microseconds at 2.5
// million events per second, so that even a run of slow events (huge systems, islands of
// sleeping discs waking) stops at once. A check costs nanoseconds when no signal came: even one
// after every event slowed a run by only 1 to 2%.
constexpr std::int64_t kEventsBetweenSignalChecks = 100;

// The contents of a Python bytes object, without a copy.
std::string_view bytes_view(const py::bytes& data) {
  return std::string_view(PyBytes_AS_STRING(data.ptr()), static_cast<std::size_t>(PyBytes_GET_SIZE(data.ptr())));
}

// Real numbers only: numpy would also cast booleans, complex numbers and text to float64.
bool real_kind(const py::array& array) {
  const char kind = array ? array.dtype().kind() : '\0';
  return kind == 'f' || kind == 'i' || kind == 'u';
}

// A sequence of numbers (a list or a 1-D array).
std::vector<double> to_values(const py::object& value, const char* name) {
  const std::string refusal = std::string(name) + " must be a sequence of numbers, got " + short_repr(value);
  const py::array raw = py::array::ensure(value);
  if (!real_kind(raw)) throw std::invalid_argument(refusal);
  const auto array = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(raw);
  if (!array || array.ndim() != 1) throw std::invalid_argument(refusal);
  return std::vector<double>(array.data(), array.data() + array.size());
}

py::dict state_dict(const Simulation& sim, const State& state) {
  py::dict d;
  d["time"] = state.time;
  d["position"] = to_numpy(state.positions);
  d["velocity"] = to_numpy(state.velocities);
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
  Coordinates position(k, 2), velocity(k, 2), other_position(k, 2), other_velocity(k, 2);
  for (py::ssize_t n = 0; n < k; ++n) {
    const EventRecord& e = log[static_cast<std::size_t>(n)];
    time.mutable_at(n) = e.time;
    kind.mutable_at(n) = static_cast<int>(e.kind);
    disc.mutable_at(n) = e.disc;
    other.mutable_at(n) = e.other;
    wall.mutable_at(n) = e.wall;
    spin.mutable_at(n) = e.spin;
    other_spin.mutable_at(n) = e.other_spin;
    position.row(n) = e.position;
    velocity.row(n) = e.velocity;
    other_position.row(n) = e.other_position;
    other_velocity.row(n) = e.other_velocity;
  }
  py::dict d;
  d["time"] = time;
  d["kind"] = kind;
  d["disc"] = disc;
  d["other"] = other;
  d["wall"] = wall;
  d["position"] = to_numpy(position);
  d["velocity"] = to_numpy(velocity);
  d["spin"] = spin;
  d["other_position"] = to_numpy(other_position);
  d["other_velocity"] = to_numpy(other_velocity);
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

py::list walls_list(const Container& c) {
  py::list out;
  for (const WallShape& w : c.walls()) {
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
}

py::tuple pair(const Vector& v) { return py::make_tuple(v.x(), v.y()); }

// "1 segment", "4 points": a count and a noun.
std::string counted(std::size_t n, const char* noun) { return std::to_string(n) + " " + noun + (n == 1 ? "" : "s"); }

// What the container is, from what it holds (it does not remember which function made it).
std::string container_repr(const Container& c) {
  const auto number = [](double x) { return py::repr(py::float_(x)).cast<std::string>(); };
  if (c.periodic())
    return "Container(periodic box " + number(c.period().x()) + " x " + number(c.period().y()) + ", no walls)";
  std::size_t outlines = 0, holes = 0;
  for (const Outline& o : c.outlines()) (o.hole ? holes : outlines) += 1;
  std::string what;
  if (c.has_table()) what = "circular table of radius " + number(c.table_radius());
  if (outlines > 0) what += (what.empty() ? "" : ", ") + counted(outlines, "closed outline");
  if (holes > 0) what += (what.empty() ? "" : ", ") + counted(holes, "obstacle");
  std::size_t kinds[4] = {0, 0, 0, 0};  // segment, arc, circle, point
  for (const WallShape& w : c.walls()) {
    kinds[w.kind == WallKind::Segment ? 0 : w.kind == WallKind::Arc ? 1 : w.kind == WallKind::Circle ? 2 : 3] += 1;
  }
  std::string walls = counted(c.walls().size(), "wall");
  const char* nouns[4] = {"segment", "arc", "circle", "point"};
  std::string parts;
  for (int k = 0; k < 4; ++k) {
    if (kinds[k] > 0) parts += (parts.empty() ? "" : ", ") + counted(kinds[k], nouns[k]);
  }
  return "Container(" + what + "; " + walls + (parts.empty() ? "" : ": " + parts) + ")";
}

// settings.restitution: a number (the normal coefficient; smooth discs) or a pair (normal,
// tangential). The values are checked by Simulation(...), as in C++.
Restitution to_restitution(const py::object& value, const char* name) {
  const py::array raw = py::array::ensure(value);
  if (real_kind(raw) && (raw.ndim() == 0 || (raw.ndim() == 1 && raw.size() == 2))) {
    const auto array = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(raw);
    if (array) {
      if (array.ndim() == 0) return Restitution{array.data()[0], -1.0};
      return Restitution{array.data()[0], array.data()[1]};
    }
  }
  throw std::invalid_argument(std::string(name) +
                              " must be a number (the normal coefficient) or a pair (normal, tangential), got " +
                              short_repr(value));
}

Prefetch to_prefetch(const py::object& value) {
  if (py::isinstance<py::str>(value)) {
    const auto mode = value.cast<std::string>();
    if (mode == "auto") return Prefetch::Automatic;
    if (mode == "on") return Prefetch::On;
    if (mode == "off") return Prefetch::Off;
  }
  throw std::invalid_argument("settings.prefetch must be 'auto', 'on' or 'off', got " + short_repr(value));
}

const char* prefetch_name(Prefetch p) {
  switch (p) {
    case Prefetch::On: return "on";
    case Prefetch::Off: return "off";
    case Prefetch::Automatic: break;
  }
  return "auto";
}

py::str settings_repr(const py::object& self) {
  return py::str(
             "Settings(gravity={!r}, restitution={!r}, exchange_velocities={!r}, contact_duration={!r}, "
             "elastic_impact_speed={!r}, sleep_speed={!r}, cell_size={!r}, prefetch={!r})")
      .format(self.attr("gravity"), self.attr("restitution"), self.attr("exchange_velocities"),
              self.attr("contact_duration"), self.attr("elastic_impact_speed"), self.attr("sleep_speed"),
              self.attr("cell_size"), self.attr("prefetch"));
}

// A field of Settings read and written as it is; the setter's argument carries the field's name,
// so that a value of the wrong type is a TypeError naming it.
template <typename T>
void plain_field(py::class_<Settings>& cls, const char* name, T Settings::*member, const char* doc) {
  cls.def_property(
      name, [member](const Settings& s) { return s.*member; },
      py::cpp_function([member](Settings& s, T value) { s.*member = value; }, py::name(name), py::is_method(cls),
                       py::arg(name)),
      doc);
}

const char* const kShapes =
    "billiard.circular_table, periodic_box, box, polygon, stadium, sinai_billiard, mushroom or union_of_circles";

void bind_container(py::module_& m) {
  py::class_<Container> container(m, "Container",
                                  R"(The space the discs live in, with its walls: made by one of the shape functions
(billiard.circular_table, periodic_box, box, polygon, stadium, sinai_billiard, mushroom,
union_of_circles), then extended with add_segment, add_arc and add_obstacle, then given to
billiard.Simulation, which keeps a copy (changing the container afterwards changes no simulation):

    table = billiard.sinai_billiard((0, 0), (10, 10), 2.0)
    table.add_segment((1, 1), (3, 1))          # a free wall
    sim = billiard.Simulation(table)

Bad arguments raise ValueError naming the argument; a refused call leaves the container as it was.
Points are (x, y) pairs, lists of points arrays of shape (n, 2). Angles in radians,
counter-clockwise from +x.)");
  container
      .def(py::init([](const py::args&, const py::kwargs&) -> Container {
             throw py::type_error(std::string("billiard.Container has no constructor: make one with ") + kShapes);
           }),
           "(Refused: a container is made by a shape function, e.g. billiard.box((0, 0), (10, 10)).)")
      .def(
          "add_segment",
          [](Container& c, const py::object& a, const py::object& b) {
            return c.add_segment(to_vector(a, "add_segment: a"), to_vector(b, "add_segment: b"));
          },
          py::arg("a"), py::arg("b"),
          "A straight wall from a to b (both faces, and its end points); returns its index in walls. Not in a\n"
          "periodic box.")
      .def(
          "add_arc",
          [](Container& c, const py::object& centre, double radius, double start_angle, double end_angle) {
            return c.add_arc(to_vector(centre, "add_arc: centre"), radius, start_angle, end_angle);
          },
          py::arg("centre"), py::arg("radius"), py::arg("start_angle"), py::arg("end_angle"),
          "A circular arc wall (both faces, and its end points), counter-clockwise from start_angle to end_angle\n"
          "(radians, 0 < end_angle - start_angle <= 2 pi); returns its index in walls. Not in a periodic box.")
      .def(
          "add_obstacle", [](Container& c, const Container& shape) { c.add_obstacle(shape); }, py::arg("shape"),
          "An obstacle of any outlined shape (a container made by box, polygon, stadium, mushroom or\n"
          "union_of_circles, without free walls): discs stay outside of it. Not in a periodic box.")
      .def(
          "add_obstacle",
          [](Container& c, const py::object& centre, double radius) {
            c.add_obstacle(to_vector(centre, "add_obstacle: centre"), radius);
          },
          py::arg("centre"), py::arg("radius"),
          "A disc obstacle: a whole circle that discs stay outside of. Not in a periodic box.")
      .def_property_readonly(
          "walls", &walls_list,
          "The walls as dicts: kind ('segment', 'point', 'circle', 'arc'), a, b, radius, start_angle, sweep\n"
          "(an arc: centre a, from start_angle counter-clockwise through sweep radians). A new list each time.")
      .def_property_readonly(
          "period", [](const Container& c) { return pair(c.period()); },
          "(width, height) of the periodic box; (0, 0) if none.")
      .def_property_readonly("table_radius", &Container::table_radius, "Radius of the circular table; 0 if none.")
      .def_property_readonly("periodic", &Container::periodic, "Whether this is a periodic box.")
      .def_property_readonly(
          "bounds",
          [](const Container& c) {
            Vector lower, upper;
            bounds(c, lower, upper);
            return py::make_tuple(pair(lower), pair(upper));
          },
          "((xmin, ymin), (xmax, ymax)): a box holding every place a disc's centre can reach (the periodic\n"
          "box itself, or the box around the table and the outlines).")
      .def("__repr__", &container_repr)
      .def("__copy__", [](const Container& c) { return Container(c); })
      .def(
          "__deepcopy__", [](const Container& c, const py::dict&) { return Container(c); }, py::arg("memo"))
      // (Picklable, so that containers can be parameters of billiard.sweep's runs.)
      .def(py::pickle([](const Container& c) { return py::bytes(c.to_bytes()); },
                      [](const py::bytes& data) { return Container::from_bytes(bytes_view(data), "the pickled container"); }));

  m.def("circular_table", &circular_table, py::arg("radius"),
        "A circular table of this radius centred at the origin; discs live inside it.");
  m.def("periodic_box", &periodic_box, py::arg("width"), py::arg("height"),
        "The periodic box [0, width) x [0, height): the bulk system. It has no walls, and none can be added.");
  m.def(
      "box",
      [](const py::object& lower, const py::object& upper) {
        return box(to_vector(lower, "box: lower"), to_vector(upper, "box: upper"));
      },
      py::arg("lower"), py::arg("upper"),
      "The axis-aligned box [lower, upper] (points (x, y)): four walls, discs inside.");
  m.def(
      "polygon", [](const py::object& vertices) { return polygon(to_coordinates(vertices, "polygon: vertices")); },
      py::arg("vertices"), "A closed polygon, vertices (n, 2) in order (n >= 3): one wall per side, discs inside.");
  m.def(
      "stadium",
      [](const py::object& centre, double radius, double length) {
        return stadium(to_vector(centre, "stadium: centre"), radius, length);
      },
      py::arg("centre"), py::arg("radius"), py::arg("length"),
      "A stadium: half circles of radius whose centres are length apart (horizontally, about centre),\n"
      "joined by straight sides; discs live inside it.");
  m.def(
      "sinai_billiard",
      [](const py::object& lower, const py::object& upper, double obstacle_radius) {
        return sinai_billiard(to_vector(lower, "sinai_billiard: lower"), to_vector(upper, "sinai_billiard: upper"),
                              obstacle_radius);
      },
      py::arg("lower"), py::arg("upper"), py::arg("obstacle_radius"),
      "The box [lower, upper] with a disc obstacle in its middle.");
  m.def(
      "mushroom",
      [](const py::object& centre, double cap_radius, double stem_width, double stem_height) {
        return mushroom(to_vector(centre, "mushroom: centre"), cap_radius, stem_width, stem_height);
      },
      py::arg("centre"), py::arg("cap_radius"), py::arg("stem_width"), py::arg("stem_height"),
      "A mushroom: a half-disc cap above centre (the middle of its flat side) on a stem_width x stem_height\n"
      "stem below it (stem_width < 2 cap_radius); discs live inside it.");
  m.def(
      "union_of_circles",
      [](const py::object& centres, const py::object& radii) {
        return union_of_circles(to_coordinates(centres, "union_of_circles: centres"),
                                to_values(radii, "union_of_circles: radii"));
      },
      py::arg("centres"), py::arg("radii"),
      "The union of circles (centres (n, 2), radii (n,)): discs live inside it; its boundary arcs and the\n"
      "points where they meet are the walls.");
}

void bind_settings(py::module_& m) {
  py::class_<Settings> settings(
      m, "Settings", R"(The physics and the engine's choices for a simulation, as one value with defaults. Keyword
arguments only; every field is an attribute that can be read and changed before the simulation
is made:

    settings = billiard.Settings(gravity=(0, -1), restitution=0.9)
    sim = billiard.Simulation(billiard.box((0, 0), (10, 10)), settings)

billiard.Simulation(container, settings) checks the values (ValueError naming the field, e.g.
"settings.gravity ...") and keeps a copy. Gravity, the cell size and prefetching are fixed from
then on; the restitution, the exchange rule and the granular model can be changed during a run
with the simulation's setters of the same names.)");
  settings
      .def(py::init([](const py::object& gravity, const py::object& restitution, bool exchange_velocities,
                       std::optional<double> contact_duration, std::optional<double> elastic_impact_speed,
                       std::optional<double> sleep_speed, double cell_size, const py::object& prefetch) {
             Settings s;
             s.gravity = to_vector(gravity, "settings.gravity");
             s.restitution = to_restitution(restitution, "settings.restitution");
             s.exchange_velocities = exchange_velocities;
             s.contact_duration = contact_duration;
             s.elastic_impact_speed = elastic_impact_speed;
             s.sleep_speed = sleep_speed;
             s.cell_size = cell_size;
             s.prefetch = to_prefetch(prefetch);
             return s;
           }),
           py::kw_only(), py::arg("gravity") = py::make_tuple(0.0, 0.0),
           py::arg("restitution") = py::make_tuple(1.0, -1.0), py::arg("exchange_velocities") = false,
           py::arg("contact_duration") = py::none(), py::arg("elastic_impact_speed") = py::none(),
           py::arg("sleep_speed") = py::none(), py::arg("cell_size") = 0.0, py::arg("prefetch") = "auto",
           "Settings with these values; the defaults are no gravity, smooth elastic discs, automatic choices.")
      .def_property(
          "gravity", [](const Settings& s) { return pair(s.gravity); },
          [](Settings& s, const py::object& g) { s.gravity = to_vector(g, "settings.gravity"); },
          "Uniform gravity (gx, gy); default (0, 0). In a periodic box it moves every disc alike: the discs are\n"
          "simulated in the freely falling frame (their relative motion as precise as without gravity) and the\n"
          "fall is added to what the simulation reports.")
      .def_property(
          "restitution",
          [](const Settings& s) { return py::make_tuple(s.restitution.normal, s.restitution.tangential); },
          [](Settings& s, const py::object& r) { s.restitution = to_restitution(r, "settings.restitution"); },
          "Coefficients of restitution (normal, tangential): normal in [0, 1] (1 elastic), tangential in [-1, 1]\n"
          "(-1 smooth, +1 rough); default (1.0, -1.0). A number sets the normal coefficient (tangential -1).");
  plain_field(
      settings, "exchange_velocities", &Settings::exchange_velocities,
      "The exchange rule: discs that meet swap their whole velocities (equal masses), walls still reflect only\n"
      "the normal component; the rule of the box exercise (the `particles` program). Default False.");
  plain_field(settings, "contact_duration", &Settings::contact_duration,
              "Granular gases (restitution < 1), TC model: a collision less than this after either disc's previous\n"
              "collision is elastic, which stops an inelastic collapse. None: automatic (default); 0: off.");
  plain_field(settings, "elastic_impact_speed", &Settings::elastic_impact_speed,
              "Granular gases: a collision whose normal approach speed is below this is elastic. None: automatic\n"
              "(default); 0: off.");
  plain_field(settings, "sleep_speed", &Settings::sleep_speed,
              "Granular beds under gravity: discs slower than this, resting on a wall or on sleeping discs, fall\n"
              "asleep (see Simulation.set_sleep_speed). None: automatic (default); 0: off.");
  plain_field(settings, "cell_size", &Settings::cell_size,
              "Side of the cells (>= the largest diameter); 0 chooses it automatically (default).");
  settings
      .def_property(
          "prefetch", [](const Settings& s) { return prefetch_name(s.prefetch); },
          [](Settings& s, const py::object& mode) { s.prefetch = to_prefetch(mode); },
          "Whether each event starts loading the next event's data into the caches: 'auto' (default: on from\n"
          "about 87,000 discs, where it pays), 'on' or 'off'. Speed only: the events are the same.")
      .def("__repr__", &settings_repr)
      .def(
          "__eq__",
          [](const Settings& a, const Settings& b) {
            return a.gravity == b.gravity && a.restitution.normal == b.restitution.normal &&
                   a.restitution.tangential == b.restitution.tangential &&
                   a.exchange_velocities == b.exchange_velocities && a.contact_duration == b.contact_duration &&
                   a.elastic_impact_speed == b.elastic_impact_speed && a.sleep_speed == b.sleep_speed &&
                   a.cell_size == b.cell_size && a.prefetch == b.prefetch;
          },
          py::is_operator())
      .def("__copy__", [](const Settings& s) { return Settings(s); })
      .def(
          "__deepcopy__", [](const Settings& s, const py::dict&) { return Settings(s); }, py::arg("memo"))
      // (Picklable, so that settings can be parameters of billiard.sweep's runs.)
      .def(py::pickle(
          [](const py::object& self) {
            py::dict state;
            for (const char* name : {"gravity", "restitution", "exchange_velocities", "contact_duration",
                                     "elastic_impact_speed", "sleep_speed", "cell_size", "prefetch"}) {
              state[name] = self.attr(name);
            }
            return state;
          },
          [](const py::dict& state) {
            Settings s;
            py::object target = py::cast(s);
            for (const auto& item : state) target.attr(item.first) = item.second;
            return target.cast<Settings>();
          }));
}

}  // namespace

void bind_simulation(py::module_& m) {
  m.attr("DISC_DISC") = static_cast<int>(EventKind::DiscDisc);
  m.attr("DISC_WALL") = static_cast<int>(EventKind::DiscWall);
  m.attr("SLEEP") = static_cast<int>(EventKind::Sleep);
  m.attr("WAKE") = static_cast<int>(EventKind::Wake);

  bind_container(m);
  bind_settings(m);

  py::class_<Simulation> sim(m, "Simulation", R"(Event-driven simulation of hard discs (the library in lib/).

A system is described first, as a billiard.Container (made by a shape function, then given
walls and obstacles) and billiard.Settings (gravity, restitution, ...), then made into a
simulation, given discs and run:

    table = billiard.box((0, 0), (10, 10))
    sim = billiard.Simulation(table, billiard.Settings(gravity=(0, -1)))
    sim.add_random_discs(20, 0.3, seed=1)     # or add_disc(position, velocity, radius, ...)
    sim.advance(events=1000)                  # or time=..., or both

Discs can be added until the first advance(); afterwards the restitution, the exchange rule,
the granular model and the event log can still change. Units are yours. States are dicts of
numpy arrays: time, position (n, 2), velocity (n, 2), spin (n,), mass (n,), radius (n,),
inertia (n,). Bad input raises ValueError naming the argument (and the disc) and its value.)");

  sim.def(py::init([](const Container& container, const std::optional<Settings>& settings) {
            return Simulation(container, settings.value_or(Settings()));
          }),
          py::arg("container"), py::arg("settings") = py::none(),
          "A simulation of discs in a copy of `container` (a billiard.Container) under `settings` (a\n"
          "billiard.Settings; None: the defaults), with no discs yet. Bad settings raise ValueError naming the\n"
          "field (\"settings.gravity ...\").")
      // (Anything else, an empty Simulation() in particular, is a TypeError saying what is needed.)
      .def(py::init([](const py::args& args, const py::kwargs& kwargs) -> Simulation {
             if (args.empty() && kwargs.empty()) {
               throw py::type_error(
                   std::string("Simulation needs a container: billiard.Simulation(container, settings=None), the "
                               "container made by ") +
                   kShapes + " (and settings by billiard.Settings(...))");
             }
             throw py::type_error(
                 std::string("Simulation(container, settings=None): container must be a billiard.Container (made by ") +
                 kShapes + ") and settings a billiard.Settings or None, got " + short_repr(args) +
                 (kwargs.empty() ? "" : " " + short_repr(kwargs)));
           }),
           "(Refused with a TypeError saying what Simulation needs.)")
      .def(
          "set_restitution",
          [](Simulation& s, const py::object& r) { s.set_restitution(to_restitution(r, "set_restitution: restitution")); },
          py::arg("restitution"),
          "Changes the coefficients of restitution (at first Settings.restitution, and given the same way: a number\n"
          "for the normal coefficient, or a pair (normal, tangential)), also during a run: normal in [0, 1]\n"
          "(1 elastic), tangential in [-1, 1] (-1 smooth, +1 rough).")
      .def("set_exchange_velocities", &Simulation::set_exchange_velocities, py::arg("on") = true,
           "Switches the exchange rule (at first Settings.exchange_velocities), also during a run: discs that meet\n"
           "swap their whole velocities (equal masses), walls still reflect only the normal component; the rule of\n"
           "the box exercise (the `particles` program).")
      .def_property_readonly("exchange_velocities", &Simulation::exchange_velocities,
                             "Whether the exchange rule is on (set_exchange_velocities).")
      .def("set_contact_duration", &Simulation::set_contact_duration, py::arg("duration"),
           "Changes Settings.contact_duration, also during a run. Granular gases (restitution < 1), TC model: a\n"
           "collision less than `duration` after either disc's previous collision is elastic, which stops an\n"
           "inelastic collapse. None: automatic (default, 1e-4 mean radius / rms speed at the first advance, under\n"
           "gravity at least 0.01 sqrt(radius / |g|)); 0: off. Energy never increases.")
      .def("set_elastic_impact_speed", &Simulation::set_elastic_impact_speed, py::arg("speed"),
           "Changes Settings.elastic_impact_speed, also during a run. Granular gases (restitution < 1): a collision\n"
           "whose normal approach speed is below `speed` is elastic, so discs resting on a floor under gravity g\n"
           "bounce at most speed^2 / (2 g) high. None: automatic (sqrt(2 |g| 0.05 mean radius); 0 without gravity\n"
           "or while discs can sleep); 0: off.")
      .def("set_sleep_speed", &Simulation::set_sleep_speed, py::arg("speed"),
           "Changes Settings.sleep_speed, also during a run. Granular beds under gravity: discs slower than `speed`\n"
           "for 3 speed / |g|, connected by contacts and touching a wall or a sleeping disc, fall asleep together\n"
           "(stop; no events; immovable). A hit at a normal speed of at least `speed` wakes a sleeping disc and the\n"
           "ones resting on it. None: automatic (sqrt(2 |g| 0.05 mean radius) when gravity acts and restitution < 1,\n"
           "else 0); 0: off (wakes every sleeping disc). While discs can sleep, the automatic elastic impact speed\n"
           "is 0.")
      .def_property_readonly("sleep_speed", &Simulation::sleep_speed,
                             "The sleep speed in use (chosen at the first advance when automatic).")
      .def_property_readonly("sleeping_discs", &Simulation::sleeping_discs,
                             "The indices of the discs asleep now, in increasing order.")
      .def_property_readonly("contact_duration", &Simulation::contact_duration,
                             "The TC model's duration in use (chosen at the first advance when automatic).")
      .def_property_readonly("elastic_impact_speed", &Simulation::elastic_impact_speed,
                             "The elastic impact speed in use (chosen at the first advance when automatic).")
      .def(
          "add_disc",
          [](Simulation& s, const py::object& position, const py::object& velocity, double radius, double mass,
             std::optional<double> inertia, double spin) {
            Disc d;
            d.position = to_vector(position, "position");
            d.velocity = to_vector(velocity, "velocity");
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
            return s.add_discs(to_coordinates(positions, "positions"), to_coordinates(velocities, "velocities"), radius, mass);
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
            if (time && !(*time >= 0)) {
              throw std::invalid_argument("advance: time must be a number >= 0, got " + short_repr(py::float_(*time)) +
                                          (std::isnan(*time) ? " (not a number)" : ""));
            }
            // The engine holds the GIL while it runs, so Python's signal handlers (Ctrl-C's
            // KeyboardInterrupt) would wait for the whole run: let them run every
            // kEventsBetweenSignalChecks events. A handler that raises stops the engine at that
            // event boundary (the state stays valid), and its exception leaves advance.
            const auto raise_pending_signal = [](const AdvanceResult&) {
              if (PyErr_CheckSignals() != 0) throw py::error_already_set();
              return false;
            };
            const AdvanceResult r = s.advance(events.value_or(kAllEvents), time.value_or(kNever), raise_pending_signal,
                                              kEventsBetweenSignalChecks);
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
          "(what happened when stuck; the state stays valid). Ctrl-C (or any signal handler that raises) stops\n"
          "the run within a millisecond at an event boundary and raises KeyboardInterrupt (the handler's\n"
          "exception); the state stays valid and advance may go on.")
      .def_property_readonly("time", &Simulation::time, "The current time.")
      .def("__len__", &Simulation::size, "Number of discs.")
      .def_property_readonly(
          "current_state", [](const Simulation& s) { return state_dict(s, s.current_state()); },
          "The discs now (all advanced to `time`), as a dict of numpy arrays.")
      .def_property_readonly(
          "initial_state", [](const Simulation& s) { return state_dict(s, s.initial_state()); },
          "The discs at the first advance() (or now, before it).")
      .def_property_readonly(
          "images", &Simulation::images,
          "Periodic image counts now, an int64 array (n, 2), row i for disc i of current_state: how many times\n"
          "each disc was wrapped across the periodic box along x and y (+1 at the upper face, -1 at the lower).\n"
          "position + images * container.period is the unwrapped position (for displacements); zeros without a\n"
          "periodic box.")
      .def("set_log_events", &Simulation::set_log_events, py::arg("on") = true,
           "Record every event (enable before the first advance() to replay).")
      .def("clear_event_log", &Simulation::clear_event_log, "Forget the recorded events (the log keeps recording if enabled).")
      .def_property_readonly(
          "event_log", [](const Simulation& s) { return event_log_dict(s.event_log()); },
          "The recorded events as a dict of arrays: time, kind (DISC_DISC, DISC_WALL, or SLEEP and WAKE for a disc\n"
          "falling asleep or waking up), disc, other (-1 when there is no other disc: a wall, or none), wall (-1\n"
          "unless a wall), and position, velocity, spin of disc and other just after the event.")
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
          "container", [](const Simulation& s) { return Container(s.container()); },
          "The container (a copy: changing it changes nothing here): its walls, period, table_radius, periodic.")
      .def_property_readonly(
          "gravity", [](const Simulation& s) { return pair(s.gravity()); }, "Uniform gravity (gx, gy).")
      .def_property_readonly(
          "restitution",
          [](const Simulation& s) { return py::make_tuple(s.restitution().normal, s.restitution().tangential); },
          "Coefficients of restitution in use (normal, tangential).")
      .def(
          "save",
          [](const Simulation& s, const py::object& path) {
            py::module_::import("pathlib").attr("Path")(path).attr("write_bytes")(py::bytes(s.to_bytes()));
          },
          py::arg("path"),
          "Saves the whole simulation to the file at `path` (a str or os.PathLike): everything that decides its\n"
          "future, so that Simulation.load(path) continues exactly as this one would (the same events, bit for bit).")
      .def_static(
          "load",
          [](const py::object& path) {
            const py::bytes data = py::module_::import("pathlib").attr("Path")(path).attr("read_bytes")();
            return Simulation::from_bytes(bytes_view(data), std::string(py::str(path)));
          },
          py::arg("path"),
          "The simulation saved by save(path). A file that is not one, was written by another format version, is\n"
          "truncated or damaged is refused with a ValueError saying so (never half-loaded).")
      .def(
          "to_bytes", [](const Simulation& s) { return py::bytes(s.to_bytes()); },
          "The saved simulation as bytes (what save writes).")
      .def_static(
          "from_bytes", [](const py::bytes& data) { return Simulation::from_bytes(bytes_view(data)); }, py::arg("data"),
          "The simulation saved as these bytes by to_bytes (refused like load).")
      // (Picklable, so that Dask can move a simulation between processes.)
      .def(py::pickle([](const Simulation& s) { return py::bytes(s.to_bytes()); },
                      [](const py::bytes& data) { return Simulation::from_bytes(bytes_view(data), "the pickled simulation"); }));

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

// Saving a simulation (or a container) as bytes and loading it back (Simulation::to_bytes,
// from_bytes; Container::to_bytes, from_bytes). A loaded simulation must continue exactly as the
// original would, so every member of the engine that the future depends on is kept as it is:
// the disc arrays, the cells (the order of their lists decides which of two equal times is
// found first), the event queue's arrays (the order of equal keys), every scalar. Only scratch
// space is left out (it is rebuilt empty) and the stop request.
//
// One function per structure lists its fields (transfer below); a Writer appends each field's
// bytes and a Reader fills each field from them, so the two directions cannot disagree. Numbers
// are stored in the machine's own byte order, checked by a mark in the header.
#include "billiard/engine/container.hpp"
#include "billiard/engine/simulation.hpp"

#include "engine.hpp"

#include <cstring>
#include <istream>
#include <iterator>
#include <ostream>
#include <stdexcept>
#include <type_traits>

#ifndef BILLIARD_VERSION
#define BILLIARD_VERSION "unknown"
#endif

namespace billiard {
namespace {

constexpr std::uint32_t kByteOrderMark = 0x01020304;
const char* const kLibraryVersion = BILLIARD_VERSION;

template <class T>
struct IsOptional : std::false_type {};
template <class T>
struct IsOptional<std::optional<T>> : std::true_type {};
template <class T>
struct IsVector : std::false_type {};
template <class T, class A>
struct IsVector<std::vector<T, A>> : std::true_type {};

// What Writer and Reader share: how each kind of field becomes bytes. Numbers and enums are
// their bytes; optionals a flag and the value; strings, vectors and dynamic matrices their
// sizes and then their elements.
template <class Derived>
class Io {
 public:
  template <class T>
  void operator()(T& x) {
    Derived& self = static_cast<Derived&>(*this);
    if constexpr (std::is_arithmetic_v<T> || std::is_enum_v<T>) {
      self.bytes(&x, sizeof x);
    } else if constexpr (IsOptional<T>::value) {
      bool present = x.has_value();
      (*this)(present);
      if (!present) {
        x.reset();
      } else {
        if (!x) x.emplace();
        (*this)(*x);
      }
    } else if constexpr (std::is_same_v<T, std::string>) {
      std::uint64_t n = x.size();
      self.count(n, 1);
      x.resize(n);
      self.bytes(x.data(), n);
    } else if constexpr (IsVector<T>::value) {
      using Element = typename T::value_type;
      static_assert(std::is_arithmetic_v<Element>, "a vector of structures goes through sequence()");
      std::uint64_t n = x.size();
      self.count(n, sizeof(Element));
      x.resize(n);
      self.bytes(x.data(), n * sizeof(Element));
    } else {  // an Eigen vector or matrix of doubles
      static_assert(std::is_same_v<typename T::Scalar, double>, "a field of an unknown kind");
      if constexpr (T::SizeAtCompileTime == Eigen::Dynamic) {
        std::int64_t rows = x.rows(), cols = x.cols();
        (*this)(rows);
        (*this)(cols);
        self.check(rows >= 0 && (T::ColsAtCompileTime == Eigen::Dynamic ? cols >= 0 : cols == T::ColsAtCompileTime) &&
                       (T::RowsAtCompileTime == Eigen::Dynamic || rows == T::RowsAtCompileTime),
                   "matrix shape");
        std::uint64_t n = static_cast<std::uint64_t>(rows) * static_cast<std::uint64_t>(cols);
        self.count(n, sizeof(double));  // (writes the count again: cheap, and checks the size)
        x.resize(rows, cols);
      }
      self.bytes(x.data(), static_cast<std::size_t>(x.size()) * sizeof(double));
    }
  }

  // A vector of structures, each element passed to `each`, which transfers its fields.
  template <class Vector, class Each>
  void sequence(Vector& v, std::size_t least_bytes_each, Each each) {
    std::uint64_t n = v.size();
    static_cast<Derived&>(*this).count(n, least_bytes_each);
    v.resize(n);
    for (auto& element : v) each(element);
  }
};

class Writer : public Io<Writer> {
 public:
  std::string data;
  void bytes(const void* p, std::size_t n) { data.append(static_cast<const char*>(p), n); }
  void count(std::uint64_t n, std::size_t) { bytes(&n, sizeof n); }
  void check(bool, const char*) {}
};

class Reader : public Io<Reader> {
 public:
  Reader(std::string_view data, const std::string& source) : data_(data), source_(source) {}
  void bytes(void* p, std::size_t n) {
    if (n > data_.size() - at_) fail("it ends inside its data");
    if (n > 0) std::memcpy(p, data_.data() + at_, n);
    at_ += n;
  }
  // A count of elements of at least `least_bytes` each, which must fit in what is left.
  void count(std::uint64_t& n, std::size_t least_bytes) {
    bytes(&n, sizeof n);
    if (n > (data_.size() - at_) / std::max<std::size_t>(least_bytes, 1)) fail("a count larger than the data");
  }
  void check(bool ok, const char* what) {
    if (!ok) fail(std::string("an impossible ") + what);
  }
  [[noreturn]] void fail(const std::string& why) const {
    throw std::invalid_argument(source_ + " is damaged (" + why + ", at byte " + std::to_string(at_) +
                                " of the data, though its checksum matches): it was not written by this library");
  }
  bool at_end() const { return at_ == data_.size(); }

 private:
  std::string_view data_;
  std::size_t at_ = 0;
  const std::string& source_;
};

// ---- The fields of each structure ----

template <class Io>
void transfer(Io& io, WallShape& w) {
  io(w.kind);
  io(w.a);
  io(w.b);
  io(w.radius);
  io(w.start_angle);
  io(w.sweep);
}

template <class Io>
void transfer(Io& io, HotDisc& d) {
  io(d.position);
  io(d.velocity);
  io(d.time);
  io(d.radius);
  io(d.inverse_mass);
  io(d.counter);
  io(d.cx);
  io(d.cy);
}

template <class Io>
void transfer(Io& io, ColdDisc& c) {
  io(c.mass);
  io(c.inertia);
  io(c.inverse_inertia);
  io(c.spin);
  io(c.last_collision);
  io(c.last_disc_collision);
  io(c.slow_since);
  io(c.next_sleep_try);
}

template <class Io>
void transfer(Io& io, Scheduled& s) {
  io(s.contact_time);
  io(s.crossing_time);
  io(s.partner);
  io(s.partner_counter);
  io(s.wall);
  io(s.crossing);
}

template <class Io>
void transfer(Io& io, EventRecord& e) {
  io(e.time);
  io(e.kind);
  io(e.disc);
  io(e.other);
  io(e.wall);
  io(e.position);
  io(e.velocity);
  io(e.spin);
  io(e.other_position);
  io(e.other_velocity);
  io(e.other_spin);
}

template <class Io>
void transfer(Io& io, Grid& g) {
  io(g.lower);
  io(g.extent);
  io(g.cell);
  io(g.nx);
  io(g.ny);
  io(g.periodic);
  io(g.capacity);
  io(g.records);
  io(g.spill);
  io(g.spill_free);
  io(g.wall_ranges);
  io(g.wall_items);
}

// Everything of the engine but its container (transferred first: the engine is made from it).
template <class Io>
void transfer(Io& io, Engine& e) {
  // Setup: the settings and the granular model's chosen values.
  io(e.gravity);
  io(e.has_gravity);
  io(e.gravity_norm);
  io(e.fall);
  io(e.restitution.normal);
  io(e.restitution.tangential);
  io(e.smooth_elastic);
  io(e.exchange_velocities);
  io(e.mirror_walls);
  io(e.contact_duration_setting);
  io(e.elastic_impact_speed_setting);
  io(e.sleep_speed_setting);
  io(e.contact_duration);
  io(e.elastic_impact_speed);
  io(e.resting_speed);
  io(e.sleep_speed);
  io(e.cell_size);
  // Discs.
  io.sequence(e.hot, 64, [&io](HotDisc& d) { transfer(io, d); });
  io.sequence(e.cold, 64, [&io](ColdDisc& c) { transfer(io, c); });
  io.sequence(e.scheduled, 28, [&io](Scheduled& s) { transfer(io, s); });
  io.sequence(e.image_counts, 16, [&io](std::array<std::int64_t, 2>& images) {
    io(images[0]);
    io(images[1]);
  });
  io(e.max_radius);
  io(e.min_radius);
  io(e.setup_hash.cell);
  // The run.
  io(e.prepared);
  io(e.prefetch_mode);
  io(e.prefetch_ahead);
  io(e.now);
  io(e.epoch);
  io(e.speed_bound);
  io(e.rebase_at);
  io(e.slowest_squared);
  io(e.too_slow);
  io(e.instant);
  io(e.events_at_instant);
  transfer(io, e.grid);
  e.queue.transfer(io);
  io(e.totals.wall_momentum);
  io(e.totals.virial);
  io(e.totals.disc_collisions);
  io(e.totals.wall_collisions);
  io(e.totals.cell_crossings);
  io(e.initial.time);
  io(e.initial.positions);
  io(e.initial.velocities);
  io(e.initial.spins);
  io(e.logging);
  io.sequence(e.log, 100, [&io](EventRecord& r) { transfer(io, r); });
  io(e.sleeping);
  io(e.validate_every_event);
  io(e.check_event_discs);
  io(e.problem);
}

// ---- The frame: header, data and checksum ----

std::uint64_t fnv1a(std::string_view bytes) {
  std::uint64_t hash = 0xcbf29ce484222325ULL;
  for (const char c : bytes) {
    hash ^= static_cast<unsigned char>(c);
    hash *= 0x100000001b3ULL;
  }
  return hash;
}

template <class T>
void append(std::string& out, T value) {
  out.append(reinterpret_cast<const char*>(&value), sizeof value);
}

std::string magic_of(const char* kind) { return std::string("billiard-") + kind + '\0'; }

std::string framed(const char* kind, const std::string& data) {
  std::string out = magic_of(kind);
  append(out, kByteOrderMark);
  append(out, Simulation::kFileFormatVersion);
  const std::string version = kLibraryVersion;
  append(out, static_cast<std::uint32_t>(version.size()));
  out += version;
  append(out, static_cast<std::uint64_t>(data.size()));
  out.reserve(out.size() + data.size() + 8);
  out += data;
  append(out, fnv1a(out));
  return out;
}

// The data inside a frame of this kind, after every check of the frame; std::invalid_argument
// naming `source` if one fails.
std::string_view unframed(std::string_view bytes, const char* kind, const std::string& source) {
  const std::string magic = magic_of(kind);
  const std::string what = std::string("billiard ") + kind + " file";
  const auto refuse = [&](const std::string& why) { throw std::invalid_argument(source + " " + why); };
  if (bytes.empty()) refuse("is empty, not a " + what);
  if (bytes.substr(0, magic.size()) != magic) {
    const std::string_view prefix = "billiard-";
    const std::size_t end = bytes.find('\0');
    if (bytes.substr(0, prefix.size()) == prefix && end != std::string_view::npos && end < 40) {
      refuse("is a billiard " + std::string(bytes.substr(prefix.size(), end - prefix.size())) + " file, not a " + what);
    }
    if (magic.compare(0, bytes.size(), bytes.data(), bytes.size()) == 0) refuse("is truncated: it ends inside its header");
    refuse("is not a " + what + " (it does not start with \"billiard-" + kind + "\")");
  }
  std::size_t at = magic.size();
  const auto take = [&](void* p, std::size_t n) {
    if (n > bytes.size() - at) refuse("is truncated: it ends inside its header");
    std::memcpy(p, bytes.data() + at, n);
    at += n;
  };
  std::uint32_t mark = 0, version = 0, version_length = 0;
  take(&mark, sizeof mark);
  if (mark != kByteOrderMark) refuse("was written on a machine with another byte order; it can be read only on such a machine");
  take(&version, sizeof version);
  take(&version_length, sizeof version_length);
  std::string library(std::min<std::size_t>(version_length, bytes.size() - at), '\0');
  take(library.data(), library.size());
  if (version != Simulation::kFileFormatVersion) {
    refuse("was written by format version " + std::to_string(version) + " of " + what + "s (billiard " + library +
           "); this library (billiard " + kLibraryVersion + ") reads version " +
           std::to_string(Simulation::kFileFormatVersion) + " only");
  }
  std::uint64_t length = 0;
  take(&length, sizeof length);
  const std::uint64_t present = bytes.size() - at;
  if (present < 8 || present - 8 < length) {
    refuse("is truncated: " + std::to_string(bytes.size()) + " bytes, where its header promises " +
           std::to_string(at + length + 8));
  }
  if (present - 8 > length) {
    refuse("is damaged: " + std::to_string(present - 8 - length) + " bytes follow its end");
  }
  std::uint64_t checksum = 0;
  std::memcpy(&checksum, bytes.data() + at + length, sizeof checksum);
  if (checksum != fnv1a(bytes.substr(0, at + length))) refuse("is damaged (checksum mismatch)");
  return bytes.substr(at, length);
}

const char* const kSimulationKind = "simulation";
const char* const kContainerKind = "container";

}  // namespace

// Container's private members, for to_bytes and from_bytes (a friend of Container).
struct ContainerFields {
  static Container empty() { return Container(); }
  template <class Io>
  static void transfer(Io& io, Container& c) {
    io.sequence(c.walls_, 60, [&io](WallShape& w) { billiard::transfer(io, w); });
    io.sequence(c.outlines_, 9, [&io](Outline& outline) {
      io.sequence(outline.pieces, 60, [&io](WallShape& w) { billiard::transfer(io, w); });
      io(outline.hole);
    });
    io(c.has_table_);
    io(c.table_radius_);
    io(c.periodic_);
    io(c.period_);
    io(c.free_walls_);
  }
};

std::string Container::to_bytes() const {
  Writer writer;
  ContainerFields::transfer(writer, const_cast<Container&>(*this));  // (the writer only reads)
  return framed(kContainerKind, writer.data);
}

Container Container::from_bytes(std::string_view bytes, const std::string& source) {
  Reader reader(unframed(bytes, kContainerKind, source), source);
  Container container = ContainerFields::empty();
  ContainerFields::transfer(reader, container);
  if (!reader.at_end()) reader.fail("data after the container");
  return container;
}

std::string Simulation::to_bytes() const {
  Engine& engine = *static_cast<Engine*>(engine_.get());  // (the writer only reads)
  Writer writer;
  ContainerFields::transfer(writer, engine.container);
  transfer(writer, engine);
  return framed(kSimulationKind, writer.data);
}

void Simulation::save(std::ostream& out) const {
  const std::string bytes = to_bytes();
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

Simulation Simulation::from_bytes(std::string_view bytes, const std::string& source) {
  Reader reader(unframed(bytes, kSimulationKind, source), source);
  Container container = ContainerFields::empty();
  ContainerFields::transfer(reader, container);
  // A fresh simulation, filled in; returned only once it is whole.
  Simulation simulation(std::move(container));
  Engine& e = *static_cast<Engine*>(simulation.engine_.get());
  transfer(reader, e);
  if (!reader.at_end()) reader.fail("data after the simulation");
  // The sizes everything else relies on.
  const std::size_t n = e.hot.size();
  reader.check(e.cold.size() == n && e.scheduled.size() == n, "number of discs");
  if (e.prepared) {
    const std::size_t cells = static_cast<std::size_t>(e.grid.nx) * static_cast<std::size_t>(e.grid.ny);
    reader.check(e.grid.nx > 0 && e.grid.ny > 0 && e.grid.records.size() == 4 * cells &&
                     e.grid.wall_ranges.size() == 2 * cells && e.image_counts.size() == n &&
                     e.queue.size() == static_cast<int>(n),
                 "grid or queue size");
    for (const HotDisc& d : e.hot) reader.check(d.cx < e.grid.nx && d.cy < e.grid.ny, "cell of a disc");
    e.queue.set_keys(ScheduledKeys{&e, e.scheduled.data()});
  } else {
    e.rebuild_setup_hash(e.setup_hash.cell);  // (discs may still be added)
  }
  return simulation;
}

Simulation Simulation::load(std::istream& in, const std::string& source) {
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw std::invalid_argument(source + " could not be read");
  return from_bytes(bytes, source);
}

}  // namespace billiard

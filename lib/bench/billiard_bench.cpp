// billiard_bench: collisions per second of the event-driven engine.
//
// For each N, area fraction, container (box, table, periodic, stadium, sinai) and gravity
// setting: discs of radius 1 on a square lattice (so any density up to pi/4 is reachable without a
// slow random placement), random Gaussian velocities, a warm-up of --warmup collisions per disc...
// then --repeats timed runs of --events collisions each (at one N the runs of all containers and
// densities take turns); the
// median rate is reported. "Collisions" are disc-disc plus disc-wall events (cell crossings are
// counted apart). The course's all-pairs propagate (O(N^2) per event) is timed at small N for
// comparison.
//
//   billiard_bench [--n 100,1000,...] [--density 0.1,0.5] [--containers box,table,periodic,stadium,sinai]
//                  [--gravity 0,1] [--repeats 5] [--events 1000000] [--course-n 100,1000]
//                  [--cell SIZE] [--prefetch auto|on|off] [--json FILE] [--wall]
//   billiard_bench --granular 0.5,0.8 [--n 1000] [--containers box,table] [--settle-time 200]
//   billiard_bench --memory 1,4,16,256
// --granular times, instead, beds settling under gravity g = (0, -1): N discs of radius 1 at random
// places (area fraction 0.3), kT = 1, the given restitutions, the granular model at its defaults,
// run to --settle-time in quarters. It prints collisions per second and the collisions per disc
// per unit of simulated time in each quarter, which fall to 0 once the bed has fallen asleep.
// Rates are per second of this thread's CPU time (--wall: elapsed time instead). --memory prints,
// instead, what the machine's memory does for one thread with arrays of the given sizes (MB),
// allocated like the engine's: the latency of one random cache-line read that depends on the
// one before, and how many independent random lines per second it delivers. Where the
// engine's arrays outgrow the fast sizes, its cost per collision steps up.
#include "memory.hpp"
#include "billiard/engine/simulation.hpp"
#ifdef BILLIARD_BENCH_COURSE
#include "billiard/course.hpp"
#endif

#include <algorithm>
#include <chrono>
#include <ctime>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <iostream>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace {

using billiard::Vector;
using Clock = std::chrono::steady_clock;

// CPU time of this thread in seconds: the rate of one core, insensitive to other processes
// sharing the machine (wall-clock rates are printed by --wall).
bool use_wall_clock = false;
double now_seconds() {
  if (use_wall_clock) return std::chrono::duration<double>(Clock::now().time_since_epoch()).count();
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// One granular settling run (see --granular above): prints its row.
void granular_settling(const std::string& container, long n, double restitution, double duration) {
  const double kPi = 3.14159265358979323846;
  const double area = static_cast<double>(n) * kPi / 0.3;
  // About 2.9 times as high as wide, and a whole number of diameters wide: a bottom row can fill
  // the floor exactly, the hardest case (without sleeping it rattles ever faster).
  const double width = 2 * std::floor(std::sqrt(area / 2.9) / 2);
  billiard::Settings settings;
  settings.gravity = Vector(0, -1);
  settings.restitution.normal = restitution;
  billiard::Simulation sim(container == "box" ? billiard::box(Vector(0, 0), Vector(width, area / width))
                                              : billiard::circular_table(std::sqrt(area / kPi)),
                           settings);
  sim.add_random_discs(static_cast<int>(n), 1.0, 1.0, 1.0, 11);
  const double start = now_seconds();
  double collisions = 0;
  std::printf("%-9s %9ld %11.2f", container.c_str(), n, restitution);
  for (int quarter = 0; quarter < 4; ++quarter) {
    const billiard::AdvanceResult r = sim.advance(billiard::kAllEvents, duration / 4);
    collisions += static_cast<double>(r.collisions);
    std::printf(" %10.0f", static_cast<double>(r.collisions) / (duration / 4) / static_cast<double>(n));
    if (r.stuck) std::fprintf(stderr, "warning: %s\n", r.stuck_reason.c_str());
  }
  if (const auto problem = sim.validate()) std::fprintf(stderr, "validation failed: %s\n", problem->c_str());
  std::printf(" %14.0f %12.0f\n", collisions / (now_seconds() - start), collisions);
  std::fflush(stdout);
}

std::vector<double> parse_list(const std::string& text) {
  std::vector<double> values;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) values.push_back(std::stod(item));
  return values;
}
std::vector<std::string> parse_words(const std::string& text) {
  std::vector<std::string> values;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) values.push_back(item);
  return values;
}

struct Row {
  std::string engine, container;
  long n;
  double density;
  int gravity;
  double rate;          // median collisions per second
  double crossings;     // cell crossings per collision
  double stale;         // stale queue entries per collision
  double bytes_per_disc;
  double setup_seconds;
};

// Square lattice of n points with spacing `spacing`, centred on the origin, keeping only points
// that `inside` accepts (for the table); returns at most n points.
billiard::Coordinates lattice(long n, double spacing, const Vector& origin, long per_row) {
  billiard::Coordinates points(n, 2);
  for (long k = 0; k < n; ++k) {
    points(k, 0) = origin.x() + (0.5 + static_cast<double>(k % per_row)) * spacing;
    points(k, 1) = origin.y() + (0.5 + static_cast<double>(k / per_row)) * spacing;
  }
  return points;
}

// --prefetch: Settings::prefetch for every system (default automatic).
billiard::Prefetch prefetch_mode = billiard::Prefetch::Automatic;

billiard::Simulation make_system(const std::string& container, long n, double density, bool gravity,
                                 double cell, std::mt19937_64& rng) {
  const double area = static_cast<double>(n) * M_PI / density;  // radius 1
  std::optional<billiard::Container> shape;
  billiard::Coordinates positions;
  // Curved containers: a square lattice clipped to the points whose discs fit (clear of the walls
  // by 1e-7), the spacing shrunk until n fit.
  std::function<bool(const Vector&)> fits;
  double reach = 0;         // the lattice covers [-reach, reach]^2
  double fitting_area = 0;  // roughly where centres fit: the first spacing tried fills it
  if (container == "table") {
    const double radius = std::sqrt(area / M_PI);
    shape = billiard::circular_table(radius);
    fits = [radius](const Vector& p) { return p.norm() <= radius - 1.0000001; };
    reach = radius;
    fitting_area = M_PI * (radius - 1) * (radius - 1);
  } else if (container == "stadium") {
    // Straight sides as long as the diameter: area = (pi + 4) R^2.
    const double radius = std::sqrt(area / (M_PI + 4));
    shape = billiard::stadium(Vector(0, 0), radius, 2 * radius);
    fits = [radius](const Vector& p) {
      const Vector nearest_centre(std::clamp(p.x(), -radius, radius), 0.0);
      return (p - nearest_centre).norm() <= radius - 1.0000001;
    };
    reach = 2 * radius;
    fitting_area = area;
  } else if (container == "sinai") {
    // A square of side s with an obstacle of radius s / 4 in the middle: area = (1 - pi / 16) s^2.
    const double side = std::sqrt(area / (1 - M_PI / 16));
    shape = billiard::sinai_billiard(Vector(-side / 2, -side / 2), Vector(side / 2, side / 2), side / 4);
    fits = [side](const Vector& p) {
      return p.cwiseAbs().maxCoeff() <= side / 2 - 1.0000001 && p.norm() >= side / 4 + 1.0000001;
    };
    reach = side / 2;
    fitting_area = area;
  }
  if (fits) {
    double spacing = std::sqrt(fitting_area / static_cast<double>(n));
    std::vector<Vector> points;
    while (true) {
      points.clear();
      const long half = static_cast<long>(std::ceil(reach / spacing)) + 1;
      for (long iy = -half; iy <= half; ++iy) {
        for (long ix = -half; ix <= half; ++ix) {
          const Vector p((static_cast<double>(ix) + 0.5) * spacing, (static_cast<double>(iy) + 0.5) * spacing);
          if (fits(p)) points.push_back(p);
        }
      }
      if (static_cast<long>(points.size()) >= n || spacing < 2) break;  // found, or no room at all
      spacing *= 0.995;
    }
    if (spacing < 2) {
      throw std::runtime_error("N = " + std::to_string(n) + " discs of radius 1 do not fit the " + container +
                             " at area fraction " + (std::ostringstream() << density).str() + " (lattice start); use a lower --density or a larger --n");
    }
    std::shuffle(points.begin(), points.end(), rng);
    positions.resize(n, 2);
    for (long k = 0; k < n; ++k) positions.row(k) = points[k];
  } else {
    const double side = std::sqrt(area);
    const long per_row = static_cast<long>(std::ceil(std::sqrt(static_cast<double>(n))));
    const double spacing = side / static_cast<double>(per_row);
    if (spacing < 2.0000001) {
      throw std::runtime_error("N = " + std::to_string(n) + " discs of radius 1 do not fit the " + container +
                             " at area fraction " + (std::ostringstream() << density).str() + " (lattice start); use a lower --density or a larger --n");
    }
    if (container == "periodic") {
      shape = billiard::periodic_box(side, side);
    } else {
      shape = billiard::box(Vector(0, 0), Vector(side, side));
    }
    positions = lattice(n, spacing, Vector(0, 0), per_row);
  }
  std::normal_distribution<double> normal(0.0, 1.0);
  billiard::Velocities velocities(n, 2);
  for (long k = 0; k < n; ++k) velocities.row(k) << normal(rng), normal(rng);
  billiard::Settings settings;
  if (gravity) settings.gravity = Vector(0, -0.1);  // weak: a fall of 10 radii gains a speed ~1.4
  if (cell > 0) settings.cell_size = cell;
  settings.prefetch = prefetch_mode;
  billiard::Simulation sim(*shape, settings);
  sim.add_discs(positions, velocities, 1.0, 1.0);
  return sim;
}

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const std::size_t m = values.size() / 2;
  return values.size() % 2 ? values[m] : 0.5 * (values[m - 1] + values[m]);
}

}  // namespace

// Latency (ns) of dependent random cache-line reads and rate (lines/s) of independent ones, in
// an array of `megabytes` MB. The dependent chase follows a random cycle through every line, so
// neither the hardware prefetcher nor the caches (beyond the array's size) can help.
void memory_probe(double megabytes) {
  const std::size_t lines = std::max<std::size_t>(static_cast<std::size_t>(megabytes * (1 << 20) / 64), 2);
  struct alignas(64) Line {
    std::uint64_t next;
    std::uint64_t pad[7];
  };
  billiard::BigVector<Line> memory(lines);
  std::vector<std::uint32_t> order(lines);
  for (std::size_t i = 0; i < lines; ++i) order[i] = static_cast<std::uint32_t>(i);
  std::mt19937_64 rng(7);
  std::shuffle(order.begin(), order.end(), rng);
  for (std::size_t i = 0; i < lines; ++i) memory[order[i]].next = order[(i + 1) % lines];
  const std::size_t steps = 20000000;
  std::uint64_t at = order[0];
  double t0 = now_seconds();
  for (std::size_t k = 0; k < steps; ++k) at = memory[at].next;
  const double latency = (now_seconds() - t0) / static_cast<double>(steps);
  std::uint64_t x = 88172645463325252ull, sum = 0;
  t0 = now_seconds();
  for (std::size_t k = 0; k < steps; ++k) {
    x ^= x << 13;  // xorshift: the next address does not depend on the data read
    x ^= x >> 7;
    x ^= x << 17;
    sum += memory[x % lines].next;
  }
  const double rate = static_cast<double>(steps) / (now_seconds() - t0);
  std::printf("%10g %14.1f %18.1f%s\n", megabytes, latency * 1e9, rate * 1e-6, (at + sum) == 1 ? " " : "");
  std::fflush(stdout);
}

int run(int argc, char** argv) {
  std::vector<double> ns = {100, 1000, 10000, 100000, 1000000};
  std::vector<double> densities = {0.1, 0.5};
  std::vector<std::string> containers = {"box", "table"};
  std::vector<double> gravities = {0, 1};
  std::vector<double> course_ns = {100, 1000};
  int repeats = 5;
  double events = 1e6;
  double warmup = 2;  // collisions per disc before timing
  double cell = 0;
  std::string json;
  std::vector<double> memory_sizes;
  std::vector<double> granular;
  double settle_time = 200;
  for (int k = 1; k < argc; ++k) {
    const std::string arg = argv[k];
    auto value = [&]() -> std::string {
      if (k + 1 >= argc) {
        std::cerr << "billiard_bench: " << arg << " needs a value (--help lists the options)\n";
        std::exit(2);
      }
      return argv[++k];
    };
    try {
      if (arg == "--n") ns = parse_list(value());
      else if (arg == "--density") densities = parse_list(value());
      else if (arg == "--containers") containers = parse_words(value());
      else if (arg == "--gravity") gravities = parse_list(value());
      else if (arg == "--course-n") course_ns = parse_list(value());
      else if (arg == "--repeats") repeats = std::stoi(value());
      else if (arg == "--events") events = std::stod(value());
      else if (arg == "--warmup") warmup = std::stod(value());
      else if (arg == "--cell") cell = std::stod(value());
      else if (arg == "--prefetch") {
        const std::string mode = value();
        if (mode == "auto") prefetch_mode = billiard::Prefetch::Automatic;
        else if (mode == "on") prefetch_mode = billiard::Prefetch::On;
        else if (mode == "off") prefetch_mode = billiard::Prefetch::Off;
        else {
          std::cerr << "billiard_bench: --prefetch takes auto, on or off, got '" << mode << "'\n";
          return 2;
        }
      }
      else if (arg == "--json") json = value();
      else if (arg == "--wall") use_wall_clock = true;
      else if (arg == "--memory") memory_sizes = parse_list(value());
      else if (arg == "--granular") granular = parse_list(value());
      else if (arg == "--settle-time") settle_time = std::stod(value());
      else if (arg != "--help") {
        std::cerr << "billiard_bench: unknown option '" << arg << "' (--help lists the options)\n";
        return 2;
      } else {
        std::cout << "usage: billiard_bench [--n LIST] [--density LIST] [--containers box,table,periodic,stadium,sinai]\n"
                     "                      [--gravity 0,1] [--repeats R] [--events E] [--warmup W]\n"
                     "                      [--course-n LIST] [--cell SIZE] [--prefetch auto|on|off]\n"
                     "                      [--json FILE] [--wall]\n"
                     "       billiard_bench --granular LIST_OF_RESTITUTIONS [--n LIST] [--containers box,table]\n"
                     "                      [--settle-time T]\n"
                     "       billiard_bench --memory LIST_OF_MEGABYTES\n";
        return 0;
      }
    } catch (const std::exception&) {  // std::stod / std::stoi: not a number
      std::cerr << "billiard_bench: " << arg << " takes numbers (a comma-separated list where it says LIST), got '"
                << argv[k] << "'\n";
      return 2;
    }
  }
  for (const std::string& container : containers) {
    if (container != "box" && container != "table" && container != "periodic" && container != "stadium" && container != "sinai") {
      std::cerr << "billiard_bench: --containers takes box, table, periodic, stadium and sinai, got '" << container << "'\n";
      return 2;
    }
  }
  // Sizes the systems can be built with: at least one disc (two for the course's table), no
  // more than memory allows, area fractions a random start can reach.
  auto whole_numbers_within = [](const std::vector<double>& values, double lowest, double highest) {
    return std::all_of(values.begin(), values.end(),
                       [&](double v) { return v >= lowest && v <= highest && v == std::floor(v); });
  };
  if (!whole_numbers_within(ns, 1, 1e8) || !whole_numbers_within(course_ns, 2, 1e5)) {
    std::cerr << "billiard_bench: --n takes whole numbers from 1 to 1e8 and --course-n from 2 to 1e5\n";
    return 2;
  }
  if (!std::all_of(densities.begin(), densities.end(), [](double d) { return d > 0 && d <= 0.7; })) {
    std::cerr << "billiard_bench: --density takes area fractions above 0 and at most 0.7\n";
    return 2;
  }
  if (repeats < 1 || !(events >= 1) || !(warmup >= 0)) {
    std::cerr << "billiard_bench: --repeats and --events must be at least 1, --warmup at least 0\n";
    return 2;
  }
  if (!memory_sizes.empty()) {
    for (double megabytes : memory_sizes) {
      if (!(megabytes > 0 && megabytes <= 65536)) {
        std::cerr << "billiard_bench: --memory sizes must be between 0 and 65536 MB, got " << megabytes << "\n";
        return 2;
      }
    }
    std::printf("%10s %14s %18s\n", "array MB", "latency ns", "random lines M/s");
    for (double megabytes : memory_sizes) memory_probe(megabytes);
    return 0;
  }
  if (!granular.empty()) {
    for (double e : granular) {
      if (!(e >= 0 && e <= 1)) {
        std::cerr << "billiard_bench: --granular takes restitutions in [0, 1], got " << e << "\n";
        return 2;
      }
    }
    if (!(settle_time > 0 && settle_time < 1e6)) {
      std::cerr << "billiard_bench: --settle-time must be positive (and below 1e6), got " << settle_time << "\n";
      return 2;
    }
    std::printf("granular settling to t = %g, g = (0, -1): collisions per disc per time unit by quarter\n",
                settle_time);
    std::printf("%-9s %9s %11s %10s %10s %10s %10s %14s %12s\n", "container", "N", "restitution", "1st", "2nd",
                "3rd", "4th", "collisions/s", "collisions");
    for (const std::string& container : containers) {
      if (container != "box" && container != "table") continue;  // (periodic: no floor)
      for (double nd : ns) {
        for (double e : granular) granular_settling(container, static_cast<long>(nd), e, settle_time);
      }
    }
    return 0;
  }
  std::mt19937_64 rng(12345);
  std::vector<Row> rows;
  std::printf("%-8s %-9s %9s %7s %4s %14s %10s %10s %10s %8s\n", "engine", "container", "N", "eta", "g",
              "collisions/s", "cross/coll", "stale/coll", "bytes/disc", "setup s");
  auto print = [](const Row& r) {
    std::printf("%-8s %-9s %9ld %7.3f %4d %14.0f %10.3f %10.3f %10.0f %8.2f\n", r.engine.c_str(), r.container.c_str(), r.n,
                r.density, r.gravity, r.rate, r.crossings, r.stale, r.bytes_per_disc, r.setup_seconds);
    std::fflush(stdout);
  };
  for (double g : gravities) {
    // For each N, the timed runs of every container and density take turns (run r of each, then
    // run r + 1), so that a slow minute of a shared machine hits all the rows alike instead of
    // one of them: their ratios are fair.
    for (double nd : ns) {
      const long n = static_cast<long>(nd);
      struct Timed {
        std::string container;
        double density;
        billiard::Simulation sim;
        double setup;
        std::vector<double> rates;
        double crossings = 0, collisions = 0, stale = 0;
      };
      std::vector<Timed> systems;
      for (const std::string& container : containers) {
        // A periodic box has no floor: under gravity the speeds grow without bound while the
        // collision rate does not (all discs fall alike), so the run would time only crossings.
        if (container == "periodic" && g != 0) continue;
        for (double density : densities) {
          const auto t0 = Clock::now();
          billiard::Simulation sim = make_system(container, n, density, g != 0, cell, rng);
          sim.advance(static_cast<std::int64_t>(warmup * static_cast<double>(n)));
          systems.push_back({container, density, std::move(sim), std::chrono::duration<double>(Clock::now() - t0).count(), {}});
        }
      }
      for (int r = 0; r < repeats; ++r) {
        for (Timed& t : systems) {
          const double start = now_seconds();
          const billiard::AdvanceResult result = t.sim.advance(static_cast<std::int64_t>(events));
          const double seconds = now_seconds() - start;
          t.rates.push_back(static_cast<double>(result.collisions) / seconds);
          t.crossings += static_cast<double>(result.cell_crossings);
          t.collisions += static_cast<double>(result.collisions);
          t.stale += static_cast<double>(result.stale_events);
          if (result.stuck) std::fprintf(stderr, "warning: run stuck\n");
        }
      }
      for (Timed& t : systems) {
        if (const auto problem = t.sim.validate()) std::fprintf(stderr, "validation failed: %s\n", problem->c_str());
        Row row{"engine", t.container, n, t.density, g != 0 ? 1 : 0, median(t.rates),
                t.crossings / std::max(t.collisions, 1.0), t.stale / std::max(t.collisions, 1.0),
                t.sim.memory_bytes() / static_cast<double>(n), t.setup};
        rows.push_back(row);
        print(row);
      }
    }
  }
#ifdef BILLIARD_BENCH_COURSE
  // The course's reference propagate: all pairs every event, equal discs in the circular table.
  for (double nd : course_ns) {
    for (double density : densities) {
      const int n = static_cast<int>(nd);
      const double table = std::sqrt(n / density);  // radius 1 discs, area fraction n / R^2
      billiard::Simulation sim = make_system("table", n, density, false, 0, rng);
      const billiard::State s = sim.current_state();
      billiard::Coordinates r = s.positions;
      billiard::Velocities v = s.velocities;
      const int count = std::max(10, static_cast<int>(2e7 / (nd * nd)));
      std::vector<double> rates;
      for (int rep = 0; rep < repeats; ++rep) {
        const double start = now_seconds();
        for (int k = 0; k < count; ++k) billiard::propagate(table, 1.0, n, r, v);
        rates.push_back(count / (now_seconds() - start));
      }
      Row row{"course", "table", static_cast<long>(n), density, 0, median(rates), 0, 0, 0, 0};
      rows.push_back(row);
      print(row);
    }
  }
#endif
  if (!json.empty()) {
    std::ofstream out(json);
    out << "[\n";
    for (std::size_t k = 0; k < rows.size(); ++k) {
      const Row& r = rows[k];
      out << "  {\"engine\": \"" << r.engine << "\", \"container\": \"" << r.container << "\", \"n\": " << r.n
          << ", \"density\": " << r.density << ", \"gravity\": " << r.gravity << ", \"collisions_per_second\": " << r.rate
          << ", \"crossings_per_collision\": " << r.crossings << ", \"stale_per_collision\": " << r.stale << ", \"bytes_per_disc\": " << r.bytes_per_disc
          << ", \"repeats\": " << repeats << ", \"events\": " << events << "}" << (k + 1 < rows.size() ? "," : "") << "\n";
    }
    out << "]\n";
  }
  return 0;
}

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& error) {  // a system that cannot be built: one line, exit 2
    std::cerr << "billiard_bench: " << error.what() << "\n";
    return 2;
  }
}

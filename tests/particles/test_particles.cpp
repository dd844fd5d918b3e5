// Tests of the `particles` command: against the independent implementation (reference.cpp) on
// random files, hand-computed cases, the examples, and every kind of malformed file.
#include "reference.hpp"

#include "cli/cli_runner.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using particles_reference::Box;
using particles_reference::Particle;

const fs::path& folder() {
  static const fs::path path = [] {
    const fs::path p = fs::temp_directory_path() / ("particles_tests_" + std::to_string(::getpid()));
    fs::create_directories(p);
    return p;
  }();
  return path;
}

cli::Run particles(const std::vector<std::string>& arguments) {
  return cli::run_program(PARTICLES_EXE, arguments, folder(), folder() / "log");
}

fs::path write(const std::string& name, const std::string& content) {
  const fs::path file = folder() / name;
  std::ofstream(file, std::ios::binary) << content;
  return file;
}

std::string end_text(double end) {
  char text[40];
  std::snprintf(text, sizeof text, "%.17g", end);
  return text;
}

// Runs the command and the reference on `box` and expects the same output, byte for byte.
void expect_same(const Box& box, double end, bool physical, const std::string& what) {
  const fs::path file = write("random.txt", particles_reference::file_text(box));
  std::vector<std::string> arguments{file.string(), end_text(end)};
  if (physical) arguments.insert(arguments.begin(), "--physical");
  const cli::Run run = particles(arguments);
  ASSERT_EQ(run.status, 0) << what << ": " << run.err;
  const std::string expected = particles_reference::run(box, end, physical).output;
  EXPECT_EQ(run.out, expected) << what << ", END_TIME " << end_text(end) << (physical ? " --physical" : "") << "\n"
                               << particles_reference::file_text(box);
}

// N discs placed at random, clear of each other and the walls by 1% of the radius (so no two
// start touching), velocities uniform in [-1, 1]^2.
Box random_box(std::mt19937_64& rng, int n, double area_fraction) {
  Box box;
  box.radius = 1;
  const double area = n * M_PI / area_fraction;
  std::uniform_real_distribution<double> aspect(0.5, 2.0);
  const double a = aspect(rng);
  box.lx = std::max(2.1, std::sqrt(area * a));
  box.ly = std::max(2.1, area / box.lx);
  std::uniform_real_distribution<double> x(1.01, box.lx - 1.01), y(1.01, box.ly - 1.01), speed(-1, 1);
  while (static_cast<int>(box.particles.size()) < n) {
    Particle p{x(rng), y(rng), speed(rng), speed(rng)};
    bool clear = true;
    for (const Particle& q : box.particles) clear = clear && std::hypot(p.x - q.x, p.y - q.y) > 2.02;
    if (clear) box.particles.push_back(p);
  }
  return box;
}

// END_TIME halfway between the reference's collisions number k and k + 1: no collision comes
// close to it, so both codes process the same ones.
double end_after(const Box& box, long k, bool physical) {
  const auto times = particles_reference::run(box, HUGE_VAL, physical, k + 1).event_times;
  return times.size() > static_cast<std::size_t>(k) ? 0.5 * (times[k - 1] + times[k]) : 1.0;
}

TEST(Compare, OneParticleWallsOnly) {
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> unit(0, 1);
  for (int c = 0; c < 60; ++c) {
    Box box;
    box.lx = 2 + 48 * unit(rng);
    box.ly = 2 + 48 * unit(rng);
    box.radius = 0.05 + 0.9 * unit(rng);
    const double r = box.radius;
    box.particles.push_back({r + (box.lx - 2 * r) * unit(rng), r + (box.ly - 2 * r) * unit(rng), 10 * unit(rng) - 5, 10 * unit(rng) - 5});
    // A single particle is not chaotic: its rounding errors only add up, so long runs compare.
    expect_same(box, 50 * unit(rng), false, "one particle, case " + std::to_string(c));
    if (HasFailure()) return;
  }
}

TEST(Compare, HeadOnPairsFarFromWalls) {
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<double> unit(0, 1);
  for (int c = 0; c < 40; ++c) {
    Box box;
    box.radius = 0.5 + unit(rng);
    box.lx = box.ly = 1000;
    const double angle = 2 * M_PI * unit(rng), gap = 2 * box.radius + 20 * unit(rng);
    const double cx = std::cos(angle), cy = std::sin(angle);
    const double s1 = 0.5 + 2 * unit(rng), s2 = -0.5 - 2 * unit(rng);  // along the line: head-on
    box.particles.push_back({500, 500, s1 * cx, s1 * cy});
    box.particles.push_back({500 + gap * cx, 500 + gap * cy, s2 * cx, s2 * cy});
    const double meet = (gap - 2 * box.radius) / (s1 - s2);
    const double end = meet * (c % 2 == 0 ? 2.5 * unit(rng) + 1.01 : 0.98 * unit(rng));  // after, or before it
    expect_same(box, end, false, "head-on pair, case " + std::to_string(c));
    // Head-on, the physical rule is the same rule.
    expect_same(box, end, true, "head-on pair --physical, case " + std::to_string(c));
    if (HasFailure()) return;
  }
}

// Two correct codes that round differently drift apart exponentially with the number of
// collisions (the discs are chaotic), so END_TIME is chosen after about one collision per
// particle (and halfway between two collisions): then the 6-decimal outputs agree.
TEST(Compare, ManyParticlesMixed) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> unit(0, 1);
  for (int c = 0; c < 100; ++c) {
    const int n = c < 2 ? 1000 : c < 10 ? 100 + static_cast<int>(200 * unit(rng)) : 2 + static_cast<int>(60 * unit(rng));
    const Box box = random_box(rng, n, 0.05 + 0.25 * unit(rng));
    const bool physical = c % 3 == 0;
    const double end = end_after(box, std::max(2, n), physical);
    expect_same(box, end, physical, "N = " + std::to_string(n) + ", case " + std::to_string(c));
    if (HasFailure()) return;
  }
}

TEST(Hand, ParticleBouncingBetweenTwoWalls) {
  // x: 5 -> 9 (t = 2, wall), -> 1 (t = 6, wall), -> 9 (t = 10, wall), -> 7 at t = 11.
  const fs::path file = write("walls.txt", "1\n1\n10 10\n5 5 2 0\n");
  const cli::Run run = particles({file.string(), "11"});
  EXPECT_EQ(run.status, 0) << run.err;
  EXPECT_EQ(run.out, "7.000000, 5.000000, 3, 0\n");
}

TEST(Hand, HeadOnPairExchangesVelocities) {
  // Centres 10 apart closing at 2, radius 1: contact at t = 4 (x = 9 and 11), then they swap.
  const fs::path file = write("pair.txt", "2\n1\n20 10\n5 5 1 0\n15 5 -1 0\n");
  for (const char* rule : {"", "--physical"}) {
    std::vector<std::string> arguments{file.string(), "5"};
    if (*rule) arguments.insert(arguments.begin(), rule);
    const cli::Run run = particles(arguments);
    EXPECT_EQ(run.status, 0) << run.err;
    EXPECT_EQ(run.out, "8.000000, 5.000000, 0, 1\n12.000000, 5.000000, 0, 1\n") << rule;
  }
}

TEST(Hand, CornerHitCountsTwoWallCollisions) {
  // The disc meets x = 0 and y = 0 together at t = 0.5: the exercise's array holds one wall
  // entry per particle, so the two walls come one after the other at the same instant: 2.
  const fs::path file = write("corner.txt", "1\n0.5\n10 10\n1 1 -1 -1\n");
  const cli::Run run = particles({file.string(), "1"});
  EXPECT_EQ(run.status, 0) << run.err;
  EXPECT_EQ(run.out, "1.000000, 1.000000, 2, 0\n");
  Box box;
  box.radius = 0.5;
  box.particles.push_back({1, 1, -1, -1});
  EXPECT_EQ(particles_reference::run(box, 1).output, run.out);
}

TEST(Hand, PhysicalChangesOnlyObliqueCollisions) {
  // Particle 1 at rest is hit off-centre: the rules differ. (Head-on: see HeadOnPairs above.)
  const fs::path file = write("oblique.txt", "2\n1\n20 10\n5 5 1 0.5\n7 6.5 0 0\n");
  const cli::Run exchange = particles({file.string(), "3"});
  const cli::Run physical = particles({"--physical", file.string(), "3"});
  EXPECT_EQ(exchange.status, 0);
  EXPECT_EQ(physical.status, 0);
  EXPECT_NE(exchange.out, physical.out);
  Box box;
  box.lx = 20;
  box.particles = {{5, 5, 1, 0.5}, {7, 6.5, 0, 0}};
  EXPECT_EQ(exchange.out, particles_reference::run(box, 3, false).output);
  EXPECT_EQ(physical.out, particles_reference::run(box, 3, true).output);
  // Exchange: particle 0 stops at the contact, particle 1 leaves with (1, 0.5).
  EXPECT_NE(exchange.out.find(", 0, 1\n"), std::string::npos);
}

TEST(Examples, MatchTheirExpectedOutputs) {
  const fs::path examples = fs::path(PARTICLES_SOURCE_DIR) / "examples";
  std::ifstream cases(examples / "cases.txt");
  int count = 0;
  for (std::string line; std::getline(cases, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream in(line);
    std::string name, end, option;
    in >> name >> end >> option;
    std::vector<std::string> arguments{(examples / (name + ".txt")).string(), end};
    if (!option.empty()) arguments.insert(arguments.begin(), option);
    const cli::Run run = particles(arguments);
    EXPECT_EQ(run.status, 0) << name << ": " << run.err;
    const std::string expected = name + (option == "--physical" ? "_physical" : "") + ".expected";
    EXPECT_EQ(run.out, cli::slurp(examples / expected)) << name << " " << option;
    ++count;
  }
  EXPECT_GE(count, 2);
}

struct Malformed {
  const char* content;
  int line;
  const char* says;
};

TEST(Malformed, EveryKindExitsTwoWithItsLine) {
  const Malformed cases[] = {
      {"", 1, "empty"},
      {"\n\n", 1, "empty"},
      {"-3\n1\n10 10\n", 1, "negative"},
      {"2.5\n1\n10 10\n", 1, "whole number"},
      {"two\n1\n10 10\n", 1, "whole number"},
      {"1e3\n1\n10 10\n", 1, "whole number"},
      {"99999999999999999999\n1\n10 10\n", 1, "too large"},
      {"1 2\n1\n10 10\n5 5 0 0\n", 1, "expected 1 number"},
      {"1\n", 2, "radius"},
      {"1\n0\n10 10\n5 5 0 0\n", 2, "positive"},
      {"1\n-1\n10 10\n5 5 0 0\n", 2, "positive"},
      {"1\nnan\n10 10\n5 5 0 0\n", 2, "decimal number"},
      {"1\ninf\n10 10\n5 5 0 0\n", 2, "decimal number"},
      {"1\n1e-9\n10 10\n5 5 0 0\n", 2, "too small"},
      {"1\n6\n10 10\n5 5 0 0\n", 2, "too large"},
      {"1\n1\n", 3, "box lengths"},
      {"1\n1\n10\n5 5 0 0\n", 3, "expected 2 numbers"},
      {"1\n1\n10 10 10\n5 5 0 0\n", 3, "expected 2 numbers"},
      {"1\n1\n0 10\n5 5 0 0\n", 3, "Lx must be positive"},
      {"1\n1\n10 -1\n5 5 0 0\n", 3, "Ly must be positive"},
      {"1\n1\n10 1e400\n5 5 0 0\n", 3, "1e50"},
      {"1\n1\n10 10\n", 4, "ends after 0 particle"},
      {"3\n1\n10 10\n2 2 0 0\n5 5 0 0\n", 6, "ends after 2 particle"},
      {"1\n1\n10 10\n5 5 0 0\n7 7 0 0\n", 5, "too many"},
      {"1\n1\n10 10\n\n5 5 0 0\n", 4, "empty line"},
      {"1\n1\n10 10\n5 5 0\n", 4, "expected 4 numbers"},
      {"1\n1\n10 10\n5 5 0 0 0\n", 4, "expected 4 numbers"},
      {"1\n1\n10 10\n5 5 x 0\n", 4, "u of particle 0"},
      {"1\n1\n10 10\n5 5 0 nan\n", 4, "v of particle 0"},
      {"1\n1\n10 10\n5 5 0 -inf\n", 4, "v of particle 0"},
      {"1\n1\n10 10\n5 5 0 0x10\n", 4, "decimal number"},
      {"1\n1\n10 10\n5,5 5 0 0\n", 4, "x of particle 0"},
      {"1\n1\n10 10\n11 5 0 0\n", 4, "outside the box"},
      {"1\n1\n10 10\n5 -3 0 0\n", 4, "outside the box"},
      {"1\n1\n10 10\n0.5 5 0 0\n", 4, "overlaps a wall"},
      {"1\n1\n10 10\n5 9.5 0 0\n", 4, "overlaps a wall"},
      {"2\n1\n10 10\n3 3 0 0\n4 4 0 0\n", 5, "overlaps particle 0"},
      {"3\n1\n10 10\n2 2 0 0\n5 5 0 0\n6.5 5.5 0 0\n", 6, "overlaps particle 1"},
  };
  for (const Malformed& c : cases) {
    const fs::path file = write("bad.txt", c.content);
    const cli::Run run = particles({file.string(), "1"});
    const std::string where = "bad.txt:" + std::to_string(c.line) + ": ";
    EXPECT_EQ(run.status, 2) << c.content;
    EXPECT_EQ(run.out, "") << c.content;
    EXPECT_NE(run.err.find(where), std::string::npos) << "expected " << where << " in: " << run.err;
    EXPECT_NE(run.err.find(c.says), std::string::npos) << "expected '" << c.says << "' in: " << run.err;
    EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
  }
}

TEST(Malformed, AcceptsCrlfAndTrailingBlankLines) {
  const fs::path file = write("crlf.txt", "2\r\n1\r\n20 10\r\n5 5 1 0\r\n  15\t5 -1 0 \r\n\r\n\n   \n");
  const cli::Run run = particles({file.string(), "5"});
  EXPECT_EQ(run.status, 0) << run.err;
  EXPECT_EQ(run.out, "8.000000, 5.000000, 0, 1\n12.000000, 5.000000, 0, 1\n");
  const fs::path none = write("none.txt", "0\n1\n10 10\n");
  EXPECT_EQ(particles({none.string(), "3"}).status, 0);
}

TEST(Malformed, BadArgumentsExitTwo) {
  const fs::path file = write("ok.txt", "1\n1\n10 10\n5 5 1 0\n");
  const std::vector<std::vector<std::string>> cases = {
      {},          {file.string()},          {file.string(), "-1"},   {file.string(), "nan"}, {file.string(), "inf"},
      {file.string(), "abc"}, {file.string(), "1", "2"}, {"--fast", file.string(), "1"}, {(folder() / "missing.txt").string(), "1"},
      {file.string(), "1e300"}};
  for (const auto& arguments : cases) {
    const cli::Run run = particles(arguments);
    EXPECT_EQ(run.status, 2) << cli::shown(arguments);
    EXPECT_EQ(run.out, "") << cli::shown(arguments);
    EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
  }
  const cli::Run help = particles({"--help"});
  EXPECT_EQ(help.status, 0);
  EXPECT_NE(help.out.find("--physical"), std::string::npos);
  EXPECT_NE(help.out.find("limits"), std::string::npos);
}

TEST(Limits, TooManyCollisionsIsRefused) {
  // Two particles shuttling in a small box: about 2 collisions per time unit each way.
  const fs::path file = write("busy.txt", "2\n1\n10 10\n3 5 100 0\n7 5 -100 0\n");
  const cli::Run run = particles({file.string(), "1e9"});
  EXPECT_EQ(run.status, 2);
  EXPECT_EQ(run.out, "");
  EXPECT_NE(run.err.find("smaller END_TIME"), std::string::npos) << run.err;
  EXPECT_LT(run.seconds, 60);
}

}  // namespace

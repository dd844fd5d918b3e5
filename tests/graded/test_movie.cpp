// Graded tests of task 5, movie(table_radius, circle_radius, n, coordinates, velocities,
// collisions, svg_file): calls propagate `collisions` times and writes an animated SVG (SMIL
// <animate> of cx and cy, linear between collisions).
//
// movie uses propagate by design, so these tests call billiard::propagate themselves (on copies
// of the same inputs) to get the true event times T_k and positions, and then play the
// animation by the SMIL rules (values at keyTimes, linear in between; evenly spaced without
// keyTimes) at the fractions T_k / T_total of its duration. The picture may use any scale, any
// position of the table's centre and a flipped y axis; discs are recognised by where they
// start, so their order in the file does not matter. Inputs come from the test fixtures.
#include "support/failure_pictures.hpp"
#include "support/fixtures.hpp"
#include "support/graded.hpp"
#include "support/student_messages.hpp"
#include "support/svg_reader.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace billiard::testing {
namespace {

// The hint for an animation a browser cannot play: about keyTimes when they are what is wrong.
std::string animation_hint(const std::string& problem) {
  if (problem.find("keyTimes must") != std::string::npos) {
    return "keyTimes are moments as fractions of the whole duration, so they grow from 0 to 1: use the running "
           "total of the collision times, T_k = t_1 + ... + t_k (the sum of what propagate returned so far), "
           "divided by the total T, not each collision's own time t_k";
  }
  return "each disc's <circle> needs one <animate attributeName=\"cx\" values=\"x0;x1;...\" keyTimes=\"0;...;1\" "
         "dur=\"...s\"/> and one for cy";
}

namespace fs = std::filesystem;

constexpr double kInf = std::numeric_limits<double>::infinity();

// Positions shown by the animation must match the true ones within this fraction of the table
// radius (numbers are printed, so we cannot ask for more), and the state movie leaves behind
// must match propagate's within kStateTolerance (the same computation, so only rounding).
constexpr double kPictureTolerance = 1e-3;
constexpr double kStateTolerance = 1e-9;

struct System {
  double R;
  double a;
  int n;
  int collisions;
  std::uint64_t seed;  // for scattered_circles and gaussian_velocities

  Coordinates coordinates() const { return scattered_circles(R, a, n, seed); }
  Velocities velocities() const { return gaussian_velocities(n, seed); }
};

const std::vector<System> kSystems = {{10, 1, 10, 50, 1}, {10, 1, 10, 50, 2}, {4, 0.5, 5, 30, 3}};

std::string call(const System& s) {
  return text("movie(", s.R, ", ", s.a, ", ", s.n, ", coordinates, velocities, ", s.collisions, ", svg_file)");
}

// A failure about the file's text draws the file's lines around `marked` (the lines the message
// is about), not a table.
void show_lines(const std::string& file_text, std::vector<int> marked, std::string heading) {
  set_case_source([file_text, marked = std::move(marked), heading = std::move(heading)] {
    return std::optional<FailingCase>(lines_case(file_text, "the movie's SVG file", marked, heading));
  });
}

// The lines of the first few circles, for a failure about how many there are.
std::vector<int> circle_lines(const std::vector<const SvgCircle*>& circles) {
  std::vector<int> lines;
  for (std::size_t k = 0; k < circles.size() && k < 3; ++k) lines.push_back(circles[k]->line);
  return lines;
}

// The truth: `collisions` calls of propagate on copies of the inputs.
struct Truth {
  std::vector<double> times;             // T_0 = 0, T_1, ..., T_K (time since the start)
  std::vector<Coordinates> positions;    // at T_0, ..., T_K
  std::vector<Velocities> velocities;    // just after T_0, ..., T_K
  double total() const { return times.back(); }
};

Truth truth(const System& s) {
  Coordinates c = s.coordinates();
  Velocities v = s.velocities();
  Truth t;
  t.times.push_back(0);
  t.positions.push_back(c);
  t.velocities.push_back(v);
  for (int k = 0; k < s.collisions; ++k) {
    const Collision collision = propagate(s.R, s.a, s.n, c, v);
    t.times.push_back(t.times.back() + collision.time);
    t.positions.push_back(c);
    t.velocities.push_back(v);
  }
  return t;
}

// Calls movie on the system's inputs (left in c and v). NotImplemented passes on; other
// exceptions are failures, reported here.
bool run_movie(const System& s, Coordinates& c, Velocities& v, const fs::path& file) {
  try {
    movie(s.R, s.a, s.n, c, v, s.collisions, file);
    return true;
  } catch (const NotImplemented&) {
    throw;
  } catch (const std::exception& error) {
    ADD_FAILURE() << explain(text(call(s), " to run ", s.collisions, " collisions and write the movie"),
                             text("it threw \"", error.what(), "\""),
                             "the inputs were valid (no overlaps, moving circles); check the loop that calls "
                             "propagate and the file you open (svg_file)");
    return false;
  }
}

std::optional<SvgDocument> read_movie(const System& s, const fs::path& file) {
  try {
    return read_svg(file);
  } catch (const SvgError& error) {
    std::ifstream in(file, std::ios::binary);
    std::ostringstream file_text;
    file_text << in.rdbuf();
    show_lines(file_text.str(), error.line() ? std::vector<int>{error.line()} : std::vector<int>{},
               "The file as written, where the reader stopped");
    ADD_FAILURE() << explain(text(call(s), " to write a well-formed SVG file: <svg xmlns=\"http://www.w3.org/2000/svg\" "
                                              "...> with a <circle> for the table and one per disc, each with "
                                              "<animate> children, then </svg>"),
                             error.what(),
                             "open the file in a browser or a text editor to see the problem; every tag must be "
                             "closed (<animate ... />, </circle>) and attribute values quoted");
    return std::nullopt;
  }
}

std::optional<FailingCase> movie_case(const System& s, const SvgDocument& picture);

// Runs the movie of system s into a scratch file and reads it back; a failure from here on draws
// the first moment at which the animation leaves the discs' paths.
std::optional<SvgDocument> film(const System& s) {
  ScratchFolder folder;
  const fs::path file = folder / "movie.svg";
  Coordinates c = s.coordinates();
  Velocities v = s.velocities();
  if (!run_movie(s, c, v, file)) return std::nullopt;
  auto picture = read_movie(s, file);
  if (picture) set_case_source([s, picture] { return movie_case(s, *picture); });
  return picture;
}

// The movie as seen in table coordinates.
struct Film {
  const SvgCircle* table = nullptr;
  double k = 1;                             // SVG units per table unit
  double sign = 1;                          // +1: y down as in the file, -1: y flipped
  std::vector<const SvgCircle*> discs;      // discs[i] shows row i
  const SvgDocument* document = nullptr;    // the file they are in
};

// How an animation that breaks the rules is read: as an error for the student, or as a browser
// plays it (it ignores such an animation and shows the attribute), for the picture of a failure.
enum class Reading { strict, as_a_browser_plays_it };

// The value of `attribute` (cx or cy) shown at `fraction` of the animation: its <animate> if it
// has one, else the static attribute.
double shown_value(const SvgCircle& circle, const char* attribute, double fraction, Reading reading) {
  const auto animations = circle.animations_of(attribute);
  const double base = attribute[1] == 'x' ? circle.cx : circle.cy;
  if (animations.empty()) return base;
  try {
    if (animations.size() > 1) {
      throw SvgError(text("line ", circle.line, ": this <circle> has ", animations.size(), " <animate attributeName=\"",
                          attribute, "\"> children; the test expects one that holds all the positions"));
    }
    return sample_animation(*animations.front(), fraction, base);
  } catch (const SvgError&) {
    if (reading == Reading::strict) throw;
    return base;
  }
}

// Position of `disc` at `fraction` in table coordinates; throws SvgError when reading strictly.
std::array<double, 2> shown_position(const Film& film, const SvgCircle& disc, double fraction,
                                     Reading reading = Reading::strict) {
  const auto p = disc.map(shown_value(disc, "cx", fraction, reading), shown_value(disc, "cy", fraction, reading));
  return {(p[0] - film.table->x) / film.k, film.sign * (p[1] - film.table->y) / film.k};
}

// Finds the table (largest circle), the scale, the direction of y and which disc shows which
// row (by the positions at the start of the animation); `worst` receives the largest distance of
// a row from its disc there. Nullopt when the file does not hold n + 1 circles; throws SvgError
// when reading strictly an animation a browser cannot play.
std::optional<Film> match_discs(const SvgDocument& picture, const System& s, const Coordinates& start, Reading reading,
                                double& worst) {
  Film film;
  film.document = &picture;
  const auto circles = picture.rendered_circles();
  for (const SvgCircle* circle : circles) {
    if (!film.table || circle->radius > film.table->radius) film.table = circle;
  }
  if (static_cast<int>(circles.size()) != s.n + 1 || !(film.table->radius > 0) || !std::isfinite(film.table->radius)) {
    return std::nullopt;
  }
  film.k = film.table->radius / s.R;
  std::vector<const SvgCircle*> discs;
  for (const SvgCircle* circle : circles) {
    if (circle != film.table) discs.push_back(circle);
  }
  // For each direction of y, match every row to the nearest disc at the start; keep the
  // direction whose worst match is best.
  worst = kInf;
  for (const double sign : {+1.0, -1.0}) {
    Film trial = film;
    trial.sign = sign;
    trial.discs.assign(static_cast<std::size_t>(s.n), nullptr);
    double trial_worst = 0;
    for (Eigen::Index i = 0; i < start.rows(); ++i) {
      double nearest = kInf;
      for (const SvgCircle* disc : discs) {
        const auto p = shown_position(trial, *disc, 0.0, reading);
        const double error = std::hypot(p[0] - start(i, 0), p[1] - start(i, 1));
        if (error < nearest) {
          nearest = error;
          trial.discs[static_cast<std::size_t>(i)] = disc;
        }
      }
      trial_worst = std::max(trial_worst, nearest);
    }
    if (trial_worst < worst) {
      worst = trial_worst;
      film.sign = trial.sign;
      film.discs = trial.discs;
    }
  }
  return film;
}

// match_discs, reporting what keeps the file from being understood.
std::optional<Film> understand(const SvgDocument& picture, const System& s, const Coordinates& start) {
  double best_error = kInf;
  std::optional<Film> film;
  try {
    film = match_discs(picture, s, start, Reading::strict, best_error);
  } catch (const SvgError& error) {
    show_lines(picture.text, {error.line()}, "The animation a browser cannot play");
    ADD_FAILURE() << explain(text(call(s), " to write <animate> elements a browser can play"), error.what(),
                             animation_hint(error.what()));
    return std::nullopt;
  }
  if (!film) {
    const auto circles = picture.rendered_circles();
    const SvgCircle* table = nullptr;
    for (const SvgCircle* circle : circles) {
      if (!table || circle->radius > table->radius) table = circle;
    }
    show_lines(picture.text, circle_lines(circles), text("The file's first <circle> elements, of ", circles.size()));
    ADD_FAILURE() << explain(text(call(s), " to draw ", s.n + 1, " <circle> elements: the table (the largest, with "
                                                                  "radius table_radius times any scale) and one per disc"),
                             text("the file has ", circles.size(), " <circle> elements",
                                  table ? text(", the largest with radius ", table->radius) : std::string()),
                             "write one <circle> for the table and one for each disc, with <animate> children for "
                             "the discs' cx and cy");
    return std::nullopt;
  }
  if (!(best_error <= kPictureTolerance * s.R)) {
    ADD_FAILURE() << explain(
        text(call(s), ": at the start of the animation (fraction 0 of dur) every disc is at its row of "
                      "coordinates, in the table's frame (centre (", film->table->x, ", ", film->table->y, "), ",
             film->k, " per unit of length)"),
        text("some row has no disc within ", kPictureTolerance * s.R, ": the closest match is ", best_error, " away"),
        "the first value of each cx/cy animation must be the starting position, scaled and shifted like the table: "
        "cx = centre_x + k * x, cy = centre_y + k * y (or centre_y - k * y)");
    return std::nullopt;
  }
  return film;
}

// The picture of a failure: `expected` (the discs where they are, with their velocities) and
// where something else puts the discs that are elsewhere (`shown`), at one moment.
FailingCase positions_case(const System& s, const Coordinates& expected, const Velocities& velocities,
                           const Coordinates& shown, std::string heading, const std::string& elsewhere) {
  FailingCase failing;
  failing.kind = "positions";
  failing.heading = std::move(heading);
  failing.board = table_board(s.R, s.a);
  failing.board.coordinates = expected;
  failing.board.velocities = velocities;
  failing.expected_outcome.coordinates = expected;
  failing.expected_outcome.velocities = velocities;
  failing.your_outcome.coordinates = shown;
  failing.your_outcome.velocities = velocities;
  std::vector<int> off;
  for (int i = 0; i < s.n; ++i) {
    if (!(std::hypot(shown(i, 0) - expected(i, 0), shown(i, 1) - expected(i, 1)) <= kPictureTolerance * s.R)) {
      off.push_back(i);
      failing.expected.ghosts.push_back({i, expected.row(i), velocities.row(i), false});
      if (std::isfinite(shown(i, 0)) && std::isfinite(shown(i, 1))) failing.yours.ghosts.push_back({i, shown.row(i), Vector::Zero(), false});
    }
  }
  std::string listed;
  for (std::size_t k = 0; k < off.size() && k < 8; ++k) listed += text(k ? ", " : "", off[k]);
  if (off.size() > 8) listed += text(" and ", off.size() - 8, " more");
  failing.key = "Numbered circles: where the discs are at that moment, arrows their velocities. Dotted: where "
                "the movie shows the discs that are elsewhere, each joined to its place by a line.";
  failing.expected.label = text("the discs where propagate puts them (numbered)");
  failing.yours.label = off.empty() ? elsewhere + ": every disc where it should be"
                                    : text(elsewhere, ": disc", off.size() > 1 ? "s " : " ", listed, " elsewhere (dotted)");
  return failing;
}

// The picture of a failing test of a movie file: the first moment (a collision, or half way
// between two) at which the animation, as a browser plays it, shows a disc visibly away from its
// place (by a quarter of its radius), else the first at which it shows one away at all.
std::optional<FailingCase> movie_case(const System& s, const SvgDocument& picture) {
  const Truth t = truth(s);
  double worst = kInf;
  const auto film = match_discs(picture, s, t.positions.front(), Reading::as_a_browser_plays_it, worst);
  if (!film) return std::nullopt;
  struct Moment {
    double time;
    Coordinates expected;
    const Velocities* velocities;
    std::string what;
  };
  std::vector<Moment> moments;
  for (std::size_t k = 0; k < t.times.size(); ++k) {
    moments.push_back({t.times[k], t.positions[k], &t.velocities[k],
                       k == 0 ? std::string("at the start") : text("at collision ", k)});
    if (k + 1 < t.times.size()) {
      const double dt = (t.times[k + 1] - t.times[k]) / 2;
      moments.push_back({t.times[k] + dt, t.positions[k] + dt * t.velocities[k], &t.velocities[k],
                         text("half way between collisions ", k, " and ", k + 1)});
    }
  }
  const double fraction_of = t.total() > 0 ? 1 / t.total() : 0.0;
  for (const bool visibly : {true, false}) {
    const double away = visibly ? std::max(0.25 * s.a, kPictureTolerance * s.R) : kPictureTolerance * s.R;
    for (const Moment& moment : moments) {
      Coordinates shown(s.n, 2);
      for (int i = 0; i < s.n; ++i) {
        const auto p = shown_position(*film, *film->discs[static_cast<std::size_t>(i)], moment.time * fraction_of,
                                      Reading::as_a_browser_plays_it);
        shown.row(i) << p[0], p[1];
      }
      if (!((shown - moment.expected).rowwise().norm().maxCoeff() > away)) continue;
      return positions_case(s, moment.expected, *moment.velocities, shown,
                            text("Time ", moment.time, " of ", t.total(), " (", moment.what, ", fraction ",
                                 moment.time * fraction_of, " of the animation): the first moment the animation "
                                 "shows discs ", visibly ? "visibly " : "", "away from their paths"),
                            "the animation, as a browser plays it");
    }
  }
  return std::nullopt;
}

// Checks the positions shown at `fractions` against `expected` (one Coordinates per fraction, and
// the velocities there for the picture); `moment(j)` describes moment j for the message. Reports
// the first moment at which a disc is off (its farthest disc there), which is where the mistake
// shows first, and draws that same moment.
template <typename Describe>
void expect_positions(const System& s, const Film& film, const std::vector<double>& fractions,
                      const std::vector<Coordinates>& expected, const std::vector<Velocities>& velocities,
                      Describe moment, const std::string& hint) {
  struct Off {
    std::size_t j = 0;
    Eigen::Index i = 0;
    double error = 0;
    std::array<double, 2> shown{0, 0};
  };
  std::optional<Off> first, farthest;
  Coordinates first_shown;
  try {
    for (std::size_t j = 0; j < fractions.size(); ++j) {
      Coordinates shown(s.n, 2);
      std::optional<Off> here;
      for (Eigen::Index i = 0; i < s.n; ++i) {
        const auto p = shown_position(film, *film.discs[static_cast<std::size_t>(i)], fractions[j]);
        shown.row(i) << p[0], p[1];
        double error = std::hypot(p[0] - expected[j](i, 0), p[1] - expected[j](i, 1));
        if (std::isnan(error)) error = kInf;
        if (!(error <= kPictureTolerance * s.R) && (!here || error > here->error)) here = Off{j, i, error, p};
      }
      if (here && (!farthest || here->error > farthest->error)) farthest = here;
      if (here && !first) {
        first = here;
        first_shown = shown;
      }
    }
  } catch (const SvgError& error) {
    show_lines(film.document->text, {error.line()}, "The animation a browser cannot play");
    ADD_FAILURE() << explain(text(call(s), " to write <animate> elements a browser can play"), error.what(),
                             animation_hint(error.what()));
    return;
  }
  if (!first) return;
  const std::size_t j = first->j;
  set_case_source([s, expected = expected[j], velocities = velocities[j], first_shown,
                   heading = text("The moment the message reports, ", moment(j), ", fraction ", fractions[j],
                                  " of the animation: the first at which it shows a disc away from its place")] {
    return positions_case(s, expected, velocities, first_shown, heading, "the animation");
  });
  const std::string later = farthest->j != j ? text("; later, up to ", farthest->error, " away ", moment(farthest->j))
                                             : std::string();
  ADD_FAILURE() << explain(
      text(call(s), ": ", moment(j), ", i.e. at fraction ", fractions[j], " of the animation's duration, disc ",
           first->i, " (row ", first->i, " of coordinates) should be shown at ", row(expected[j], first->i),
           " (within ", kPictureTolerance * s.R, ")"),
      text("the animation shows it at (", first->shown[0], ", ", first->shown[1], "), ", first->error, " away (line ",
           film.discs[static_cast<std::size_t>(first->i)]->line, "): the first moment a disc is off", later),
      hint);
}

// --- State -----------------------------------------------------------------------------------

GRADED_TEST(Movie, LeavesTheStateAfterTheCollisions, 3, visible) {
  for (const System& s : kSystems) {
    ScratchFolder folder;
    Coordinates c = s.coordinates();
    Velocities v = s.velocities();
    if (!run_movie(s, c, v, folder / "movie.svg")) return;
    const Truth t = truth(s);
    const double position_error = (c - t.positions.back()).cwiseAbs().maxCoeff();
    const double velocity_error = (v - t.velocities.back()).cwiseAbs().maxCoeff();
    const double speed = t.velocities.back().cwiseAbs().maxCoeff();
    if (position_error > kStateTolerance * s.R || velocity_error > kStateTolerance * speed) {
      set_case_source([&] {
        return positions_case(s, t.positions.back(), t.velocities.back(), c,
                              text("After the call: where ", s.collisions, " calls of propagate leave the discs"),
                              "where your movie left the coordinates");
      });
      ADD_FAILURE() << explain(
          text(call(s), " to leave coordinates and velocities as ", s.collisions,
               " calls of propagate leave them (e.g. circle 0 at ", row(t.positions.back(), 0), " with velocity ",
               row(t.velocities.back(), 0), ")"),
          text("circle 0 was left at ", row(c, 0), " with velocity ", row(v, 0), "; largest differences ",
               position_error, " in position and ", velocity_error, " in velocity"),
          "call propagate(table_radius, circle_radius, n, coordinates, velocities) exactly `collisions` times on "
          "the arrays you were given (they are references), not on copies, and do not move the circles otherwise");
      return;
    }
  }
}

// --- The file --------------------------------------------------------------------------------

GRADED_TEST(Movie, DrawsTheTableAndOneCirclePerDisc, 2, visible) {
  for (const System& s : kSystems) {
    const auto picture = film(s);
    if (!picture) return;
    const auto circles = picture->rendered_circles();
    if (static_cast<int>(circles.size()) != s.n + 1) {
      show_lines(picture->text, circle_lines(circles), text("The file's first <circle> elements, of ", circles.size()));
      ADD_FAILURE() << explain(text(call(s), " to draw ", s.n + 1, " <circle> elements: the table and one per disc"),
                               text("the file has ", circles.size(), " <circle> elements"),
                               "write one <circle> per disc with its <animate> children inside, not one circle per "
                               "frame or per collision");
      return;
    }
  }
}

GRADED_TEST(Movie, EveryDiscAnimatesCxAndCy, 2, visible) {
  for (const System& s : kSystems) {
    const auto picture = film(s);
    if (!picture) return;
    const auto circles = picture->rendered_circles();
    const SvgCircle* table = nullptr;  // the largest circle; every other one is a disc
    for (const SvgCircle* circle : circles) {
      if (!table || circle->radius > table->radius) table = circle;
    }
    if (circles.size() < 2) {
      show_lines(picture->text, circle_lines(circles), text("The file's <circle> elements, ", circles.size()));
      ADD_FAILURE() << explain(text(call(s), " to draw the table and ", s.n, " discs as <circle> elements"),
                               text("the file has ", circles.size(), " <circle> elements"),
                               "write one <circle> for the table and one for each disc");
      return;
    }
    for (const SvgCircle* disc : circles) {
      if (disc == table) continue;
      for (const char* attribute : {"cx", "cy"}) {
        const std::size_t count = disc->animations_of(attribute).size();
        if (count != 1) {
          show_lines(picture->text, {disc->line}, text("A disc's <circle> with ", count, " <animate> of ", attribute));
          ADD_FAILURE() << explain(
              text(call(s), ": every disc's <circle> to contain one <animate attributeName=\"", attribute,
                   "\" .../> with all its positions"),
              text("the <circle> on line ", disc->line, " contains ", count, " of them"),
              "inside each disc's <circle>...</circle>, write <animate attributeName=\"cx\" values=\"...\" "
              "keyTimes=\"...\" dur=\"...\"/> and the same for cy (attribute names are case-sensitive)");
          return;
        }
      }
    }
  }
}

// Discs move at constant velocity between collisions, so linear interpolation (SVG's default)
// is exact; "discrete" jumps, "paced" ignores keyTimes and "spline" accelerates.
GRADED_TEST(Movie, AnimationsInterpolateLinearly, 2, after_due_date) {
  const System s = kSystems.front();
  const auto picture = film(s);
  if (!picture) return;
  int animations = 0;
  for (const SvgCircle* circle : picture->rendered_circles()) {
    for (const char* attribute : {"cx", "cy"}) {
      for (const SvgAnimation* animation : circle->animations_of(attribute)) {
        ++animations;
        if (!animation->calc_mode.empty() && animation->calc_mode != "linear") {
          show_lines(picture->text, {animation->line}, "An <animate> that does not move at constant velocity");
          ADD_FAILURE() << explain(
              text(call(s), " to animate cx and cy with calcMode=\"linear\" (or no calcMode, which means linear)"),
              text("the <animate> on line ", animation->line, " has calcMode=\"", animation->calc_mode, "\""),
              "between collisions a disc moves at constant velocity, which linear interpolation shows exactly; "
              "remove calcMode or write calcMode=\"linear\"");
          return;
        }
      }
    }
  }
  EXPECT_GT(animations, 0) << explain(text(call(s), " to animate the discs with <animate attributeName=\"cx\"> and "
                                                    "\"cy\" inside their <circle> elements"),
                                      "the file has no such <animate> element",
                                      "write <circle ...><animate attributeName=\"cx\" .../><animate "
                                      "attributeName=\"cy\" .../></circle> for each disc");
}

// Whether two animations start together: the same clock value (absent means 0), or the same text
// for anything else (e.g. "click").
bool same_begin(const SvgAnimation& one, const SvgAnimation& other) {
  const double a = one.begin_seconds(), b = other.begin_seconds();
  if (std::isnan(a) || std::isnan(b)) return one.begin == other.begin;
  return std::abs(a - b) <= 1e-9 * std::max(1.0, std::abs(a));
}

GRADED_TEST(Movie, AnimationsShareAPositiveDuration, 2, after_due_date) {
  const System s = kSystems.front();
  const auto picture = film(s);
  if (!picture) return;
  const SvgAnimation* first = nullptr;
  for (const SvgCircle* circle : picture->rendered_circles()) {
    for (const char* attribute : {"cx", "cy"}) {
      for (const SvgAnimation* animation : circle->animations_of(attribute)) {
        const double seconds = animation->dur_seconds();
        if (!(seconds > 0) || !std::isfinite(seconds)) {
          show_lines(picture->text, {animation->line}, "An <animate> without a positive duration");
          ADD_FAILURE() << explain(
              text(call(s), ": every <animate> to have a duration dur=\"...\" of a positive, finite number of "
                            "seconds (e.g. dur=\"12.5s\")"),
              text("the <animate> on line ", animation->line, " has ",
                   animation->dur.empty() ? std::string("no dur") : text("dur=\"", animation->dur, "\"")),
              "write dur=\"<total time of all collisions>s\" (or that time scaled by a constant factor)");
          return;
        }
        if (!first) {
          first = animation;
        } else if (std::abs(seconds - first->dur_seconds()) > 1e-6 * first->dur_seconds() ||
                   !same_begin(*animation, *first)) {
          show_lines(picture->text, {first->line, animation->line}, "Two <animate> elements on different clocks");
          ADD_FAILURE() << explain(
              text(call(s), ": all discs to be animated on one clock: the same dur (and begin) for every <animate>"),
              text("line ", first->line, " has dur=\"", first->dur, "\" begin=\"", first->begin, "\", line ",
                   animation->line, " has dur=\"", animation->dur, "\" begin=\"", animation->begin, "\""),
              "use the total time of all the collisions for every disc, so that keyTimes mean the same moments for "
              "all of them");
          return;
        }
      }
    }
  }
  EXPECT_TRUE(first != nullptr) << explain(text(call(s), " to animate the discs with <animate> elements with a dur"),
                                           "the file has no <animate attributeName=\"cx\"> or \"cy\"",
                                           "write <animate attributeName=\"cx\" values=\"...\" keyTimes=\"...\" "
                                           "dur=\"...s\"/> inside each disc's <circle>");
}

// --- What the animation shows ----------------------------------------------------------------

GRADED_TEST(Movie, AnimationShowsTheDiscsAtEveryCollision, 3, visible) {
  for (const System& s : kSystems) {
    const auto picture = film(s);
    if (!picture) return;
    const Truth t = truth(s);
    const auto understood = understand(*picture, s, t.positions.front());
    if (!understood) return;
    std::vector<double> fractions;
    for (const double time : t.times) fractions.push_back(time / t.total());
    const bool key_times = !understood->discs.empty() && !understood->discs.front()->animations_of("cx").empty() &&
                           understood->discs.front()->animations_of("cx").front()->has_key_times;
    expect_positions(
        s, *understood, fractions, t.positions, t.velocities,
        [&](std::size_t k) {
          return k == 0 ? std::string("at the start (time 0)")
                        : text("at collision ", k, " (time ", t.times[k], " of ", t.total(), ")");
        },
        key_times ? "after each call of propagate, record the time so far T_k (the sum of the returned times) and "
                    "every disc's position; write values=\"x_0;x_1;...\" with keyTimes=\"T_0/T;T_1/T;...;1\" (T the "
                    "total), recording the positions after propagate returns, for every disc"
                  : "without keyTimes the values are spread evenly over dur, but collisions are not evenly spaced in "
                    "time: add keyTimes=\"0;T_1/T;...;1\" with T_k the time of collision k and T the total");
    if (::testing::Test::HasFailure()) return;
  }
}

GRADED_TEST(Movie, AnimationMovesTheDiscsInStraightLinesBetweenCollisions, 2, after_due_date) {
  for (const System& s : kSystems) {
    const auto picture = film(s);
    if (!picture) return;
    const Truth t = truth(s);
    const auto understood = understand(*picture, s, t.positions.front());
    if (!understood) return;
    // Half way between collisions k - 1 and k every disc is where its straight-line motion
    // (position and velocity just after collision k - 1) takes it.
    std::vector<double> fractions;
    std::vector<Coordinates> expected;
    std::vector<Velocities> velocities;
    std::vector<std::size_t> after;
    for (std::size_t k = 1; k < t.times.size(); ++k) {
      const double dt = t.times[k] - t.times[k - 1];
      fractions.push_back((t.times[k - 1] + dt / 2) / t.total());
      expected.push_back(t.positions[k - 1] + dt / 2 * t.velocities[k - 1]);
      velocities.push_back(t.velocities[k - 1]);
      after.push_back(k - 1);
    }
    expect_positions(
        s, *understood, fractions, expected, velocities,
        [&](std::size_t j) {
          return text("half way between ", after[j] == 0 ? std::string("the start") : text("collision ", after[j]),
                      " and collision ", after[j] + 1, " (time ", t.times[after[j]] + (t.times[after[j] + 1] - t.times[after[j]]) / 2, ")");
        },
        "between collisions a disc moves in a straight line at constant speed, which linear animation shows "
        "exactly if every collision's moment is a keyframe: one value per collision for every disc, keyTimes "
        "T_k / T (T the total time), calcMode linear");
    if (::testing::Test::HasFailure()) return;
  }
}

// --- No collisions ---------------------------------------------------------------------------

GRADED_TEST(Movie, ZeroCollisionsLeaveTheStateUnchanged, 2, after_due_date) {
  System s = kSystems.front();
  s.collisions = 0;
  ScratchFolder folder;
  Coordinates c = s.coordinates();
  Velocities v = s.velocities();
  if (!run_movie(s, c, v, folder / "movie.svg")) return;
  const double position_error = (c - s.coordinates()).cwiseAbs().maxCoeff();
  const double velocity_error = (v - s.velocities()).cwiseAbs().maxCoeff();
  EXPECT_TRUE(position_error == 0 && velocity_error == 0) << explain(
      text(call(s), " to leave coordinates and velocities unchanged"),
      text("they changed by up to ", position_error, " (positions) and ", velocity_error, " (velocities)"),
      "with collisions = 0 the loop over propagate must not run at all");
}

GRADED_TEST(Movie, ZeroCollisionsDrawAStillTable, 2, after_due_date) {
  System s = kSystems.front();
  s.collisions = 0;
  const auto picture = film(s);
  if (!picture) return;
  const Coordinates start = s.coordinates();
  const auto understood = understand(*picture, s, start);
  if (!understood) return;
  expect_positions(
      s, *understood, {0.0, 0.5, 1.0}, {start, start, start}, std::vector<Velocities>(3, s.velocities()),
      [](std::size_t) { return std::string("in the still picture"); },
      "with no collisions the total time is 0: avoid dividing by it (keyTimes 0/0 is NaN); write each disc at its "
      "position, e.g. with a single value values=\"x\" or no <animate> at all");
}

// --- Invalid arguments -------------------------------------------------------------------------

GRADED_TEST(Movie, RejectsNegativeCollisions, 1, after_due_date) {
  const System s{10, 1, 5, -1, 4};
  ScratchFolder folder;
  Coordinates c = s.coordinates();
  Velocities v = s.velocities();
  expect_invalid_argument([&] { movie(s.R, s.a, s.n, c, v, -1, folder / "movie.svg"); }, "collisions = -1",
                          "collisions",
                          "check collisions >= 0 at the start and throw std::invalid_argument naming `collisions` "
                          "otherwise");
}

// propagate throws std::invalid_argument when no collision can ever happen; movie passes it on.
GRADED_TEST(Movie, RejectsCirclesThatAreAllAtRest, 1, after_due_date) {
  const System s{10, 1, 5, 5, 4};
  ScratchFolder folder;
  Coordinates c = s.coordinates();
  Velocities v = Velocities::Zero(s.n, 2);
  expect_invalid_argument([&] { movie(s.R, s.a, s.n, c, v, s.collisions, folder / "movie.svg"); },
                          "5 collisions of circles that are all at rest (no collision can ever happen)",
                          "",  // any message: it comes from propagate
                          "let the std::invalid_argument from propagate pass (do not catch it), and do not call "
                          "propagate in a way that hides it");
}

}  // namespace
}  // namespace billiard::testing

#include "support/failure_pictures.hpp"

#include "billiard/table_svg.hpp"
#include "support/json_text.hpp"
#include "support/student_messages.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <system_error>

namespace billiard::testing {
namespace {

// The record keeps at most this many numbers (64 MB): every step of the longest runs (20000
// steps of 50 circles take a quarter of it), and past it the latest step.
constexpr std::size_t kMaxRecordedNumbers = std::size_t{8} << 20;

// The two accounts' colours and dash patterns: blue and orange are told apart by every kind of
// colour vision, and the dashes tell them apart in grey too.
constexpr const char* kExpectedColour = "#1565c0";
constexpr const char* kYourColour = "#e65100";

struct RecordedStep {
  Board board;
  Outcome outcome;
  bool after_is_next_board = false;  // outcome's state not kept: it is the next step's board
};

struct TestRecord {
  std::vector<RecordedStep> steps;          // from the test's first step, up to the cap
  std::optional<RecordedStep> latest;       // the latest step, once past the cap
  std::size_t numbers = 0;
  long long calls = 0;
  CaseSource source;
  bool drawn = false;
  std::string picture;
};

TestRecord& record() {
  static TestRecord current;
  return current;
}

struct Registered {
  std::string function = "the step function";
  StepJudge judge;
};
Registered& registered() {
  static Registered suite;
  return suite;
}

std::size_t numbers_in(const Board& board, const Outcome& outcome) {
  return static_cast<std::size_t>(board.coordinates.size() + board.velocities.size() + outcome.coordinates.size() +
                                  outcome.velocities.size());
}

bool same_state(const Coordinates& c1, const Velocities& v1, const Coordinates& c2, const Velocities& v2) {
  return c1.rows() == c2.rows() && v1.rows() == v2.rows() && c1 == c2 && v1 == v2;
}

int circle_count(const Board& board) { return static_cast<int>(board.coordinates.rows()); }

bool is_circle(int index, const Board& board) { return index >= 0 && index < circle_count(board); }

bool finite_row(const Eigen::Matrix<double, Eigen::Dynamic, 2>& rows, int i) {
  return i >= 0 && i < rows.rows() && std::isfinite(rows(i, 0)) && std::isfinite(rows(i, 1));
}

// The point of segment `wall` nearest to p.
Vector nearest_on(const Wall& wall, const Vector& p) {
  const Vector d = wall.b - wall.a;
  const double length2 = d.squaredNorm();
  const double s = length2 > 0 ? std::clamp((p - wall.a).dot(d) / length2, 0.0, 1.0) : 0.0;
  return wall.a + s * d;
}

// The account of an outcome: its event's circles where it leaves them, the point of contact.
Account account_of(const Board& board, const Outcome& outcome) {
  Account account;
  account.label = describe_outcome(outcome, circle_count(board), static_cast<int>(board.walls.size()));
  if (!outcome.error.empty() || outcome.none) return account;
  // A position or velocity that is not a number cannot be drawn where it is: it is marked where
  // the circle was, and said in words.
  for (int i = 0; i < circle_count(board); ++i) {
    std::string what;
    for (const auto& [rows, name] : {std::pair{&outcome.coordinates, "position"}, std::pair{&outcome.velocities, "velocity"}}) {
      if (i >= rows->rows() || finite_row(*rows, i)) continue;
      const bool nan = std::isnan((*rows)(i, 0)) || std::isnan((*rows)(i, 1));
      what += text(what.empty() ? "" : " and ", name, nan ? " is NaN (not a number)" : " is infinite");
    }
    if (!what.empty()) {
      account.not_finite.push_back({i, what});
      account.label += text("; circle ", i, "'s ", what);
    }
  }
  const Collision& e = outcome.event;
  const auto ghost = [&](int i) {
    if (finite_row(outcome.coordinates, i) && finite_row(outcome.velocities, i)) {
      account.ghosts.push_back({i, outcome.coordinates.row(i), outcome.velocities.row(i), true});
    }
  };
  if (!is_circle(e.circle, board) || !finite_row(outcome.coordinates, e.circle)) return account;
  ghost(e.circle);
  const Vector centre = outcome.coordinates.row(e.circle);
  if (is_circle(e.other, board) && e.other != e.circle) {
    ghost(e.other);
    if (finite_row(outcome.coordinates, e.other)) {
      account.contacts.push_back((centre + Vector(outcome.coordinates.row(e.other))) / 2);
    }
  } else if (e.other == kWall && centre.norm() > 0) {
    account.contacts.push_back(centre.normalized() * (centre.norm() + board.circle_radius));
  } else if (e.other <= -2 && -2 - e.other < static_cast<int>(board.walls.size())) {
    account.wall = -2 - e.other;
    account.contacts.push_back(nearest_on(board.walls[static_cast<std::size_t>(account.wall)], centre));
  }
  return account;
}

bool in_event(int i, const Outcome& outcome) {
  return outcome.error.empty() && !outcome.none && (outcome.event.circle == i || outcome.event.other == i);
}

std::string number(double value) {
  if (!std::isfinite(value)) return "null";
  std::ostringstream out;
  out.precision(17);
  out << value;
  return out.str();
}

std::string json_rows(const Eigen::Matrix<double, Eigen::Dynamic, 2>& rows) {
  std::string result = "[";
  for (Eigen::Index i = 0; i < rows.rows(); ++i) {
    result += (i ? ", [" : "[") + number(rows(i, 0)) + ", " + number(rows(i, 1)) + "]";
  }
  return result + "]";
}

std::string json_outcome(const Outcome& outcome) {
  return text("{\"time\": ", number(outcome.event.time), ", \"circle\": ", outcome.event.circle,
              ", \"other\": ", outcome.event.other, ", \"none\": ", outcome.none ? "true" : "false",
              ", \"error\": ", json_string(outcome.error), ", \"coordinates\": ", json_rows(outcome.coordinates),
              ", \"velocities\": ", json_rows(outcome.velocities), "}");
}

// The case's data, for programs that read the picture back.
std::string metadata_of(const FailingCase& failing, std::string_view test) {
  const Board& b = failing.board;
  std::string walls = "[";
  for (std::size_t k = 0; k < b.walls.size(); ++k) {
    walls += text(k ? ", [" : "[", number(b.walls[k].a(0)), ", ", number(b.walls[k].a(1)), ", ",
                  number(b.walls[k].b(0)), ", ", number(b.walls[k].b(1)), "]");
  }
  walls += "]";
  std::string marked = "[";
  for (std::size_t k = 0; k < failing.listing.marked.size(); ++k) marked += text(k ? ", " : "", failing.listing.marked[k]);
  marked += "]";
  return text("{\"test\": ", json_string(test), ", \"kind\": ", json_string(failing.kind),
              ", \"heading\": ", json_string(failing.heading),
              ", \"table_radius\": ", number(b.table_radius), ", \"circle_radius\": ", number(b.circle_radius),
              ", \"walls\": ", walls, ", \"gravity\": [", number(b.gravity(0)), ", ", number(b.gravity(1)),
              "], \"cell_size\": ", number(b.cell_size), ", \"coordinates\": ", json_rows(b.coordinates),
              ", \"velocities\": ", json_rows(b.velocities), ", \"expected\": ", json_outcome(failing.expected_outcome),
              ", \"yours\": ", json_outcome(failing.your_outcome), ", \"marked_lines\": ", marked, "}");
}

// Lines of at most `width` characters, broken at spaces.
std::vector<std::string> wrapped(std::string_view text, std::size_t width) {
  std::vector<std::string> lines;
  std::istringstream paragraphs{std::string(text)};
  for (std::string paragraph; std::getline(paragraphs, paragraph);) {
    std::string line;
    std::istringstream words(paragraph);
    for (std::string word; words >> word;) {
      if (!line.empty() && line.size() + 1 + word.size() > width) {
        lines.push_back(line);
        line.clear();
      }
      line += (line.empty() ? "" : " ") + word;
    }
    if (!line.empty()) lines.push_back(line);
  }
  return lines;
}

// Where a circle flies from `from` with velocity v for time t (a parabola under gravity).
Vector flown(const Vector& from, const Vector& v, const Vector& g, double t) { return from + t * v + 0.5 * t * t * g; }

// The paths from the start of the step to where an account puts its circles (drawn under the
// circles, so that the velocities' arrows stay on top).
void draw_paths(TableSvg& picture, const Board& board, const Account& account, const Outcome& outcome,
                const char* colour, const char* css) {
  if (!(std::isfinite(outcome.event.time) && outcome.event.time >= 0)) return;
  for (const Ghost& ghost : account.ghosts) {
    const int i = ghost.circle;
    if (!is_circle(i, board) || !finite_row(board.coordinates, i) || !finite_row(board.velocities, i)) continue;
    const Vector start = board.coordinates.row(i), v = board.velocities.row(i);
    const int pieces = board.gravity.squaredNorm() > 0 ? 16 : 1;  // a parabola under gravity
    Vector previous = start;
    for (int k = 1; k <= pieces; ++k) {
      const Vector next = k == pieces ? ghost.at : flown(start, v, board.gravity, outcome.event.time * k / pieces);
      picture.line(previous, next,
                   text("class=\"", css, " path\" stroke=\"", colour, "\" stroke-width=\"", 0.5 * picture.unit(),
                        "\" stroke-opacity=\"0.6\""));
      previous = next;
    }
  }
}

// An account over the board: the wall it touches, its circles (dashed) with their velocities
// after the event, and the points of contact (the student's drawn smaller, on top of the
// expected ones, so that both show where they coincide).
void draw_account(TableSvg& picture, const Board& board, const Account& account, const char* colour,
                  const std::string& dashes, const char* css, double arrow_scale, double contact_size,
                  double side) {
  const double a = board.circle_radius;
  if (account.wall >= 0) {
    const Wall& wall = board.walls[static_cast<std::size_t>(account.wall)];
    picture.line(wall.a, wall.b,
                 text("class=\"", css, " wall-hit\" data-wall=\"", account.wall, "\" stroke=\"", colour,
                      "\" stroke-width=\"", 1.5 * picture.unit(), "\" stroke-dasharray=\"", dashes, "\""));
  }
  for (const Ghost& ghost : account.ghosts) {
    picture.circle(ghost.at, a,
                   text("class=\"", css, "\" data-circle=\"", ghost.circle, "\" fill=\"", colour,
                        "\" fill-opacity=\"0.12\" stroke=\"", colour, "\" stroke-width=\"",
                        std::max(0.12 * a, 0.4 * picture.unit()), "\" stroke-dasharray=\"", dashes, "\""));
    if (ghost.moved && arrow_scale > 0) {
      // The student's arrows a little to the side of the expected ones (they often start at the
      // same place), each with its speed at its tip, so that both lengths read.
      const Vector along = ghost.velocity.norm() > 0 ? Vector(ghost.velocity.normalized()) : Vector(1, 0);
      const Vector from = ghost.at + side * 0.35 * a * Vector(-along.y(), along.x());
      const Vector tip = from + arrow_scale * ghost.velocity;
      picture.arrow(from, tip, colour, 0.6 * picture.unit(), text("class=\"", css, " velocity\""));
      std::ostringstream speed;
      speed.precision(3);
      speed << ghost.velocity.norm();
      picture.text(tip + along * 1.5 * picture.unit() + side * Vector(-along.y(), along.x()) * 1.5 * picture.unit(),
                   speed.str(), std::clamp(0.9 * a, 2.2 * picture.unit(), 4.0 * picture.unit()),
                   text("class=\"", css, " speed\" data-circle=\"", ghost.circle, "\" fill=\"", colour,
                        "\" text-anchor=\"middle\" dominant-baseline=\"central\""));
    }
  }
  for (const auto& [i, what] : account.not_finite) {
    if (!finite_row(board.coordinates, i)) continue;
    const Vector at = board.coordinates.row(i);
    const double arm = 1.2 * a;  // a cross over the circle where it was, and the word
    const std::string style = text("class=\"", css, " not-finite\" data-circle=\"", i, "\" stroke=\"", colour,
                                   "\" stroke-width=\"", std::max(0.2 * a, 0.6 * picture.unit()), "\"");
    picture.line(at + Vector(-arm, -arm), at + Vector(arm, arm), style);
    picture.line(at + Vector(-arm, arm), at + Vector(arm, -arm), style);
    picture.text(at + Vector(1.4 * arm, 0.4 * arm), what.find("NaN") != std::string::npos ? "NaN" : "inf",
                 std::clamp(1.4 * a, 2.5 * picture.unit(), 6.0 * picture.unit()),
                 text("class=\"", css, " not-finite-label\" fill=\"", colour, "\" font-weight=\"bold\""));
  }
  for (const Vector& contact : account.contacts) {
    picture.circle(contact, contact_size,
                   text("class=\"", css, " contact\" fill=\"", colour, "\" stroke=\"white\" stroke-width=\"",
                        0.3 * picture.unit(), "\""));
  }
}

// What the student's code did at recorded step k (its state after: the next step's board when
// the record keeps only that).
Outcome outcome_at(const TestRecord& r, std::size_t k) {
  if (!r.steps[k].after_is_next_board) return r.steps[k].outcome;
  const Board& next = k + 1 < r.steps.size() ? r.steps[k + 1].board : r.latest->board;
  Outcome outcome = r.steps[k].outcome;
  outcome.coordinates = next.coordinates;
  outcome.velocities = next.velocities;
  return outcome;
}

std::optional<Judgement> judged(const Board& board, const Outcome& got) {
  try {
    return registered().judge(board, got);
  } catch (const std::exception&) {
    return std::nullopt;  // the judge cannot step this state: it says nothing about the student's code
  }
}

std::optional<FailingCase> case_of_steps() {
  TestRecord& r = record();
  const Registered& suite = registered();
  if (!suite.judge || (r.steps.empty() && !r.latest)) return std::nullopt;
  const std::string calls = text(" of ", r.calls, " in this test");
  if (const auto departure = first_departure()) {
    return step_case(departure->board, departure->expected, departure->got,
                     text(suite.function, " call ", departure->call, calls,
                          ": the first where your code differs from the expected step"));
  }
  const RecordedStep& last = r.latest ? *r.latest : r.steps.back();
  const Outcome got = r.latest ? r.latest->outcome : outcome_at(r, r.steps.size() - 1);
  const auto judgement = judged(last.board, got);
  if (!judgement) return std::nullopt;
  return step_case(last.board, judgement->expected, got,
                   text(suite.function, " call ", r.calls, calls, judgement->agrees
                                                     ? ", the last before the failure (its event agrees with the "
                                                       "expected one; the test checks more than the event)"
                                                     : ": the first where your code differs from the expected step"));
}

class PictureListener : public ::testing::EmptyTestEventListener {
 public:
  void OnTestStart(const ::testing::TestInfo& info) override {
    record() = TestRecord{};
    if (const char* folder = std::getenv("BILLIARD_PICTURES"); folder != nullptr && *folder != '\0') {
      std::error_code ignored;
      std::filesystem::remove(std::filesystem::path(folder) / file_name(info), ignored);
    }
  }
  void OnTestEnd(const ::testing::TestInfo&) override { record() = TestRecord{}; }

  static std::string file_name(const ::testing::TestInfo& info) {
    return std::string(info.test_suite_name()) + "." + info.name() + ".svg";
  }
};

}  // namespace

std::optional<Departure> first_departure() {
  const TestRecord& r = record();
  if (!registered().judge) return std::nullopt;
  for (std::size_t k = 0; k < r.steps.size(); ++k) {
    const Outcome got = outcome_at(r, k);
    const auto judgement = judged(r.steps[k].board, got);
    if (judgement && !judgement->agrees) return Departure{r.steps[k].board, got, judgement->expected, static_cast<int>(k) + 1};
  }
  return std::nullopt;
}

bool register_step_judge(std::string function, StepJudge judge) {
  registered() = Registered{std::move(function), std::move(judge)};
  return true;
}

void record_step(Board&& board, Outcome&& outcome) {
  TestRecord& r = record();
  ++r.calls;
  if (r.drawn) return;  // the picture is out: later steps change nothing
  if (!r.steps.empty()) {
    RecordedStep& previous = r.steps.back();
    if (!previous.after_is_next_board &&
        same_state(previous.outcome.coordinates, previous.outcome.velocities, board.coordinates, board.velocities)) {
      r.numbers -= static_cast<std::size_t>(previous.outcome.coordinates.size() + previous.outcome.velocities.size());
      previous.outcome.coordinates.resize(0, 2);
      previous.outcome.velocities.resize(0, 2);
      previous.after_is_next_board = true;
    }
  }
  const std::size_t numbers = numbers_in(board, outcome);
  if (!r.latest && r.numbers + numbers <= kMaxRecordedNumbers) {
    r.numbers += numbers;
    r.steps.push_back({std::move(board), std::move(outcome), false});
  } else {
    if (!r.steps.empty() && r.steps.back().after_is_next_board && !r.latest) {
      // The last kept step's state after it is this board: keep it with that step.
      r.steps.back().outcome.coordinates = board.coordinates;
      r.steps.back().outcome.velocities = board.velocities;
      r.steps.back().after_is_next_board = false;
    }
    r.latest = RecordedStep{std::move(board), std::move(outcome), false};
  }
}

void set_case_source(CaseSource source) { record().source = std::move(source); }

std::string describe_outcome(const Outcome& outcome, int circles, int walls) {
  if (!outcome.error.empty()) return text("threw \"", outcome.error, "\"");
  if (outcome.none) return "no event ever (no circle can reach anything)";
  const Collision& e = outcome.event;
  const std::string after = text(" after time ", e.time);
  if (e.circle < 0 || e.circle >= circles) return text("circle ", e.circle, " (not a circle of this table)", after);
  if (e.other == kWall) return text("circle ", e.circle, " hits the table's wall", after);
  if (e.other >= 0 && e.other < circles && e.other != e.circle) {
    return text("circles ", e.circle, " and ", e.other, " collide", after);
  }
  if (e.other <= -2 && -2 - e.other < walls) return text("circle ", e.circle, " hits walls[", -2 - e.other, "]", after);
  return text("circle ", e.circle, " and other = ", e.other, " (no such circle or wall)", after);
}

FailingCase step_case(const Board& board, const Outcome& expected, const Outcome& yours, std::string heading) {
  FailingCase failing;
  failing.heading = std::move(heading);
  failing.board = board;
  failing.expected_outcome = expected;
  failing.your_outcome = yours;
  failing.expected = account_of(board, expected);
  failing.yours = account_of(board, yours);
  // Circles outside both events that the two accounts leave in different places or with
  // different velocities (a bystander not moved, a velocity changed that should not be). Only
  // when both events come at the same time: else every circle is elsewhere, and drawing them all
  // would hide the events.
  const double scale = board.table_radius / std::max(std::sqrt(board.velocities.squaredNorm()), 1e-300);
  const bool both_states = expected.error.empty() && yours.error.empty() && !expected.none && !yours.none &&
                           std::abs(expected.event.time - yours.event.time) <= 1e-9 * (scale + expected.event.time) &&
                           expected.coordinates.rows() == board.coordinates.rows() &&
                           yours.coordinates.rows() == board.coordinates.rows() &&
                           expected.velocities.rows() == board.velocities.rows() &&
                           yours.velocities.rows() == board.velocities.rows();
  if (both_states) {
    const double speed = std::max(board.velocities.rowwise().norm().maxCoeff(), 1e-300);
    for (int i = 0; i < circle_count(board); ++i) {
      if (in_event(i, expected) || in_event(i, yours)) continue;
      const bool moved_apart = !((expected.coordinates.row(i) - yours.coordinates.row(i)).norm() <=
                                 1e-9 * board.table_radius);
      const bool turned_apart = !((expected.velocities.row(i) - yours.velocities.row(i)).norm() <= 1e-9 * speed);
      if (!moved_apart && !turned_apart) continue;
      failing.expected.ghosts.push_back({i, expected.coordinates.row(i), expected.velocities.row(i), true});
      if (finite_row(yours.coordinates, i) && finite_row(yours.velocities, i)) {
        failing.yours.ghosts.push_back({i, yours.coordinates.row(i), yours.velocities.row(i), true});
      }
    }
  }
  return failing;
}

FailingCase state_case(Board board, std::string heading) {
  if (!(board.table_radius > 0)) {
    double farthest = 1;
    for (int i = 0; i < circle_count(board); ++i) {
      if (finite_row(board.coordinates, i)) farthest = std::max(farthest, board.coordinates.row(i).norm());
    }
    board.table_radius = 1.25 * farthest;
    if (!(board.circle_radius > 0)) board.circle_radius = 0.06 * board.table_radius;
  }
  FailingCase failing;
  failing.heading = std::move(heading);
  failing.board = std::move(board);
  failing.expected_outcome.none = failing.your_outcome.none = true;
  failing.kind = "state";
  failing.key = "Numbered circles: the state the test gave, arrows their velocities.";
  return failing;
}

FailingCase lines_case(std::string_view file_text, std::string file_name, std::vector<int> marked,
                       std::string heading) {
  constexpr int kContext = 4;  // lines shown before and after each marked one
  std::vector<std::string> all;
  std::istringstream in{std::string(file_text)};
  for (std::string line; std::getline(in, line);) all.push_back(line);
  const int count = static_cast<int>(all.size());
  std::vector<bool> shown(all.size(), false);
  if (marked.empty()) {
    for (int k = 0; k < std::min(count, 2 * kContext + 1); ++k) shown[static_cast<std::size_t>(k)] = true;
  }
  for (const int line : marked) {
    for (int k = std::max(1, line - kContext); k <= std::min(count, line + kContext); ++k) {
      shown[static_cast<std::size_t>(k - 1)] = true;
    }
  }
  FailingCase failing;
  failing.kind = "lines";
  failing.heading = std::move(heading);
  failing.listing.file_name = std::move(file_name);
  failing.listing.marked = std::move(marked);
  for (int k = 0; k < count; ++k) {
    if (!shown[static_cast<std::size_t>(k)]) continue;
    if (k > 0 && !shown[static_cast<std::size_t>(k - 1)]) failing.listing.lines.push_back({0, ""});
    failing.listing.lines.push_back({k + 1, all[static_cast<std::size_t>(k)]});
  }
  if (count > 0 && !shown.back()) failing.listing.lines.push_back({0, ""});
  return failing;
}

namespace {

// The picture of a "lines" case: the file's lines in a fixed-width font, numbered, the marked
// ones on an orange ground, with the test's message under them; sized to the window as the
// tables' pictures are.
void draw_listing(const FailingCase& failing, std::string_view test, std::string_view expected, std::string_view got,
                  const std::string& file) {
  constexpr std::size_t kColumns = 110;  // characters of a file's line per row
  constexpr std::size_t kRowsPerLine = 3;  // a longer line is cut after these
  constexpr double kSize = 14, kLineHeight = 1.45 * kSize, kCharacter = 0.6 * kSize, kMargin = 12;
  const double number_width = 7 * kCharacter;
  const double width = 2 * kMargin + number_width + kColumns * kCharacter;
  std::ostringstream body;
  double y = kMargin + kSize;
  const auto row = [&](double x, const std::string& words, const std::string& attributes) {
    body << "  <text x=\"" << x << "\" y=\"" << y << "\" font-size=\"" << kSize << "\" " << attributes
         << " xml:space=\"preserve\">" << TableSvg::escaped(words) << "</text>\n";
    y += kLineHeight;
  };
  const std::string sans = "font-family=\"sans-serif\" fill=\"#212121\"";
  const std::string mono = "font-family=\"monospace\" fill=\"#212121\"";
  const std::size_t text_width = static_cast<std::size_t>((width - 2 * kMargin) / (0.55 * kSize));
  row(kMargin, std::string(test), "font-family=\"sans-serif\" font-weight=\"bold\" fill=\"#000000\"");
  for (const auto& line : wrapped(failing.heading, text_width)) row(kMargin, line, sans);
  row(kMargin, text("Lines of ", failing.listing.file_name, ": what the message is about on an orange ground"),
      "font-family=\"sans-serif\" font-weight=\"bold\" fill=\"" + std::string(kYourColour) + "\"");
  for (const auto& [number, line] : failing.listing.lines) {
    if (number == 0) {
      row(kMargin, "   ...", mono);
      continue;
    }
    const bool marked = std::find(failing.listing.marked.begin(), failing.listing.marked.end(), number) !=
                        failing.listing.marked.end();
    for (std::size_t part = 0; part * kColumns < std::max<std::size_t>(line.size(), 1); ++part) {
      if (marked) {
        body << "  <rect x=\"" << kMargin / 2 << "\" y=\"" << y - kSize << "\" width=\"" << width - kMargin
             << "\" height=\"" << kLineHeight << "\" fill=\"#ffe0b2\" class=\"marked\"/>\n";
      }
      if (part == kRowsPerLine) {
        row(kMargin + number_width, text("... (", line.size() - part * kColumns, " more characters on this line)"),
            mono + " font-style=\"italic\"");
        break;
      }
      const std::string number_text = part == 0 ? std::to_string(number) : "";
      row(kMargin, std::string(6 - std::min<std::size_t>(6, number_text.size()), ' ') + number_text,
          "font-family=\"monospace\" fill=\"#757575\"");
      y -= kLineHeight;
      row(kMargin + number_width, line.substr(part * kColumns, kColumns), mono);
    }
  }
  y += kLineHeight / 2;
  row(kMargin, "The test's message", "font-family=\"sans-serif\" font-weight=\"bold\" fill=\"#000000\"");
  for (const auto& line : wrapped(text("Expected: ", expected), text_width)) row(kMargin, line, sans);
  for (const auto& line : wrapped(text("Your code: ", got), text_width)) row(kMargin, line, sans);
  const double height = y + kMargin;
  std::ofstream out(file);
  out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"100%\" height=\"100%\" viewBox=\"0 0 " << width << ' '
      << height << "\">\n  <title>" << TableSvg::escaped(text(test, ": ", failing.heading)) << "</title>\n  <metadata>"
      << TableSvg::escaped(metadata_of(failing, test)) << "</metadata>\n"
      << "  <rect width=\"100%\" height=\"100%\" fill=\"#ffffff\"/>\n" << body.str() << "</svg>\n";
  if (!out.flush()) throw std::runtime_error("writing " + file + " failed");
}

}  // namespace

void draw_failing_case(const FailingCase& failing, std::string_view test, std::string_view expected,
                       std::string_view got, const std::string& file) {
  if (failing.kind == "lines") {
    draw_listing(failing, test, expected, got, file);
    return;
  }
  const Board& board = failing.board;
  const double R = board.table_radius, a = board.circle_radius;
  const int n = circle_count(board);

  // Arrows: the fastest velocity in the picture as long as 15% of the table.
  double fastest = 0;
  for (int i = 0; i < n; ++i) {
    if (finite_row(board.velocities, i)) fastest = std::max(fastest, board.velocities.row(i).norm());
  }
  for (const Account* account : {&failing.expected, &failing.yours}) {
    for (const Ghost& ghost : account->ghosts) {
      if (std::isfinite(ghost.velocity.norm())) fastest = std::max(fastest, ghost.velocity.norm());
    }
  }
  const double arrow_scale = fastest > 0 ? 0.15 * R / fastest : 0;

  // The legend's lines, under the table: their number sets the picture's height.
  constexpr std::size_t kWidth = 105;  // characters per line at the legend's size
  const double size = 3.4 * R / 100, line_height = 1.45 * size;
  std::vector<std::pair<std::string, std::string>> legend;  // (style, text); style "" = plain
  legend.push_back({"title", std::string(test)});
  for (const auto& line : wrapped(failing.heading, kWidth)) legend.push_back({"", line});
  const auto add = [&](const char* style, const std::string& words) {
    const auto lines = wrapped(words, kWidth - 6);
    for (std::size_t k = 0; k < lines.size(); ++k) legend.push_back({k == 0 || !*style ? style : "indent", lines[k]});
  };
  if (!failing.expected.label.empty()) add("expected", "Expected: " + failing.expected.label);
  if (!failing.yours.label.empty()) add("yours", "Your code: " + failing.yours.label);
  add("", failing.key.empty() ? "Numbered circles: where they are before the call, arrows their velocities. Dashed: "
                                 "where each answer puts them, with their velocities after (each speed at its arrow's "
                                 "tip); dots: the points of contact."
                               : failing.key);
  if (arrow_scale > 0) {
    std::ostringstream scale;
    scale.precision(3);
    scale << "Arrows: a speed of " << fastest << " is drawn as long as " << 0.15 * R << " (15% of the table's radius).";
    add("", scale.str());
  }
  legend.push_back({"", ""});
  legend.push_back({"title", "The test's message"});
  for (const auto& line : wrapped(text("Expected: ", expected), kWidth)) legend.push_back({"", line});
  for (const auto& line : wrapped(text("Your code: ", got), kWidth)) legend.push_back({"", line});

  TableSvg picture(R, (static_cast<double>(legend.size()) + 2.5) * line_height / R, 800);
  picture.fit_window();  // the legend under the table stays in view in a window of any shape
  picture.title(text(test, ": ", failing.heading));
  picture.metadata(metadata_of(failing, test));
  picture.table("#f1f8e9", "class=\"table\"");
  for (std::size_t k = 0; k < board.walls.size(); ++k) picture.wall(board.walls[k], text("class=\"wall\" data-wall=\"", k, "\""));
  if (board.cell_size > 0 && R / board.cell_size <= 200) {
    // The cells, as a light grid over the table (lines at multiples of the cell size).
    for (double x = -std::floor(R / board.cell_size) * board.cell_size; x <= R; x += board.cell_size) {
      const double half = std::sqrt(std::max(R * R - x * x, 0.0));
      const std::string style = text("class=\"cell\" stroke=\"#9e9e9e\" stroke-width=\"", 0.3 * picture.unit(), "\"");
      picture.line(Vector(x, -half), Vector(x, half), style);
      picture.line(Vector(-half, x), Vector(half, x), style);
    }
  }

  if (board.gravity.squaredNorm() > 0 && std::isfinite(board.gravity.norm())) {
    // Gravity: an arrow in the top left corner, outside the table.
    const Vector corner(-0.92 * R, 0.92 * R);
    picture.arrow(corner, corner + 0.12 * R * board.gravity.normalized(), "#6a1b9a", 0.8 * picture.unit(),
                  "class=\"gravity\"");
    picture.text(corner + Vector(2 * picture.unit(), 2 * picture.unit()),
                 text("g = (", board.gravity(0), ", ", board.gravity(1), ")"), 3.4 * picture.unit(),
                 "fill=\"#6a1b9a\"");
  }


  draw_paths(picture, board, failing.expected, failing.expected_outcome, kExpectedColour, "expected");
  draw_paths(picture, board, failing.yours, failing.your_outcome, kYourColour, "yours");
  for (int i = 0; i < n; ++i) {
    if (!finite_row(board.coordinates, i)) continue;
    const Vector centre = board.coordinates.row(i);
    picture.circle(centre, a,
                   text("class=\"circle\" data-circle=\"", i, "\" fill=\"#fff59d\" stroke=\"#424242\" stroke-width=\"",
                        std::max(0.06 * a, 0.2 * picture.unit()), "\""));
    if (arrow_scale > 0 && finite_row(board.velocities, i) && board.velocities.row(i).norm() > 0) {
      picture.arrow(centre, centre + arrow_scale * Vector(board.velocities.row(i)), "#212121", 0.5 * picture.unit(),
                    "class=\"velocity\"");
    }
  }
  for (int i = 0; i < n; ++i) {
    if (!finite_row(board.coordinates, i)) continue;
    picture.text(board.coordinates.row(i), std::to_string(i), std::clamp(1.1 * a, 1.5 * picture.unit(), 5.0 * picture.unit()),
                 "class=\"number\" text-anchor=\"middle\" dominant-baseline=\"central\" fill=\"#000000\"");
  }
  const double contact = std::max(0.25 * a, 1.2 * picture.unit());
  draw_account(picture, board, failing.expected, kExpectedColour, text(0.5 * a, " ", 0.25 * a), "expected",
               arrow_scale, contact, 1.0);
  draw_account(picture, board, failing.yours, kYourColour, text(0.12 * a, " ", 0.18 * a), "yours", arrow_scale,
               0.6 * contact, -1.0);

  // The legend.
  const double left = picture.left() + 2 * picture.unit();
  double y = -1.05 * R - 1.2 * line_height;
  for (const auto& [style, words] : legend) {
    double x = left;
    std::string attributes = "fill=\"#212121\"";
    if (style == "title") attributes = "fill=\"#000000\" font-weight=\"bold\"";
    if (style == "indent") x += 5 * size;
    if (style == "expected" || style == "yours") {
      const bool mine = style == "yours";
      const char* colour = mine ? kYourColour : kExpectedColour;
      const double r = 0.4 * size;
      picture.circle(Vector(x + 2 * r, y + 0.35 * size), r,
                     text("class=\"legend ", style, "\" fill=\"none\" stroke=\"", colour, "\" stroke-width=\"",
                          0.25 * size, "\" stroke-dasharray=\"", mine ? text(0.1 * size, " ", 0.15 * size)
                                                                      : text(0.35 * size, " ", 0.15 * size), "\""));
      x += 5 * size;
      attributes = text("fill=\"", colour, "\" font-weight=\"bold\"");
    }
    if (!words.empty()) picture.text(Vector(x, y), words, size, attributes);
    y -= line_height;
  }
  picture.write(file);
}

std::string picture_of_failure(std::string_view expected, std::string_view got) {
  TestRecord& r = record();
  if (r.drawn) return r.picture;
  const char* folder = std::getenv("BILLIARD_PICTURES");
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  if (folder == nullptr || *folder == '\0' || info == nullptr) return "";
  r.drawn = true;
  try {
    const std::optional<FailingCase> failing = r.source ? r.source() : case_of_steps();
    if (!failing) return "";
    std::filesystem::create_directories(folder);
    const std::string file = (std::filesystem::path(folder) / PictureListener::file_name(*info)).string();
    draw_failing_case(*failing, std::string(info->test_suite_name()) + "." + info->name(), expected, got, file);
    r.picture = file;
  } catch (const std::exception&) {
    r.picture.clear();  // no picture is no reason to fail otherwise: the message stands alone
  }
  return r.picture;
}

void install_picture_listener() {
  ::testing::UnitTest::GetInstance()->listeners().Append(new PictureListener);  // owned by GoogleTest
}

}  // namespace billiard::testing

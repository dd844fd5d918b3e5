// Tests of the pictures of a failing case (failure_pictures.hpp), not graded: which step of a
// test is drawn, that the drawing shows that step (read back with the suites' SVG reader), that a
// test's old picture goes when it starts, and that nothing is drawn when pictures are off.
// Label "support": ctest --preset release -L support
#include "billiard/table_svg.hpp"
#include "support/failure_pictures.hpp"
#include "support/fixtures.hpp"
#include "support/oracle.hpp"
#include "support/student_messages.hpp"
#include "support/svg_reader.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <utility>

namespace billiard::testing {
namespace {

namespace fs = std::filesystem;

const bool kJudged = register_step_judge("propagate", oracle_judgement);

// A correct step of a plain table: the oracle's own.
Collision oracle_propagate(double R, double a, Coordinates& c, Velocities& v) {
  const OracleStep step = oracle_step(R, a, c, v, 0);
  oracle_advance(step, c, v);
  const OracleEvent& e = step.events.front();
  return Collision{e.time, e.circle, e.other};
}

// Pictures on, into a scratch folder, for one test.
class Pictures : public ::testing::Test {
 protected:
  void SetUp() override { ::setenv("BILLIARD_PICTURES", folder_.path().c_str(), 1); }
  void TearDown() override { ::unsetenv("BILLIARD_PICTURES"); }
  fs::path file() const {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    return folder_ / (std::string(info->test_suite_name()) + "." + info->name() + ".svg");
  }
  ScratchFolder folder_;
};

// The circles of a picture by class and number: {class, data-circle} -> centre in table units.
std::map<std::pair<std::string, int>, std::array<double, 2>> circles_of(const fs::path& file) {
  std::map<std::pair<std::string, int>, std::array<double, 2>> found;
  const SvgDocument document = read_svg(file);  // the circles point into it
  for (const SvgCircle* circle : document.rendered_circles()) {
    const auto number = circle->attributes.find("data-circle");
    if (number == circle->attributes.end()) continue;
    found[{circle->attributes.at("class"), std::stoi(number->second)}] = {circle->x, -circle->y};
  }
  return found;
}

// One circle at (x, y) with velocity (vx, vy).
struct OneCircle {
  Coordinates c = Coordinates(1, 2);
  Velocities v = Velocities(1, 2);
  OneCircle(double x, double y, double vx, double vy) {
    c << x, y;
    v << vx, vy;
  }
};

std::string text_of(const fs::path& file) {
  std::ifstream in(file);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

TEST_F(Pictures, ADifferentEventIsDrawnWithBothAccountsAtTheirPlaces) {
  // Head-on: the circles touch at (-1, 0) and (1, 0) after time 4. A "student" step that says
  // circle 0 hits the wall after time 9 instead, at (9, 0).
  Coordinates c(2, 2);
  Velocities v(2, 2);
  c << -5, 0, 5, 0;
  v << 1, 0, -1, 0;
  recorded_step(table_board(10, 1), c, v, [&] {
    c << 9, 0, -4, 0;
    v << -1, 0, -1, 0;
    return Collision{9, 0, kWall};
  });
  const std::string message = explain("circles 0 and 1 after time 4", "circle 0 hits the wall", "a hint");
  ASSERT_NE(message.find("Picture: " + file().string()), std::string::npos) << message;
  const auto drawn = circles_of(file());
  const auto near = [&](std::pair<std::string, int> key, double x, double y) {
    ASSERT_TRUE(drawn.count(key)) << key.first << " " << key.second;
    EXPECT_NEAR(drawn.at(key)[0], x, 1e-9);
    EXPECT_NEAR(drawn.at(key)[1], y, 1e-9);
  };
  near({"circle", 0}, -5, 0);  // the state before the call
  near({"circle", 1}, 5, 0);
  near({"expected", 0}, -1, 0);  // where the expected event puts them: touching
  near({"expected", 1}, 1, 0);
  near({"yours", 0}, 9, 0);  // where the student's code put circle 0
  EXPECT_FALSE(drawn.count({"yours", 1}));  // different event times: no bystanders drawn
  const std::string svg = text_of(file());
  EXPECT_NE(svg.find("circles 0 and 1 collide after time 4"), std::string::npos);
  EXPECT_NE(svg.find("circle 0 hits the table's wall after time 9"), std::string::npos);
}

TEST_F(Pictures, AVelocityThatIsNotANumberIsMarkedAndSaid) {
  // A wall hit whose new velocity the "student" computed as NaN (a wrong root, say): nothing of
  // theirs can be drawn where it is, so circle 0 is crossed out where it was, with "NaN" beside it.
  OneCircle one(0, 0, 1, 0);
  recorded_step(table_board(10, 1), one.c, one.v, [&] {
    one.c << 9, 0;
    one.v << std::nan(""), 0;
    return Collision{9, 0, kWall};
  });
  const std::string message = explain("a velocity of (-1, 0)", "a velocity of (nan, 0)", "a hint");
  ASSERT_NE(message.find("Picture: " + file().string()), std::string::npos) << message;
  const std::string svg = text_of(file());
  EXPECT_NE(svg.find("class=\"yours not-finite\" data-circle=\"0\""), std::string::npos) << svg;
  EXPECT_NE(svg.find(">NaN<"), std::string::npos);
  EXPECT_NE(svg.find("circle 0's velocity is NaN (not a number)"), std::string::npos);  // in the legend
}

TEST_F(Pictures, VelocitiesAfterAnEventReadBySizeAndDirection) {
  // Circle 0 at speed 3 catches circle 1 at speed 1: after time 2 they touch at x = 3 and 5 and
  // exchange velocities (1 and 3). A "student" step that keeps them (3 and 1): the same places,
  // so the arrows start together; each account's arrows carry their speeds, the student's are
  // drawn to the side, and the legend states the arrows' scale.
  Coordinates c(2, 2);
  Velocities v(2, 2);
  c << -3, 0, 3, 0;
  v << 3, 0, 1, 0;
  recorded_step(table_board(10, 1), c, v, [&] {
    c << 3, 0, 5, 0;
    return Collision{2, 0, 1};
  });
  const std::string message = explain("circle 0 at speed 1", "circle 0 at speed 3", "a hint");
  ASSERT_NE(message.find("Picture: " + file().string()), std::string::npos) << message;
  const std::string svg = text_of(file());
  for (const char* speed : {"class=\"expected speed\" data-circle=\"0\"", "class=\"yours speed\" data-circle=\"0\""}) {
    EXPECT_NE(svg.find(speed), std::string::npos) << speed;
  }
  const auto speed_of = [&](const std::string& css) {
    const std::size_t at = svg.find(css);
    return at == std::string::npos ? std::string() : svg.substr(svg.find('>', at) + 1, 1);
  };
  EXPECT_EQ(speed_of("class=\"expected speed\" data-circle=\"0\""), "1");
  EXPECT_EQ(speed_of("class=\"yours speed\" data-circle=\"0\""), "3");
  EXPECT_NE(svg.find("Arrows: a speed of 3 is drawn as long as 1.5"), std::string::npos);
}

TEST_F(Pictures, TheFirstStepThatLeavesTheExpectedRunIsDrawnNotTheLast) {
  // Twenty correct steps of a lone circle, then a wrong one, then more correct ones: the
  // picture shows call 21 (the failure is only found later).
  OneCircle one(0, 3, 1, 0.3);
  Coordinates& c = one.c;
  Velocities& v = one.v;
  for (int k = 1; k <= 30; ++k) {
    recorded_step(table_board(6, 1), c, v, [&] {
      const Collision event = oracle_propagate(6, 1, c, v);
      if (k == 21) v = -v;  // the whole velocity reversed at the wall
      return event;
    });
  }
  explain("a constant chord time", "it changed", "a hint");
  const std::string svg = text_of(file());
  EXPECT_NE(svg.find("propagate call 21 of 30 in this test: the first where"), std::string::npos);
}

TEST_F(Pictures, WithoutADifferenceTheLastStepIsDrawn) {
  OneCircle one(0, 0, 1, 0);
  Coordinates& c = one.c;
  Velocities& v = one.v;
  for (int k = 0; k < 3; ++k) recorded_step(table_board(10, 1), c, v, [&] { return oracle_propagate(10, 1, c, v); });
  explain("something the event does not show", "something else", "a hint");
  const std::string svg = text_of(file());
  EXPECT_NE(svg.find("propagate call 3 of 3 in this test, the last before the failure"), std::string::npos);
}

TEST_F(Pictures, AFailureAboutAFileShowsItsLinesNotATable) {
  // A file of 30 lines whose line 15 is what the message is about, 500 characters long: the
  // picture shows lines 11 to 19 numbered, line 15 on the marked ground and cut after three rows
  // with what is left said, gaps before and after, and the message; no table.
  std::string file_text;
  for (int line = 1; line <= 30; ++line) {
    file_text += line == 15 ? "<animate keyTimes=\"" + std::string(500, '7') + "\"/>\n" : text("<line ", line, "/>\n");
  }
  set_case_source([file_text] { return lines_case(file_text, "movie.svg", {15}, "The animation a browser cannot play"); });
  const std::string message = explain("keyTimes from 0 to 1", "line 15: keyTimes go from 0 to 0.5", "a hint");
  ASSERT_NE(message.find("Picture: " + file().string()), std::string::npos) << message;
  const std::string svg = text_of(file());
  for (int line = 1; line <= 30; ++line) {
    const bool shown = svg.find(TableSvg::escaped(text("<line ", line, "/>"))) != std::string::npos;
    if (line != 15) {
      EXPECT_EQ(shown, line >= 11 && line <= 19) << line;
    }
  }
  EXPECT_NE(svg.find("class=\"marked\""), std::string::npos);
  EXPECT_NE(svg.find(std::string(110, '7')), std::string::npos);  // a whole row of the long line
  EXPECT_NE(svg.find("more characters on this line"), std::string::npos);
  EXPECT_EQ(std::count(svg.begin(), svg.end(), '7') < 500, true);  // not all of it
  EXPECT_NE(svg.find(">   ...<"), std::string::npos);  // the gaps
  EXPECT_NE(svg.find("line 15: keyTimes go from 0 to 0.5"), std::string::npos);  // the message
  EXPECT_EQ(svg.find("<circle"), std::string::npos);
}

TEST_F(Pictures, ATestWithoutStepsDrawsNothing) {
  const std::string message = explain("3 rows", "2 rows", "a hint");
  EXPECT_EQ(message.find("Picture:"), std::string::npos);
  EXPECT_FALSE(fs::exists(file()));
}

std::string program;  // this test program, from main()

// A test that passes: the one the next test runs again in a process of its own.
TEST(PicturesRerun, PassesNow) {}

TEST_F(Pictures, AnOldPictureGoesWhenItsTestRunsAgain) {
  // A picture left by a failing run of PicturesRerun.PassesNow goes when that test runs again
  // (the listener removes it as the test starts), so the folder holds the last run's failures.
  const fs::path old = folder_ / "PicturesRerun.PassesNow.svg";
  std::ofstream(old) << "<svg xmlns=\"http://www.w3.org/2000/svg\"/>";
  const std::string command = "'" + program + "' --gtest_filter=PicturesRerun.PassesNow > /dev/null";
  ASSERT_EQ(std::system(command.c_str()), 0);
  EXPECT_FALSE(fs::exists(old));
}

TEST(PicturesOff, NothingIsWrittenWithoutTheVariable) {
  ::unsetenv("BILLIARD_PICTURES");
  OneCircle one(0, 0, 1, 0);
  Coordinates& c = one.c;
  Velocities& v = one.v;
  recorded_step(table_board(10, 1), c, v, [&] { return Collision{1, 0, kWall}; });
  EXPECT_EQ(explain("a", "b", "c").find("Picture:"), std::string::npos);
}

}  // namespace
}  // namespace billiard::testing

int main(int argc, char** argv) {
  billiard::testing::program = std::filesystem::absolute(argv[0]).string();
  ::testing::InitGoogleTest(&argc, argv);
  billiard::testing::install_picture_listener();
  return RUN_ALL_TESTS();
}

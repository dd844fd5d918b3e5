// Tests of the judge's protocol (wire.hpp, endings.hpp, files.hpp): values cross exactly,
// exceptions come back as the same standard type with the same message, a file argument is
// made the same on the other side and copied back, and a malformed or oversized message is a
// ProtocolError, never a crash or a huge allocation.
#include "judge/endings.hpp"
#include "judge/files.hpp"
#include "judge/wire.hpp"

#include "billiard/not_implemented.hpp"

#include <gtest/gtest.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <thread>

namespace {

namespace fs = std::filesystem;
using namespace billiard;
using namespace billiard::judge;

// Bit for bit: NaN equals NaN of the same bits, -0 differs from +0.
bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

TEST(Values, CrossBitForBit) {
  const double specials[] = {0.0, -0.0, 1e-320, -1e308, std::numeric_limits<double>::infinity(),
                             -std::numeric_limits<double>::infinity(), std::nan("7"), 0.1};
  Coordinates rows(8, 2);
  for (int i = 0; i < 8; ++i) {
    rows(i, 0) = specials[i];
    rows(i, 1) = specials[7 - i];
  }
  Rng rng(42);
  rng.discard(1000);
  const Collision collision{2.5, 3, kWall};
  const std::vector<Wall> walls{{Vector(1, 2), Vector(-3, 4)}, {Vector(0, 0), Vector(5, -6)}};
  Writer writer;
  writer << Call::movie << specials[6] << std::int32_t{-7} << std::int64_t{1} << 40 << rows << rng << collision
         << walls << Vector(8, 9) << std::string("text\0with a zero", 16);
  Reader reader(writer.bytes());
  EXPECT_EQ(reader.get<Call>(), Call::movie);
  EXPECT_TRUE(same_bits(reader.get<double>(), specials[6]));
  EXPECT_EQ(reader.get<std::int32_t>(), -7);
  EXPECT_EQ(reader.get<std::int64_t>(), 1);
  EXPECT_EQ(reader.get<std::int32_t>(), 40);
  const auto read_rows = reader.get<Coordinates>();
  ASSERT_EQ(read_rows.rows(), 8);
  for (int i = 0; i < 8; ++i) {
    EXPECT_TRUE(same_bits(read_rows(i, 0), rows(i, 0)) && same_bits(read_rows(i, 1), rows(i, 1))) << "row " << i;
  }
  auto read_rng = reader.get<Rng>();
  EXPECT_EQ(read_rng(), rng()) << "the generator continues where it was";
  const auto read_collision = reader.get<Collision>();
  EXPECT_EQ(read_collision.time, 2.5);
  EXPECT_EQ(read_collision.circle, 3);
  EXPECT_EQ(read_collision.other, kWall);
  const auto read_walls = reader.get<std::vector<Wall>>();
  ASSERT_EQ(read_walls.size(), 2u);
  EXPECT_EQ(read_walls[1].b, Vector(5, -6));
  EXPECT_EQ(reader.get<Vector>(), Vector(8, 9));
  EXPECT_EQ(reader.get<std::string>(), std::string("text\0with a zero", 16));
  EXPECT_NO_THROW(reader.expect_end());
}

TEST(Values, MalformedMessagesAreProtocolErrors) {
  Writer writer;
  writer << Call::propagate << 1.0;
  std::string truncated = writer.bytes();
  truncated.pop_back();
  Reader short_reader(truncated);
  short_reader.get<Call>();
  EXPECT_THROW(short_reader.get<double>(), ProtocolError);

  Writer too_many;
  too_many << (std::int64_t{1} << 60);  // an array of 2^60 rows
  Reader huge(too_many.bytes());
  EXPECT_THROW(huge.get<Coordinates>(), ProtocolError) << "a count beyond the limit is refused before allocating";
  Reader negative((Writer() << std::int64_t{-1}).bytes());
  EXPECT_THROW(negative.get<std::string>(), ProtocolError);
  Reader longer_than_message((Writer() << std::int64_t{100} << std::string("x")).bytes());
  EXPECT_THROW(longer_than_message.get<std::string>(), ProtocolError);
  Reader bad_ending((Writer() << std::uint8_t{200}).bytes());
  EXPECT_THROW(bad_ending.get<Ending>(), ProtocolError);
  Reader short_rng((Writer() << std::string("not a generator")).bytes());
  EXPECT_THROW(short_rng.get<Rng>(), ProtocolError);
  Writer broken;  // a generator whose position lies beyond its state
  for (std::size_t word = 0; word <= Rng::state_size; ++word) broken << std::int64_t{1000};
  Reader broken_rng(broken.bytes());
  EXPECT_THROW(broken_rng.get<Rng>(), ProtocolError);
  Reader extra((Writer() << 1.0 << 2.0).bytes());
  extra.get<double>();
  EXPECT_THROW(extra.expect_end(), ProtocolError);
}

TEST(Channel, MessagesCrossASocketAndItsEndIsAProtocolError) {
  int pair[2];
  ASSERT_EQ(::socketpair(AF_UNIX, SOCK_STREAM, 0, pair), 0);
  const std::string big(3u << 20, 'x');  // larger than the socket's buffer: written in parts
  std::thread sender([&] {
    send(pair[0], "one");
    send(pair[0], big);
    ::close(pair[0]);
  });
  EXPECT_EQ(receive(pair[1]), "one");
  EXPECT_EQ(receive(pair[1]), big);
  sender.join();
  EXPECT_THROW(receive(pair[1]), ProtocolError);
  ::close(pair[1]);

  ASSERT_EQ(::socketpair(AF_UNIX, SOCK_STREAM, 0, pair), 0);
  const std::uint32_t oversized = kMaxMessageBytes + 1;
  ASSERT_EQ(::write(pair[0], &oversized, sizeof oversized), static_cast<ssize_t>(sizeof oversized));
  EXPECT_THROW(receive(pair[1]), ProtocolError) << "a length beyond the limit is refused before reading";
  ::close(pair[0]);
  ::close(pair[1]);
}

// Throws `error` in a "worker", writes it, and throws it again on the "judge" side.
template <typename Error>
void round_trip(const Error& error) {
  Writer writer;
  try {
    throw error;
  } catch (...) {
    write_current_exception(writer);
  }
  Reader reader(writer.bytes());
  throw_again(reader.get<Ending>(), reader);
}

TEST(Endings, ExceptionsComeBackAsTheirStandardTypeWithTheirMessage) {
  try {
    round_trip(std::invalid_argument("circle_radius must be positive"));
    FAIL();
  } catch (const std::invalid_argument& error) {
    EXPECT_STREQ(error.what(), "circle_radius must be positive");
  }
  try {
    round_trip(NotImplemented(4, "propagate", "tasks/propagate.cpp"));
    FAIL();
  } catch (const NotImplemented& error) {
    EXPECT_EQ(error.task_number(), 4);
    EXPECT_EQ(error.what(), std::string(NotImplemented(4, "propagate", "tasks/propagate.cpp").what()));
  }
  EXPECT_THROW(round_trip(std::out_of_range("row 7")), std::out_of_range);
  EXPECT_THROW(round_trip(std::logic_error("logic")), std::logic_error);
  EXPECT_THROW(round_trip(std::overflow_error("big")), std::overflow_error);
  EXPECT_THROW(round_trip(std::bad_alloc()), std::bad_alloc);
  // A file-system error is a std::runtime_error, as the course's contract asks for.
  EXPECT_THROW(round_trip(fs::filesystem_error("cannot write", std::make_error_code(std::errc::not_a_directory))),
               std::runtime_error);
  try {
    round_trip(OtherException("something else"));
    FAIL();
  } catch (const std::invalid_argument&) {
    FAIL() << "an exception of another type is not an invalid_argument";
  } catch (const std::runtime_error&) {
    FAIL() << "an exception of another type is not a runtime_error";
  } catch (const std::exception& error) {
    EXPECT_STREQ(error.what(), "something else");
  }
  // throw 42; is not a std::exception on either side.
  Writer writer;
  try {
    throw 42;
  } catch (...) {
    write_current_exception(writer);
  }
  Reader reader(writer.bytes());
  EXPECT_THROW(throw_again(reader.get<Ending>(), reader), NotAStandardException);
}

// The judge's path `path` made in a worker folder, changed by `change` there, and copied back.
void mirror(const fs::path& path, const fs::path& work, void (*change)(const fs::path&)) {
  Writer writer;
  writer << describe_file(path);
  Reader reader(writer.bytes());
  const fs::path theirs = make_file(reader.get<FileState>(), work);
  change(theirs);
  Writer back;
  back << describe_file(theirs);
  Reader returned(back.bytes());
  copy_back(path, returned.get<FileState>());
}

TEST(Files, AFileArgumentIsMadeTheSameAndCopiedBack) {
  const fs::path root = fs::temp_directory_path() / ("billiard-wire-" + std::to_string(::getpid()));
  fs::remove_all(root);
  fs::create_directories(root / "judge");
  fs::create_directories(root / "worker");

  // A file in a folder, replaced: the worker saw the old content, the judge gets the new one.
  const fs::path table = root / "judge" / "table.svg";
  std::ofstream(table) << "old";
  mirror(table, root / "worker", [](const fs::path& theirs) {
    std::ifstream in(theirs);
    std::string old;
    in >> old;
    std::ofstream(theirs, std::ios::trunc) << "new after " << old;
  });
  std::ifstream in(table);
  std::string content((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(content, "new after old");

  // A path under a regular file cannot be created there either.
  const fs::path blocker = root / "judge" / "plain_file";
  std::ofstream(blocker) << "a file";
  mirror(blocker / "table.svg", root / "worker", [](const fs::path& theirs) {
    std::ofstream out(theirs);
    EXPECT_FALSE(out.good()) << theirs << " should not be writable: its folder is a file";
  });
  EXPECT_TRUE(fs::is_regular_file(blocker));

  // A file the worker removed is removed.
  mirror(table, root / "worker", [](const fs::path& theirs) { fs::remove(theirs); });
  EXPECT_FALSE(fs::exists(table));
  fs::remove_all(root);
}

}  // namespace

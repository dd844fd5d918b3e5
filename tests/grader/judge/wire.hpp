// The judge's protocol with the worker: messages of plain data over a pipe each way (a pipe's
// round trip takes half a socket's on one core: a test may make tens of thousands). The judge (the
// graded suite's process) sends a call of a course function with its arguments; the worker (the
// process with the student's code, in its cell) makes the call and sends back what it returned or
// threw, and the arguments it may change. Nothing else crosses: whatever the student's code does
// in its own process, the judge sees only these answers, and judges them.
//
// A message is a 4-byte length and that many bytes. Numbers are sent as their bytes on this
// machine (judge and worker run on the same one), so doubles cross exactly, NaN and infinity
// included. The judge reads defensively: a message too long, too short or malformed is a
// ProtocolError, which the suite reports as a wrong answer.
#pragma once

#include "judge/calls.hpp"

#include "billiard/extensions.hpp"

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace billiard::judge {

// The largest message either side accepts, and the most rows an array may have in one.
inline constexpr std::uint32_t kMaxMessageBytes = 256u << 20;
inline constexpr std::int64_t kMaxRows = 8'000'000;

// The calls a worker answers: running a program task's program, and the course's functions
// (calls.hpp).
enum class Call : std::uint8_t {
  run_program = 1,
#define BILLIARD_CALL_NAME(type, name, parameters, arguments) name,
  BILLIARD_COURSE_CALLS(BILLIARD_CALL_NAME)
#undef BILLIARD_CALL_NAME
};

// How a parameter of a course function crosses: a file's path as the file (FileState); a
// reference to something the function may change both ways; anything else to the worker only.
template <typename Parameter>
inline constexpr bool is_path = std::is_same_v<std::decay_t<Parameter>, std::filesystem::path>;
template <typename Parameter>
inline constexpr bool comes_back = std::is_lvalue_reference_v<Parameter> &&
                                   !std::is_const_v<std::remove_reference_t<Parameter>>;

// How a call ended in the worker: it returned, or it threw an exception of one of these kinds,
// which the judge throws again as the same standard type with the same message.
enum class Ending : std::uint8_t {
  returned = 0,
  not_implemented,
  invalid_argument,
  domain_error,
  length_error,
  out_of_range,
  logic_error,
  range_error,
  overflow_error,
  underflow_error,
  runtime_error,
  bad_alloc,
  other_exception,  // derived from std::exception, none of the above
  not_an_exception,  // something else was thrown (throw 42;)
};

// A malformed or oversized message, or a channel that ended mid-message.
class ProtocolError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A file argument (the svg_file of visualize_table and movie) as the call found it: its name
// and what its folder held. The worker makes the same in a folder of its own, calls with that
// path, and sends back what the file became; the judge then makes its own file the same.
struct FileState {
  enum class Parent : std::uint8_t { folder = 0, file = 1, missing = 2 };
  enum class Kind : std::uint8_t { absent = 0, regular = 1, other = 2 };
  std::string name;  // the file's name, without folders
  Parent parent = Parent::folder;
  Kind kind = Kind::absent;
  std::string content;  // of a regular file
};

// A run of a program task's program (the C track): its arguments, the files its folder holds
// when it starts, and a limit on its wall time.
struct ProgramRun {
  std::vector<std::string> arguments;
  std::vector<std::pair<std::string, std::string>> inputs;  // file name, content
  double seconds = 60;
};
struct ProgramResult {
  int status = -1;  // exit status, or -1
  int signal = 0;   // the signal that ended it, or 0
  bool timed_out = false;
  double seconds = 0;
  std::string out, err;
};

// Builds a message.
class Writer {
 public:
  Writer& operator<<(double value) { return raw(&value, sizeof value); }
  Writer& operator<<(std::int32_t value) { return raw(&value, sizeof value); }
  Writer& operator<<(std::int64_t value) { return raw(&value, sizeof value); }
  Writer& operator<<(long long value) { return raw(&value, sizeof value); }
  Writer& operator<<(std::uint8_t value) { return raw(&value, sizeof value); }
  Writer& operator<<(bool value) { return *this << static_cast<std::uint8_t>(value); }
  Writer& operator<<(Call call) { return *this << static_cast<std::uint8_t>(call); }
  Writer& operator<<(Ending ending) { return *this << static_cast<std::uint8_t>(ending); }
  Writer& operator<<(const std::string& text);
  Writer& operator<<(const Eigen::Matrix<double, Eigen::Dynamic, 2>& rows);
  Writer& operator<<(const Vector& vector);
  Writer& operator<<(const std::vector<Wall>& walls);
  Writer& operator<<(const Collision& collision);
  Writer& operator<<(const Rng& rng);
  Writer& operator<<(const FileState& file);
  Writer& operator<<(const ProgramRun& run);
  Writer& operator<<(const ProgramResult& result);

  // Appends what another writer holds.
  Writer& append(const Writer& other) {
    bytes_ += other.bytes_;
    return *this;
  }
  const std::string& bytes() const { return bytes_; }

 private:
  Writer& raw(const void* data, std::size_t size);
  std::string bytes_;
};

// Reads a message; every read past its end, or of a size beyond the limits above, throws
// ProtocolError.
class Reader {
 public:
  explicit Reader(std::string bytes) : bytes_(std::move(bytes)) {}
  Reader& operator>>(double& value) { return raw(&value, sizeof value); }
  Reader& operator>>(std::int32_t& value) { return raw(&value, sizeof value); }
  Reader& operator>>(std::int64_t& value) { return raw(&value, sizeof value); }
  Reader& operator>>(long long& value) { return raw(&value, sizeof value); }
  Reader& operator>>(std::uint8_t& value) { return raw(&value, sizeof value); }
  Reader& operator>>(bool& value);
  Reader& operator>>(Call& call);
  Reader& operator>>(Ending& ending);
  Reader& operator>>(std::string& text);
  Reader& operator>>(Eigen::Matrix<double, Eigen::Dynamic, 2>& rows);
  Reader& operator>>(Vector& vector);
  Reader& operator>>(std::vector<Wall>& walls);
  Reader& operator>>(Collision& collision);
  Reader& operator>>(Rng& rng);
  Reader& operator>>(FileState& file);
  Reader& operator>>(ProgramRun& run);
  Reader& operator>>(ProgramResult& result);

  template <typename T>
  T get() {
    T value{};
    *this >> value;
    return value;
  }
  // Throws unless every byte was read.
  void expect_end() const;

 private:
  Reader& raw(void* data, std::size_t size);
  std::size_t count(std::size_t limit, const char* what);
  std::string bytes_;
  std::size_t at_ = 0;
};

// Sends a message on a descriptor; throws ProtocolError if the other side has gone.
void send(int fd, const std::string& message);
// Receives a whole message; throws ProtocolError on end of channel or an oversized length.
std::string receive(int fd);

}  // namespace billiard::judge

// The judge's side of the course's functions: linked into a graded suite instead of the course's
// code, each function sends its call to the running test's worker (worker_main.cpp), waits for
// the answer and returns it, or throws what the student's code threw, as if the call had been
// made here. The suite's assertions, its verdict and everything it trusts stay in this process,
// where no submitted code runs; the worker's answers are data to judge, nothing more.
//
// When the worker ends during a call (a crash, exit(), a limit) or answers with a malformed
// message, the test fails with a message that says so, and every later call of the test fails at
// once: the call throws WorkerGone, which is no std::exception, so that no `catch` in a suite
// takes it for an error the student's code reported.
#include "judge/endings.hpp"
#include "judge/files.hpp"
#include "judge/wire.hpp"
#include "support/student_code.hpp"
#include "support/student_messages.hpp"

#include <gtest/gtest.h>

#include <string>

namespace billiard {

namespace judge {
namespace {

int channel = -1;
bool gone = false;

struct WorkerGone {};

// Fails the test once, for the first call that could not be made.
[[noreturn]] void worker_gone(const std::string& call, const std::string& what) {
  gone = true;
  ADD_FAILURE() << testing::explain(
      call + " to return or to throw an exception", "the process running your code ended during the call" + what,
      "what ends a program: exit() or abort(), a failed assert, an uncaught exception in a thread, reading or "
      "writing outside an array (a segmentation fault), an endless recursion, or running out of memory or time "
      "(the first line of this message says which, where the grader can tell)");
  throw WorkerGone{};
}

// Sends a call and receives the worker's answer.
Reader call_worker(const Writer& request, const std::string& call) {
  if (channel < 0) throw std::logic_error("the grader's judge has no worker to call " + call);
  if (gone) throw WorkerGone{};
  try {
    send(channel, request.bytes());
    return Reader(receive(channel));
  } catch (const ProtocolError&) {
    worker_gone(call, "");
  }
}

// The end of an answer: returns if the call returned, else throws what it threw. A malformed
// answer ends the worker's use, as if it had ended.
void finish(Reader& reply, const std::string& call) {
  try {
    const auto ending = reply.get<Ending>();
    if (ending != Ending::returned) throw_again(ending, reply);
  } catch (const ProtocolError& error) {
    worker_gone(
        call, std::string(", or wrote something else than its answer to the grader's channel (") + error.what() + ")");
  }
}

// Reads the result of a call that returned, after finish().
template <typename T>
T result(Reader& reply, const std::string& call) {
  try {
    T value{};
    reply >> value;
    reply.expect_end();
    return value;
  } catch (const ProtocolError& error) {
    worker_gone(
        call, std::string(", or wrote something else than its answer to the grader's channel (") + error.what() + ")");
  }
}

// Reads the arguments a call may change, which come first in every answer.
template <typename... T>
void read_back(Reader& reply, const std::string& call, T&... arguments) {
  try {
    (reply >> ... >> arguments);
  } catch (const ProtocolError& error) {
    worker_gone(
        call, std::string(", or wrote something else than its answer to the grader's channel (") + error.what() + ")");
  }
}

void expect_end(Reader& reply, const std::string& call) {
  try {
    reply.expect_end();
  } catch (const ProtocolError& error) {
    worker_gone(
        call, std::string(", or wrote something else than its answer to the grader's channel (") + error.what() + ")");
  }
}

// A call of the propagate family: the state goes both ways, the collision comes back.
template <typename... Extra>
Collision step(Call which, const std::string& call, double table_radius, double circle_radius, int n,
               Coordinates& coordinates, Velocities& velocities, const Extra&... extra) {
  Writer request;
  request << which << table_radius << circle_radius << n << coordinates << velocities;
  if constexpr (sizeof...(extra) > 0) (request << ... << extra);
  auto reply = call_worker(request, call);
  read_back(reply, call, coordinates, velocities);
  finish(reply, call);
  return result<Collision>(reply, call);
}

}  // namespace
}  // namespace judge

namespace testing {

void use_worker(int worker_channel) {
  judge::channel = worker_channel;
  judge::gone = false;
}

}  // namespace testing

using judge::Call;
using judge::Writer;

Coordinates init_billiard(double table_radius, double circle_radius, int n, Rng& rng) {
  const std::string call = "init_billiard";
  Writer request;
  request << Call::init_billiard << table_radius << circle_radius << n << rng;
  auto reply = judge::call_worker(request, call);
  judge::read_back(reply, call, rng);
  judge::finish(reply, call);
  return judge::result<Coordinates>(reply, call);
}

Velocities init_velocities(int n, const Coordinates& coordinates, Rng& rng) {
  const std::string call = "init_velocities";
  Writer request;
  request << Call::init_velocities << n << coordinates << rng;
  auto reply = judge::call_worker(request, call);
  judge::read_back(reply, call, rng);
  judge::finish(reply, call);
  return judge::result<Velocities>(reply, call);
}

void visualize_table(double table_radius, double circle_radius, int n, const Coordinates& coordinates,
                     const std::filesystem::path& svg_file) {
  const std::string call = "visualize_table";
  Writer request;
  request << Call::visualize_table << table_radius << circle_radius << n << coordinates
          << judge::describe_file(svg_file);
  auto reply = judge::call_worker(request, call);
  judge::FileState file;
  judge::read_back(reply, call, file);
  judge::copy_back(svg_file, file);
  judge::finish(reply, call);
  judge::expect_end(reply, call);
}

Collision propagate(double table_radius, double circle_radius, int n, Coordinates& coordinates,
                    Velocities& velocities) {
  return judge::step(Call::propagate, "propagate", table_radius, circle_radius, n, coordinates, velocities);
}

void movie(double table_radius, double circle_radius, int n, Coordinates& coordinates, Velocities& velocities,
           int collisions, const std::filesystem::path& svg_file) {
  const std::string call = "movie";
  Writer request;
  request << Call::movie << table_radius << circle_radius << n << coordinates << velocities << collisions
          << judge::describe_file(svg_file);
  auto reply = judge::call_worker(request, call);
  judge::FileState file;
  judge::read_back(reply, call, coordinates, velocities, file);
  judge::copy_back(svg_file, file);
  judge::finish(reply, call);
  judge::expect_end(reply, call);
}

double kinetic_energy(int n, const Velocities& velocities) {
  const std::string call = "kinetic_energy";
  Writer request;
  request << Call::kinetic_energy << n << velocities;
  auto reply = judge::call_worker(request, call);
  judge::finish(reply, call);
  return judge::result<double>(reply, call);
}

void correct_energy_drift(int n, Velocities& velocities, double target_mean_square) {
  const std::string call = "correct_energy_drift";
  Writer request;
  request << Call::correct_energy_drift << n << velocities << target_mean_square;
  auto reply = judge::call_worker(request, call);
  judge::read_back(reply, call, velocities);
  judge::finish(reply, call);
  judge::expect_end(reply, call);
}

Collision propagate_gravity(double table_radius, double circle_radius, int n, Coordinates& coordinates,
                            Velocities& velocities, const Vector& g) {
  return judge::step(Call::propagate_gravity, "propagate_gravity", table_radius, circle_radius, n, coordinates,
                     velocities, g);
}

double mean_energy(int n, const Coordinates& coordinates, const Velocities& velocities, const Vector& g) {
  const std::string call = "mean_energy";
  Writer request;
  request << Call::mean_energy << n << coordinates << velocities << g;
  auto reply = judge::call_worker(request, call);
  judge::finish(reply, call);
  return judge::result<double>(reply, call);
}

Collision propagate_walls(double table_radius, double circle_radius, int n, Coordinates& coordinates,
                          Velocities& velocities, const std::vector<Wall>& walls) {
  return judge::step(Call::propagate_walls, "propagate_walls", table_radius, circle_radius, n, coordinates, velocities,
                     walls);
}

Collision propagate_sectors(double table_radius, double circle_radius, int n, Coordinates& coordinates,
                            Velocities& velocities, double cell_size) {
  return judge::step(Call::propagate_sectors, "propagate_sectors", table_radius, circle_radius, n, coordinates,
                     velocities, cell_size);
}

// Counted where task 9's code calls pair_time: in the worker.
long long pair_time_calls() {
  const std::string call = "pair_time_calls";
  Writer request;
  request << Call::pair_time_calls;
  auto reply = judge::call_worker(request, call);
  judge::finish(reply, call);
  return judge::result<std::int64_t>(reply, call);
}

namespace testing {

cli::Run run_student_program(const std::vector<std::string>& arguments,
                             const std::vector<std::pair<std::string, std::string>>& inputs,
                             const cli::Limits& limits) {
  const std::string call = "your program";
  judge::ProgramRun run{arguments, inputs, limits.seconds};
  Writer request;
  request << Call::run_program << run;
  auto reply = judge::call_worker(request, call);
  judge::finish(reply, call);
  const auto result = judge::result<judge::ProgramResult>(reply, call);
  cli::Run done;
  done.status = result.status;
  done.signal = result.signal;
  done.timed_out = result.timed_out;
  done.seconds = result.seconds;
  done.out = result.out;
  done.err = result.err;
  return done;
}

}  // namespace testing
}  // namespace billiard

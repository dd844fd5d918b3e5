// The worker: the process in which the student's code runs under the grader, linked with the
// student's task file and the code of the other tasks (the reference's, as compiled objects, or
// the student's own). It answers the judge's calls (proxy.cpp) one at a time on descriptor 3
// until the judge closes it: reads a call, makes it, and sends back the arguments the call may
// change and what it returned or threw. Whatever else the student's code does here (print,
// exit, crash, write to the channel itself) costs only this test's answers.
//
// It runs in a cell (tests/grader/cell/cell.c): its own folder, which holds the files of the
// calls that take a path, and nothing of the grader's or of other tests.
#include "judge/endings.hpp"
#include "judge/files.hpp"
#include "judge/wire.hpp"

#include "billiard/extensions.hpp"

#include <sys/prctl.h>

#include <cstdio>
#include <iostream>
#include <tuple>
#include <type_traits>

namespace {

using namespace billiard;
using judge::Call;
using judge::Ending;
using judge::Reader;
using judge::Writer;

constexpr int kChannel = 3;

// Makes `call`, then writes what `changed` writes (the arguments the call may change, whether it
// returned or threw) and how the call ended: Ending::returned and its value, or what it threw.
template <typename Function, typename Changed>
void answer(Writer& reply, Function&& call, Changed&& changed) {
  Writer ending;
  try {
    if constexpr (std::is_void_v<decltype(call())>) {
      call();
      ending << Ending::returned;
    } else {
      const auto value = call();
      ending << Ending::returned << value;
    }
  } catch (...) {
    judge::write_current_exception(ending);
  }
  changed(reply);
  reply.append(ending);
}

void nothing(Writer&) {}

// Answers a call of the propagate family: reads the table, the state and what else the function
// takes (`Extra`, or nothing), makes the call and sends the state back with the collision.
template <typename... Extra, typename Function>
void step(Reader& request, Writer& reply, Function function) {
  const auto R = request.get<double>();
  const auto a = request.get<double>();
  const auto n = request.get<std::int32_t>();
  auto coordinates = request.get<Coordinates>();
  auto velocities = request.get<Velocities>();
  const auto extra = std::make_tuple(request.get<Extra>()...);
  answer(
      reply,
      [&] {
        return std::apply([&](const auto&... more) { return function(R, a, n, coordinates, velocities, more...); },
                          extra);
      },
      [&](Writer& out) { out << coordinates << velocities; });
}

// Answers one call.
void serve(Reader& request, Writer& reply) {
  const auto call = request.get<Call>();
  switch (call) {
    case Call::init_billiard: {
      const auto R = request.get<double>();
      const auto a = request.get<double>();
      const auto n = request.get<std::int32_t>();
      auto rng = request.get<Rng>();
      answer(
          reply, [&] { return init_billiard(R, a, n, rng); }, [&](Writer& out) { out << rng; });
      return;
    }
    case Call::init_velocities: {
      const auto n = request.get<std::int32_t>();
      const auto coordinates = request.get<Coordinates>();
      auto rng = request.get<Rng>();
      answer(
          reply, [&] { return init_velocities(n, coordinates, rng); }, [&](Writer& out) { out << rng; });
      return;
    }
    case Call::visualize_table: {
      const auto R = request.get<double>();
      const auto a = request.get<double>();
      const auto n = request.get<std::int32_t>();
      const auto coordinates = request.get<Coordinates>();
      const auto file = judge::make_file(request.get<judge::FileState>(), {});
      answer(
          reply, [&] { visualize_table(R, a, n, coordinates, file); },
          [&](Writer& out) { out << judge::describe_file(file); });
      return;
    }
    case Call::propagate:
      step(request, reply, propagate);
      return;
    case Call::movie: {
      const auto R = request.get<double>();
      const auto a = request.get<double>();
      const auto n = request.get<std::int32_t>();
      auto coordinates = request.get<Coordinates>();
      auto velocities = request.get<Velocities>();
      const auto collisions = request.get<std::int32_t>();
      const auto file = judge::make_file(request.get<judge::FileState>(), {});
      answer(
          reply, [&] { movie(R, a, n, coordinates, velocities, collisions, file); },
          [&](Writer& out) { out << coordinates << velocities << judge::describe_file(file); });
      return;
    }
    case Call::kinetic_energy: {
      const auto n = request.get<std::int32_t>();
      const auto velocities = request.get<Velocities>();
      answer(
          reply, [&] { return kinetic_energy(n, velocities); }, nothing);
      return;
    }
    case Call::correct_energy_drift: {
      const auto n = request.get<std::int32_t>();
      auto velocities = request.get<Velocities>();
      const auto target = request.get<double>();
      answer(
          reply, [&] { correct_energy_drift(n, velocities, target); }, [&](Writer& out) { out << velocities; });
      return;
    }
    case Call::propagate_gravity:
      step<Vector>(request, reply, propagate_gravity);
      return;
    case Call::mean_energy: {
      const auto n = request.get<std::int32_t>();
      const auto coordinates = request.get<Coordinates>();
      const auto velocities = request.get<Velocities>();
      const auto g = request.get<Vector>();
      answer(
          reply, [&] { return mean_energy(n, coordinates, velocities, g); }, nothing);
      return;
    }
    case Call::propagate_walls:
      step<std::vector<Wall>>(request, reply, propagate_walls);
      return;
    case Call::propagate_sectors:
      step<double>(request, reply, propagate_sectors);
      return;
    case Call::pair_time_calls:
      answer(
          reply, [] { return static_cast<std::int64_t>(pair_time_calls()); }, nothing);
      return;
    case Call::run_program:
      break;
  }
  answer(
      reply, []() -> int { throw std::logic_error("this worker runs course functions, not programs"); }, nothing);
}

}  // namespace

int main() {
  // Not traceable by processes of the same user (where cells share one): the cell's filter keeps it so.
  ::prctl(PR_SET_DUMPABLE, 0, 0, 0, 0);
  for (;;) {
    std::string message;
    try {
      message = judge::receive(kChannel);
    } catch (const judge::ProtocolError&) {
      return 0;  // the judge is done with this test
    }
    Reader request(std::move(message));
    Writer reply;
    serve(request, reply);
    std::cout.flush();
    std::fflush(nullptr);  // what the code printed reaches the grader before the answer's end
    judge::send(kChannel, reply.bytes());
  }
}

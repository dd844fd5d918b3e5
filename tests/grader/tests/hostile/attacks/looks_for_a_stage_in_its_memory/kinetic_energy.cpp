// Attack: a stage's reference code in this task's process. Without gravity, the gravity stage's
// mean_energy is the mean kinetic energy, and code in the same process can be reached without
// naming it (the grader refuses a file that names another task's function). This file looks
// through its own program's memory for a message only the gravity stage's reference code holds
// and says "FOUND" if it is there: the worker of task 6 must hold no other task's reference code.
#include <link.h>

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <string>

#include "billiard/course.hpp"

namespace billiard {
namespace {

// The gravity stage's message for circles at rest without gravity, reversed (so that this file
// does not hold it itself).
std::string marker() {
  std::string text = "neppah reve lliw noisilloc on os ,0 = g dna tser ta era selcric lla";
  std::reverse(text.begin(), text.end());
  return text;
}

bool in_my_program(const std::string& text) {
  struct Search {
    const std::string* text;
    bool found;
  } search{&text, false};
  dl_iterate_phdr(
      [](dl_phdr_info* info, std::size_t, void* data) {
        auto* search = static_cast<Search*>(data);
        for (int k = 0; k < info->dlpi_phnum; ++k) {
          const ElfW(Phdr)& segment = info->dlpi_phdr[k];
          if (segment.p_type != PT_LOAD || !(segment.p_flags & PF_R)) continue;
          const char* start = reinterpret_cast<const char*>(info->dlpi_addr + segment.p_vaddr);
          if (memmem(start, segment.p_filesz, search->text->data(), search->text->size()) != nullptr) {
            search->found = true;
          }
        }
        return 1;  // the program itself only: the first object listed
      },
      &search);
  return search.found;
}

}  // namespace

double kinetic_energy(int, const Velocities&) {
  throw std::runtime_error(in_my_program(marker()) ? "FOUND: the gravity stage's reference code is in this process"
                                                   : "no other task's reference code here");
}

void correct_energy_drift(int n, Velocities& velocities, double) { kinetic_energy(n, velocities); }

}  // namespace billiard

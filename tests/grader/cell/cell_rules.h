/* The cell's seccomp filter (cell.c), shared with the program runner, which forbids new
 * processes to the program it starts (tests/grader/judge/program_runner.cpp). */
#ifndef BILLIARD_CELL_RULES_H
#define BILLIARD_CELL_RULES_H

#include <sys/types.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Loads the filter described at the top of cell.c; with `no_fork`, no new processes either
 * (threads only). `self` is the process's pid, which signals may still reach. Returns 0, or a
 * negative errno with errno set. */
int cell_seccomp(pid_t self, int no_fork);

/* Loads a filter that forbids new processes (threads only), on top of any filter in force. */
int cell_forbid_new_processes(void);

/* 1 where seccomp filters can be loaded here, else 0. */
int cell_seccomp_available(void);

#ifdef __cplusplus
}
#endif

#endif

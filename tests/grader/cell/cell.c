/* The cell: starts one program of a grading confined, so that submitted code can give wrong
 * answers and nothing else (the instructors' guide, "What a submission can and cannot do").
 *
 *   cell [OPTIONS] -- PROGRAM [ARGUMENT...]
 *   cell --probe
 *   cell --user ID --kill-all
 *
 * --probe prints what this machine lets a cell use, one "NAME VALUE" line each: "landlock N"
 * (the Landlock ABI, 0 where there is none), "seccomp 1|0", "user-ids 1|0" (running as root).
 *
 * --kill-all stops every process of user ID (as root): the end of a cell, whatever it started.
 *
 * Otherwise, in this order, then PROGRAM replaces the cell (same process):
 *   --dir DIR            the working folder, also HOME and TMPDIR
 *   --cpu SECONDS        RLIMIT_CPU (the grader stops tests at their limits itself: a backstop)
 *   --memory BYTES       RLIMIT_AS, per process
 *   --file-size BYTES    RLIMIT_FSIZE, per file written
 *   --open-files N       RLIMIT_NOFILE
 *   --processes N        RLIMIT_NPROC: processes and threads of the user id (with --user)
 *   --user ID            run as user and group ID, no supplementary groups (as root only)
 *   --read PATH          Landlock: read and execute beneath PATH (repeatable)
 *   --write PATH         Landlock: also write, create and remove beneath PATH (repeatable)
 *   --require-landlock   fail where Landlock cannot be applied
 *   --no-landlock        leave Landlock out (the cell's tests try each protection alone)
 *   --no-fork            seccomp: no new processes, threads only
 *   --fd FROM:TO         descriptor FROM becomes TO (repeatable); all others but 0, 1, 2 close
 *   --env NAME=VALUE     the environment holds only these, PATH, LANG, HOME and TMPDIR
 *
 * Always: a session of its own (the grader stops the whole group), no core files, no new
 * privileges, Landlock where the kernel has it (the system's program folders read-only, only the
 * --read and --write paths beyond them; no TCP; no signals or abstract sockets out of the cell),
 * and a seccomp filter that refuses what lets one process reach another or outlive the grading:
 * tracing, reading or writing another's memory, signals to any process but its own group,
 * sockets, System V and POSIX message queues and shared memory, memory files, key rings, BPF,
 * performance counters, io_uring, user faults, namespaces and mounts, and making itself
 * traceable again. A cell that cannot be set up exits with status 125 and says why on stderr.
 */
#define _GNU_SOURCE
#include <errno.h>
#include <dirent.h>
#include <fcntl.h>
#include <grp.h>
#include <linux/landlock.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <unistd.h>

#include "cell_rules.h"

/* Landlock's newer rights, from the kernel's uapi (Debian 12's headers stop at ABI 2). */
#ifndef LANDLOCK_ACCESS_FS_TRUNCATE
#define LANDLOCK_ACCESS_FS_TRUNCATE (1ULL << 14) /* ABI 3 */
#endif
#ifndef LANDLOCK_ACCESS_FS_IOCTL_DEV
#define LANDLOCK_ACCESS_FS_IOCTL_DEV (1ULL << 15) /* ABI 5 */
#endif
#define CELL_ACCESS_NET_BIND_TCP (1ULL << 0)           /* ABI 4 */
#define CELL_ACCESS_NET_CONNECT_TCP (1ULL << 1)        /* ABI 4 */
#define CELL_SCOPE_ABSTRACT_UNIX_SOCKET (1ULL << 0)    /* ABI 6 */
#define CELL_SCOPE_SIGNAL (1ULL << 1)                  /* ABI 6 */

/* The ruleset's attributes as ABI 6 has them; older kernels are given the prefix they know. */
struct cell_ruleset_attr {
  uint64_t handled_access_fs;
  uint64_t handled_access_net;
  uint64_t scoped;
};

enum { kCellFailed = 125, kMaxPaths = 64, kMaxFds = 16, kMaxEnv = 32 };

static void fail(const char* what) {
  fprintf(stderr, "cell: %s: %s\n", what, strerror(errno));
  exit(kCellFailed);
}

static void refuse(const char* what, const char* value) {
  fprintf(stderr, "cell: %s%s\n", what, value ? value : "");
  exit(kCellFailed);
}

static int landlock_abi(void) {
  const long abi = syscall(SYS_landlock_create_ruleset, NULL, 0, LANDLOCK_CREATE_RULESET_VERSION);
  return abi < 0 ? 0 : (int)abi;
}

/* The file-system rights Landlock knows at `abi`, all of which the cell handles (denies unless a
 * rule allows them). */
static uint64_t handled_fs(int abi) {
  uint64_t rights = (LANDLOCK_ACCESS_FS_MAKE_SYM << 1) - 1; /* ABI 1: bits 0 to 12 */
  if (abi >= 2) rights |= LANDLOCK_ACCESS_FS_REFER;
  if (abi >= 3) rights |= LANDLOCK_ACCESS_FS_TRUNCATE;
  if (abi >= 5) rights |= LANDLOCK_ACCESS_FS_IOCTL_DEV;
  return rights;
}

static const uint64_t kReadRights =
    LANDLOCK_ACCESS_FS_EXECUTE | LANDLOCK_ACCESS_FS_READ_FILE | LANDLOCK_ACCESS_FS_READ_DIR;
/* Rights that apply to a file itself (a rule on a file, not a folder, may grant only these). */
static const uint64_t kFileRights = LANDLOCK_ACCESS_FS_EXECUTE | LANDLOCK_ACCESS_FS_WRITE_FILE |
                                    LANDLOCK_ACCESS_FS_READ_FILE | LANDLOCK_ACCESS_FS_TRUNCATE |
                                    LANDLOCK_ACCESS_FS_IOCTL_DEV;

/* Allows `rights` beneath `path` (a folder, or a single file); a path that does not exist on this
 * machine (such as /lib64 on some systems) is left out. */
static void allow_path(int ruleset, const char* path, uint64_t rights, uint64_t handled) {
  const int fd = open(path, O_PATH | O_CLOEXEC);
  if (fd < 0) {
    if (errno == ENOENT) return;
    fail(path);
  }
  struct stat info;
  if (fstat(fd, &info) != 0) fail(path);
  if (!S_ISDIR(info.st_mode)) rights &= kFileRights;
  struct landlock_path_beneath_attr rule = {.allowed_access = rights & handled, .parent_fd = fd};
  if (syscall(SYS_landlock_add_rule, ruleset, LANDLOCK_RULE_PATH_BENEATH, &rule, 0) != 0) fail(path);
  close(fd);
}

/* What every program needs to start and run: the system's programs and libraries, the dynamic
 * linker's cache, the time zone, and the harmless devices. */
static const char* const kSystemPaths[] = {"/usr", "/lib", "/lib64", "/lib32", "/libx32", "/bin", "/sbin",
                                           "/etc/ld.so.cache", "/etc/localtime", "/dev/zero",
                                           "/dev/urandom", "/dev/random"};

/* Applies Landlock: returns the ABI used, 0 where the kernel has none. */
static int apply_landlock(const char* const* reads, int read_count, const char* const* writes, int write_count,
                          int required) {
  const int abi = landlock_abi();
  if (abi == 0) {
    if (required) refuse("Landlock is required (--require-landlock) but this kernel does not offer it", NULL);
    return 0;
  }
  struct cell_ruleset_attr attr = {.handled_access_fs = handled_fs(abi)};
  size_t size = sizeof attr.handled_access_fs;
  if (abi >= 4) {
    attr.handled_access_net = CELL_ACCESS_NET_BIND_TCP | CELL_ACCESS_NET_CONNECT_TCP;
    size += sizeof attr.handled_access_net;
  }
  if (abi >= 6) {
    attr.scoped = CELL_SCOPE_ABSTRACT_UNIX_SOCKET | CELL_SCOPE_SIGNAL;
    size += sizeof attr.scoped;
  }
  const int ruleset = (int)syscall(SYS_landlock_create_ruleset, &attr, size, 0);
  if (ruleset < 0) fail("creating the Landlock ruleset");
  const uint64_t handled = attr.handled_access_fs;
  for (size_t i = 0; i < sizeof kSystemPaths / sizeof kSystemPaths[0]; ++i) {
    allow_path(ruleset, kSystemPaths[i], kReadRights, handled);
  }
  allow_path(ruleset, "/dev/null", kReadRights | LANDLOCK_ACCESS_FS_WRITE_FILE, handled);
  for (int i = 0; i < read_count; ++i) allow_path(ruleset, reads[i], kReadRights, handled);
  /* Writing: everything but making device files (which needs privileges anyway). */
  const uint64_t write_rights = handled & ~(uint64_t)(LANDLOCK_ACCESS_FS_MAKE_CHAR | LANDLOCK_ACCESS_FS_MAKE_BLOCK);
  for (int i = 0; i < write_count; ++i) allow_path(ruleset, writes[i], write_rights, handled);
  if (syscall(SYS_landlock_restrict_self, ruleset, 0) != 0) fail("applying the Landlock ruleset");
  close(ruleset);
  return abi;
}

static long long number(const char* option, const char* text) {
  char* end = NULL;
  errno = 0;
  const long long value = strtoll(text, &end, 10);
  if (errno != 0 || end == text || *end != '\0' || value < 0) refuse(option, " needs a non-negative whole number");
  return value;
}

static void set_limit(int resource, long long soft, long long hard, const char* name) {
  const struct rlimit limit = {(rlim_t)soft, (rlim_t)hard};
  if (setrlimit(resource, &limit) != 0) fail(name);
}

/* Closes every descriptor from 3 up but the `kept` ones. */
static void close_others(const int* kept, int count) {
  unsigned first = 3;
  for (;;) {
    unsigned next = ~0U; /* the lowest kept descriptor at or above `first` */
    for (int i = 0; i < count; ++i) {
      if ((unsigned)kept[i] >= first && (unsigned)kept[i] < next) next = (unsigned)kept[i];
    }
    if (next > first && syscall(SYS_close_range, first, next == ~0U ? ~0U : next - 1, 0) != 0) {
      for (unsigned fd = first; fd < (next == ~0U ? 65536U : next); ++fd) close((int)fd);
    }
    if (next == ~0U) return;
    first = next + 1;
  }
}

/* The number of processes of user `user` still running (zombies, which are over, not counted). */
static int running_processes(uid_t user) {
  DIR* proc = opendir("/proc");
  if (proc == NULL) return 0;
  int count = 0;
  for (struct dirent* entry; (entry = readdir(proc)) != NULL;) {
    if (entry->d_name[0] < '0' || entry->d_name[0] > '9') continue;
    char path[300], line[256];
    snprintf(path, sizeof path, "/proc/%s/status", entry->d_name);
    FILE* status = fopen(path, "r");
    if (status == NULL) continue;
    int zombie = 0, mine = 0;
    while (fgets(line, sizeof line, status) != NULL) {
      if (strncmp(line, "State:", 6) == 0) zombie = strchr(line, 'Z') != NULL || strchr(line, 'X') != NULL;
      unsigned real = 0;
      if (sscanf(line, "Uid: %u", &real) == 1) mine = real == user;
    }
    fclose(status);
    count += mine && !zombie;
  }
  closedir(proc);
  return count;
}

/* As user `user`, signals every process it may: all of that user's but this one (kill(-1)), until
 * none is left running (a process may start others while they are stopped). */
static int kill_everything(long long user) {
  if (user < 0 || geteuid() != 0) refuse("--kill-all needs root and --user", NULL);
  if (setgroups(0, NULL) != 0 || setresgid((gid_t)user, (gid_t)user, (gid_t)user) != 0 ||
      setresuid((uid_t)user, (uid_t)user, (uid_t)user) != 0) {
    fail("changing the user id");
  }
  for (int round = 0; round < 1000; ++round) {
    for (int again = 0; again < 20; ++again) {
      if (kill(-1, SIGKILL) != 0 && errno == ESRCH) return 0;
    }
    if (running_processes((uid_t)user) <= 1) return 0;  /* this one */
    usleep(1000);
  }
  refuse("processes kept appearing while they were stopped", NULL);
  return kCellFailed;
}

static int probe(void) {
  printf("landlock %d\n", landlock_abi());
  printf("seccomp %d\n", cell_seccomp_available());
  printf("user-ids %d\n", geteuid() == 0);
  return 0;
}

int main(int argc, char** argv) {
  const char* reads[kMaxPaths];
  const char* writes[kMaxPaths];
  const char* environment[kMaxEnv + 5];
  int fd_from[kMaxFds], fd_to[kMaxFds];
  int read_count = 0, write_count = 0, env_count = 0, fd_count = 0;
  const char* dir = NULL;
  long long cpu = -1, memory = -1, file_size = -1, open_files = -1, processes = -1, user = -1;
  int no_fork = 0, require_landlock = 0, no_landlock = 0, kill_all = 0;
  int at = 1;
  for (; at < argc; ++at) {
    const char* option = argv[at];
    if (strcmp(option, "--") == 0) {
      ++at;
      break;
    }
    if (strcmp(option, "--probe") == 0) return probe();
    if (strcmp(option, "--no-fork") == 0) {
      no_fork = 1;
      continue;
    }
    if (strcmp(option, "--kill-all") == 0) {
      kill_all = 1;
      continue;
    }
    if (strcmp(option, "--no-landlock") == 0) {
      no_landlock = 1;
      continue;
    }
    if (strcmp(option, "--require-landlock") == 0) {
      require_landlock = 1;
      continue;
    }
    if (at + 1 >= argc) refuse("missing the value of ", option);
    const char* value = argv[++at];
    if (strcmp(option, "--dir") == 0) {
      dir = value;
    } else if (strcmp(option, "--cpu") == 0) {
      cpu = number(option, value);
    } else if (strcmp(option, "--memory") == 0) {
      memory = number(option, value);
    } else if (strcmp(option, "--file-size") == 0) {
      file_size = number(option, value);
    } else if (strcmp(option, "--open-files") == 0) {
      open_files = number(option, value);
    } else if (strcmp(option, "--processes") == 0) {
      processes = number(option, value);
    } else if (strcmp(option, "--user") == 0) {
      user = number(option, value);
    } else if (strcmp(option, "--read") == 0 || strcmp(option, "--write") == 0) {
      const int write = option[2] == 'w';
      if ((write ? write_count : read_count) == kMaxPaths) refuse("too many paths: ", value);
      if (write) {
        writes[write_count++] = value;
      } else {
        reads[read_count++] = value;
      }
    } else if (strcmp(option, "--fd") == 0) {
      char* colon = strchr(value, ':');
      if (colon == NULL || fd_count == kMaxFds) refuse("--fd takes FROM:TO, got ", value);
      *colon = '\0';
      fd_from[fd_count] = (int)number(option, value);
      fd_to[fd_count++] = (int)number(option, colon + 1);
    } else if (strcmp(option, "--env") == 0) {
      if (strchr(value, '=') == NULL || env_count == kMaxEnv) refuse("--env takes NAME=VALUE, got ", value);
      environment[env_count++] = value;
    } else {
      refuse("unknown option ", option);
    }
  }
  if (kill_all) return kill_everything(user);
  if (at >= argc) refuse("no program to run: cell [OPTIONS] -- PROGRAM [ARGUMENT...]", NULL);

  if (setsid() < 0 && errno != EPERM) fail("setsid");

  /* Descriptors: each FROM moves to its TO (through numbers above them all, so that moves do not
   * overwrite one another), and every other one but 0, 1 and 2 is closed. */
  int highest = 2;
  for (int i = 0; i < fd_count; ++i) highest = fd_from[i] > highest ? fd_from[i] : highest;
  for (int i = 0; i < fd_count; ++i) highest = fd_to[i] > highest ? fd_to[i] : highest;
  for (int i = 0; i < fd_count; ++i) {
    const int moved = fcntl(fd_from[i], F_DUPFD_CLOEXEC, highest + 1);
    if (moved < 0) fail("--fd");
    fd_from[i] = moved;
  }
  for (int i = 0; i < fd_count; ++i) {
    if (dup2(fd_from[i], fd_to[i]) < 0) fail("--fd");
  }
  close_others(fd_to, fd_count);

  set_limit(RLIMIT_CORE, 0, 0, "RLIMIT_CORE");
  /* CPU: SIGXCPU at the limit, SIGKILL a second later. */
  if (cpu >= 0) set_limit(RLIMIT_CPU, cpu, cpu + 1, "RLIMIT_CPU");
  if (memory >= 0) set_limit(RLIMIT_AS, memory, memory, "RLIMIT_AS");
  if (file_size >= 0) set_limit(RLIMIT_FSIZE, file_size, file_size, "RLIMIT_FSIZE");
  if (open_files >= 0) set_limit(RLIMIT_NOFILE, open_files, open_files, "RLIMIT_NOFILE");

  if (dir != NULL && chdir(dir) != 0) fail(dir);
  if (user >= 0) {
    if (geteuid() != 0) refuse("--user needs root", NULL);
    if (processes >= 0) set_limit(RLIMIT_NPROC, processes, processes, "RLIMIT_NPROC");
    if (setgroups(0, NULL) != 0 || setresgid((gid_t)user, (gid_t)user, (gid_t)user) != 0 ||
        setresuid((uid_t)user, (uid_t)user, (uid_t)user) != 0) {
      fail("changing the user id");
    }
  } else if (processes >= 0) {
    set_limit(RLIMIT_NPROC, processes, processes, "RLIMIT_NPROC");
  }
  if (prctl(PR_SET_NO_NEW_PRIVS, 1, 0, 0, 0) != 0) fail("no_new_privs");
  if (!no_landlock) apply_landlock(reads, read_count, writes, write_count, require_landlock);

  const char* home = dir != NULL ? dir : "/";
  static char home_line[4200], tmp_line[4200];
  snprintf(home_line, sizeof home_line, "HOME=%s", home);
  snprintf(tmp_line, sizeof tmp_line, "TMPDIR=%s", home);
  environment[env_count++] = "PATH=/usr/bin:/bin";
  environment[env_count++] = "LANG=C.UTF-8";
  environment[env_count++] = home_line;
  environment[env_count++] = tmp_line;
  environment[env_count] = NULL;

  if (cell_seccomp(getpid(), no_fork) != 0) fail("loading the seccomp filter");
  execve(argv[at], argv + at, (char* const*)environment);
  fail(argv[at]);
  return kCellFailed;
}

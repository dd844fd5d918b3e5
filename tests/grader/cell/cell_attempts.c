/* What submitted code might try from inside a cell, one attempt per run, for the cell's tests
 * (test_cell.py):
 *
 *   cell_attempts ATTEMPT [ARGUMENT]
 *
 * prints "allowed" when the attempt succeeded, else "denied ERRNO_NAME", and exits 0. An attempt
 * the cell ends (a call of another architecture) prints nothing. Signals are sent as signal 0,
 * which only asks whether a signal could be sent, so that a failing test harms nothing.
 */
#define _GNU_SOURCE
#include <errno.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <pthread.h>
#include <sched.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ipc.h>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <sys/ptrace.h>
#include <sys/shm.h>
#include <sys/socket.h>
#include <sys/syscall.h>
#include <sys/uio.h>
#include <sys/wait.h>
#include <unistd.h>

static int report(long result) {
  if (result >= 0) {
    puts("allowed");
  } else {
    printf("denied %s\n", strerrorname_np(errno) ? strerrorname_np(errno) : "?");
  }
  return 0;
}

static void* idle(void* unused) { return unused; }

static long pid_argument(const char* argument) { return argument ? atol(argument) : (long)getppid(); }

int main(int argc, char** argv) {
  if (argc < 2) {
    fprintf(stderr, "usage: cell_attempts ATTEMPT [ARGUMENT]\n");
    return 2;
  }
  const char* attempt = argv[1];
  const char* argument = argc > 2 ? argv[2] : NULL;
  if (strcmp(attempt, "fork") == 0) {
    const pid_t child = fork();
    if (child == 0) _exit(0);
    if (child > 0) waitpid(child, NULL, 0);
    return report(child);
  }
  if (strcmp(attempt, "thread") == 0) {
    pthread_t thread;
    const int error = pthread_create(&thread, NULL, idle, NULL);
    if (error == 0) pthread_join(thread, NULL);
    errno = error;
    return report(error == 0 ? 0 : -1);
  }
  if (strcmp(attempt, "clone3") == 0) {
    errno = 0;
    long result = syscall(SYS_clone3, NULL, 0);
    /* A real clone3 refuses a null argument with EFAULT or EINVAL: it was looked at, so allowed. */
    if (result < 0 && (errno == EFAULT || errno == EINVAL)) result = 0;
    return report(result);
  }
  if (strcmp(attempt, "signal") == 0) return report(kill((pid_t)pid_argument(argument), 0));
  if (strcmp(attempt, "signal-everyone") == 0) return report(kill(-1, 0));
  if (strcmp(attempt, "signal-self") == 0) return report(kill(getpid(), 0) == 0 || kill(0, 0) == 0 ? 0 : -1);
  if (strcmp(attempt, "raise") == 0) return report(syscall(SYS_tgkill, getpid(), getpid(), 0));
  if (strcmp(attempt, "tgkill") == 0) {
    const long pid = pid_argument(argument);
    return report(syscall(SYS_tgkill, pid, pid, 0));
  }
  if (strcmp(attempt, "ptrace") == 0) {
    const long result = ptrace(PTRACE_SEIZE, (pid_t)pid_argument(argument), NULL, NULL);
    if (result == 0) ptrace(PTRACE_DETACH, (pid_t)pid_argument(argument), NULL, NULL);
    return report(result);
  }
  if (strcmp(attempt, "read-memory") == 0) {
    char buffer[16];
    struct iovec local = {buffer, sizeof buffer};
    struct iovec remote = {(void*)0x400000, sizeof buffer};
    const long result = process_vm_readv((pid_t)pid_argument(argument), &local, 1, &remote, 1, 0);
    /* ESRCH/EFAULT mean the kernel let the call through to the other process. */
    return report(result < 0 && errno == EFAULT ? 0 : result);
  }
  if (strcmp(attempt, "read") == 0 || strcmp(attempt, "list") == 0) {
    const int fd = open(argument, strcmp(attempt, "list") == 0 ? O_RDONLY | O_DIRECTORY : O_RDONLY);
    if (fd < 0) return report(-1);
    char byte;
    const long result = strcmp(attempt, "list") == 0 ? 0 : read(fd, &byte, 1);
    close(fd);
    return report(result);
  }
  if (strcmp(attempt, "write") == 0) {
    const int fd = open(argument, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd < 0) return report(-1);
    const long result = write(fd, "x", 1);
    close(fd);
    return report(result);
  }
  if (strcmp(attempt, "execute") == 0) {
    const pid_t child = vfork();
    if (child == 0) {
      execl(argument, argument, (char*)NULL);
      _exit(127);
    }
    int status = 0;
    if (child < 0) return report(-1);
    waitpid(child, &status, 0);
    errno = EACCES;
    return report(WIFEXITED(status) && WEXITSTATUS(status) != 127 ? 0 : -1);
  }
  if (strcmp(attempt, "socket-inet") == 0) return report(socket(AF_INET, SOCK_STREAM, 0));
  if (strcmp(attempt, "socket-unix") == 0) return report(socket(AF_UNIX, SOCK_STREAM, 0));
  if (strcmp(attempt, "socketpair") == 0) {
    int pair[2];
    return report(socketpair(AF_UNIX, SOCK_STREAM, 0, pair));
  }
  if (strcmp(attempt, "sysv-shared-memory") == 0) return report(shmget(IPC_PRIVATE, 4096, IPC_CREAT | 0600));
  if (strcmp(attempt, "memory-file") == 0) return report(memfd_create("stash", 0));
  if (strcmp(attempt, "user-namespace") == 0) return report(unshare(CLONE_NEWUSER));
  if (strcmp(attempt, "dumpable") == 0) return report(prctl(PR_SET_DUMPABLE, 1, 0, 0, 0));
  if (strcmp(attempt, "become-root") == 0) return report(setuid(0));
  if (strcmp(attempt, "x32") == 0) return report(syscall(0x40000000 | SYS_getpid));
  if (strcmp(attempt, "i386") == 0) {
    long result = 20; /* getpid in the 32-bit table */
    __asm__ volatile("int $0x80" : "+a"(result) : : "memory");
    errno = result < 0 ? (int)-result : 0;
    return report(result < 0 ? -1 : 0);
  }
  fprintf(stderr, "cell_attempts: unknown attempt %s\n", attempt);
  return 2;
}

#define _GNU_SOURCE
#include "cell_rules.h"

#include <errno.h>
#include <sched.h>
#include <seccomp.h>
#include <stddef.h>
#include <stdint.h>
#include <sys/prctl.h>

/* Adds a rule that fails `call` with `error` when `arguments` match. A call this libseccomp or
 * kernel does not know cannot be made either: nothing to add. */
static int deny(scmp_filter_ctx filter, int error, int call, unsigned count, const struct scmp_arg_cmp* arguments) {
  const int status = seccomp_rule_add_array(filter, SCMP_ACT_ERRNO(error), call, count, arguments);
  return status == -EDOM ? 0 : status;
}

static int deny_named(scmp_filter_ctx filter, int error, const char* name) {
  const int call = seccomp_syscall_resolve_name(name);
  return call == __NR_SCMP_ERROR ? 0 : deny(filter, error, call, 0, NULL);
}

/* What a process of the cell may never do (see cell.c). */
static const char* const kDenied[] = {
    "ptrace", "process_vm_readv", "process_vm_writev", "kcmp", "process_madvise", "pidfd_open", "pidfd_getfd",
    "pidfd_send_signal", "socket", "shmget", "msgget", "semget", "mq_open", "memfd_create", "memfd_secret",
    "keyctl", "add_key", "request_key", "bpf", "perf_event_open", "userfaultfd", "io_uring_setup",
    "io_uring_enter", "io_uring_register", "unshare", "setns", "mount", "umount2", "pivot_root", "chroot",
    "fsopen", "fsmount", "open_tree", "move_mount", "name_to_handle_at", "open_by_handle_at", "fanotify_init",
    "syslog", "acct", "swapon", "swapoff", "reboot", "kexec_load", "init_module", "finit_module",
    "delete_module", "quotactl", "migrate_pages", "move_pages", "personality"};

static int add_process_rules(scmp_filter_ctx filter) {
  int status = deny_named(filter, EPERM, "fork");
  if (status == 0) status = deny_named(filter, EPERM, "vfork");
  /* clone without CLONE_THREAD makes a process; with it, a thread. clone3 passes its flags in
   * memory a filter cannot read: "not implemented" makes the C library fall back to clone. */
  const struct scmp_arg_cmp process[] = {SCMP_A0_64(SCMP_CMP_MASKED_EQ, CLONE_THREAD, 0)};
  if (status == 0) status = deny(filter, EPERM, SCMP_SYS(clone), 1, process);
  if (status == 0) status = deny_named(filter, ENOSYS, "clone3");
  return status;
}

static int load(scmp_filter_ctx filter, int status) {
  /* Calls of another architecture (int 0x80 on x86-64, x32) end the process: libseccomp's
   * default for a filter of the native architecture alone. seccomp_load sets no_new_privs. */
  if (status == 0) status = seccomp_load(filter);
  seccomp_release(filter);
  if (status != 0) errno = -status;
  return status;
}

int cell_seccomp(pid_t self, int no_fork) {
  scmp_filter_ctx filter = seccomp_init(SCMP_ACT_ALLOW);
  if (filter == NULL) {
    errno = ENOSYS;
    return -ENOSYS;
  }
  int status = 0;
  for (size_t i = 0; status == 0 && i < sizeof kDenied / sizeof kDenied[0]; ++i) {
    status = deny_named(filter, EPERM, kDenied[i]);
  }
  /* Signals: kill(0, ...) reaches the cell's own group; tgkill and the queued signals only its
   * own threads (raise() and abort() use tgkill). */
  const struct scmp_arg_cmp not_group[] = {SCMP_A0_32(SCMP_CMP_NE, 0)};
  const struct scmp_arg_cmp not_self[] = {SCMP_A0_32(SCMP_CMP_NE, (uint32_t)self)};
  if (status == 0) status = deny(filter, EPERM, SCMP_SYS(kill), 1, not_group);
  if (status == 0) status = deny(filter, EPERM, SCMP_SYS(tgkill), 1, not_self);
  if (status == 0) status = deny(filter, EPERM, SCMP_SYS(tkill), 1, not_self);
  if (status == 0) status = deny(filter, EPERM, SCMP_SYS(rt_sigqueueinfo), 1, not_self);
  if (status == 0) status = deny(filter, EPERM, SCMP_SYS(rt_tgsigqueueinfo), 1, not_self);
  /* Once not dumpable (the grader's processes make themselves so), never dumpable again, and no
   * process may be named as one allowed to trace it. */
  const struct scmp_arg_cmp dumpable[] = {SCMP_A0_32(SCMP_CMP_EQ, PR_SET_DUMPABLE), SCMP_A1_64(SCMP_CMP_NE, 0)};
  const struct scmp_arg_cmp ptracer[] = {SCMP_A0_32(SCMP_CMP_EQ, PR_SET_PTRACER)};
  if (status == 0) status = deny(filter, EPERM, SCMP_SYS(prctl), 2, dumpable);
  if (status == 0) status = deny(filter, EPERM, SCMP_SYS(prctl), 1, ptracer);
  if (status == 0 && no_fork) status = add_process_rules(filter);
  return load(filter, status);
}

int cell_forbid_new_processes(void) {
  scmp_filter_ctx filter = seccomp_init(SCMP_ACT_ALLOW);
  if (filter == NULL) {
    errno = ENOSYS;
    return -ENOSYS;
  }
  return load(filter, add_process_rules(filter));
}

int cell_seccomp_available(void) {
  scmp_filter_ctx filter = seccomp_init(SCMP_ACT_ALLOW);
  if (filter == NULL) return 0;
  seccomp_release(filter);
  return prctl(PR_GET_SECCOMP, 0, 0, 0, 0) >= 0;
}

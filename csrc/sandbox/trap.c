/* The sandboxed worker's SIGSYS handler.
 *
 * The worker's seccomp filter (crslab/sandbox/syscalls.py) answers every system call a run does
 * not need with SECCOMP_RET_TRAP: the call is not made and the kernel raises SIGSYS in the
 * calling thread, with the call's number in siginfo and its arguments in the saved registers.
 * This handler writes them, with the path the call named, into the shared block the crslab
 * process reads (crs_shared.refusal, csrc/board/board.h) and ends the worker at once: the run ends
 * with a diagnosis instead of a lab that carries on after a silent EPERM.
 *
 * Two calls are answered instead of refused:
 * - The filter is loaded before the lab's shared object, so that its constructors already run
 *   inside it, and the dynamic loader must still open that one file. While loading is on, an
 *   open of exactly that path for reading gets a duplicate of a descriptor the worker opened
 *   before the sandbox (rewound to the start), which is all the loader needs.
 * - With --sanitize, the sanitizer runtime's own opens for reading are made with openat2,
 *   which the filter allows (Landlock still decides what they may read): those of
 *   /proc/self/maps, /cmdline and /environ (all of them the lab can already read in its own
 *   memory), and, once the sanitizer has begun its report (its
 *   report file is no longer empty), those of the lab's debug information. Before that, any
 *   other open is the lab's and is refused.
 * - A signal mask that would block SIGSYS (glibc blocks every signal before it starts a process
 *   for fork(), system() or posix_spawn(), and the kernel would then kill the worker without
 *   a word) is applied here without SIGSYS, through the mask the handler returns to.
 * Everything here is async-signal-safe: raw system calls and plain copies. */
#define _GNU_SOURCE
#include "trap.h"

#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <ucontext.h>
#include <unistd.h>

enum { PATH_CAPACITY = 4096, ALT_STACK_BYTES = 65536 };

static crs_shared *g_shared;
static char g_lab_path[PATH_CAPACITY];
static int g_lab_fd = -1;
static int g_report_fd = -1;
static volatile int32_t g_loading;
static int8_t g_path_arg[CRS_TRAP_SYSCALLS];
static char g_alt_stack[ALT_STACK_BYTES];

#if defined(__x86_64__)
static const int ARG_REG[6] = {REG_RDI, REG_RSI, REG_RDX, REG_R10, REG_R8, REG_R9};
static uint64_t arg_of(const ucontext_t *uc, int i) { return (uint64_t)uc->uc_mcontext.gregs[ARG_REG[i]]; }
static void set_result(ucontext_t *uc, long value) { uc->uc_mcontext.gregs[REG_RAX] = value; }
#elif defined(__aarch64__)
static uint64_t arg_of(const ucontext_t *uc, int i) { return (uint64_t)uc->uc_mcontext.regs[i]; }
static void set_result(ucontext_t *uc, long value) { uc->uc_mcontext.regs[0] = (uint64_t)value; }
#else
#error "crslab's sandbox knows the registers of x86_64 and aarch64 only"
#endif

static int same_path(const char *a, const char *b)
{
    if (a == NULL) return 0;
    size_t i = 0;
    for (; i < PATH_CAPACITY && a[i] != '\0' && a[i] == b[i]; ++i) {
    }
    return i < PATH_CAPACITY && a[i] == b[i];
}

/* With --sanitize: an open the sanitizer runtime makes (what it reads about the process
 * whenever it starts a report, or anything once its report file is no longer empty). */
static int sanitizer_open(const char *path)
{
    static const char *const RUNTIME_FILES[] = {"/proc/self/maps", "/proc/self/cmdline",
                                                "/proc/self/environ"};
    if (g_report_fd < 0) return 0;
    for (size_t i = 0; i < sizeof RUNTIME_FILES / sizeof RUNTIME_FILES[0]; ++i) {
        if (same_path(path, RUNTIME_FILES[i])) return 1;
    }
    struct stat st;
    return syscall(SYS_fstat, g_report_fd, &st) == 0 && st.st_size > 0;
}

/* An open for reading answered instead of refused: the loader opening the lab's shared object
 * (a rewound duplicate of the descriptor opened before the sandbox), or a sanitizer reading
 * what its report needs (opened with openat2, within what Landlock allows). */
static int answer_open(ucontext_t *uc, int nr)
{
    const char *path = NULL;
    uint64_t flags = 0;
    long dirfd = AT_FDCWD;
    if (nr == SYS_openat) {
        dirfd = (long)arg_of(uc, 0);
        path = (const char *)arg_of(uc, 1);
        flags = arg_of(uc, 2);
    }
#ifdef SYS_open
    else if (nr == SYS_open) {
        path = (const char *)arg_of(uc, 0);
        flags = arg_of(uc, 1);
    }
#endif
    if (path == NULL || (flags & (O_ACCMODE | O_CREAT | O_TRUNC | O_APPEND)) != O_RDONLY) return 0;
    if (g_loading && g_lab_fd >= 0 && same_path(path, g_lab_path)) {
        long fd = syscall(SYS_fcntl, g_lab_fd, F_DUPFD_CLOEXEC, 0);
        if (fd >= 0) syscall(SYS_lseek, fd, 0L, SEEK_SET);
        set_result(uc, fd >= 0 ? fd : -EMFILE);
        return 1;
    }
#ifdef SYS_openat2
    if (sanitizer_open(path)) {
        struct { uint64_t flags, mode, resolve; } how = {flags | O_CLOEXEC, 0, 0};
        set_result(uc, syscall(SYS_openat2, dirfd, path, &how, sizeof how));
        return 1;
    }
#endif
    return 0;
}

/* newfstatat(fd, "", buf, AT_EMPTY_PATH), which is how the C library's fstat() asks: the status of
 * an open descriptor, answered with fstat. With any path it would tell whether a file exists, its
 * size and its times: refused. (statx is refused outright: the C library falls back to this.) */
static int answer_fstat(ucontext_t *uc, int nr)
{
#ifdef SYS_newfstatat
    if (nr != SYS_newfstatat || !(arg_of(uc, 3) & AT_EMPTY_PATH)) return 0;
    const char *path = (const char *)arg_of(uc, 1);
    if (path == NULL || path[0] != '\0') return 0;
    set_result(uc, syscall(SYS_fstat, (long)arg_of(uc, 0), (void *)arg_of(uc, 2)));
    return 1;
#else
    (void)uc, (void)nr;
    return 0;
#endif
}

/* rt_sigprocmask(how, set, old, size) that would change the mask: applied, SIGSYS kept open. */
static int answer_signal_mask(ucontext_t *uc, int nr)
{
    if (nr != SYS_rt_sigprocmask || arg_of(uc, 3) != sizeof(uint64_t)) return 0;
    const uint64_t sigsys_bit = 1ULL << (SIGSYS - 1);
    const int how = (int)arg_of(uc, 0);
    const uint64_t *set = (const uint64_t *)arg_of(uc, 1);
    uint64_t *old = (uint64_t *)arg_of(uc, 2);
    uint64_t mask;
    memcpy(&mask, &uc->uc_sigmask, sizeof mask); /* the mask in force when the call was made */
    if (old != NULL) *old = mask;
    if (set != NULL) {
        if (how == SIG_BLOCK) mask |= *set;
        else if (how == SIG_UNBLOCK) mask &= ~*set;
        else if (how == SIG_SETMASK) mask = *set;
        else {
            set_result(uc, -EINVAL);
            return 1;
        }
        mask &= ~sigsys_bit;
        memcpy(&uc->uc_sigmask, &mask, sizeof mask);
    }
    set_result(uc, 0);
    return 1;
}

static void on_sigsys(int sig, siginfo_t *info, void *context)
{
    (void)sig;
    ucontext_t *uc = context;
    const int nr = info->si_syscall;
    if (answer_open(uc, nr) || answer_signal_mask(uc, nr) || answer_fstat(uc, nr)) return;

    crs_refusal *r = &g_shared->refusal;
    if (!r->refused) {
        r->syscall_nr = nr;
        r->arch = info->si_arch;
        r->phase = g_shared->phase;
        r->tick = g_shared->tick;
        for (int i = 0; i < 6; ++i) r->args[i] = arg_of(uc, i);
        r->text[0] = '\0';
        __atomic_store_n(&r->refused, 1, __ATOMIC_SEQ_CST);
        const int which = (nr >= 0 && nr < CRS_TRAP_SYSCALLS) ? g_path_arg[nr] : -1;
        const char *path = which >= 0 ? (const char *)arg_of(uc, which) : NULL;
        if (path != NULL) { /* a bad pointer faults here, after the call was recorded */
            size_t i = 0;
            for (; i + 1 < CRS_REFUSAL_TEXT && path[i] != '\0'; ++i) r->text[i] = path[i];
            r->text[i] = '\0';
        }
    }
    syscall(SYS_exit_group, CRS_TRAP_EXIT);
}

int crs_trap_arm(crs_shared *shared, const char *lab_path, int32_t lab_fd, const int8_t *path_arg,
                 int32_t report_fd)
{
    if (shared == NULL || lab_path == NULL || strlen(lab_path) >= PATH_CAPACITY) return -EINVAL;
    g_shared = shared;
    memcpy(g_lab_path, lab_path, strlen(lab_path) + 1);
    g_lab_fd = lab_fd;
    g_report_fd = report_fd;
    memcpy(g_path_arg, path_arg, sizeof g_path_arg);

    stack_t ss;
    memset(&ss, 0, sizeof ss);
    ss.ss_sp = g_alt_stack;
    ss.ss_size = sizeof g_alt_stack;
    if (sigaltstack(&ss, NULL) != 0) return -errno;
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_sigaction = on_sigsys;
    sa.sa_flags = SA_SIGINFO | SA_ONSTACK;
    sigfillset(&sa.sa_mask);
    if (sigaction(SIGSYS, &sa, NULL) != 0) return -errno;
    sigset_t set;
    sigemptyset(&set);
    sigaddset(&set, SIGSYS);
    if (sigprocmask(SIG_UNBLOCK, &set, NULL) != 0) return -errno;
    return 0;
}

void crs_trap_loading(int32_t on) { g_loading = on; }

// Model files: the compiler's process, which must never outlive the caller's wish.
//
// The compiler is not one process: the driver (g++) starts cc1plus, as and ld, which do the
// work. Ending only the driver would leave them running (minutes and gigabytes for a large
// model) and writing temporary files. So the compiler runs in a process group of its own,
// led by a small supervisor that this process forks:
//
//   this process ── supervisor (group leader; forked, never exec'd)
//                       └── the compiler driver (exec'd) ── cc1plus, as, ld ...
//
// - Cancelled (Ctrl-C in the CLI, KeyboardInterrupt in Python): this process sends SIGTERM
//   to the group (the driver deletes its temporary files on it; the supervisor ignores it
//   and waits for the driver), then SIGKILL to whatever is left, and reaps the supervisor.
// - This process dies, even by SIGKILL: the supervisor gets SIGHUP (PR_SET_PDEATHSIG) and
//   does the same to its group, then kills itself. It also checks getppid() on its own, for
//   a death before the prctl or a lost signal.
// - The supervisor dies: the driver gets SIGKILL (its own PR_SET_PDEATHSIG).
// The group has its own id, so a Ctrl-C typed at the terminal reaches only this process,
// which decides. Between fork and exec only async-signal-safe calls are made (the caller may
// have other threads): everything the children need is prepared before the fork.
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "model_file_detail.hpp"
#include "vimpact/core/cancelled.hpp"
#include "vimpact/core/input_error.hpp"

extern char** environ;

namespace vimpact::model_file_detail {

unique_fd& unique_fd::operator=(unique_fd&& o) noexcept
{
    if (this != &o) {
        if (m_fd >= 0) ::close(m_fd);
        m_fd = o.release();
    }
    return *this;
}

unique_fd::~unique_fd()
{
    if (m_fd >= 0) ::close(m_fd);
}

namespace {

// How long a compiler has to end on SIGTERM before SIGKILL (the driver only deletes its files).
constexpr long grace_ms = 300;
// The output kept for the message (the first error line is what is reported).
constexpr std::size_t max_output = 1 << 20;

void sleep_ms(long ms)
{
    timespec t{ms / 1000, (ms % 1000) * 1000000L};
    while (::nanosleep(&t, &t) != 0 && errno == EINTR) {
    }
}

// ---- in the children (async-signal-safe only)

[[noreturn]] void child_exit(int code) { ::_exit(code); }

void write_all(int fd, const char* s)
{
    std::size_t n = 0;
    while (s[n] != '\0') ++n;
    while (n > 0) {
        const ssize_t w = ::write(fd, s, n);
        if (w <= 0) {
            if (w < 0 && errno == EINTR) continue;
            return;
        }
        s += w;
        n -= static_cast<std::size_t>(w);
    }
}

// The driver: standard streams, default signals, death with the supervisor, the working
// directory (the cache: the compiler is given names relative to it), exec.
[[noreturn]] void exec_compiler(const char* program, char* const* argv, char* const* envp, int devnull, int out,
                                int dir_fd, pid_t supervisor)
{
    // Above 2 first, so that no dup2 below overwrites a descriptor still needed.
    const int in = ::fcntl(devnull, F_DUPFD_CLOEXEC, 3), log = ::fcntl(out, F_DUPFD_CLOEXEC, 3);
    if (in < 0 || log < 0 || ::dup2(in, 0) < 0 || ::dup2(log, 1) < 0 || ::dup2(log, 2) < 0) child_exit(127);
    for (const int s : {SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGPIPE, SIGCHLD}) ::signal(s, SIG_DFL);
    sigset_t none;
    sigemptyset(&none);
    ::sigprocmask(SIG_SETMASK, &none, nullptr);
    if (::prctl(PR_SET_PDEATHSIG, SIGKILL) != 0 || ::getppid() != supervisor) child_exit(127);
    if (::fchdir(dir_fd) != 0) child_exit(127);
    ::execve(program, argv, envp);
    // strerror may translate (and allocate); the errno's name is a constant string
    const char* name = ::strerrorname_np(errno);
    write_all(2, "error: cannot execute the compiler: ");
    write_all(2, name ? name : "unknown errno");
    write_all(2, "\n");
    child_exit(127);
}

// Ends the group (the supervisor ignores SIGTERM and keeps waiting for the driver), then
// kills what is left, the supervisor included.
[[noreturn]] void supervisor_end_group(pid_t driver, const sigset_t& waited)
{
    ::kill(0, SIGTERM);
    for (long waited_ms = 0; waited_ms < grace_ms; waited_ms += 20) {
        int status = 0;
        if (::waitpid(driver, &status, WNOHANG) == driver) break;
        const timespec step{0, 20 * 1000000L};
        siginfo_t info;
        (void)::sigtimedwait(&waited, &info, &step);
    }
    ::kill(0, SIGKILL);
    child_exit(128 + SIGKILL);
}

[[noreturn]] void supervise(const char* program, char* const* argv, char* const* envp, int devnull, int out,
                            int dir_fd, pid_t caller)
{
    ::setpgid(0, 0);
    ::signal(SIGTERM, SIG_IGN);
    ::signal(SIGINT, SIG_IGN);
    ::signal(SIGQUIT, SIG_IGN);
    ::signal(SIGCHLD, SIG_DFL);  // not SIG_IGN, which would reap the driver before waitpid
    ::signal(SIGHUP, SIG_DFL);
    sigset_t waited;
    sigemptyset(&waited);
    sigaddset(&waited, SIGCHLD);
    sigaddset(&waited, SIGHUP);
    ::sigprocmask(SIG_SETMASK, &waited, nullptr);  // taken by sigtimedwait, never delivered
    if (::prctl(PR_SET_PDEATHSIG, SIGHUP) != 0 || ::getppid() != caller) child_exit(126);
    const pid_t self = ::getpid();
    const pid_t driver = ::fork();
    if (driver < 0) child_exit(126);
    if (driver == 0) exec_compiler(program, argv, envp, devnull, out, dir_fd, self);
    ::close(out);  // the output ends when the driver and its children have closed it
    int status = 0;
    for (;;) {
        const timespec tick{0, 100 * 1000000L};
        siginfo_t info;
        const int sig = ::sigtimedwait(&waited, &info, &tick);
        if (sig == SIGHUP || ::getppid() != caller) supervisor_end_group(driver, waited);
        if (::waitpid(driver, &status, WNOHANG) == driver) break;
    }
    if (WIFEXITED(status)) child_exit(WEXITSTATUS(status));
    if (WIFSIGNALED(status)) {  // die of the same signal, so the caller reports it
        const int s = WTERMSIG(status);
        ::signal(s, SIG_DFL);
        sigset_t only;
        sigemptyset(&only);
        sigaddset(&only, s);
        ::sigprocmask(SIG_UNBLOCK, &only, nullptr);
        ::kill(self, s);
        child_exit(128 + s);
    }
    child_exit(126);
}

// ---- in this process

// The supervisor's process group: whatever happens, nothing of it outlives this object.
class compiler_group {
public:
    explicit compiler_group(pid_t leader) : m_pid(leader) {}
    compiler_group(const compiler_group&) = delete;
    compiler_group& operator=(const compiler_group&) = delete;
    ~compiler_group()
    {
        if (!m_reaped) (void)kill_and_reap();
    }

    // Whether the supervisor has ended (a zombie, not yet reaped: its pid, which is the group's
    // id, stays reserved, so that signals to the group reach no stranger).
    bool ended()
    {
        siginfo_t info{};
        if (::waitid(P_PID, static_cast<id_t>(m_pid), &info, WEXITED | WNOHANG | WNOWAIT) != 0)
            return errno != EINTR;  // ECHILD: a caller that ignores SIGCHLD has it reaped already
        return info.si_pid == m_pid;
    }

    // SIGTERM, a short grace, SIGKILL; then the supervisor's status.
    int stop()
    {
        ::kill(-m_pid, SIGTERM);
        for (long ms = 0; ms < grace_ms && !ended(); ms += 10) sleep_ms(10);
        return kill_and_reap();
    }

    // The stragglers of a finished run (a helper that kept running), then the status.
    int kill_and_reap()
    {
        ::kill(-m_pid, SIGKILL);
        int status = 0;
        while (::waitpid(m_pid, &status, 0) < 0 && errno == EINTR) {
        }
        m_reaped = true;
        return status;
    }

private:
    pid_t m_pid;
    bool m_reaped = false;
};

void read_available(int fd, std::string& output, bool& eof)
{
    char buf[65536];
    for (;;) {
        const ssize_t n = ::read(fd, buf, sizeof buf);
        if (n > 0) {
            if (output.size() < max_output)
                output.append(buf, std::min(static_cast<std::size_t>(n), max_output - output.size()));
            continue;
        }
        if (n == 0) eof = true;
        else if (errno == EINTR) continue;
        else if (errno != EAGAIN && errno != EWOULDBLOCK) eof = true;
        return;
    }
}

}  // namespace

compiler_run run_compiler(const std::string& program, const std::vector<std::string>& args, int dir_fd,
                          const std::atomic<bool>* cancel)
{
    std::vector<char*> argv;
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    int pipe_fds[2];
    if (::pipe2(pipe_fds, O_CLOEXEC) != 0)
        throw std::runtime_error(std::string("cannot start the C++ compiler: pipe: ") + std::strerror(errno));
    unique_fd output_end(pipe_fds[0]), input_end(pipe_fds[1]);
    const unique_fd devnull(::open("/dev/null", O_RDONLY | O_CLOEXEC));
    if (!devnull.valid())
        throw std::runtime_error(std::string("cannot start the C++ compiler: /dev/null: ") + std::strerror(errno));
    const pid_t caller = ::getpid();
    char* const* envp = environ;
    const pid_t pid = ::fork();
    if (pid < 0) throw std::runtime_error(std::string("cannot start the C++ compiler: fork: ") + std::strerror(errno));
    if (pid == 0) supervise(program.c_str(), argv.data(), envp, devnull.get(), input_end.get(), dir_fd, caller);
    ::setpgid(pid, pid);  // as the supervisor does, so that no signal below can miss the group
    compiler_group group(pid);
    input_end = unique_fd();
    ::fcntl(output_end.get(), F_SETFL, O_NONBLOCK);

    compiler_run run;
    bool eof = false;
    for (;;) {
        if (cancel && cancel->load(std::memory_order_relaxed)) {
            (void)group.stop();
            throw cancelled();
        }
        pollfd p{output_end.get(), POLLIN, 0};
        // A signal handler's flag (Ctrl-C) interrupts the poll: it is seen at once.
        if (::poll(&p, eof ? 0 : 1, 20) > 0) read_available(output_end.get(), run.output, eof);
        if (group.ended()) break;
    }
    read_available(output_end.get(), run.output, eof);
    run.status = group.kill_and_reap();
    return run;
}

}  // namespace vimpact::model_file_detail

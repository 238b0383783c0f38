#include "interrupts.hpp"

#include <csignal>

namespace vimpact::cli {

namespace {

// A signal handler can reach only static storage: this flag is the one piece of global state
// of the program, set here and read through interrupt_flag().
std::atomic<bool> g_interrupted{false};
static_assert(std::atomic<bool>::is_always_lock_free);

struct sigaction g_old_int {}, g_old_term {};

extern "C" void on_interrupt(int sig)
{
    if (g_interrupted.exchange(true)) {  // the second time: end now, as without a handler
        std::signal(sig, SIG_DFL);
        std::raise(sig);
    }
}

}  // namespace

interrupt_guard::interrupt_guard()
{
    g_interrupted.store(false);
    struct sigaction sa {};
    sa.sa_handler = on_interrupt;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, &g_old_int);
    sigaction(SIGTERM, &sa, &g_old_term);
}

interrupt_guard::~interrupt_guard()
{
    sigaction(SIGINT, &g_old_int, nullptr);
    sigaction(SIGTERM, &g_old_term, nullptr);
}

const std::atomic<bool>& interrupt_flag() { return g_interrupted; }

void throw_if_interrupted()
{
    if (g_interrupted.load()) throw interrupted();
}

}  // namespace vimpact::cli

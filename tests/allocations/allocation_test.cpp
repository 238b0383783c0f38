// Heap allocations of a run on states sized at run time (a model file of a dimension without
// fixed-size states: table_model<Eigen::Dynamic>). A free flight that lasts twice as long takes
// twice the steps and must not allocate more: nothing in the step allocates. The test counts
// every malloc of the process, so it is a program of its own, and is not built with the
// sanitizers (which replace malloc).
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <string>

#include "vimpact/analysis/protocol.hpp"
#include "vimpact/model/model.hpp"
#include "vimpact/system/tangent_system.hpp"

// Every way glibc hands out memory that Eigen, the standard library or the model could use.
static std::atomic<long> allocations{0};
extern "C" void* __libc_malloc(std::size_t);
extern "C" void* __libc_calloc(std::size_t, std::size_t);
extern "C" void* __libc_realloc(void*, std::size_t);
extern "C" void* __libc_memalign(std::size_t, std::size_t);
extern "C" void* malloc(std::size_t n)
{
    allocations.fetch_add(1, std::memory_order_relaxed);
    return __libc_malloc(n);
}
extern "C" void* calloc(std::size_t n, std::size_t size)
{
    allocations.fetch_add(1, std::memory_order_relaxed);
    return __libc_calloc(n, size);
}
extern "C" void* realloc(void* p, std::size_t n)
{
    allocations.fetch_add(1, std::memory_order_relaxed);
    return __libc_realloc(p, n);
}
extern "C" void* aligned_alloc(std::size_t alignment, std::size_t n)
{
    allocations.fetch_add(1, std::memory_order_relaxed);
    return __libc_memalign(alignment, n);
}
extern "C" int posix_memalign(void** out, std::size_t alignment, std::size_t n)
{
    allocations.fetch_add(1, std::memory_order_relaxed);
    *out = __libc_memalign(alignment, n);
    return *out ? 0 : 12;  // ENOMEM
}

using namespace vimpact;

namespace {

struct counted_run {
    long steps = 0, impacts = 0, allocations = 0;
};

// Two copies of the two-sided impact oscillator (6 states), stops at +-d.
model copies(double d)
{
    model m = model::from_file(std::string(VIMPACT_SOURCE_DIR) + "/bench/models/two_oscillators.toml");
    m = m.with_parameter(m.info().parameter_index("d"), d);
    return m.with_parameter(m.info().parameter_index("a1"), 1.01);
}

Eigen::VectorXd start()
{
    Eigen::VectorXd x0 = Eigen::VectorXd::Zero(6);
    x0[3] = 0.1;
    return x0;
}

counted_run run(double quiet_time, double d)
{
    const model m = copies(d);
    const Eigen::VectorXd x0 = start();
    protocol_options o;
    o.quiet_time = quiet_time;
    o.transient_impacts = 100000;
    const long before = allocations.load();
    const simulation s = simulate(m, x0, o);
    return {s.stats.steps, s.stats.impacts, allocations.load() - before};
}

}  // namespace

// The model's 6 states must be sized at run time here: not one of the build's fixed sizes.
static bool six_states_fixed()
{
    const auto& dims = engine_dimensions();
    return std::find(dims.begin(), dims.end(), 6) != dims.end();
}

TEST(Allocations, RuntimeSizedStepsAllocateNothing)
{
    if (six_states_fixed()) GTEST_SKIP() << "this build has fixed-size states for 6";
    // Stops at d = 100: never reached; the run ends after quiet_time without an impact. The
    // first run loads the engine module and the model: what happens once is not counted.
    (void)run(100.0, 100.0);
    const counted_run shorter = run(2000.0, 100.0);
    const counted_run longer = run(4000.0, 100.0);
    ASSERT_EQ(shorter.impacts, 0);
    ASSERT_EQ(longer.impacts, 0);
    ASSERT_GT(longer.steps, shorter.steps + 5000);
    // The section crossings' records grow by doubling: a few reallocations, not one per step.
    EXPECT_LE(longer.allocations - shorter.allocations, 16)
        << shorter.allocations << " allocations in " << shorter.steps << " steps, " << longer.allocations << " in "
        << longer.steps;
}

// The tangent flow (6 + 36 + 1 numbers per state) stepped as a researcher steps it: a thousand
// steps more cost no allocation.
TEST(Allocations, RuntimeSizedTangentStepsAllocateNothing)
{
    if (six_states_fixed()) GTEST_SKIP() << "this build has fixed-size states for 6";
    tangent_system t(copies(100.0), start());
    ASSERT_EQ(t.step(200), outcome::ok);  // vectors sized, the engine loaded
    const long before = allocations.load();
    ASSERT_EQ(t.step(1000), outcome::ok);
    const long during = allocations.load() - before;
    EXPECT_EQ(t.stats().impacts, 0);
    EXPECT_LE(during, 4) << "allocations in 1000 tangent steps";
}

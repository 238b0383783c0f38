// What a crossing of a switch costs against an impact, like for like: two systems whose
// motions are mirror images of each other, so that they take the same steps and the same
// number of events per unit time.
//  - impact: x'' + 2 zeta x' + x = F cos(phi), phi' = omega, a rigid barrier at x = 0 with
//    restitution 1 (gap x, reset x' -> -x');
//  - switch: the same field on x > 0, its mirror image x'' + 2 zeta x' + x = -F cos(phi) on
//    x < 0, the side a switch at x = 0 with no reset. Its motion is side * (the impacting
//    one): each impact is a crossing, the field (the forcing's sign) changes there, and the
//    saltation matrix is not the identity.
// Two runs of each (DOP853, rtol = atol = 1e-10): the protocol point (500 events discarded,
// 200 strobe points kept: the same span of time for both), and the Lyapunov spectrum with the
// saltation matrices over a fixed time (tangent flow, 12 integrated components). Counters:
// steps, rhs calls, impacts and crossings (Lyapunov: of the reference in the window). Both models are C++ definitions called
// through their function tables (model::from_definition), derivatives by automatic
// differentiation. Goal: a switch's runs no slower than the impact's (ratio <= 1, within the
// noise).
#include <benchmark/benchmark.h>

#include <array>
#include <cmath>
#include <numbers>
#include <span>
#include <string_view>

#include <Eigen/Core>

#include "vimpact/analysis/lyapunov.hpp"
#include "vimpact/analysis/protocol.hpp"
#include "vimpact/model/export.hpp"
#include "vimpact/model/model.hpp"

namespace {

using vimpact::crossing;
using vimpact::vec_t;

constexpr std::array<vimpact::state_variable, 3> variables{{{"x"}, {"v"}, {"phi", "", "", 2.0 * std::numbers::pi}}};
constexpr std::array<vimpact::parameter, 3> values{{{"zeta", 0.05}, {"omega", 0.8}, {"F", 1.0}}};
constexpr std::array<vimpact::poincare_section, 1> strobe{{{"strobe", crossing::up}}};

struct impacting {
    static constexpr std::string_view name = "bench_impacting";
    static constexpr std::string_view description = "a forced oscillator bouncing on a rigid barrier at x = 0";
    static constexpr auto state = variables;
    static constexpr auto parameters = values;
    static constexpr std::array<vimpact::impact_surface, 1> surfaces{{{"barrier", "x = 0"}}};
    static constexpr auto sections = strobe;
    explicit impacting(std::span<const double> p) : zeta(p[0]), omega(p[1]), F(p[2]) {}
    template <class T>
    vec_t<T, 3> derivatives(const vec_t<T, 3>& X) const
    {
        using std::cos;
        return {X[1], -X[0] - 2.0 * zeta * X[1] + F * cos(X[2]), T(omega)};
    }
    template <class T>
    T gap(int, const vec_t<T, 3>& X) const { return X[0]; }
    template <class T>
    vec_t<T, 3> reset(int, const vec_t<T, 3>& X) const { return {X[0], -X[1], X[2]}; }
    template <class T>
    T section(int, const vec_t<T, 3>& X) const
    {
        using std::sin;
        return sin(X[2]);
    }
    double zeta, omega, F;
};

struct mirrored {
    static constexpr std::string_view name = "bench_switching";
    static constexpr std::string_view description = "the mirror image of bench_impacting: a switch at x = 0";
    static constexpr auto state = variables;
    static constexpr auto parameters = values;
    static constexpr std::array<vimpact::impact_surface, 0> surfaces{};
    static constexpr auto sections = strobe;
    static constexpr std::array<vimpact::switching_surface, 1> switches{{{"mirror", "x = 0"}}};
    explicit mirrored(std::span<const double> p) : zeta(p[0]), omega(p[1]), F(p[2]) {}
    template <class T>
    T switching(int, const vec_t<T, 3>& X) const { return X[0]; }
    template <class T>
    vec_t<T, 3> derivatives(const vec_t<T, 3>& X, const vimpact::switch_sides& s) const
    {
        using std::cos;
        return {X[1], -X[0] - 2.0 * zeta * X[1] + s.side(0) * F * cos(X[2]), T(omega)};
    }
    template <class T>
    T section(int, const vec_t<T, 3>& X) const
    {
        using std::sin;
        return sin(X[2]);
    }
    double zeta, omega, F;
};

const Eigen::Vector3d x0(0.5, 0.0, 0.0);

void protocol_point(benchmark::State& state, const vimpact::model& m)
{
    const vimpact::protocol_options po;
    vimpact::run_stats s;
    for (auto _ : state) {
        const auto r = vimpact::simulate(m, x0, po);
        benchmark::DoNotOptimize(r.points.values().data());
        if (r.status != vimpact::outcome::ok) state.SkipWithError("the run did not end ok");
        s = r.stats;
    }
    state.counters["steps"] = static_cast<double>(s.steps);
    state.counters["rhs_calls"] = static_cast<double>(s.rhs_calls);
    state.counters["impacts"] = static_cast<double>(s.impacts);
    state.counters["switchings"] = static_cast<double>(s.switchings);
}

void lyapunov_point(benchmark::State& state, const vimpact::model& m)
{
    vimpact::lyapunov_options o;
    o.time = 2000.0;
    vimpact::lyapunov_result r;
    for (auto _ : state) {
        r = vimpact::lyapunov(m, x0, o);
        benchmark::DoNotOptimize(r.exponents.data());
        if (r.status != vimpact::outcome::ok) state.SkipWithError("the run did not end ok");
    }
    state.counters["steps"] = static_cast<double>(r.stats.steps);
    state.counters["rhs_calls"] = static_cast<double>(r.stats.rhs_calls);
    state.counters["impacts"] = static_cast<double>(r.stats.impacts);
    state.counters["switchings"] = static_cast<double>(r.stats.switchings);
}

void protocol_impact(benchmark::State& s) { protocol_point(s, vimpact::model::from_definition<impacting>()); }
void protocol_switch(benchmark::State& s) { protocol_point(s, vimpact::model::from_definition<mirrored>()); }
void lyapunov_impact(benchmark::State& s) { lyapunov_point(s, vimpact::model::from_definition<impacting>()); }
void lyapunov_switch(benchmark::State& s) { lyapunov_point(s, vimpact::model::from_definition<mirrored>()); }

}  // namespace

// Medians of 9 repetitions each; bench/run_switching_bench.sh interleaves them
// (--benchmark_enable_random_interleaving), so that a slow spell of the machine hits both.
BENCHMARK(protocol_impact)->Name("protocol/impact")->Unit(benchmark::kMillisecond)->Repetitions(9)->ReportAggregatesOnly();
BENCHMARK(protocol_switch)->Name("protocol/switch")->Unit(benchmark::kMillisecond)->Repetitions(9)->ReportAggregatesOnly();
BENCHMARK(lyapunov_impact)->Name("lyapunov/impact")->Unit(benchmark::kMillisecond)->Repetitions(9)->ReportAggregatesOnly();
BENCHMARK(lyapunov_switch)->Name("lyapunov/switch")->Unit(benchmark::kMillisecond)->Repetitions(9)->ReportAggregatesOnly();
BENCHMARK_MAIN();

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
// The same pair written as model files, 16 jobs of each (F from 0.6 to 1.35, the protocol
// point), run in the SIMD lanes and one at a time (simulate_many with the lanes' width and
// with 1): what the lanes give a model with switches, and the switch's jobs against the
// impact's in lanes (goal <= 1, as alone). Their forcing is a linear oscillator (c, s) =
// (cos, sin) of the phase, not cos(phi): the lanes compute a transcendental function lane by
// lane, so a field that calls one per step gains little from them, impacts or switches.
// Last, what locating a kink buys: the compliant stop (a spring-dashpot stop at y = d) as a
// switch, and the same law written with a ternary (`y > d ? force : 0`) in a C++ definition,
// which the integrator steps across unlocated; the first 100 strobe points from rest at the
// default tolerance against a reference (the switch at rtol = atol = 1e-13): the largest
// error of a point and the time.
#include <benchmark/benchmark.h>

#include <array>
#include <cmath>
#include <numbers>
#include <span>
#include <string_view>

#include <Eigen/Core>

#include "vimpact/analysis/lyapunov.hpp"
#include "vimpact/analysis/protocol.hpp"
#include "vimpact/core/lanes.hpp"
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

// The compliant stop, located (a switch) or not (a kink inside the steps).
constexpr std::array<vimpact::parameter, 6> stop_values{
    {{"zeta", 0.05}, {"omega", 0.8}, {"F", 1.0}, {"d", 1.0}, {"kc", 4.0}, {"cc", 0.4}}};

struct stop_base {
    static constexpr auto state = variables;
    static constexpr auto parameters = stop_values;
    static constexpr std::array<vimpact::impact_surface, 0> surfaces{};
    static constexpr auto sections = strobe;
    explicit stop_base(std::span<const double> p) : zeta(p[0]), omega(p[1]), F(p[2]), d(p[3]), kc(p[4]), cc(p[5]) {}
    template <class T>
    vec_t<T, 3> field(const vec_t<T, 3>& X, const T& contact) const
    {
        using std::cos;
        return {X[1], -X[0] - 2.0 * zeta * X[1] + F * cos(X[2]) - contact, T(omega)};
    }
    template <class T>
    T section(int, const vec_t<T, 3>& X) const
    {
        using std::sin;
        return sin(X[2]);
    }
    double zeta, omega, F, d, kc, cc;
};

struct located_stop : stop_base {
    static constexpr std::string_view name = "bench_located_stop";
    static constexpr std::string_view description = "the compliant stop, its contact a switch";
    static constexpr std::array<vimpact::switching_surface, 1> switches{{{"contact", "y = d"}}};
    using stop_base::stop_base;
    template <class T>
    T switching(int, const vec_t<T, 3>& X) const { return X[0] - d; }
    template <class T>
    vec_t<T, 3> derivatives(const vec_t<T, 3>& X, const vimpact::switch_sides& s) const
    {
        return field<T>(X, T(s.on(0) * (kc * (X[0] - d) + cc * X[1])));
    }
};

struct unlocated_stop : stop_base {
    static constexpr std::string_view name = "bench_unlocated_stop";
    static constexpr std::string_view description = "the compliant stop, its contact a ternary inside the steps";
    using stop_base::stop_base;
    template <class T>
    vec_t<T, 3> derivatives(const vec_t<T, 3>& X) const
    {
        return field<T>(X, X[0] - d > 0.0 ? T(kc * (X[0] - d) + cc * X[1]) : T(0.0));
    }
};

const Eigen::Vector3d x0(0.5, 0.0, 0.0);
const Eigen::Vector3d stop_x0(0.0, 0.0, 0.5);

// The first 100 strobe points from rest, at rtol = atol = tol.
vimpact::simulation stop_points(const vimpact::model& m, double tol)
{
    vimpact::protocol_options po;
    po.transient_impacts = 0;
    po.record_points = 100;
    if (tol > 0.0) po.flow.integration.rtol = po.flow.integration.atol = tol;
    return vimpact::simulate(m, stop_x0, po);
}

void stop_run(benchmark::State& state, const vimpact::model& m)
{
    static const vimpact::simulation reference = stop_points(vimpact::model::from_definition<located_stop>(), 1e-13);
    vimpact::simulation r;
    for (auto _ : state) {
        r = stop_points(m, 0.0);
        benchmark::DoNotOptimize(r.points.values().data());
    }
    if (r.status != vimpact::outcome::ok || r.points.size() != reference.points.size()) {
        state.SkipWithError("the run did not give the reference's points");
        return;
    }
    double error = 0.0;
    for (std::size_t k = 0; k < r.points.size(); ++k)
        error = std::max(error, (r.points.x(k) - reference.points.x(k)).cwiseAbs().maxCoeff());
    state.counters["error"] = error;
    state.counters["steps"] = static_cast<double>(r.stats.steps);
    state.counters["rejected"] = static_cast<double>(r.stats.rejected);
}

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

// The pair as model files: the same oscillator, bouncing on a barrier at x = 0 (impact) or
// crossing a switch there where its forcing changes sign.
std::string pair_file(bool switching)
{
    const std::string kind = switching ? "switching" : "impacting";
    return "name = \"bench_" + kind + "_file\"\ndescription = \"bench_" + kind + " as a model file\"\n" +
           R"toml(state = [{ name = "x" }, { name = "v" }, { name = "c" }, { name = "s" }]
[parameters]
zeta = { default = 0.05 }
omega = { default = 0.8 }
F = { default = 1.0 }
[derivatives]
x = "v"
c = "-omega*s"
s = "omega*c"
)toml" + (switching ? R"toml(v = "-x - 2*zeta*v + side(mirror)*F*c"
[[switches]]
name = "mirror"
when = "x"
)toml"
                     : R"toml(v = "-x - 2*zeta*v + F*c"
[[surfaces]]
name = "barrier"
gap = "x"
reset = { v = "-v" }
)toml") + R"toml([[sections]]
name = "strobe"
when = "s"
direction = "up"
)toml";
}

// 16 jobs of a model file: F = 0.6, 0.65, ..., 1.35.
std::vector<vimpact::model> file_jobs(const std::string& text)
{
    const vimpact::model m = vimpact::model::from_toml(text, "bench.toml");
    std::vector<vimpact::model> jobs;
    for (int k = 0; k < 16; ++k) jobs.push_back(m.with_parameter(m.info().parameter_index("F"), 0.6 + 0.05 * k));
    return jobs;
}

void jobs_point(benchmark::State& state, const std::string& text, int batch)
{
    const std::vector<vimpact::model> jobs = file_jobs(text);
    const std::vector<Eigen::VectorXd> x0s(jobs.size(), Eigen::Vector4d(x0[0], x0[1], std::cos(x0[2]), std::sin(x0[2])));
    const vimpact::protocol_options po;
    double steps = 0.0, impacts = 0.0, switchings = 0.0;
    for (auto _ : state) {
        const auto r = vimpact::simulate_many(jobs, x0s, po, batch);
        steps = impacts = switchings = 0.0;
        for (const auto& j : r) {
            if (j.status != vimpact::outcome::ok) state.SkipWithError("a job did not end ok");
            steps += static_cast<double>(j.stats.steps);
            impacts += static_cast<double>(j.stats.impacts);
            switchings += static_cast<double>(j.stats.switchings);
        }
    }
    state.counters["steps"] = steps;
    state.counters["impacts"] = impacts;
    state.counters["switchings"] = switchings;
}

void protocol_impact(benchmark::State& s) { protocol_point(s, vimpact::model::from_definition<impacting>()); }
void protocol_switch(benchmark::State& s) { protocol_point(s, vimpact::model::from_definition<mirrored>()); }
void lyapunov_impact(benchmark::State& s) { lyapunov_point(s, vimpact::model::from_definition<impacting>()); }
void lyapunov_switch(benchmark::State& s) { lyapunov_point(s, vimpact::model::from_definition<mirrored>()); }
void stop_located(benchmark::State& s) { stop_run(s, vimpact::model::from_definition<located_stop>()); }
void stop_unlocated(benchmark::State& s) { stop_run(s, vimpact::model::from_definition<unlocated_stop>()); }
void lanes_impact(benchmark::State& s) { jobs_point(s, pair_file(false), vimpact::lane_width); }
void lanes_switch(benchmark::State& s) { jobs_point(s, pair_file(true), vimpact::lane_width); }
void alone_impact(benchmark::State& s) { jobs_point(s, pair_file(false), 1); }
void alone_switch(benchmark::State& s) { jobs_point(s, pair_file(true), 1); }

}  // namespace

// Medians of 9 repetitions each; bench/run_switching_bench.sh interleaves them
// (--benchmark_enable_random_interleaving), so that a slow spell of the machine hits both.
BENCHMARK(protocol_impact)->Name("protocol/impact")->Unit(benchmark::kMillisecond)->Repetitions(9)->ReportAggregatesOnly();
BENCHMARK(protocol_switch)->Name("protocol/switch")->Unit(benchmark::kMillisecond)->Repetitions(9)->ReportAggregatesOnly();
BENCHMARK(lyapunov_impact)->Name("lyapunov/impact")->Unit(benchmark::kMillisecond)->Repetitions(9)->ReportAggregatesOnly();
BENCHMARK(lyapunov_switch)->Name("lyapunov/switch")->Unit(benchmark::kMillisecond)->Repetitions(9)->ReportAggregatesOnly();
BENCHMARK(lanes_impact)->Name("lanes/impact")->Unit(benchmark::kMillisecond)->Repetitions(9)->ReportAggregatesOnly();
BENCHMARK(lanes_switch)->Name("lanes/switch")->Unit(benchmark::kMillisecond)->Repetitions(9)->ReportAggregatesOnly();
BENCHMARK(alone_impact)->Name("alone/impact")->Unit(benchmark::kMillisecond)->Repetitions(9)->ReportAggregatesOnly();
BENCHMARK(alone_switch)->Name("alone/switch")->Unit(benchmark::kMillisecond)->Repetitions(9)->ReportAggregatesOnly();
BENCHMARK(stop_located)->Name("stop/located")->Unit(benchmark::kMillisecond)->Repetitions(9)->ReportAggregatesOnly();
BENCHMARK(stop_unlocated)->Name("stop/unlocated")->Unit(benchmark::kMillisecond)->Repetitions(9)->ReportAggregatesOnly();
BENCHMARK_MAIN();

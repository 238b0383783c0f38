// The price of defining a model another way, measured side by side on the paper's model
// (Ur = 16, sigma = -0.150298, paper preset, DOP853, rtol = atol = 1e-10):
//  - the protocol point (500 impacts discarded, 200 maxima kept) with the built-in model
//    against the same model as a model file (examples/models/wake_impact.toml, compiled to
//    native code and called through its function table); goal: within 1.15x, same steps;
//    and as the equations read (bench/models/wake_impact_natural.toml: the parameter groups
//    inside the equations, no derived quantities): goal within 1.1x of the built-in;
//  - a Floquet point (protocol, Newton shooting, monodromy) with the hand-written Jacobian and
//    impact derivatives against the same definition with every derivative from automatic
//    differentiation (both compiled natively); goal: within 1.3x;
//  - the tangent part of that point alone (Newton shooting from the protocol's first section
//    point, then the monodromy: engine::floquet_from_point), the same two definitions: the
//    protocol is state only and the same for both, so it dilutes the price of automatic
//    derivatives in the Floquet point; here it is undiluted.
// Counters: steps and rhs calls of the measured run (equal steps show the same arithmetic);
// for the tangent part, those of the last map evaluation and the number of evaluations.
// Run with the repository as the working directory (it reads the model file).
#include <benchmark/benchmark.h>

#include <span>

#include "vimpact/analysis/floquet.hpp"
#include "vimpact/analysis/protocol.hpp"
#include "vimpact/engine/floquet.hpp"
#include "vimpact/engine/protocol.hpp"
#include "vimpact/model/builtin/wake_impact.hpp"
#include "vimpact/model/model.hpp"
#include "vimpact/model/native_model.hpp"

namespace {

// The paper's model with every hand-written derivative removed: the automatic ones only.
struct wake_impact_ad {
    static constexpr auto name = vimpact::wake_impact::name;
    static constexpr auto description = vimpact::wake_impact::description;
    static constexpr auto state = vimpact::wake_impact::state;
    static constexpr auto parameters = vimpact::wake_impact::parameters;
    static constexpr auto surfaces = vimpact::wake_impact::surfaces;
    static constexpr auto sections = vimpact::wake_impact::sections;
    vimpact::wake_impact w;
    explicit wake_impact_ad(std::span<const double> p) : w(p) {}
    template <class T>
    vimpact::vec_t<T, 4> derivatives(const vimpact::vec_t<T, 4>& x) const { return w.derivatives(x); }
    template <class T>
    T gap(int i, const vimpact::vec_t<T, 4>& x) const { return w.gap(i, x); }
    template <class T>
    vimpact::vec_t<T, 4> reset(int i, const vimpact::vec_t<T, 4>& x) const { return w.reset(i, x); }
    template <class T>
    T section(int k, const vimpact::vec_t<T, 4>& x) const { return w.section(k, x); }
    template <class T>
    vimpact::vec_t<T, 4> sticking_derivatives(int i, const vimpact::vec_t<T, 4>& x) const
    {
        return w.sticking_derivatives(i, x);
    }
    template <class T>
    T release(int i, const vimpact::vec_t<T, 4>& x) const { return w.release(i, x); }
    vimpact::vec<4> rest(int i, const vimpact::vec<4>& x) const { return w.rest(i, x); }
};

vimpact::model with_ur16(vimpact::model m) { return m.with_parameter(m.info().parameter_index("Ur"), 16.0); }

void set_counters(benchmark::State& state, const vimpact::run_stats& s)
{
    state.counters["steps"] = static_cast<double>(s.steps);
    state.counters["rhs_calls"] = static_cast<double>(s.rhs_calls);
}

void protocol_point(benchmark::State& state, const vimpact::model& m)
{
    const vimpact::protocol_options po;
    vimpact::run_stats s;
    for (auto _ : state) {
        const auto r = vimpact::simulate(m, m.initial_state(), po);
        benchmark::DoNotOptimize(r.points.values().data());
        s = r.stats;
    }
    set_counters(state, s);
}

void protocol_builtin(benchmark::State& state) { protocol_point(state, with_ur16(vimpact::model::builtin("wake_impact"))); }

void protocol_model_file(benchmark::State& state)
{
    protocol_point(state, with_ur16(vimpact::model::from_file("examples/models/wake_impact.toml")));
}

void protocol_model_file_natural(benchmark::State& state)
{
    protocol_point(state, with_ur16(vimpact::model::from_file("bench/models/wake_impact_natural.toml")));
}

template <class Definition>
void floquet_point(benchmark::State& state)
{
    const vimpact::model m = with_ur16(vimpact::model::builtin("wake_impact"));
    const vimpact::native_model<Definition> em(m.parameters());
    const vimpact::floquet_options fo;
    const vimpact::vec<4> x0 = m.initial_state();
    vimpact::run_stats s;
    for (auto _ : state) {
        const auto pr = vimpact::engine::run_protocol<vimpact::dop853>(em, x0, fo.protocol);
        const auto r = vimpact::engine::floquet_after_protocol<vimpact::dop853>(em, pr, fo, m.info());
        benchmark::DoNotOptimize(r.multipliers.data());
        s = r.tangent_stats;
    }
    set_counters(state, s);
}

// The orbit the tangent part starts from: the protocol's run and period (computed once).
struct found_orbit {
    Eigen::VectorXd guess;
    int returns = 0;
};

const found_orbit& ur16_orbit()
{
    static const found_orbit orbit = [] {
        const vimpact::model m = with_ur16(vimpact::model::builtin("wake_impact"));
        const auto r = vimpact::floquet(m, m.initial_state(), vimpact::floquet_options{});
        return found_orbit{r.section_points.x(0), r.section_returns};
    }();
    return orbit;
}

template <class Definition>
void tangent_part(benchmark::State& state)
{
    const vimpact::model m = with_ur16(vimpact::model::builtin("wake_impact"));
    const vimpact::native_model<Definition> em(m.parameters());
    const vimpact::floquet_options fo;
    const found_orbit& orbit = ur16_orbit();
    const vimpact::vec<4> x(orbit.guess);
    vimpact::floquet_result r;
    for (auto _ : state) {
        r = vimpact::engine::floquet_from_point<vimpact::dop853>(em, x, orbit.returns, fo);
        benchmark::DoNotOptimize(r.multipliers.data());
    }
    set_counters(state, r.tangent_stats);
    state.counters["map_evaluations"] = static_cast<double>(r.map_evaluations);
}

}  // namespace

BENCHMARK(protocol_builtin)->Name("protocol_Ur16/built-in")->Unit(benchmark::kMillisecond)->Repetitions(9)->ReportAggregatesOnly(true);
BENCHMARK(protocol_model_file)->Name("protocol_Ur16/model-file")->Unit(benchmark::kMillisecond)->Repetitions(9)->ReportAggregatesOnly(true);
BENCHMARK(protocol_model_file_natural)->Name("protocol_Ur16/model-file-natural")->Unit(benchmark::kMillisecond)->Repetitions(9)->ReportAggregatesOnly(true);
BENCHMARK(floquet_point<vimpact::wake_impact>)->Name("floquet_Ur16/hand-written")->Unit(benchmark::kMillisecond)->Repetitions(9)->ReportAggregatesOnly(true);
BENCHMARK(floquet_point<wake_impact_ad>)->Name("floquet_Ur16/automatic")->Unit(benchmark::kMillisecond)->Repetitions(9)->ReportAggregatesOnly(true);
BENCHMARK(tangent_part<vimpact::wake_impact>)->Name("floquet_tangent_Ur16/hand-written")->Unit(benchmark::kMillisecond)->Repetitions(9)->ReportAggregatesOnly(true);
BENCHMARK(tangent_part<wake_impact_ad>)->Name("floquet_tangent_Ur16/automatic")->Unit(benchmark::kMillisecond)->Repetitions(9)->ReportAggregatesOnly(true);

BENCHMARK_MAIN();

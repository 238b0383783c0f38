// The cost of one Runge-Kutta trial on the paper's model (paper preset, Ur = 16), alone: a
// serial chain of trials, each starting from the last one's end (as the integrator's steps
// do), with a fixed step h = 0.01, so that the time per iteration is the trial's latency with
// nothing of step-size control, events or the hybrid flow around it.
//   - vimpact's dopri5<4> and dop853<4> attempt() on the library's model (native_model of the
//     built-in definition, the field the protocol runs), their squared error norm included;
//   - Boost.Odeint's runge_kutta_dopri5 do_step with its error vector (std::array state, the
//     bench/baseline_odeint.cpp field), no norm: the part of Odeint's step that corresponds.
//     Its error vector is summed into a result, as ours is returned: an error vector nothing
//     reads is computed after the loop only (GCC moves it there), which left the error estimate
//     out of Odeint's timing.
// The step size is read at run time on both sides, as an integrator's is: a constant one folds
// into Odeint's stage coefficients (the library's attempt is out of line and cannot fold it).
// Compiled with -ffp-contract=off, like the library's engine sources (a SIMD lane must round
// as a job alone does), so both sides round the same way.
// Usage: build/trial_bench [--benchmark_repetitions=N ...] (Google Benchmark's options).
#include <array>
#include <vector>

#include <benchmark/benchmark.h>
#include <boost/numeric/odeint.hpp>

#include "vimpact/hybrid/stepper.hpp"
#include "vimpact/integrate/runge_kutta.hpp"
#include "vimpact/model/builtin/wake_impact.hpp"
#include "vimpact/model/native_model.hpp"

namespace {

using wake = vimpact::native_model<vimpact::wake_impact>;
// volatile: a run-time value, as an adaptive integrator's step size is.
volatile double step_size = 0.01;

std::vector<double> protocol_point_parameters()
{
    std::vector<double> p;
    for (const auto& d : vimpact::wake_impact::parameters) p.push_back(d.default_value);
    p[0] = 16.0;  // Ur
    return p;
}

template <template <int> class Method>
void vimpact_trial(benchmark::State& state)
{
    const wake model(protocol_point_parameters());
    const vimpact::free_field<wake> rhs{&model};
    Method<4> method;
    vimpact::vec<4> x(vimpact::wake_impact::initial_state.data()), f = rhs(x), x_new, f_new;
    const double step = step_size;
    double sum = 0.0;
    for (auto _ : state) {
        sum += method.attempt(rhs, x, f, step, 1e-10, 1e-10, x_new, f_new);
        x = x_new;
        f = f_new;
    }
    benchmark::DoNotOptimize(sum);
    benchmark::DoNotOptimize(x.data());
    state.counters["stages"] = Method<4>::stages_per_step;
}

// bench/baseline_odeint.cpp's field, with the same derived constants as the library's model.
struct odeint_field {
    double delta2, alpha, M, eps, A;
    void operator()(const std::array<double, 4>& X, std::array<double, 4>& d, double) const
    {
        const double a = -delta2 * X[0] - alpha * X[1] + M * X[2];
        d[0] = X[1];
        d[1] = a;
        d[2] = X[3];
        d[3] = -X[2] - eps * (X[2] * X[2] - 1.0) * X[3] + A * a;
    }
};

// flatten: Odeint's step inlined into the loop, as in a program that steps it (out of line,
// its arrays go through memory between the calls: 2.3x the time).
[[gnu::flatten]] void odeint_dopri5_do_step(benchmark::State& state)
{
    const vimpact::wake_impact def(protocol_point_parameters());
    const auto p = protocol_point_parameters();
    const odeint_field field{def.delta() * def.delta(), def.alpha(), def.coupling_M(), p[4], p[3]};
    boost::numeric::odeint::runge_kutta_dopri5<std::array<double, 4>> stepper;
    std::array<double, 4> x{}, dxdt{}, x_out{}, dxdt_out{}, err{};
    for (int i = 0; i < 4; ++i) x[static_cast<std::size_t>(i)] = vimpact::wake_impact::initial_state[static_cast<std::size_t>(i)];
    field(x, dxdt, 0.0);
    const double step = step_size;
    double t = 0.0, sum = 0.0;
    for (auto _ : state) {
        stepper.do_step(field, x, dxdt, t, x_out, dxdt_out, step, err);
        sum += (err[0] + err[1]) + (err[2] + err[3]);
        x = x_out;
        dxdt = dxdt_out;
        t += step;
    }
    benchmark::DoNotOptimize(sum);
    benchmark::DoNotOptimize(x.data());
    state.counters["stages"] = 6;
}

}  // namespace

BENCHMARK(vimpact_trial<vimpact::dopri5>)->Name("vimpact_dopri5_attempt");
BENCHMARK(vimpact_trial<vimpact::dop853>)->Name("vimpact_dop853_attempt");
BENCHMARK(odeint_dopri5_do_step)->Name("odeint_dopri5_do_step");

BENCHMARK_MAIN();

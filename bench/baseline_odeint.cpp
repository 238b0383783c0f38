// Peer baseline: the paper's impact-oscillator protocol, written plainly with Boost.Odeint.
//   --method dopri5 (default): make_dense_output(tol, tol, runge_kutta_dopri5), events by
//     bisection on the dense output (calc_state);
//   --method rkf78: the controlled Runge-Kutta-Fehlberg 7(8) stepper (odeint has no dense
//     output for it), events by bisection on single re-steps from the accepted step's start.
//
// Standalone: depends only on the C++ standard library and Boost headers.
//
// Build:  g++ -O3 -march=native -std=c++20 -DNDEBUG bench/baseline_odeint.cpp -o build/baseline_odeint
// Run:    build/baseline_odeint [--method dopri5|rkf78] [common options, bench/baseline_common.hpp]
//
// Model (state X = (y, v, x, w)):
//   dy/dt = v
//   dv/dt = a(X) = -delta^2 y - alpha v + M x
//   dx/dt = w
//   dw/dt = -x - eps (x^2 - 1) w + A a(X)
//   delta = 1/(St Ur), alpha = 2 xi delta + gamma/mu, M = 0.05/mu
// Impact: y decreasing through sigma -> (y, v, x, w) := (sigma, -r v, x, w).
// Section: maxima of y (v crosses 0 downward).
// Protocol: discard the first 500 impacts, then record the next 200 section
// points and stop (or, with --horizon H, every section point up to t = H).
#include <boost/numeric/odeint.hpp>

#include "baseline_common.hpp"

namespace odeint = boost::numeric::odeint;

using state_t = std::array<double, 4>;

namespace {

using namespace baseline;

constexpr double dt0 = 1e-3;

// The system functor. Odeint copies the system object, so the counter is held
// by pointer.
struct wake_oscillator {
    long* rhs_calls;
    double delta2, alpha, M;
    void operator()(const state_t& X, state_t& dXdt, double /*t*/) const
    {
        ++*rhs_calls;
        const double y = X[0], v = X[1], x = X[2], w = X[3];
        const double a = -delta2 * y - alpha * v + M * x;
        dXdt[0] = v;
        dXdt[1] = a;
        dXdt[2] = w;
        dXdt[3] = -x - eps * (x * x - 1.0) * w + A * a;
    }
};

// Plain bisection for a root of f in [a, b] with f(a) > 0 >= f(b), down to
// |b - a| < bisect_tol or until the midpoint no longer separates a and b
// (machine precision of t). Returns the midpoint of the final bracket.
template <class F>
double bisect(F&& f, double a, double b)
{
    while (b - a > bisect_tol) {
        const double m = 0.5 * (a + b);
        if (m <= a || m >= b) break;
        if (f(m) > 0.0) a = m;
        else b = m;
    }
    return 0.5 * (a + b);
}

// One accepted step [t0, t1] from X0 to X1 with the state inside it given by state_at(t):
// the impact, the section point before it, and the reset. Returns true when the run is done.
template <class StateAt>
bool handle_step(const problem& p, run_result& res, double t0, double t1, const state_t& Xp, const state_t& Xc,
                 StateAt&& state_at, double& t_imp, state_t& X_reset)
{
    const bool impact = (Xp[0] - p.sigma > 0.0) && (Xc[0] - p.sigma <= 0.0);
    t_imp = t1;
    if (impact) t_imp = bisect([&](double t) { return state_at(t)[0] - p.sigma; }, t0, t1);
    // Section: v goes from > 0 to <= 0. Only the part of the step before the impact (if any)
    // belongs to the actual trajectory.
    const double v_end = impact ? state_at(t_imp)[1] : Xc[1];
    if (Xp[1] > 0.0 && v_end <= 0.0) {
        const double t_sec = bisect([&](double t) { return state_at(t)[1]; }, t0, t_imp);
        if (res.recording(p)) {
            res.points.push_back({t_sec, state_at(t_sec)});
            if (res.done(p)) return true;
        }
    }
    if (!impact) return false;
    X_reset = state_at(t_imp);
    X_reset[0] = p.sigma;
    X_reset[1] = -p.r * X_reset[1];
    ++res.impacts;
    return false;
}

run_result run_dopri5(const problem& p)
{
    run_result res;
    const wake_oscillator sys{&res.rhs_calls, p.delta() * p.delta(), p.alpha(), p.M()};
    auto stepper = odeint::make_dense_output(p.tol, p.tol, odeint::runge_kutta_dopri5<state_t>());
    const auto wall0 = clock::now();
    stepper.initialize(state_t{0.0, 0.0, 0.0, 0.1}, 0.0, dt0);
    state_t tmp;
    auto state_at = [&](double t) {
        stepper.calc_state(t, tmp);
        return tmp;
    };
    while (!res.done(p) && stepper.current_time() < p.t_end()) {
        const auto [t0, t1] = stepper.do_step(sys);
        ++res.steps;
        double t_imp;
        state_t X;
        const state_t Xp = stepper.previous_state(), Xc = stepper.current_state();
        if (handle_step(p, res, t0, t1, Xp, Xc, state_at, t_imp, X)) break;
        if (t_imp < t1) stepper.initialize(X, t_imp, stepper.current_time_step());
    }
    res.wall_s = seconds_since(wall0);
    return res;
}

run_result run_rkf78(const problem& p)
{
    run_result res;
    const wake_oscillator sys{&res.rhs_calls, p.delta() * p.delta(), p.alpha(), p.M()};
    auto stepper = odeint::make_controlled(p.tol, p.tol, odeint::runge_kutta_fehlberg78<state_t>());
    odeint::runge_kutta_fehlberg78<state_t> single;
    const auto wall0 = clock::now();
    state_t X{0.0, 0.0, 0.0, 0.1};
    double t = 0.0, dt = dt0;
    while (!res.done(p) && t < p.t_end()) {
        const state_t Xp = X;
        const double t0 = t;
        if (stepper.try_step(sys, X, t, dt) == odeint::fail) {
            ++res.rejected;
            continue;
        }
        ++res.steps;
        state_t tmp;
        auto state_at = [&](double s) {
            single.do_step(sys, Xp, t0, tmp, s - t0);
            return tmp;
        };
        double t_imp;
        state_t Xr;
        if (handle_step(p, res, t0, t, Xp, X, state_at, t_imp, Xr)) break;
        if (t_imp < t) {
            X = Xr;
            t = t_imp;
        }
    }
    res.wall_s = seconds_since(wall0);
    return res;
}

}  // namespace

int main(int argc, char** argv)
{
    const auto a = parse_with_method(argc, argv, {"dopri5", "rkf78"});
    if (!a) return 2;
    const auto& [method, p] = *a;
    if (method == "rkf78") return report(p, "odeint-rkf78", [&] { return run_rkf78(p); });
    return report(p, "odeint-dopri5", [&] { return run_dopri5(p); });
}

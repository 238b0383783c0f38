// Peer baseline: the paper's impact-oscillator protocol, written plainly with
// Boost.Odeint (dense-output Dormand-Prince 5(4), rtol = atol = 1e-10).
//
// Standalone: depends only on the C++ standard library and Boost headers.
//
// Build:  g++ -O3 -march=native -std=c++20 -DNDEBUG bench/baseline_odeint.cpp -o build/baseline_odeint
// Run:    build/baseline_odeint [--points FILE] [--repeat N]
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
// points and stop.

#include <boost/numeric/odeint.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace odeint = boost::numeric::odeint;

using state_t = std::array<double, 4>;

namespace {

// ---- paper preset ---------------------------------------------------------
constexpr double St = 0.2;
constexpr double xi = 0.0052;
constexpr double gamma_ = 0.8;
constexpr double mu = 1.19381;
constexpr double eps = 0.3;
constexpr double A = 12.0;
constexpr double r = 0.8;
constexpr double sigma = -0.150298;
constexpr double Ur = 16.0;

constexpr double delta = 1.0 / (St * Ur);
constexpr double alpha = 2.0 * xi * delta + gamma_ / mu;
constexpr double M = 0.05 / mu;

// ---- protocol -------------------------------------------------------------
constexpr long n_discard_impacts = 500;
constexpr std::size_t n_points = 200;
constexpr double tol = 1e-10;
constexpr double bisect_tol = 1e-14;
constexpr double dt0 = 1e-3;

struct section_point {
    double t;
    state_t X;
};

struct run_result {
    double wall_s = 0.0;
    long steps = 0;
    long rhs_calls = 0;
    long impacts = 0;
    std::vector<section_point> points;
};

// The system functor. Odeint copies the system object, so the counter is held
// by pointer.
struct wake_oscillator {
    long* rhs_calls;
    void operator()(const state_t& X, state_t& dXdt, double /*t*/) const {
        ++*rhs_calls;
        const double y = X[0], v = X[1], x = X[2], w = X[3];
        const double a = -delta * delta * y - alpha * v + M * x;
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
double bisect(F&& f, double a, double b) {
    while (b - a > bisect_tol) {
        const double m = 0.5 * (a + b);
        if (m <= a || m >= b) break;
        if (f(m) > 0.0)
            a = m;
        else
            b = m;
    }
    return 0.5 * (a + b);
}

run_result run_protocol() {
    run_result res;
    res.points.reserve(n_points);

    const wake_oscillator sys{&res.rhs_calls};
    auto stepper = odeint::make_dense_output(
        tol, tol, odeint::runge_kutta_dopri5<state_t>());

    const auto wall0 = std::chrono::steady_clock::now();

    state_t X0{0.0, 0.0, 0.0, 0.1};
    stepper.initialize(X0, 0.0, dt0);

    state_t tmp;
    auto guard_at = [&](double t) {
        stepper.calc_state(t, tmp);
        return tmp[0] - sigma;
    };
    auto section_at = [&](double t) {
        stepper.calc_state(t, tmp);
        return tmp[1];
    };

    while (res.points.size() < n_points) {
        const auto [t0, t1] = stepper.do_step(sys);
        ++res.steps;
        const state_t& Xp = stepper.previous_state();
        const state_t& Xc = stepper.current_state();

        // Impact: y - sigma goes from > 0 to <= 0 (i.e. y decreasing through sigma).
        const bool impact = (Xp[0] - sigma > 0.0) && (Xc[0] - sigma <= 0.0);
        double t_imp = t1;
        if (impact) t_imp = bisect(guard_at, t0, t1);

        // Section: v goes from > 0 to <= 0. Only the part of the step before
        // the impact (if any) belongs to the actual trajectory.
        const double t_end = t_imp;
        const double v_end = impact ? section_at(t_imp) : Xc[1];
        if (Xp[1] > 0.0 && v_end <= 0.0) {
            const double t_sec = bisect(section_at, t0, t_end);
            if (res.impacts >= n_discard_impacts) {
                stepper.calc_state(t_sec, tmp);
                res.points.push_back({t_sec, tmp});
                if (res.points.size() >= n_points) break;
            }
        }

        if (impact) {
            state_t X;
            stepper.calc_state(t_imp, X);
            X[0] = sigma;
            X[1] = -r * X[1];
            ++res.impacts;
            stepper.initialize(X, t_imp, stepper.current_time_step());
        }
    }

    const auto wall1 = std::chrono::steady_clock::now();
    res.wall_s = std::chrono::duration<double>(wall1 - wall0).count();
    return res;
}

void usage(const char* argv0) {
    std::fprintf(stderr, "usage: %s [--points FILE] [--repeat N]\n", argv0);
}

}  // namespace

int main(int argc, char** argv) {
    std::string points_file;
    int repeat = 1;
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--points") == 0 && i + 1 < argc) {
            points_file = argv[++i];
        } else if (std::strcmp(argv[i], "--repeat") == 0 && i + 1 < argc) {
            repeat = std::atoi(argv[++i]);
            if (repeat < 1) {
                usage(argv[0]);
                return 2;
            }
        } else {
            usage(argv[0]);
            return 2;
        }
    }

    std::vector<double> walls;
    run_result res;
    for (int k = 0; k < repeat; ++k) {
        res = run_protocol();
        walls.push_back(res.wall_s);
    }
    std::vector<double> sorted = walls;
    std::sort(sorted.begin(), sorted.end());
    const std::size_t n = sorted.size();
    const double median =
        (n % 2 == 1) ? sorted[n / 2] : 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]);

    if (!points_file.empty()) {
        std::FILE* f = std::fopen(points_file.c_str(), "w");
        if (!f) {
            std::perror(points_file.c_str());
            return 1;
        }
        std::fprintf(f, "t,y,v,x,w\n");
        for (const auto& p : res.points)
            std::fprintf(f, "%.17g,%.17g,%.17g,%.17g,%.17g\n", p.t, p.X[0], p.X[1],
                         p.X[2], p.X[3]);
        std::fclose(f);
    }

    std::printf("{\"wall_s\": %.9g, \"steps\": %ld, \"rhs_calls\": %ld, \"impacts\": %ld, "
                "\"points\": %zu",
                median, res.steps, res.rhs_calls, res.impacts, res.points.size());
    if (repeat > 1) {
        std::printf(", \"wall_all\": [");
        for (std::size_t i = 0; i < walls.size(); ++i)
            std::printf("%s%.9g", i ? ", " : "", walls[i]);
        std::printf("]");
    }
    std::printf("}\n");
    return 0;
}

// Peer baseline: the paper's impact-oscillator protocol as a plain hand-written loop: the
// Dormand-Prince 5(4) pair with its dense output (Hairer's DOPRI5 coefficients), the textbook
// step-size controller (err^(-1/5), safety 0.9, factors in [0.2, 10]), and events by
// bisection on the interpolant. What a careful engineer writes in an afternoon, with nothing
// but the standard library; templated on the floating type so that a long double build of the
// same loop serves as an independent reference (bench/work_precision.py).
//
// Build:  g++ -O3 -march=native -std=c++20 -DNDEBUG bench/baseline_plain.cpp -o build/baseline_plain
// Run:    build/baseline_plain [common options, bench/baseline_common.hpp] [--long-double]
//
// Model, impact, section and protocol: as bench/baseline_odeint.cpp.
#include <cmath>
#include <cstring>

#include "baseline_common.hpp"

namespace {

using namespace baseline;

template <class R>
struct state4 {
    R v[4];
};

template <class R>
struct plain_dopri5 {
    const problem& p;
    long rhs_calls = 0;
    R delta2, alpha, M;

    explicit plain_dopri5(const problem& pr) : p(pr)
    {
        const R delta = R(1) / (R(St) * R(p.ur));
        delta2 = delta * delta;
        alpha = R(2) * R(xi) * delta + R(gamma_) / R(mu);
        M = R(0.05) / R(mu);
    }

    void f(const R* X, R* d)
    {
        ++rhs_calls;
        const R a = -delta2 * X[0] - alpha * X[1] + M * X[2];
        d[0] = X[1];
        d[1] = a;
        d[2] = X[3];
        d[3] = -X[2] - R(eps) * (X[2] * X[2] - R(1)) * X[3] + R(A) * a;
    }

    run_result run()
    {
        using std::abs;
        using std::max;
        using std::min;
        using std::pow;
        using std::sqrt;
        run_result res;
        const R tol = R(p.tol);
        R t = 0, h = R(1e-3);
        R x[4] = {0, 0, 0, R(0.1)}, k1[4], k2[4], k3[4], k4[4], k5[4], k6[4], k7[4], y[4], xn[4];
        f(x, k1);
        // Dense output (Hairer's contd5): x(t + th h) from rcont1..5.
        R rc[5][4];
        R t_old = 0, h_old = 0;
        auto dense = [&](R tt, int i) {
            const R th = (tt - t_old) / h_old, th1 = R(1) - th;
            return rc[0][i] + th * (rc[1][i] + th1 * (rc[2][i] + th * (rc[3][i] + th1 * rc[4][i])));
        };
        auto bisect = [&](auto&& g, R a, R b) {
            for (int it = 0; it < 200 && b - a > R(bisect_tol); ++it) {
                const R m = R(0.5) * (a + b);
                if (m <= a || m >= b) break;
                if (g(m) > 0) a = m;
                else b = m;
            }
            return R(0.5) * (a + b);
        };
        const auto wall0 = clock::now();
        bool rejected_before = false;
        while (!res.done(p)) {
            if (t + h > R(p.t_end())) h = R(p.t_end()) - t;
            for (int i = 0; i < 4; ++i) y[i] = x[i] + h * (R(1) / R(5)) * k1[i];
            f(y, k2);
            for (int i = 0; i < 4; ++i) y[i] = x[i] + h * (R(3) / R(40) * k1[i] + R(9) / R(40) * k2[i]);
            f(y, k3);
            for (int i = 0; i < 4; ++i)
                y[i] = x[i] + h * (R(44) / R(45) * k1[i] - R(56) / R(15) * k2[i] + R(32) / R(9) * k3[i]);
            f(y, k4);
            for (int i = 0; i < 4; ++i)
                y[i] = x[i] + h * (R(19372) / R(6561) * k1[i] - R(25360) / R(2187) * k2[i] +
                                   R(64448) / R(6561) * k3[i] - R(212) / R(729) * k4[i]);
            f(y, k5);
            for (int i = 0; i < 4; ++i)
                y[i] = x[i] + h * (R(9017) / R(3168) * k1[i] - R(355) / R(33) * k2[i] + R(46732) / R(5247) * k3[i] +
                                   R(49) / R(176) * k4[i] - R(5103) / R(18656) * k5[i]);
            f(y, k6);
            for (int i = 0; i < 4; ++i)
                xn[i] = x[i] + h * (R(35) / R(384) * k1[i] + R(500) / R(1113) * k3[i] + R(125) / R(192) * k4[i] -
                                    R(2187) / R(6784) * k5[i] + R(11) / R(84) * k6[i]);
            f(xn, k7);
            R err = 0;
            for (int i = 0; i < 4; ++i) {
                const R e = h * (R(71) / R(57600) * k1[i] - R(71) / R(16695) * k3[i] + R(71) / R(1920) * k4[i] -
                                 R(17253) / R(339200) * k5[i] + R(22) / R(525) * k6[i] - R(1) / R(40) * k7[i]);
                const R sc = tol + tol * max(abs(x[i]), abs(xn[i]));
                err += (e / sc) * (e / sc);
            }
            err = sqrt(err / R(4));
            if (err > R(1)) {
                ++res.rejected;
                h *= max(R(0.2), R(0.9) * pow(err, R(-0.2)));
                rejected_before = true;
                continue;
            }
            ++res.steps;
            // Dense output of the accepted step.
            for (int i = 0; i < 4; ++i) {
                const R ydiff = xn[i] - x[i], bspl = h * k1[i] - ydiff;
                rc[0][i] = x[i];
                rc[1][i] = ydiff;
                rc[2][i] = bspl;
                rc[3][i] = ydiff - h * k7[i] - bspl;
                rc[4][i] = h * (R(-12715105075.0) / R(11282082432.0) * k1[i] +
                                R(87487479700.0) / R(32700410799.0) * k3[i] -
                                R(10690763975.0) / R(1880347072.0) * k4[i] +
                                R(701980252875.0) / R(199316789632.0) * k5[i] -
                                R(1453857185.0) / R(822651844.0) * k6[i] + R(69997945.0) / R(29380423.0) * k7[i]);
            }
            t_old = t;
            h_old = h;
            const R t1 = t + h;
            const R sigma_ = R(p.sigma);
            const bool impact = x[0] - sigma_ > 0 && xn[0] - sigma_ <= 0;
            R t_imp = t1;
            if (impact) t_imp = bisect([&](R s) { return dense(s, 0) - sigma_; }, t, t1);
            const R v_end = impact ? dense(t_imp, 1) : xn[1];
            if (x[1] > 0 && v_end <= 0) {
                const R ts = bisect([&](R s) { return dense(s, 1); }, t, t_imp);
                if (res.recording(p)) {
                    std::array<double, 4> X;
                    for (int i = 0; i < 4; ++i) X[i] = static_cast<double>(dense(ts, i));
                    res.points.push_back({static_cast<double>(ts), X});
                    if (res.done(p)) break;
                }
            }
            R fac = R(0.9) * pow(err, R(-0.2));
            fac = min(R(10), max(R(0.2), fac));
            if (rejected_before) fac = min(fac, R(1));
            rejected_before = false;
            if (impact) {
                for (int i = 0; i < 4; ++i) x[i] = dense(t_imp, i);
                x[0] = sigma_;
                x[1] = -R(p.r) * x[1];
                ++res.impacts;
                t = t_imp;
                f(x, k1);
            } else {
                for (int i = 0; i < 4; ++i) {
                    x[i] = xn[i];
                    k1[i] = k7[i];
                }
                t = t1;
            }
            h *= fac;
            if (t >= R(p.t_end())) break;
        }
        res.wall_s = seconds_since(wall0);
        res.rhs_calls = rhs_calls;
        return res;
    }
};

}  // namespace

int main(int argc, char** argv)
{
    bool long_double = false;
    std::vector<char*> rest;
    for (int i = 0; i < argc; ++i) {
        if (i > 0 && std::strcmp(argv[i], "--long-double") == 0) long_double = true;
        else rest.push_back(argv[i]);
    }
    const auto p = parse(static_cast<int>(rest.size()), rest.data());
    if (!p) return 2;
    return report(*p, long_double ? "plain-dopri5-long-double" : "plain-dopri5", [&] {
        if (long_double) return plain_dopri5<long double>(*p).run();
        return plain_dopri5<double>(*p).run();
    });
}

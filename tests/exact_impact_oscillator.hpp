#pragma once
// The one-sided forced impact oscillator solved exactly, in long double, for the tests:
//
//   y'' + 2 zeta y' + y = F cos(theta),  theta = omega t,  barrier at y = sigma, v -> -r v.
//
// Between impacts y = y_p + y_h with the periodic response y_p(theta) = a cos(theta) +
// b sin(theta), a = F (1 - omega^2) / D, b = 2 zeta omega F / D, D = (1 - omega^2)^2 +
// (2 zeta omega)^2, and the free part y_h(s) = e^{-zeta s} (e0 cos(wd s) + (e0' + zeta e0) / wd
// sin(wd s)), wd = sqrt(1 - zeta^2). Impacts are found by sampling every 1e-3 time units,
// splitting at interior extrema of y (so a grazing dip between samples is found), and bisecting.
//
// The 1:1 impacting orbits (one impact per forcing period T = 2 pi / omega) in closed form: with
// the impact at phase phi, pre-impact velocity v < 0, the free part over one period is e(T) =
// E e(0) with E = exp(A T), A = [0 1; -1 -2 zeta], so periodicity (y, v) at phi + 2 pi =
// (sigma, v) from (sigma, -r v) at phi is two linear equations in (sigma, v) for each phi.
#include <array>
#include <cmath>
#include <numbers>
#include <optional>
#include <utility>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>

namespace vimpact::test {

using ld = long double;

class exact_impact_oscillator {
public:
    exact_impact_oscillator(ld zeta, ld omega, ld F, ld r) : m_zeta(zeta), m_omega(omega), m_F(F), m_r(r)
    {
        const ld D = (1 - omega * omega) * (1 - omega * omega) + (2 * zeta * omega) * (2 * zeta * omega);
        m_a = F * (1 - omega * omega) / D;
        m_b = 2 * zeta * omega * F / D;
        m_wd = std::sqrt(1 - zeta * zeta);
    }

    [[nodiscard]] ld period() const { return 2 * std::numbers::pi_v<ld> / m_omega; }

    // (y, v) at time t (phase omega t) from (y0, v0) at t0, no impact in between.
    [[nodiscard]] std::pair<ld, ld> flow(ld t0, ld y0, ld v0, ld t) const
    {
        const ld e0 = y0 - yp(t0), e1 = v0 - vp(t0), s = t - t0;
        const ld e = std::exp(-m_zeta * s), c = std::cos(m_wd * s), sn = std::sin(m_wd * s);
        return {yp(t) + e * (e0 * c + (e1 + m_zeta * e0) / m_wd * sn),
                vp(t) + e * (e1 * c - (e0 + m_zeta * e1) / m_wd * sn)};
    }

    // The first impact on y = sigma after t0 and no later than t_end, if any.
    [[nodiscard]] std::optional<ld> next_impact(ld t0, ld y0, ld v0, ld sigma, ld t_end) const
    {
        const ld ds = 1e-3L;
        auto at = [&](ld t) { return flow(t0, y0, v0, t); };
        ld ta = t0;
        ld va = v0;
        for (int step = 1;; ++step) {
            const ld tb = std::min(t0 + step * ds, t_end);
            const ld vb = at(tb).second;
            std::array<ld, 3> ts{ta, tb, tb};
            int n = 2;
            if ((va > 0) != (vb > 0) && va != 0 && vb != 0) {
                ts = {ta, bisect([&](ld t) { return (at(t).second > 0) == (va > 0); }, ta, tb), tb};
                n = 3;
            }
            for (int k = 0; k + 1 < n; ++k) {
                const ld g0 = at(ts[k]).first - sigma, g1 = at(ts[k + 1]).first - sigma;
                if (g0 > 0 && g1 <= 0) return bisect([&](ld t) { return at(t).first - sigma > 0; }, ts[k], ts[k + 1]);
            }
            if (tb >= t_end) return std::nullopt;
            ta = tb;
            va = vb;
        }
    }

    // The stroboscopic map: (y, v) at t = T from (y0, v0) at t = 0, through every impact.
    [[nodiscard]] std::pair<ld, ld> strobe(ld y0, ld v0, ld sigma, int periods = 1) const
    {
        ld t = 0, y = y0, v = v0;
        const ld T = periods * period();
        while (auto ti = next_impact(t, y, v, sigma, T)) {
            const auto [yi, vi] = flow(t, y, v, *ti);
            t = *ti;
            y = sigma;
            v = -m_r * vi;
            (void)yi;
        }
        return flow(t, y, v, T);
    }

    // The Jacobian of the strobe map (periods-fold) by central differences of step h. Near a
    // grazing (an impact velocity v -> 0) the map changes on the scale v^2, and h must be far
    // below it for both perturbed orbits to make the same impacts.
    [[nodiscard]] Eigen::Matrix2d strobe_jacobian(ld y0, ld v0, ld sigma, int periods = 1, ld h = 1e-6L) const
    {
        Eigen::Matrix2d J;
        for (int j = 0; j < 2; ++j) {
            const ld dy = j == 0 ? h : 0, dv = j == 1 ? h : 0;
            const auto p = strobe(y0 + dy, v0 + dv, sigma, periods), m = strobe(y0 - dy, v0 - dv, sigma, periods);
            J(0, j) = static_cast<double>((p.first - m.first) / (2 * h));
            J(1, j) = static_cast<double>((p.second - m.second) / (2 * h));
        }
        return J;
    }

    // The 1:1 orbit with its impact at phase phi: sigma and the pre-impact velocity.
    [[nodiscard]] std::pair<ld, ld> one_one(ld phi) const
    {
        const ld T = period();
        const ld e = std::exp(-m_zeta * T), c = std::cos(m_wd * T), s = std::sin(m_wd * T);
        const ld E00 = e * (c + m_zeta / m_wd * s), E01 = e * s / m_wd, E10 = -e * s / m_wd, E11 = e * (c - m_zeta / m_wd * s);
        const ld t = phi / m_omega;
        const ld y_p = yp(t), v_p = vp(t);
        // unknowns q = sigma - y_p and v:  q = E00 q + E01 (-r v - v_p),  v - v_p = E10 q + E11 (-r v - v_p)
        const ld a11 = 1 - E00, a12 = E01 * m_r, b1 = -E01 * v_p;
        const ld a21 = -E10, a22 = 1 + m_r * E11, b2 = v_p - E11 * v_p;
        const ld det = a11 * a22 - a12 * a21;
        const ld q = (b1 * a22 - a12 * b2) / det, v = (a11 * b2 - a21 * b1) / det;
        return {q + y_p, v};
    }

    // The strobe point (t = 0 mod T) of the 1:1 orbit with its impact at phase phi in (0, 2 pi).
    [[nodiscard]] std::pair<ld, ld> one_one_strobe_point(ld phi) const
    {
        const auto [sigma, v] = one_one(phi);
        const ld t = phi / m_omega;
        return flow(t, sigma, -m_r * v, period());
    }

    // The smallest interior minimum of y - sigma on the 1:1 orbit's flight (infinity if none).
    [[nodiscard]] ld interior_min_gap(ld phi) const
    {
        const auto [sigma, v] = one_one(phi);
        const ld t0 = phi / m_omega, T = period();
        auto at = [&](ld t) { return flow(t0, sigma, -m_r * v, t); };
        ld best = INFINITY;
        const int n = 20000;
        ld ta = t0 + T * 1e-9L;
        ld va = at(ta).second;
        for (int k = 1; k <= n; ++k) {
            const ld tb = t0 + T * k / n * (1 - 1e-9L);
            const ld vb = at(tb).second;
            if (va < 0 && vb >= 0) {
                const ld tm = bisect([&](ld t) { return at(t).second < 0; }, ta, tb);
                best = std::min(best, at(tm).first - sigma);
            }
            ta = tb;
            va = vb;
        }
        return best;
    }

    // The smallest interior minimum of y - sigma over `periods` forcing periods from (y0, v0)
    // at t = 0, through every impact (infinity if the flights have none).
    [[nodiscard]] ld smallest_interior_gap(ld y0, ld v0, ld sigma, int periods = 1) const
    {
        const ld T = periods * period();
        ld best = INFINITY, t = 0, y = y0, v = v0;
        for (;;) {
            const std::optional<ld> ti = next_impact(t, y, v, sigma, T);
            const ld t_end = ti ? *ti : T;
            auto at = [&](ld s) { return flow(t, y, v, s); };
            const int n = 20000;
            ld ta = t, va = v;
            for (int k = 1; k <= n; ++k) {
                const ld tb = t + (t_end - t) * k / n;
                const ld vb = at(tb).second;
                if (va < 0 && vb >= 0 && k < n) {
                    const ld tm = bisect([&](ld s) { return at(s).second < 0; }, ta, tb);
                    best = std::min(best, at(tm).first - sigma);
                }
                ta = tb;
                va = vb;
            }
            if (!ti) return best;
            const ld vi = at(*ti).second;
            t = *ti;
            y = sigma;
            v = -m_r * vi;
        }
    }

    // lo, hi with pred(lo) true, pred(hi) false: the boundary.
    template <class P>
    static ld bisect(P&& pred, ld lo, ld hi)
    {
        for (int it = 0; it < 200 && lo < hi; ++it) {
            const ld mid = (lo + hi) / 2;
            if (mid <= lo || mid >= hi) break;
            if (pred(mid)) lo = mid;
            else hi = mid;
        }
        return hi;
    }

private:
    [[nodiscard]] ld yp(ld t) const { return m_a * std::cos(m_omega * t) + m_b * std::sin(m_omega * t); }
    [[nodiscard]] ld vp(ld t) const { return m_omega * (-m_a * std::sin(m_omega * t) + m_b * std::cos(m_omega * t)); }

    ld m_zeta, m_omega, m_F, m_r, m_a = 0, m_b = 0, m_wd = 0;
};

}  // namespace vimpact::test

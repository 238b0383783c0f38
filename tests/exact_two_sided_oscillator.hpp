#pragma once
// The two-sided impact oscillator solved exactly, in long double, for the tests:
//
//   x'' + 2 zeta x' + x = a cos(w t),  stops at x = d and x = -d,  v -> -r v at each.
//
// Between impacts the motion is linear and its closed form is exact_impact_oscillator's flow
// (the forcing amplitude a, frequency w). Impacts on either stop are found by sampling every
// 1e-3 time units, splitting at the interior extrema of x (so a grazing dip between samples is
// found), and bisecting.
//
// The symmetric P1 orbits in closed form: the orbit hits the right stop at time t0 with
// pre-impact velocity v > 0 and, half a forcing period later, the left stop with velocity -v
// (the system is symmetric under x -> -x, t -> t + T/2). The periodic response is odd under
// that shift, so with the free part's propagator E over T/2 the two conditions x(t0 + T/2) = -d,
// v(t0 + T/2) = -v from (d, -r v) at t0 are linear in (d, v) for each phase w t0: d(phase) and
// v(phase) in closed form, and for a given d the orbit's phase is a root of d(phase) - d.
#include <cmath>
#include <numbers>
#include <optional>
#include <utility>
#include <vector>

#include "exact_impact_oscillator.hpp"

namespace vimpact::test {

class exact_two_sided_oscillator {
public:
    exact_two_sided_oscillator(ld zeta, ld a, ld w, ld r) : m_free(zeta, w, a, r), m_zeta(zeta), m_a(a), m_w(w), m_r(r)
    {
        const ld D = (1 - w * w) * (1 - w * w) + (2 * zeta * w) * (2 * zeta * w);
        m_A = a * (1 - w * w) / D;
        m_B = 2 * zeta * w * a / D;
        m_wd = std::sqrt(1 - zeta * zeta);
    }

    [[nodiscard]] ld period() const { return 2 * std::numbers::pi_v<ld> / m_w; }

    // (x, v) at t from (x0, v0) at t0, no impact in between.
    [[nodiscard]] std::pair<ld, ld> flow(ld t0, ld x0, ld v0, ld t) const { return m_free.flow(t0, x0, v0, t); }

    // The first impact on either stop after t0 and no later than t_end: its time and whether it
    // is on the right stop.
    [[nodiscard]] std::optional<std::pair<ld, bool>> next_impact(ld t0, ld x0, ld v0, ld d, ld t_end) const
    {
        const ld ds = 1e-3L;
        auto at = [&](ld t) { return flow(t0, x0, v0, t); };
        ld ta = t0, va = v0;
        for (int step = 1;; ++step) {
            const ld tb = std::min(t0 + step * ds, t_end);
            const ld vb = at(tb).second;
            ld ts[3] = {ta, tb, tb};
            int n = 2;
            if ((va > 0) != (vb > 0) && va != 0 && vb != 0) {
                ts[1] = exact_impact_oscillator::bisect([&](ld t) { return (at(t).second > 0) == (va > 0); }, ta, tb);
                n = 3;
            }
            for (int k = 0; k + 1 < n; ++k) {
                const ld x0k = at(ts[k]).first, x1k = at(ts[k + 1]).first;
                if (d - x0k > 0 && d - x1k <= 0)
                    return std::pair{exact_impact_oscillator::bisect([&](ld t) { return d - at(t).first > 0; }, ts[k], ts[k + 1]),
                                     true};
                if (x0k + d > 0 && x1k + d <= 0)
                    return std::pair{exact_impact_oscillator::bisect([&](ld t) { return at(t).first + d > 0; }, ts[k], ts[k + 1]),
                                     false};
            }
            if (tb >= t_end) return std::nullopt;
            ta = tb;
            va = vb;
        }
    }

    // The stroboscopic map: (x, v) at t = periods T from (x0, v0) at t = 0 (phase 0), through
    // every impact.
    [[nodiscard]] std::pair<ld, ld> strobe(ld x0, ld v0, ld d, int periods = 1) const
    {
        return through_impacts(0, x0, v0, d, periods * period());
    }

    // (x, v) at t_end from (x0, v0) at t0, through every impact.
    [[nodiscard]] std::pair<ld, ld> through_impacts(ld t0, ld x0, ld v0, ld d, ld t_end) const
    {
        ld t = t0, x = x0, v = v0;
        while (auto hit = next_impact(t, x, v, d, t_end)) {
            const ld vi = flow(t, x, v, hit->first).second;
            t = hit->first;
            x = hit->second ? d : -d;
            v = -m_r * vi;
        }
        return flow(t, x, v, t_end);
    }

    // The symmetric P1 orbit with its right-stop impact at phase phi: the half clearance d and
    // the impact velocity v (closed form).
    [[nodiscard]] std::pair<ld, ld> symmetric(ld phi) const
    {
        const ld tau = period() / 2;
        const ld e = std::exp(-m_zeta * tau), c = std::cos(m_wd * tau), s = std::sin(m_wd * tau);
        const ld E00 = e * (c + m_zeta / m_wd * s), E01 = e * s / m_wd, E10 = -e * s / m_wd, E11 = e * (c - m_zeta / m_wd * s);
        const ld t0 = phi / m_w;
        const ld xp = xp_at(t0), vp = vp_at(t0);
        // d (1 + E00) - r E01 v = (1 + E00) xp + E01 vp;  E10 d + (1 - r E11) v = (1 + E11) vp + E10 xp
        const ld a11 = 1 + E00, a12 = -m_r * E01, b1 = (1 + E00) * xp + E01 * vp;
        const ld a21 = E10, a22 = 1 - m_r * E11, b2 = (1 + E11) * vp + E10 * xp;
        const ld det = a11 * a22 - a12 * a21;
        return {(b1 * a22 - a12 * b2) / det, (a11 * b2 - a21 * b1) / det};
    }

    // The phases in [0, 2 pi) of the symmetric P1 orbits for half clearance d: the roots of
    // d(phi) - d with v > 0 whose flight from the right stop to the left one stays between the
    // stops (interior extrema within [-d, d] up to `slack`).
    [[nodiscard]] std::vector<ld> symmetric_phases(ld d, ld slack = 0) const
    {
        std::vector<ld> out;
        const int n = 4000;
        const ld two_pi = 2 * std::numbers::pi_v<ld>;
        for (int k = 0; k < n; ++k) {
            const ld p0 = two_pi * k / n, p1 = two_pi * (k + 1) / n;
            const ld f0 = symmetric(p0).first - d, f1 = symmetric(p1).first - d;
            if (!((f0 > 0) != (f1 > 0))) continue;
            const ld phi = exact_impact_oscillator::bisect([&](ld p) { return (symmetric(p).first - d > 0) == (f0 > 0); }, p0, p1);
            if (!(symmetric(phi).second > 0)) continue;
            const auto [hi, lo] = interior_extrema(phi);
            if (hi <= d + slack && lo >= -d - slack) out.push_back(phi);
        }
        return out;
    }

    // The phase of the symmetric P1 orbit for half clearance d nearest to `ref`, among the roots
    // of d(phi) - d within 0.1 of it (physical or not: past a grazing the orbit's flight
    // crosses a stop); NaN if there is none.
    [[nodiscard]] ld symmetric_phase_near(ld d, ld ref) const
    {
        ld best = NAN;
        const int n = 200;
        for (int k = 0; k < n; ++k) {
            const ld p0 = ref - 0.1L + 0.2L * k / n, p1 = ref - 0.1L + 0.2L * (k + 1) / n;
            const ld f0 = symmetric(p0).first - d, f1 = symmetric(p1).first - d;
            if (!((f0 > 0) != (f1 > 0))) continue;
            const ld phi = exact_impact_oscillator::bisect([&](ld p) { return (symmetric(p).first - d > 0) == (f0 > 0); }, p0, p1);
            if (std::isnan(best) || std::abs(phi - ref) < std::abs(best - ref)) best = phi;
        }
        return best;
    }

    // The largest interior maximum and the smallest interior minimum of x on the symmetric
    // orbit's flight from the right stop (phase phi) to the left one (-inf, +inf if none).
    [[nodiscard]] std::pair<ld, ld> interior_extrema(ld phi) const
    {
        const auto [d, v] = symmetric(phi);
        const ld t0 = phi / m_w, t1 = t0 + period() / 2;
        auto at = [&](ld t) { return flow(t0, d, -m_r * v, t); };
        ld hi = -INFINITY, lo = INFINITY;
        const int n = 4000;
        ld ta = t0 + (t1 - t0) * 1e-9L, va = at(ta).second;
        for (int k = 1; k <= n; ++k) {
            const ld tb = t0 + (t1 - t0) * k / n * (1 - 1e-9L);
            const ld vb = at(tb).second;
            if ((va > 0) != (vb > 0)) {
                const ld tm = exact_impact_oscillator::bisect([&](ld t) { return (at(t).second > 0) == (va > 0); }, ta, tb);
                const ld x = at(tm).first;
                if (va > 0) hi = std::max(hi, x);
                else lo = std::min(lo, x);
            }
            ta = tb;
            va = vb;
        }
        return {hi, lo};
    }

    // The strobe point (t = 0 mod T) of the symmetric orbit with its right-stop impact at phase phi.
    [[nodiscard]] std::pair<ld, ld> strobe_point(ld phi) const
    {
        const auto [d, v] = symmetric(phi);
        // From the right-stop impact to the next multiple of T, through the left-stop impact.
        const ld T = period(), t0 = phi / m_w;
        return through_impacts(t0, d, -m_r * v, d, T * std::ceil(t0 / T + 1e-15L));
    }

private:
    [[nodiscard]] ld xp_at(ld t) const { return m_A * std::cos(m_w * t) + m_B * std::sin(m_w * t); }
    [[nodiscard]] ld vp_at(ld t) const { return m_w * (-m_A * std::sin(m_w * t) + m_B * std::cos(m_w * t)); }

    exact_impact_oscillator m_free;
    ld m_zeta, m_a, m_w, m_r, m_A = 0, m_B = 0, m_wd = 0;
};

}  // namespace vimpact::test

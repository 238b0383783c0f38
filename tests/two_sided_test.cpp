// The two-sided impact oscillator, the built-in two_sided_impact_oscillator and the model file
// examples/models/two_sided_impact_oscillator.toml:
//   x'' + 2 zeta x' + x = a cos(w t),  stops at x = d ("right", gap d - x) and x = -d
//   ("left", gap x + d), both v -> -r v.
// Impacts on both stops against an exact event-driven solution built from the closed form
// between impacts; Floquet multipliers of a periodic orbit with impacts on both stops against
// a finite-difference Jacobian of the stroboscopic map and against Liouville's formula.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <complex>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include <Eigen/LU>

#include "example_models.hpp"
#include "test_support.hpp"
#include "vimpact/analysis/floquet.hpp"
#include "vimpact/analysis/protocol.hpp"
#include "vimpact/hybrid/flow.hpp"
#include "vimpact/model/builtin/two_sided_impact_oscillator.hpp"
#include "vimpact/model/native_model.hpp"
#include "vimpact/tangent/impact_jump.hpp"
#include "vimpact/tangent/section_map.hpp"

namespace {

using vimpact::crossing;
using vimpact::mat;
using vimpact::model;
using vimpact::outcome;
using vimpact::vec;
using cplx = std::complex<double>;
using native = vimpact::native_model<vimpact::two_sided_impact_oscillator>;
constexpr double pi = std::numbers::pi;
using ld = long double;

model builtin() { return model::builtin("two_sided_impact_oscillator"); }
model from_file() { return vimpact::test::example_model("two_sided_impact_oscillator"); }

double parameter(const model& m, const char* name) { return m.parameter(m.info().parameter_index(name)); }

// ---- the exact event-driven solution ------------------------------------------------------
//
// Between impacts x = x_p + y with the periodic response x_p = C cos(w t) + D sin(w t),
// C = a (1 - w^2) / Delta, D = 2 zeta w a / Delta, Delta = (1 - w^2)^2 + (2 zeta w)^2, and the
// free part y(s) = e^{-zeta s} (y0 cos(wd s) + (y0' + zeta y0) / wd sin(wd s)), wd =
// sqrt(1 - zeta^2), s the time since the last impact. An impact is the first s > 0 where a gap
// (d - x or x + d) goes from > 0 to <= 0: found by sampling every 1e-3, splitting at interior
// extrema of x (so a grazing dip between samples is found), and bisecting in long double.
struct reference_impact {
    int surface;
    ld t, v_pre, v_post;
};

class exact_two_sided {
public:
    exact_two_sided(ld zeta, ld a, ld w, ld d, ld r) : m_zeta(zeta), m_a(a), m_w(w), m_d(d), m_r(r)
    {
        const ld delta = (1 - w * w) * (1 - w * w) + (2 * zeta * w) * (2 * zeta * w);
        m_C = a * (1 - w * w) / delta;
        m_D = 2 * zeta * w * a / delta;
        m_wd = std::sqrt(1 - zeta * zeta);
    }

    // The first impacts from (x0, v0) at t = 0.
    std::vector<reference_impact> impacts(ld x0, ld v0, int count) const
    {
        std::vector<reference_impact> out;
        ld t0 = 0, xs = x0, vs = v0;
        while (static_cast<int>(out.size()) < count) {
            const auto [surface, t] = next_impact(t0, xs, vs);
            if (surface < 0) break;
            ld x, v;
            at(t0, xs, vs, t, x, v);
            out.push_back({surface, t, v, -m_r * v});
            t0 = t;
            xs = surface == 0 ? m_d : -m_d;
            vs = -m_r * v;
        }
        return out;
    }

private:
    ld xp(ld t) const { return m_C * std::cos(m_w * t) + m_D * std::sin(m_w * t); }
    ld vp(ld t) const { return m_w * (-m_C * std::sin(m_w * t) + m_D * std::cos(m_w * t)); }

    // The state at t from (x0, v0) at t0, no impact in between.
    void at(ld t0, ld x0, ld v0, ld t, ld& x, ld& v) const
    {
        const ld y0 = x0 - xp(t0), y1 = v0 - vp(t0), s = t - t0;
        const ld e = std::exp(-m_zeta * s), c = std::cos(m_wd * s), sn = std::sin(m_wd * s);
        x = xp(t) + e * (y0 * c + (y1 + m_zeta * y0) / m_wd * sn);
        v = vp(t) + e * (y1 * c - (y0 + m_zeta * y1) / m_wd * sn);
    }
    ld gap(int i, ld x) const { return i == 0 ? m_d - x : x + m_d; }

    struct found {
        int surface;
        ld t;
    };
    found next_impact(ld t0, ld x0, ld v0) const
    {
        const ld ds = 1e-3L;
        auto x_at = [&](ld t) {
            ld x, v;
            at(t0, x0, v0, t, x, v);
            return std::pair<ld, ld>{x, v};
        };
        ld ta = t0;
        ld va = x_at(ta).second;
        for (int step = 1; step < 200000; ++step) {
            const ld tb = t0 + step * ds;
            const ld vb = x_at(tb).second;
            // An interior extremum of x (v changes sign): split there.
            std::array<ld, 3> ts{ta, tb, tb};
            int n = 2;
            if ((va > 0) != (vb > 0) && va != 0 && vb != 0) {
                ld lo = ta, hi = tb;
                for (int it = 0; it < 200; ++it) {
                    const ld mid = (lo + hi) / 2;
                    if ((x_at(mid).second > 0) == (va > 0)) lo = mid;
                    else hi = mid;
                }
                ts = {ta, (lo + hi) / 2, tb};
                n = 3;
            }
            for (int k = 0; k + 1 < n; ++k) {
                found best{-1, 0};
                for (int i = 0; i < 2; ++i) {
                    const ld g0 = gap(i, x_at(ts[k]).first), g1 = gap(i, x_at(ts[k + 1]).first);
                    if (!(g0 > 0 && g1 <= 0)) continue;
                    ld lo = ts[k], hi = ts[k + 1];
                    for (int it = 0; it < 200; ++it) {
                        const ld mid = (lo + hi) / 2;
                        if (gap(i, x_at(mid).first) > 0) lo = mid;
                        else hi = mid;
                    }
                    if (best.surface < 0 || hi < best.t) best = {i, hi};
                }
                if (best.surface >= 0) return best;
            }
            ta = tb;
            va = vb;
        }
        return {-1, 0};
    }

    ld m_zeta, m_a, m_w, m_d, m_r, m_C, m_D, m_wd;
};

exact_two_sided exact_for(const model& m)
{
    return exact_two_sided(parameter(m, "zeta"), parameter(m, "a"), parameter(m, "w"), parameter(m, "d"),
                           parameter(m, "r"));
}

// Every impact from rest at the origin through the protocol with no transient: the recorded
// points are the post-impact states, the impacts (pre, post, surface) all of them.
vimpact::simulation impacts_of(const model& m, long count)
{
    vimpact::protocol_options o;
    o.transient_impacts = 0;
    o.record_points = count;
    o.section = vimpact::section_choice::impacts();
    o.flow.integration.rtol = o.flow.integration.atol = 1e-12;
    return vimpact::simulate(m, Eigen::Vector3d::Zero(), o);
}

void check_against_exact(const model& m, const char* what)
{
    const int count = 40;
    const auto ref = exact_for(m).impacts(0, 0, count);
    ASSERT_EQ(static_cast<int>(ref.size()), count);
    std::array<long, 2> by_surface{0, 0};
    for (const auto& e : ref) ++by_surface[static_cast<std::size_t>(e.surface)];
    ASSERT_GE(by_surface[0], 10);  // both stops are hit, many times
    ASSERT_GE(by_surface[1], 10);

    const auto run = impacts_of(m, count);
    ASSERT_EQ(run.status, outcome::ok) << what;
    ASSERT_EQ(run.impacts.size(), static_cast<std::size_t>(count)) << what;
    EXPECT_EQ(run.stats.impacts_by_surface, (std::vector<long>{by_surface[0], by_surface[1]})) << what;
    const double d = parameter(m, "d"), w = parameter(m, "w"), r = parameter(m, "r");
    double dt = 0.0, dx = 0.0;
    for (std::size_t k = 0; k < ref.size(); ++k) {
        const auto& e = ref[k];
        ASSERT_EQ(run.impacts.surface[k], e.surface) << what << " impact " << k;
        const double t = run.impacts.pre.t(k);
        dt = std::max(dt, std::abs(t - static_cast<double>(e.t)));
        // On the right stop at x = d, on the left at x = -d, exactly (the gap is a coordinate).
        EXPECT_EQ(run.impacts.pre.x(k, 0), e.surface == 0 ? d : -d) << what << " impact " << k;
        EXPECT_EQ(run.impacts.post.x(k, 0), run.impacts.pre.x(k, 0));
        EXPECT_EQ(run.impacts.post.x(k, 1), -r * run.impacts.pre.x(k, 1));
        dx = std::max(dx, std::abs(run.impacts.pre.x(k, 1) - static_cast<double>(e.v_pre)));
        dx = std::max(dx, std::abs(run.impacts.post.x(k, 1) - static_cast<double>(e.v_post)));
        dx = std::max(dx, std::abs(run.impacts.pre.x(k, 2) - w * static_cast<double>(e.t)));
        // Moving into the stop: v > 0 at the right one, v < 0 at the left one.
        EXPECT_GT(e.surface == 0 ? e.v_pre : -e.v_pre, 0) << what << " impact " << k;
    }
    EXPECT_LE(dt, 1e-8) << what;
    EXPECT_LE(dx, 1e-8) << what;
    std::printf("[ measured ] %s, d = %g: %d impacts (%ld right, %ld left) up to t = %.3f; largest difference "
                "from the exact solution %.1e in time, %.1e in state\n",
                what, d, count, by_surface[0], by_surface[1], static_cast<double>(ref.back().t), dt, dx);
}

}  // namespace

// d = 0.5 with the default forcing (a = 1, w = 1.2, free amplitude 2.2): the stops are hit
// alternately and irregularly; 40 impacts, at least 10 on each.
TEST(TwoSided, BuiltInImpactsBothStopsAsTheExactSolution)
{
    check_against_exact(vimpact::test::with(builtin(), "d", 0.5), "built-in");
}

TEST(TwoSided, ModelFileImpactsBothStopsAsTheExactSolution)
{
    const model m = from_file();
    ASSERT_EQ(m.native(), vimpact::native_kind::none);  // the compiled file, not the built-in
    ASSERT_EQ(m.info().surface_names(), "right, left");
    check_against_exact(vimpact::test::with(m, "d", 0.5), "model file");
}

// ---- Floquet on the symmetric period-1 orbit ------------------------------------------------

namespace {

// The stroboscopic map P^k, integrated independently of the section machinery: the k-th
// crossing of phi = 0 mod 2 pi going up after the start (crossings within half a forcing
// period of the start are the start itself).
struct strobe_observer : vimpact::flow_observer {
    int returns;
    double t_min;
    int seen = 0;
    vec<3> end = vec<3>::Zero();
    vimpact::flow_control on_section(int, crossing, double t, const vec<3>& x)
    {
        if (t < t_min) return vimpact::flow_control::proceed;
        if (++seen < returns) return vimpact::flow_control::proceed;
        end = x;
        return vimpact::flow_control::stop;
    }
};

vec<3> strobe_map(const native& m, const vec<3>& x0, int returns, double period)
{
    vimpact::flow_options o;
    o.integration.rtol = o.integration.atol = 1e-13;
    o.events = {vimpact::flow_event::section(0, crossing::up)};
    o.t_max = (returns + 1) * period;
    vimpact::hybrid_flow<native> flow(m, o);
    flow.start(0.0, x0);
    strobe_observer obs;
    obs.returns = returns;
    obs.t_min = 0.5 * period;
    const outcome st = flow.run(obs);
    EXPECT_EQ(st, outcome::ok);
    return obs.end;
}

// The nontrivial pair as an unordered pair.
double pair_distance(cplx a, cplx b, cplx c, cplx d)
{
    return std::min(std::max(std::abs(a - c), std::abs(b - d)), std::max(std::abs(a - d), std::abs(b - c)));
}

}  // namespace

// The default parameters (d = 1) have a stable symmetric P1 orbit with one impact on each stop
// per forcing period T = 2 pi / w. The trivial multiplier (the phase direction) is 1; the
// other two are the eigenvalues of the Jacobian of the stroboscopic map in the chart (x, v),
// here by central differences of the map; det of the monodromy is exp(-2 zeta T) r^4
// (divergence -2 zeta, saltation determinant r^2 per impact).
TEST(TwoSided, FloquetMultipliersOfTheP1OrbitMatchFiniteDifferencesAndLiouville)
{
    const model m = builtin();
    const double zeta = parameter(m, "zeta"), w = parameter(m, "w"), r = parameter(m, "r");
    const double T = 2.0 * pi / w;
    vimpact::floquet_options opt;
    opt.protocol.section = vimpact::section_choice::crossings(0);
    opt.protocol.transient_impacts = 200;
    opt.protocol.record_points = 20;
    const auto res = vimpact::floquet(m, Eigen::Vector3d::Zero(), opt);
    ASSERT_EQ(res.status, outcome::ok);
    EXPECT_EQ(res.label, "P1");
    EXPECT_EQ(res.section_returns, 1);
    EXPECT_NEAR(res.period, T, 1e-10);
    EXPECT_EQ(res.impacts_per_period, 2);
    EXPECT_EQ(res.impacts_by_surface, (std::vector<long>{1, 1}));
    ASSERT_EQ(res.multipliers.size(), 3u);
    EXPECT_LE(res.trivial_error, 1e-9);
    EXPECT_LE(std::abs(res.multipliers[0] - 1.0), 1e-9);
    EXPECT_TRUE(res.stable());

    // Central differences of P in (x, v) at the orbit point, phi kept.
    const native nm(m.parameters());
    const vec<3> z = res.orbit_point;
    const double h = 1e-5;
    mat<2> J;
    for (int j = 0; j < 2; ++j) {
        vec<3> plus = z, minus = z;
        plus[j] += h;
        minus[j] -= h;
        const vec<3> a = strobe_map(nm, plus, res.section_returns, T);
        const vec<3> b = strobe_map(nm, minus, res.section_returns, T);
        for (int i = 0; i < 2; ++i) J(i, j) = (a[i] - b[i]) / (2.0 * h);
    }
    const double tr = J.trace(), det = J.determinant();
    const cplx root = std::sqrt(cplx(0.25 * tr * tr - det, 0.0));
    const cplx fd1 = 0.5 * tr + root, fd2 = 0.5 * tr - root;
    const double fd_error = pair_distance(res.multipliers[1], res.multipliers[2], fd1, fd2);
    EXPECT_LE(fd_error, 1e-6);
    // The fixed point itself: P(z) = z.
    EXPECT_LE(vimpact::test::max_abs_diff(strobe_map(nm, z, res.section_returns, T).head<2>(), z.head<2>()), 1e-9);

    // Liouville: det Phi = exp(-2 zeta T) r^(2 n), n = 2 impacts.
    const double liouville = std::exp(-2.0 * zeta * T) * std::pow(r, 4.0);
    EXPECT_NEAR(res.divergence_integral, -2.0 * zeta * T, 1e-10);
    EXPECT_NEAR(res.log_det_jumps, 2.0 * std::log(r * r), 1e-12);
    EXPECT_NEAR(res.det_monodromy, liouville, 1e-9 * liouville);
    EXPECT_NEAR(std::abs(res.multipliers[1] * res.multipliers[2]), liouville, 1e-9 * liouville);

    // The saltation matrix at the orbit's two impacts, against its closed form
    // [[-r, 0, 0], [(a+ + r a-) / v, -r, 0], [0, 0, 1]] (det r^2).
    ASSERT_EQ(res.impacts.size(), 2u);
    const double a = parameter(m, "a");
    for (std::size_t k = 0; k < 2; ++k) {
        const vec<3> x = res.impacts.pre.x(k);
        const double am = -2.0 * zeta * x[1] - x[0] + a * std::cos(x[2]);
        const double ap = 2.0 * zeta * r * x[1] - x[0] + a * std::cos(x[2]);
        mat<3> S;
        S << -r, 0.0, 0.0, (ap + r * am) / x[1], -r, 0.0, 0.0, 0.0, 1.0;
        EXPECT_LE(vimpact::test::max_abs_diff(vimpact::saltation_matrix(nm, res.impacts.surface[k], x), S), 1e-13);
        EXPECT_NEAR(S.determinant(), r * r, 1e-15);
    }

    // The model file gives the same multipliers.
    const auto file = vimpact::floquet(from_file(), Eigen::Vector3d::Zero(), opt);
    ASSERT_EQ(file.status, outcome::ok);
    ASSERT_EQ(file.multipliers.size(), 3u);
    double file_diff = 0.0;
    for (std::size_t i = 0; i < 3; ++i) file_diff = std::max(file_diff, std::abs(file.multipliers[i] - res.multipliers[i]));
    EXPECT_LE(file_diff, 1e-10);

    std::printf("[ measured ] two-sided P1 (d = 1): multipliers 1 %+.2e, %.12f%+.12fi, %.12f%+.12fi; finite "
                "differences %.12f%+.12fi, %.12f%+.12fi (difference %.1e); det Phi %.12e, exp(-2 zeta T) r^4 "
                "%.12e (relative %.1e); model file multipliers within %.1e\n",
                std::abs(res.multipliers[0] - 1.0), res.multipliers[1].real(), res.multipliers[1].imag(),
                res.multipliers[2].real(), res.multipliers[2].imag(), fd1.real(), fd1.imag(), fd2.real(), fd2.imag(),
                fd_error, res.det_monodromy, liouville, std::abs(res.det_monodromy - liouville) / liouville, file_diff);
}

// The section map from a point of the strobe section whose phase lies a rounding error before
// phi = 0 mod 2 pi (sin(phi) < 0 by 1e-14): its first return is one forcing period later, not
// the start itself. (The protocol's own points are such points about half of the time: the
// section sin(phi) is located to an ulp of phi, and phi grows with t.)
TEST(TwoSided, SectionMapFromAPointJustBeforeTheStrobeReturnsAfterAFullPeriod)
{
    const model m = builtin();
    const native nm(m.parameters());
    const double T = 2.0 * pi / parameter(m, "w");
    double phi = 300.0 * pi;
    while (std::sin(phi) >= 0.0) phi = std::nextafter(phi, 0.0);
    ASSERT_GT(std::sin(phi), -1e-12);
    const auto ret = vimpact::section_map<vimpact::dop853>(nm, vec<3>(0.1, 0.2, phi), 1);
    ASSERT_EQ(ret.status, outcome::ok);
    EXPECT_NEAR(ret.time, T, 1e-9);
}

// At d = 0.6 the protocol settles on a P1 orbit with two impacts per period whose strobe
// points lie just before the section: the Floquet analysis must still return one forcing
// period, two impacts and the multipliers of that orbit.
TEST(TwoSided, FloquetOnTheStrobeSectionMeasuresAFullPeriod)
{
    const model m = vimpact::test::with(builtin(), "d", 0.6);
    vimpact::floquet_options opt;
    opt.protocol.section = vimpact::section_choice::crossings(0);
    opt.protocol.transient_impacts = 300;
    opt.protocol.record_points = 40;
    const auto res = vimpact::floquet(m, Eigen::Vector3d::Zero(), opt);
    ASSERT_EQ(res.status, outcome::ok);
    EXPECT_EQ(res.label, "P1");
    EXPECT_NEAR(res.period, 2.0 * pi / parameter(m, "w"), 1e-10);
    EXPECT_EQ(res.impacts_per_period, 2);
    const double zeta = parameter(m, "zeta"), r = parameter(m, "r");
    const double liouville = std::exp(-2.0 * zeta * res.period) * std::pow(r, 4.0);
    EXPECT_NEAR(res.det_monodromy, liouville, 1e-9 * liouville);
}

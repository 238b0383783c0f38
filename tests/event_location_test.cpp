// Tests of the event locator (event_location.hpp) on hand-made scalar functions g(theta) on
// [0, 1] whose roots are known in closed form. A downward crossing is a passage from g > 0 to
// g <= 0 and belongs to the left-open interval (0, 1]; upward crossings are those of -g.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <random>
#include <vector>

#include "vimpact/integrate/event_location.hpp"

namespace {

using vimpact::crossing_direction;
using vimpact::find_crossings;
using vimpact::find_down_crossings;
using vimpact::scalar_sample;

using scalar_fn = std::function<scalar_sample(double)>;

// Runs the locator with the end samples taken from g itself and collects the roots.
std::vector<double> crossings(crossing_direction dir, const scalar_fn& g, int* reported = nullptr,
                              int stop_after = 1000)
{
    std::vector<double> roots;
    const int n = find_crossings(
        dir, g, g(0.0), g(1.0),
        [&](double th) {
            roots.push_back(th);
            return static_cast<int>(roots.size()) < stop_after;
        });
    if (reported) *reported = n;
    return roots;
}

// theta lives in [0, 1]; the locator resolves it to a couple of ulps of 1 (its bracket stops at
// a width of 2 eps), which for theta < 1/2 is several ulps of theta itself.
constexpr double theta_tol = 4.0 * std::numeric_limits<double>::epsilon();

}  // namespace

// A simple root of a polynomial with a known root: g = (r - theta)(1 + theta^2), r = 0.37.
// The locator returns the root to within a few ulps (of 1, the scale of theta), on the g <= 0
// side.
TEST(EventLocation, SimpleRootToAFewUlps)
{
    const double r = 0.37;
    scalar_fn g = [r](double t) {
        return scalar_sample{(r - t) * (1.0 + t * t), -(1.0 + t * t) + (r - t) * 2.0 * t};
    };
    int n = 0;
    const auto roots = crossings(crossing_direction::down, g, &n);
    ASSERT_EQ(roots.size(), 1u);
    EXPECT_EQ(n, 1);
    EXPECT_LE(std::abs(roots[0] - r), theta_tol);
    EXPECT_LE(g(roots[0]).value, 0.0);  // documented: the returned point lies on the g <= 0 side
}

// Same for a root that is not a double (1/3) of a cubic with a different slope scale.
TEST(EventLocation, SimpleRootOfCubicNotRepresentable)
{
    // g = 1 - 27 theta^3 = (1 - 3 theta)(1 + 3 theta + 9 theta^2): single root 1/3.
    scalar_fn g = [](double t) { return scalar_sample{1.0 - 27.0 * t * t * t, -81.0 * t * t}; };
    const auto roots = crossings(crossing_direction::down, g);
    ASSERT_EQ(roots.size(), 1u);
    EXPECT_LE(std::abs(roots[0] - 1.0 / 3.0), theta_tol);
}

// Direction filtering: an upward crossing is not a downward one and vice versa.
TEST(EventLocation, DirectionFiltering)
{
    const double r = 0.62;
    scalar_fn up = [r](double t) { return scalar_sample{t - r, 1.0}; };
    scalar_fn down = [r](double t) { return scalar_sample{r - t, -1.0}; };

    EXPECT_TRUE(crossings(crossing_direction::down, up).empty());
    EXPECT_TRUE(crossings(crossing_direction::up, down).empty());

    const auto ru = crossings(crossing_direction::up, up);
    ASSERT_EQ(ru.size(), 1u);
    EXPECT_LE(std::abs(ru[0] - r), theta_tol);
    const auto rd = crossings(crossing_direction::down, down);
    ASSERT_EQ(rd.size(), 1u);
    EXPECT_LE(std::abs(rd[0] - r), theta_tol);
}

// Two roots in one interval with both ends positive: g = (theta - 0.3)(theta - 0.7) goes
// down at 0.3 and up at 0.7. Each direction sees exactly its own root.
TEST(EventLocation, QuadraticWithDownThenUp)
{
    scalar_fn g = [](double t) { return scalar_sample{(t - 0.3) * (t - 0.7), 2.0 * t - 1.0}; };
    const auto d = crossings(crossing_direction::down, g);
    ASSERT_EQ(d.size(), 1u);
    EXPECT_NEAR(d[0], 0.3, theta_tol);
    const auto u = crossings(crossing_direction::up, g);
    ASSERT_EQ(u.size(), 1u);
    EXPECT_NEAR(u[0], 0.7, theta_tol);
}

// Cubic g = -(theta - 0.2)(theta - 0.5)(theta - 0.8): down at 0.2, up at 0.5, down at 0.8.
// Both downward roots are reported in time order; a callback returning false after the
// first (a terminal event) stops the search there.
TEST(EventLocation, TwoDownCrossingsInOrderAndTerminalStop)
{
    scalar_fn g = [](double t) {
        const double a = t - 0.2, b = t - 0.5, c = t - 0.8;
        return scalar_sample{-a * b * c, -(b * c + a * c + a * b)};
    };
    int n = 0;
    const auto d = crossings(crossing_direction::down, g, &n);
    ASSERT_EQ(d.size(), 2u);
    EXPECT_EQ(n, 2);
    EXPECT_NEAR(d[0], 0.2, theta_tol);
    EXPECT_NEAR(d[1], 0.8, theta_tol);

    const auto first = crossings(crossing_direction::down, g, &n, 1);
    ASSERT_EQ(first.size(), 1u);
    EXPECT_EQ(n, 1);
    EXPECT_NEAR(first[0], 0.2, theta_tol);
    // (The upward crossing at 0.5 is not asserted: -g is < 0 at theta = 0, > 0 at theta = 1
    // and rising at both ends, so the crossing hides behind two interior extrema, the case
    // event_location.hpp documents as escaping its screening.)
}

// Grazing dip: g = (theta - c)^2 - 1e-10 is positive at both ends and at every sample
// theta = k/8 (c = 0.53 is 0.03 from the nearest sample), negative only on
// (c - 1e-5, c + 1e-5). The downward crossing at c - 1e-5 must be found (the locator splits
// at the interior minimum, where g' = 0), and the upward one at c + 1e-5 likewise.
// With + 1e-12 instead the function never reaches zero: nothing is reported.
TEST(EventLocation, GrazingDipBetweenSamplesIsFound)
{
    const double c = 0.53;
    for (int k = 0; k <= 8; ++k) ASSERT_GT((k / 8.0 - c) * (k / 8.0 - c) - 1e-10, 0.0);
    scalar_fn dip = [c](double t) { return scalar_sample{(t - c) * (t - c) - 1e-10, 2.0 * (t - c)}; };
    const auto d = crossings(crossing_direction::down, dip);
    ASSERT_EQ(d.size(), 1u);
    EXPECT_NEAR(d[0], c - 1e-5, 1e-13);
    const auto u = crossings(crossing_direction::up, dip);
    ASSERT_EQ(u.size(), 1u);
    EXPECT_NEAR(u[0], c + 1e-5, 1e-13);

    scalar_fn miss = [c](double t) { return scalar_sample{(t - c) * (t - c) + 1e-12, 2.0 * (t - c)}; };
    EXPECT_TRUE(crossings(crossing_direction::down, miss).empty());
    EXPECT_TRUE(crossings(crossing_direction::up, miss).empty());
}

// The mirror image: both ends negative with a thin positive bump 1e-10 - (theta - c)^2.
// The downward crossing on its far side (c + 1e-5) is a real crossing and must be found.
TEST(EventLocation, GrazingBumpFromBelowIsFound)
{
    const double c = 0.41;
    scalar_fn bump = [c](double t) { return scalar_sample{1e-10 - (t - c) * (t - c), -2.0 * (t - c)}; };
    const auto d = crossings(crossing_direction::down, bump);
    ASSERT_EQ(d.size(), 1u);
    EXPECT_NEAR(d[0], c + 1e-5, 1e-13);
    const auto u = crossings(crossing_direction::up, bump);
    ASSERT_EQ(u.size(), 1u);
    EXPECT_NEAR(u[0], c - 1e-5, 1e-13);
}

// A dip whose minimum is exactly on a sample point (theta = 1/2) is found as well.
TEST(EventLocation, GrazingDipCentredOnASample)
{
    scalar_fn dip = [](double t) { return scalar_sample{(t - 0.5) * (t - 0.5) - 1e-10, 2.0 * (t - 0.5)}; };
    const auto d = crossings(crossing_direction::down, dip);
    ASSERT_EQ(d.size(), 1u);
    EXPECT_NEAR(d[0], 0.5 - 1e-5, 1e-13);
}

// Boundary convention: a root exactly at theta = 1 (g(1) == 0.0 exactly) belongs to the step
// that ends there and is reported once with theta == 1 exactly; the next step, which starts
// with g = 0 (not > 0), does not report it again. Checked for both directions.
TEST(EventLocation, RootExactlyAtStepEndReportedOnce)
{
    // g = 1 - theta^3 on the first step, g(1) = 0 exactly; the same function continued on the
    // next step: g_next(theta) = 1 - (1 + theta)^3.
    scalar_fn g = [](double t) { return scalar_sample{1.0 - t * t * t, -3.0 * t * t}; };
    scalar_fn g_next = [](double t) {
        const double s = 1.0 + t;
        return scalar_sample{1.0 - s * s * s, -3.0 * s * s};
    };
    ASSERT_EQ(g(1.0).value, 0.0);
    ASSERT_EQ(g_next(0.0).value, 0.0);
    const auto d = crossings(crossing_direction::down, g);
    ASSERT_EQ(d.size(), 1u);
    EXPECT_EQ(d[0], 1.0);
    EXPECT_TRUE(crossings(crossing_direction::down, g_next).empty());

    // Upward: -g.
    scalar_fn h = [&](double t) { auto s = g(t); return scalar_sample{-s.value, -s.slope}; };
    scalar_fn h_next = [&](double t) { auto s = g_next(t); return scalar_sample{-s.value, -s.slope}; };
    const auto u = crossings(crossing_direction::up, h);
    ASSERT_EQ(u.size(), 1u);
    EXPECT_EQ(u[0], 1.0);
    EXPECT_TRUE(crossings(crossing_direction::up, h_next).empty());
}

// A function that starts exactly at zero and immediately goes negative (the state right at an
// event that the previous step reported) reports no downward crossing; its later genuine
// upward crossing is reported: g = theta (theta - 0.6), g(0) = 0, g < 0 on (0, 0.6).
TEST(EventLocation, StartOnRootThenGenuineCrossingLater)
{
    scalar_fn g = [](double t) { return scalar_sample{t * (t - 0.6), 2.0 * t - 0.6}; };
    ASSERT_EQ(g(0.0).value, 0.0);
    EXPECT_TRUE(crossings(crossing_direction::down, g).empty());
    const auto u = crossings(crossing_direction::up, g);
    ASSERT_EQ(u.size(), 1u);
    EXPECT_NEAR(u[0], 0.6, theta_tol);
}

// A function that stays positive (or negative) throughout, with no extremum inside, is
// rejected by the screening without evaluating g in the interior.
TEST(EventLocation, NoCrossingNoInteriorEvaluations)
{
    int evaluations = 0;
    scalar_fn g = [&](double t) {
        ++evaluations;
        return scalar_sample{2.0 - t, -1.0};
    };
    const scalar_sample s0 = g(0.0), s1 = g(1.0);
    evaluations = 0;
    const int n = find_down_crossings(g, s0, s1, [](double) { return true; });
    EXPECT_EQ(n, 0);
    EXPECT_EQ(evaluations, 0);
}

// The screening that lets a step skip the locator (find_down_crossings, and the flow's quiet
// steps, which decide from the end samples alone) never rules out a crossing of a quadratic:
// with at most one extremum on the step, a downward crossing needs the ends to go from > 0 to
// <= 0, a minimum below zero between positive ends, or a maximum above zero between ends at or
// below it. Checked on random quadratics against a dense scan of their values; every case
// the scan finds must have been let through, and the locator must then find a root too.
TEST(EventLocation, ScreeningNeverRulesOutACrossingOfAQuadratic)
{
    std::mt19937_64 rng(20261126);
    std::uniform_real_distribution<double> coef(-2.0, 2.0);
    int crossing_cases = 0, screened_out = 0;
    for (int trial = 0; trial < 20000; ++trial) {
        const double a = coef(rng), b = 2.0 * coef(rng), c = 2.0 * coef(rng);
        scalar_fn g = [=](double t) { return scalar_sample{a + t * (b + t * c), b + 2.0 * c * t}; };
        const scalar_sample s0 = g(0.0), s1 = g(1.0);
        bool crosses = false, seen_positive = s0.value > 0.0;
        for (int k = 1; k <= 4000 && !crosses; ++k) {
            const double v = g(k / 4000.0).value;
            crosses = seen_positive && v <= 0.0;
            seen_positive = seen_positive || v > 0.0;
        }
        const bool possible = vimpact::down_crossing_possible(s0.value, s1.value, s0.slope, s1.slope);
        if (!possible) ++screened_out;
        if (!crosses) continue;
        ++crossing_cases;
        EXPECT_TRUE(possible) << "a = " << a << ", b = " << b << ", c = " << c;
        EXPECT_GE(find_down_crossings(g, s0, s1, [](double) { return true; }), 1);
    }
    // Both kinds of case occur often enough for the check to mean something.
    EXPECT_GT(crossing_cases, 2000);
    EXPECT_GT(screened_out, 2000);
}

// The root search's first point is the inverse cubic Hermite interpolant at g = 0: exact
// when theta is a cubic function of g. Here theta(g) = 0.5 - 0.3 g + 0.1 g^2 - 0.05 g^3
// (falling for every g in [-0.3, 0.4]), so the root is theta(0) = 0.5; the end samples are
// the values g = 0.4 and -0.3 at theta(0.4) and theta(-0.3), with slopes 1 / theta'(g).
TEST(EventLocation, InverseHermiteStartIsExactForACubicInverse)
{
    const auto theta = [](double g) { return 0.5 + g * (-0.3 + g * (0.1 - 0.05 * g)); };
    const auto dtheta = [](double g) { return -0.3 + g * (0.2 - 0.15 * g); };
    const double ga = 0.4, gb = -0.3;
    const double x = vimpact::detail::inverse_hermite_root(theta(ga), {ga, 1.0 / dtheta(ga)}, theta(gb), {gb, 1.0 / dtheta(gb)});
    EXPECT_NEAR(x, 0.5, 4e-16);
}

namespace {

// Runs `search` (g, a, g(a), b, g(b)) -> theta on 200 pieces [a, b = a + 1/8] of [0, 1], each
// holding a point p (the root or the extremum, 1 % of the piece or more from its ends) with a
// rate k in [0.5, 6] (a phase of up to 0.75 rad over the piece): make(p, k) gives the
// function, check(p, k, theta, g(a), g(b)) tests the result. Returns the most evaluations of
// g any search took (the end samples, which the caller of a search has, not counted).
template <class Make, class Search, class Check>
int worst_evaluations_on_pieces(std::uint64_t seed, Make&& make, Search&& search, Check&& check)
{
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> where(0.0, 1.0);
    int worst = 0;
    for (int trial = 0; trial < 200; ++trial) {
        const double a = 0.875 * where(rng), p = a + 0.125 * (0.02 + 0.96 * where(rng)), k = 0.5 + 5.5 * where(rng);
        const scalar_fn f = make(p, k);
        int evaluations = 0;
        const auto g = [&](double t) {
            ++evaluations;
            return f(t);
        };
        const scalar_sample sa = f(a), sb = f(a + 0.125);
        const double theta = search(g, a, sa, a + 0.125, sb);
        worst = std::max(worst, evaluations);
        check(p, k, theta, sa, sb);
    }
    return worst;
}

}  // namespace

// On an eighth of a step, the start is close enough that Newton lands on the root of a
// smooth function, g = sin(k (r - theta)), in at most three evaluations (from the midpoint,
// as before, up to four), and the result keeps its contract: g <= 0 there, a few ulps from
// the root.
TEST(EventLocation, RootSearchFromTheHermiteStartTakesFewEvaluations)
{
    const int worst = worst_evaluations_on_pieces(
        20261128,
        [](double r, double k) {
            return scalar_fn([r, k](double t) { return scalar_sample{std::sin(k * (r - t)), -k * std::cos(k * (r - t))}; });
        },
        [](const auto& g, double a, scalar_sample sa, double b, scalar_sample sb) {
            return vimpact::detail::newton_bracketed(g, a, sa, b, sb);
        },
        [](double r, double k, double root, scalar_sample, scalar_sample) {
            EXPECT_LE(std::abs(root - r), theta_tol);
            EXPECT_LE(std::sin(k * (r - root)), 0.0);
        });
    EXPECT_LE(worst, 3);
}

// The extremum search returns a point whose value is the extremum's to rounding, and is
// within 1e-12 of it in theta, in at most five evaluations of the slope (Illinois regula
// falsi to a 4 eps bracket, as before, took four to 29 here): g = -cos(k (theta - c)) + 0.3 (theta - c)^3
// has its minimum at c, its slope changing sign there.
TEST(EventLocation, ExtremumSearchIsAccurateInFewEvaluations)
{
    const auto dip = [](double c, double k) {
        return scalar_fn([c, k](double t) {
            const double u = t - c;
            return scalar_sample{-std::cos(k * u) + 0.3 * u * u * u, k * std::sin(k * u) + 0.9 * u * u};
        });
    };
    const int worst = worst_evaluations_on_pieces(
        28112026, dip,
        [](const auto& g, double a, scalar_sample sa, double b, scalar_sample sb) {
            return vimpact::detail::extremum_bracketed(g, a, sa, b, sb);
        },
        [&dip](double c, double k, double te, scalar_sample sa, scalar_sample sb) {
            ASSERT_LT(sa.slope, 0.0);
            ASSERT_GT(sb.slope, 0.0);
            EXPECT_LE(std::abs(te - c), 1e-12) << "k = " << k;
            const scalar_fn g = dip(c, k);
            EXPECT_LE(g(te).value - g(c).value, 2.0 * std::numeric_limits<double>::epsilon());
        });
    EXPECT_LE(worst, 5);
}

// A step that starts on the surface just after an impact (g a rounding below zero, rising),
// flies above it, falls through it and turns up again below it before the step ends: both end
// slopes are positive and both ends are at or below zero, so no sign change and no turn of
// the slope shows at the ends. g = theta (theta - 1/2)(theta - 13/10) - 1e-15: the crossing is
// at 1/2 (to rounding), found from the two turns of the cubic through the end samples.
TEST(EventLocation, FlightThatEndsBelowTheSurfaceWithTheSlopeTurnedUp)
{
    scalar_fn g = [](double t) {
        return scalar_sample{t * (t - 0.5) * (t - 1.3) - 1e-15, (t - 0.5) * (t - 1.3) + t * (t - 1.3) + t * (t - 0.5)};
    };
    ASSERT_LT(g(0.0).value, 0.0);
    ASSERT_GT(g(0.0).slope, 0.0);
    ASSERT_LT(g(1.0).value, 0.0);
    ASSERT_GT(g(1.0).slope, 0.0);
    const auto roots = crossings(crossing_direction::down, g);
    ASSERT_EQ(roots.size(), 1u);
    EXPECT_NEAR(roots[0], 0.5, 1e-12);
}

// Both turns inside one of the eight sampled pieces, [3/8, 1/2]: g = (theta - 0.40)(theta -
// 0.44)(theta - 0.49) rises through the piece's ends and dips below zero between them; the
// piece is split where its cubic's slope is least, so that each half shows its turn.
TEST(EventLocation, TwoTurnsInsideOneSampledPiece)
{
    scalar_fn g = [](double t) {
        const double a = t - 0.40, b = t - 0.44, c = t - 0.49;
        return scalar_sample{a * b * c, b * c + a * c + a * b};
    };
    const auto roots = crossings(crossing_direction::down, g);
    ASSERT_EQ(roots.size(), 1u);
    EXPECT_NEAR(roots[0], 0.44, 1e-12);
    const auto up = crossings(crossing_direction::up, g);
    ASSERT_EQ(up.size(), 2u);
    EXPECT_NEAR(up[0], 0.40, 1e-12);
    EXPECT_NEAR(up[1], 0.49, 1e-12);
}

// The locator finds the first downward crossing of every cubic on the step, as a dense scan of
// its values does (a cubic has two extrema at most: the most an event function resolved on
// the step shows, integrate/event_resolution.hpp).
TEST(EventLocation, FindsTheFirstCrossingOfEveryCubic)
{
    std::mt19937_64 rng(20261128);
    std::uniform_real_distribution<double> coef(-1.0, 1.0), root(-0.3, 1.3);
    int crossing_cases = 0, two_turn_cases = 0;
    for (int trial = 0; trial < 6000; ++trial) {
        const double r1 = root(rng), r2 = root(rng), r3 = root(rng), k = coef(rng), off = 0.05 * coef(rng);
        scalar_fn g = [=](double t) {
            const double a = t - r1, b = t - r2, c = t - r3;
            return scalar_sample{k * a * b * c + off, k * (b * c + a * c + a * b)};
        };
        const scalar_sample s0 = g(0.0), s1 = g(1.0);
        double first = -1.0;
        bool seen_positive = s0.value > 0.0;
        for (int i = 1; i <= 8000 && first < 0.0; ++i) {
            const double v = g(i / 8000.0).value;
            if (seen_positive && v <= 0.0) first = i / 8000.0;
            seen_positive = seen_positive || v > 0.0;
        }
        // A dip shallower than the scan resolves is left out: the scan cannot say.
        if (first < 0.0) continue;
        ++crossing_cases;
        // Both extrema inside: the roots of g' = k (3 t^2 - 2 S1 t + S2) in (0, 1).
        const double S1 = r1 + r2 + r3, S2 = r1 * r2 + r1 * r3 + r2 * r3, disc = S1 * S1 - 3.0 * S2;
        if (disc > 0.0 && (S1 - std::sqrt(disc)) / 3.0 > 0.0 && (S1 + std::sqrt(disc)) / 3.0 < 1.0) ++two_turn_cases;
        double found = -1.0;
        find_down_crossings(g, s0, s1, [&](double th) { found = th; return false; });
        EXPECT_NEAR(found, first, 1.0 / 8000.0) << "roots " << r1 << " " << r2 << " " << r3 << " k " << k << " off " << off;
    }
    EXPECT_GT(crossing_cases, 1500);
    EXPECT_GT(two_turn_cases, 300);
}

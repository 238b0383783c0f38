// Sweep building blocks: the grid, the hand-over between branch points, attractor
// identification (synthetic and on the paper's coexisting P1 and P2 at Ur = 14.9).
#include <gtest/gtest.h>

#include "vimpact/analysis/attractor.hpp"
#include "vimpact/analysis/sweep.hpp"
#include "vimpact/model/wake_impact.hpp"

namespace {

using vimpact::attractor_catalogue;
using vimpact::make_signature;
using vimpact::vec;

TEST(Grid, EndsExactAndEvenlySpaced)
{
    const auto v = vimpact::grid_values(12.0, 25.0, 27);
    ASSERT_EQ(v.size(), 27u);
    EXPECT_EQ(v.front(), 12.0);
    EXPECT_EQ(v.back(), 25.0);
    EXPECT_EQ(v[2], 13.0);
    EXPECT_EQ(vimpact::grid_values(1.0, 2.0, 1), std::vector<double>{1.0});
    EXPECT_THROW(vimpact::grid_values(1.0, 2.0, 0), vimpact::input_error);
}

TEST(Grid, ContinueFromPutsAStateBelowTheNewBarrierOntoIt)
{
    const vimpact::wake_impact m(vimpact::wake_impact_parameters{.sigma = -0.1});
    const vec<4> above{0.05, -0.3, 0.2, 0.1};
    EXPECT_EQ(vimpact::continue_from(m, above), above);
    const vec<4> below{-0.12, -0.3, 0.2, 0.1};
    const vec<4> moved = vimpact::continue_from(m, below);
    EXPECT_DOUBLE_EQ(moved[0], -0.1);
    EXPECT_DOUBLE_EQ(moved[1], 0.3);
    EXPECT_EQ(moved[2], 0.2);
}

std::vector<vec<3>> cycle(std::initializer_list<vec<3>> pts, int repeats, int shift = 0)
{
    std::vector<vec<3>> base(pts), out;
    for (int i = 0; i < repeats * static_cast<int>(base.size()); ++i)
        out.push_back(base[static_cast<std::size_t>((i + shift) % static_cast<int>(base.size()))]);
    return out;
}

TEST(Attractors, PhaseShiftedCyclesAreOneAttractorDistantOnesTwo)
{
    const vec<3> a{0.1, 0.2, 0.3}, b{0.4, -0.5, 0.6}, c{-0.7, 0.8, 0.9};
    attractor_catalogue cat({.tolerance = 1e-6});
    EXPECT_EQ(cat.identify(make_signature("P2", 2, cycle({a, b}, 10))), 0);
    EXPECT_EQ(cat.identify(make_signature("P2", 2, cycle({a, b}, 10, 1))), 0);  // other phase
    const vec<3> nudge{5e-7, 0.0, 0.0};
    EXPECT_EQ(cat.identify(make_signature("P2", 2, cycle({a + nudge, b}, 10))), 0);  // within tolerance
    EXPECT_EQ(cat.identify(make_signature("P2", 2, cycle({a + 4 * nudge, b}, 10))), 1);  // outside it
    EXPECT_EQ(cat.identify(make_signature("P2", 2, cycle({a, c}, 10))), 2);  // another P2
    EXPECT_EQ(cat.identify(make_signature("P3", 3, cycle({a, b, c}, 10))), 3);
    EXPECT_EQ(cat.identify(make_signature("P1", 1, cycle({a}, 10))), 4);
    EXPECT_EQ(cat.entries()[0].members, 3);
}

TEST(Attractors, AperiodicByRegionAndFailuresByOutcome)
{
    std::vector<vec<3>> cloud1, cloud2, cloud3;
    for (int i = 0; i < 200; ++i) {
        const double s = std::sin(1.7 * i), t = std::cos(2.3 * i);
        cloud1.push_back({s, t, s * t});
        cloud2.push_back({0.99 * s, t, s * t});   // the same region, another sample
        cloud3.push_back({s + 3.0, t, s * t});    // elsewhere
    }
    attractor_catalogue cat;
    EXPECT_EQ(cat.identify(make_signature("aperiodic", 0, cloud1)), 0);
    EXPECT_EQ(cat.identify(make_signature("aperiodic", 0, cloud2)), 0);
    EXPECT_EQ(cat.identify(make_signature("aperiodic", 0, cloud3)), 1);
    const std::vector<vec<3>> none;
    EXPECT_EQ(cat.identify(make_signature("step_limit", -1, none)), 2);
    EXPECT_EQ(cat.identify(make_signature("step_limit", -1, none)), 2);
    EXPECT_EQ(cat.identify(make_signature("non_finite", -1, none)), 3);
}

vimpact::attractor_signature run_to_attractor(const vimpact::wake_impact& m, const vec<4>& x0)
{
    const auto r = vimpact::run_and_classify(m, x0, vimpact::protocol_options{}, 1e-8);
    std::vector<vec<3>> coords;
    for (const auto& p : r.run.points) coords.push_back(m.section_coordinates(p.x));
    return make_signature(r.label.label, r.label.period, coords);
}

// The paper (Fig. 2c, 3) reports P1 and P2 coexisting at Ur = 14.9. Starting on either
// attractor at other phases (later points of the same orbit) must give the same id; the two
// attractors must get different ids.
TEST(Attractors, CoexistingP1AndP2OfThePaperModel)
{
    const vimpact::wake_impact m(vimpact::wake_impact_parameters{.Ur = 14.9});
    const vec<4> to_p2{0.0, 0.0, 0.0, 0.1}, to_p1{0.14090909090909096, -0.2, 0.0, 0.1};
    const auto r2 = vimpact::run_and_classify(m, to_p2, vimpact::protocol_options{}, 1e-8);
    const auto r1 = vimpact::run_and_classify(m, to_p1, vimpact::protocol_options{}, 1e-8);
    ASSERT_EQ(r2.label.label, "P2");
    ASSERT_EQ(r1.label.label, "P1");
    attractor_catalogue cat;
    EXPECT_EQ(cat.identify(run_to_attractor(m, to_p2)), 0);
    EXPECT_EQ(cat.identify(run_to_attractor(m, to_p1)), 1);
    // Restart from states on each attractor, half a cycle further on.
    EXPECT_EQ(cat.identify(run_to_attractor(m, r2.run.points[1].x)), 0);
    EXPECT_EQ(cat.identify(run_to_attractor(m, r1.run.final_state)), 1);
    EXPECT_EQ(cat.entries().size(), 2u);
}

}  // namespace

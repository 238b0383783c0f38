// SIMD lanes (core/lanes.hpp, hybrid/flow_lanes.hpp): jobs integrated together give, job by
// job, exactly the result of the job integrated alone (the scalar path): the same outcome,
// counters, section points and impacts, bit for bit, also on chaotic orbits (where any
// difference in rounding would grow to the size of the attractor) and through contact phases;
// the step-size controller's polynomials against the standard library; the job commands with
// --batch 1 against the default batch; model files in their binaries' lanes.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <random>
#include <tuple>

#include "example_models.hpp"
#include "test_support.hpp"
#include "vimpact/analysis/basins.hpp"
#include "vimpact/analysis/map.hpp"
#include "vimpact/analysis/period.hpp"
#include "vimpact/analysis/protocol.hpp"
#include "vimpact/analysis/sweep.hpp"
#include "vimpact/core/first_beyond.hpp"
#include "vimpact/core/lanes.hpp"
#include "vimpact/integrate/step_control.hpp"
#include "vimpact/model/builtin/two_sided_impact_oscillator.hpp"
#include "vimpact/model/export.hpp"

using namespace vimpact;

namespace {

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

void expect_same_series(const state_series& a, const state_series& b, const std::string& what)
{
    ASSERT_EQ(a.size(), b.size()) << what;
    for (std::size_t k = 0; k < a.size(); ++k) {
        ASSERT_TRUE(same_bits(a.t(k), b.t(k))) << what << " point " << k << ": t " << a.t(k) << " vs " << b.t(k);
        for (Eigen::Index i = 0; i < a.x(k).size(); ++i)
            ASSERT_TRUE(same_bits(a.x(k)[i], b.x(k)[i])) << what << " point " << k << " coordinate " << i;
    }
}

// A run in lanes equals the run alone, bit for bit.
void expect_same_run(const simulation& alone, const simulation& lane, const std::string& what)
{
    EXPECT_EQ(alone.status, lane.status) << what;
    EXPECT_EQ(alone.stats.steps, lane.stats.steps) << what;
    EXPECT_EQ(alone.stats.rejected, lane.stats.rejected) << what;
    EXPECT_EQ(alone.stats.rhs_calls, lane.stats.rhs_calls) << what;
    EXPECT_EQ(alone.stats.impacts, lane.stats.impacts) << what;
    EXPECT_EQ(alone.stats.sticking_phases, lane.stats.sticking_phases) << what;
    EXPECT_EQ(alone.stats.sections, lane.stats.sections) << what;
    EXPECT_EQ(alone.stats.switchings, lane.stats.switchings) << what;
    EXPECT_TRUE(same_bits(alone.stats.t_final, lane.stats.t_final)) << what;
    EXPECT_TRUE(same_bits(alone.stats.h_min, lane.stats.h_min)) << what;
    EXPECT_TRUE(same_bits(alone.stats.h_max, lane.stats.h_max)) << what;
    EXPECT_EQ(alone.impacting, lane.impacting) << what;
    EXPECT_EQ(alone.transient_impacts, lane.transient_impacts) << what;
    EXPECT_TRUE(same_bits(alone.t_record_start, lane.t_record_start)) << what;
    EXPECT_TRUE(same_bits(alone.t_record_end, lane.t_record_end)) << what;
    EXPECT_TRUE(same_bits(alone.contact_time, lane.contact_time)) << what;
    ASSERT_EQ(alone.max_gap.size(), lane.max_gap.size()) << what;
    for (std::size_t i = 0; i < alone.max_gap.size(); ++i)
        EXPECT_TRUE(same_bits(alone.max_gap[i], lane.max_gap[i])) << what << " largest gap " << i;
    expect_same_series(alone.points, lane.points, what + " section points");
    expect_same_series(alone.impacts.post, lane.impacts.post, what + " impacts");
    expect_same_series(alone.switchings.pre, lane.switchings.pre, what + " crossings of switches");
    expect_same_series(alone.switchings.post, lane.switchings.post, what + " crossings of switches (after)");
    EXPECT_EQ(alone.switchings.surface, lane.switchings.surface) << what;
    for (Eigen::Index i = 0; i < alone.final_state.size(); ++i)
        EXPECT_TRUE(same_bits(alone.final_state[i], lane.final_state[i])) << what;
}

// The paper's model at every (Ur, sigma) of the two lists.
std::vector<model> paper_models(const std::vector<double>& urs, const std::vector<double>& sigmas)
{
    const model m = model::builtin("wake_impact");
    const int ur = m.info().parameter_index("Ur"), sigma = m.info().parameter_index("sigma");
    std::vector<model> models;
    for (const double u : urs)
        for (const double s : sigmas) models.push_back(m.with_parameter(ur, u).with_parameter(sigma, s));
    return models;
}

// f(po) for a protocol of `transient` impacts and `record` points (and, with hold_band > 0,
// that hold band), once with each integration method.
template <class F>
void for_each_method(long transient, long record, double hold_band, F&& f)
{
    protocol_options po;
    po.transient_impacts = transient;
    po.record_points = record;
    po.flow.integration.hold_band = hold_band;
    for (const auto method : all_integration_methods) {
        po.method = method;
        SCOPED_TRACE(std::string(to_string(method)));
        f(po);
    }
}

// Every job of simulate_many equals simulate of that job alone, bit for bit.
void expect_lanes_equal_scalar(const std::vector<model>& models, const std::vector<Eigen::VectorXd>& x0s,
                               const protocol_options& po)
{
    const auto together = simulate_many(models, x0s, po, lane_width);
    ASSERT_EQ(together.size(), models.size());
    for (std::size_t j = 0; j < models.size(); ++j)
        expect_same_run(simulate(models[j], x0s[j], po), together[j], "job " + std::to_string(j));
}

// lane_bits reads the mask register where the instruction set has one: every pattern of true
// lanes gives its bits.
TEST(Lanes, LaneBitsNameTheTrueLanes)
{
    for (unsigned p = 0; p < (1U << lane_width); ++p) {
        alignas(64) std::array<double, lane_width> a{};
        for (int i = 0; i < lane_width; ++i) a[static_cast<std::size_t>(i)] = ((p >> static_cast<unsigned>(i)) & 1U) ? 2.5 : -1.0;
        EXPECT_EQ(lane_bits(lanes::load(a.data()) > lanes(0.0)), p);
    }
}

// first_beyond(from, span) is the least double t with t - from > span, the test the driver
// replaces by one comparison: true there, false one step below, over magnitudes from 1e-3 to
// 1e6 of either sign (times, quiet times) and spans below the resolution of `from`.
TEST(Lanes, FirstBeyondIsTheLeastTimeWhoseDifferenceExceedsTheSpan)
{
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> mant(1.0, 10.0), expo(-3.0, 6.0);
    const double inf = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 20000; ++k) {
        const double from = (k % 2 ? -1.0 : 1.0) * mant(rng) * std::pow(10.0, expo(rng));
        const double span = k % 7 == 0 ? 1e-9 * std::abs(from) * mant(rng) : mant(rng) * std::pow(10.0, expo(rng));
        const double b = first_beyond(from, span);
        ASSERT_TRUE(b - from > span) << from << " " << span;
        ASSERT_FALSE(std::nextafter(b, -inf) - from > span) << from << " " << span;
    }
    EXPECT_EQ(first_beyond(0.0, inf), inf);
    EXPECT_EQ(first_beyond(-inf, 1.0), -inf);
    EXPECT_EQ(first_beyond(std::numeric_limits<double>::quiet_NaN(), 1.0), -inf);
    EXPECT_EQ(first_beyond(1e308, 1e308), -inf);
}

// The bounds are those scripts/gen_controller_polynomials.py reports for the polynomials
// (9.6e-8 and 5.1e-9), with room for the rounding of their evaluation.
TEST(Lanes, ControllerPolynomialsMatchTheLibraryFunctions)
{
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> e(-100.0, 100.0), y(-1020.0, 1020.0);
    for (int k = 0; k < 20000; ++k) {
        const double x = std::exp2(e(rng));
        EXPECT_NEAR(fast_log2(x), std::log2(x), 1.1e-7) << x;
        const double v = y(rng);
        EXPECT_NEAR(fast_exp2(v) / std::exp2(v), 1.0, 6e-9) << v;
    }
    // The reduction's edges: mantissas on either side of sqrt(2), exact powers of two, the
    // controller's floor 1e-28 and the largest double.
    for (int k = -60; k <= 60; ++k) {
        const double edge = std::ldexp(std::sqrt(2.0), k);
        for (const double x : {std::nextafter(edge, 0.0), edge, std::nextafter(edge, 1e300), std::ldexp(1.0, k)})
            EXPECT_NEAR(fast_log2(x), std::log2(x), 1.1e-7) << x;
        EXPECT_EQ(fast_log2(std::ldexp(1.0, k)), k);
        EXPECT_EQ(fast_exp2(double(k)), std::ldexp(1.0, k));
    }
    EXPECT_NEAR(fast_log2(1e-28), std::log2(1e-28), 1.1e-7);
    EXPECT_NEAR(fast_log2(std::numeric_limits<double>::max()), 1024.0, 1.1e-7);
    EXPECT_EQ(fast_log2(1.0), 0.0);
    EXPECT_EQ(fast_exp2(0.0), 1.0);
    // Half-integers round to even, on either side of zero.
    EXPECT_NEAR(fast_exp2(-2.5) / std::exp2(-2.5), 1.0, 6e-9);
    EXPECT_NEAR(fast_exp2(3.5) / std::exp2(3.5), 1.0, 6e-9);
    // A NaN error norm (the controller's input): a finite logarithm of either sign's NaN, within
    // the range control_step's bound on the power's argument assumes.
    for (const double nan : {std::nan(""), -std::nan("")}) {
        EXPECT_TRUE(std::isfinite(fast_log2(nan)));
        EXPECT_LE(std::abs(fast_log2(nan)), 1026.0);
    }
}

TEST(Lanes, ControllerPolynomialsGiveTheSameBitsInEveryLane)
{
    alignas(64) std::array<double, lane_width> in{}, out_log{}, out_exp{};
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> e(-100.0, 100.0), y(-1020.0, 1020.0);
    alignas(64) std::array<double, lane_width> in_exp{};
    for (int round = 0; round < 1000; ++round) {
        for (auto& v : in) v = std::exp2(e(rng));
        for (auto& v : in_exp) v = y(rng);
        if (round == 0) {
            in[0] = std::nan("");
            in[lane_width - 1] = -std::nan("");  // x86's default NaN (inf - inf) has the sign bit set
        }
        fast_log2(lanes::load(in.data())).store(out_log.data());
        fast_exp2(lanes::load(in_exp.data())).store(out_exp.data());
        for (int i = 0; i < lane_width; ++i) {
            ASSERT_TRUE(same_bits(out_log[i], fast_log2(in[i])));
            ASSERT_TRUE(same_bits(out_exp[i], fast_exp2(in_exp[i])));
        }
    }
}

// A map's worth of the paper's model: periodic, chaotic (Ur about 22 to 25) and non-impacting
// cells, more jobs than lanes, so lanes are refilled as their jobs end, each at its own pace.
TEST(Lanes, PaperModelJobsEqualTheirScalarRunsBitForBit)
{
    if (!runs_in_lanes(model::builtin("wake_impact"))) GTEST_SKIP() << "this build has no SIMD lanes";
    const model m = model::builtin("wake_impact");
    const auto models = paper_models({12.0, 14.9, 16.0, 18.5, 22.5, 23.3, 24.1, 25.0, 13.7, 20.0, 21.2},
                                     {-0.2, -0.150298, -0.05});
    for_each_method(100, 60, 0.0, [&](const protocol_options& po) {
        expect_lanes_equal_scalar(models, std::vector<Eigen::VectorXd>(models.size(), m.initial_state()), po);
    });
}

// The job loop's queue can be empty for a moment (between two top-ups): a source that then
// has no job leaves lanes empty, and when fewer than half the lanes are busy the jobs left
// step on their own, from wherever they are (between two steps). This source fills three
// quarters of the lanes, then gives nothing until fewer than half are busy, so that those
// step on their own mid-run, over and over; every job still gets the bits it gets alone.
TEST(Lanes, JobsThatFinishOnTheirOwnWhenTheSourceRunsDryKeepTheirBits)
{
    if (!runs_in_lanes(model::builtin("wake_impact"))) GTEST_SKIP() << "this build has no SIMD lanes";
    const model m = model::builtin("wake_impact");
    std::vector<double> urs, sigmas;
    for (int i = 0; i < 8; ++i) {
        urs.push_back(12.0 + 13.0 * i / 7.0);
        sigmas.push_back(-0.2 + 0.2 * i / 7.0);
    }
    const auto models = paper_models(urs, sigmas);
    for_each_method(50, 30, 0.0, [&](const protocol_options& po) {
        std::vector<simulation> got(models.size());
        std::size_t given = 0, ended = 0;
        bool draining = false;
        long cycles = 0;
        constexpr std::size_t fill_to = 3 * lane_width / 4, drain_to = lane_width / 2 - 1;
        const lanes_counts counts = simulate_stream(
            m, po, lane_width,
            [&]() -> std::optional<protocol_job> {
                const std::size_t running = given - ended;
                if (given == models.size()) return std::nullopt;
                if (draining) {
                    if (running <= drain_to) {
                        draining = false;
                        ++cycles;
                    }
                    return std::nullopt;
                }
                if (running >= fill_to) {
                    draining = true;
                    return std::nullopt;
                }
                const std::size_t k = given++;
                return protocol_job{static_cast<long>(k), models[k], m.initial_state()};
            },
            [&](protocol_job&& j, simulation&& s) {
                ++ended;
                got[static_cast<std::size_t>(j.key)] = std::move(s);
            });
        ASSERT_EQ(given, models.size()) << "the stream ended before its source did";
        EXPECT_GT(cycles, 5);
        EXPECT_GT(counts.steps_alone, 0) << "no lane stepped on its own";
        EXPECT_GT(counts.lane_trials, 0);
        for (std::size_t j = 0; j < models.size(); ++j)
            expect_same_run(simulate(models[j], m.initial_state(), po), got[j], "job " + std::to_string(j));
    });
}

// With a hold band (integrator_options::hold_band) the scalar integrator skips the
// controller's arithmetic on held steps; lanes run control_step for every lane: the same steps.
TEST(Lanes, HoldBandJobsEqualTheirScalarRunsBitForBit)
{
    if (!runs_in_lanes(model::builtin("wake_impact"))) GTEST_SKIP() << "this build has no SIMD lanes";
    const model m = model::builtin("wake_impact");
    const auto models = paper_models({12.0, 16.0, 22.5, 24.1, 13.7}, {-0.2, -0.150298});
    for_each_method(100, 60, 0.3, [&](const protocol_options& po) {
        expect_lanes_equal_scalar(models, std::vector<Eigen::VectorXd>(models.size(), m.initial_state()), po);
    });
}

// Fewer jobs than lanes, and contact phases: a soft restitution and a barrier near the rest
// position make the barrier catch the cylinder (chatter ends in a contact phase, released when
// the flow pulls it away): 89, 17 and 1 contact phases in these three runs.
TEST(Lanes, ContactPhasesAndFewJobsEqualTheScalarRuns)
{
    if (!runs_in_lanes(model::builtin("wake_impact"))) GTEST_SKIP() << "this build has no SIMD lanes";
    const model m = model::builtin("wake_impact");
    const int r = m.info().parameter_index("r"), ur = m.info().parameter_index("Ur"),
              sigma = m.info().parameter_index("sigma");
    std::vector<model> models;
    for (const double rv : {0.0, 0.05, 0.2})
        models.push_back(m.with_parameter(r, rv).with_parameter(ur, 15.0).with_parameter(sigma, -0.02));
    protocol_options po;
    po.transient_impacts = 50;
    po.record_points = 40;
    expect_lanes_equal_scalar(models, std::vector<Eigen::VectorXd>(models.size(), m.initial_state()), po);
    long sticking = 0;
    for (const auto& s : simulate_many(models, std::vector<Eigen::VectorXd>(models.size(), m.initial_state()), po, 8))
        sticking += s.stats.sticking_phases;
    EXPECT_GT(sticking, 0) << "the case must go through contact phases";
}

// Most steps are quiet (no crossing possible) and stay in the lanes until the run needs them:
// a step limit, a time limit or the quiet-time rule that falls inside such a stretch must end
// the run, or begin the recording, at the step where it does alone. Limits of a few hundred
// steps or time units end runs mid-orbit; a short quiet_time makes the jobs that stop
// impacting (Ur = 12, 25 at sigma = -0.2) end by the quiet-time rule at whatever step its
// time falls in.
TEST(Lanes, LimitsAndTheQuietTimeRuleInsideQuietStretchesEqualTheScalarRuns)
{
    if (!runs_in_lanes(model::builtin("wake_impact"))) GTEST_SKIP() << "this build has no SIMD lanes";
    const model m = model::builtin("wake_impact");
    const auto models = paper_models({12.0, 16.0, 22.5, 25.0}, {-0.2, -0.05});
    const std::vector<Eigen::VectorXd> x0s(models.size(), m.initial_state());
    std::map<outcome, int> seen;
    int quiet_ended = 0;
    auto check = [&](const protocol_options& po) {
        expect_lanes_equal_scalar(models, x0s, po);
        for (const auto& s : simulate_many(models, x0s, po, lane_width)) {
            ++seen[s.status];
            quiet_ended += s.impacting ? 0 : 1;
        }
    };
    for_each_method(50, 30, 0.0, [&](protocol_options po) {
        for (const long max_steps : {333L, 1001L, 4567L}) {
            po.flow.max_steps = max_steps;
            check(po);
        }
        po.flow.max_steps = protocol_options{}.flow.max_steps;
        for (const double t_max : {77.7, 512.3}) {
            po.flow.t_max = t_max;
            check(po);
        }
        po.flow.t_max = protocol_options{}.flow.t_max;
        po.quiet_time = 37.5;
        check(po);
    });
    EXPECT_GT(quiet_ended, 0) << "no job met the quiet-time rule";
    EXPECT_GT(seen[outcome::step_limit], 0);
    EXPECT_GT(seen[outcome::time_limit], 0);
    EXPECT_GT(seen[outcome::ok], 0);
}

// Different initial states of one model (a basin's jobs), with a time series sampled.
TEST(Lanes, InitialStatesAndSamplesEqualTheScalarRuns)
{
    if (!runs_in_lanes(model::builtin("wake_impact"))) GTEST_SKIP() << "this build has no SIMD lanes";
    const model m = model::builtin("wake_impact");
    std::vector<Eigen::VectorXd> x0s;
    for (int k = 0; k < 2 * lane_width + 3; ++k) {
        Eigen::VectorXd x = m.initial_state();
        x[2] = -2.0 + 0.3 * k;
        x[3] = 0.1 * (k % 5);
        x0s.push_back(x);
    }
    protocol_options po;
    po.transient_impacts = 80;
    po.record_points = 30;
    expect_lanes_equal_scalar(std::vector<model>(x0s.size(), m), x0s, po);
}

// The models of a model file at every value of its parameter `name` in `values`.
std::vector<model> file_models(const model& f, const std::string& name, const std::vector<double>& values)
{
    std::vector<model> out;
    for (const double v : values) out.push_back(f.with_parameter(f.info().parameter_index(name), v));
    return out;
}

// A model file of a fixed dimension runs its jobs in lanes (its binary's lanes, abi.h), each
// with the bits it gets alone: the paper's model (a contact phase at sigma near 0), a pendulum
// (sin and cos lane by lane, a contact phase), two stops, and a ball on a vibrating table (a
// gap and a section that are not affine, checked on every step).
TEST(Lanes, ModelFileJobsEqualTheirScalarRunsBitForBit)
{
    const model f = test::example_model("wake_impact");
    if (!wide_lanes) GTEST_SKIP() << "this build has no SIMD lanes";
    ASSERT_TRUE(runs_in_lanes(f)) << "the model file's binary has no lanes of this build's width";
    EXPECT_EQ(resolve_batch(f, 0), lane_width);
    std::vector<model> paper;
    for (const double ur : {12.0, 16.0, 18.5, 22.5, 24.1, 13.7, 21.2})
        for (const double sigma : {-0.150298, -0.05, -0.003})
            paper.push_back(f.with_parameter(f.info().parameter_index("Ur"), ur)
                                .with_parameter(f.info().parameter_index("sigma"), sigma));
    for_each_method(80, 40, 0.0, [&](const protocol_options& po) {
        expect_lanes_equal_scalar(paper, std::vector<Eigen::VectorXd>(paper.size(), f.initial_state()), po);
    });
    for (const auto& [file, parameter, values] :
         std::vector<std::tuple<std::string, std::string, std::vector<double>>>{
             {"impacting_pendulum", "a", {0.3, 0.5, 0.6, 0.8, 1.0, 1.2, 1.5, 2.0, 2.5}},
             {"two_sided_impact_oscillator", "a", {0.2, 0.5, 1.0, 1.5, 2.0, 3.0, 4.0, 5.0, 6.0}},
             {"vibrating_table", "G", {1.05, 1.2, 1.5, 2.0, 2.5, 3.0, 3.5, 4.0, 4.5}}}) {
        SCOPED_TRACE(file);
        const model m = test::example_model(file);
        ASSERT_TRUE(runs_in_lanes(m));
        const auto models = file_models(m, parameter, values);
        for_each_method(60, 30, 0.0, [&](const protocol_options& po) {
            expect_lanes_equal_scalar(models, std::vector<Eigen::VectorXd>(models.size(), m.initial_state()), po);
        });
    }
}

// A model file with switching surfaces runs its jobs in lanes too, each lane's field on its
// own sides (the lanes read them from the lane's pinned context): a compliant stop (a
// non-affine section, a dashpot force that jumps), the same with a reset where the motion
// leaves the stop, a bilinear oscillator, Housner's rocking block (a reset at every crossing,
// ending `sliding` at rest) and the paper's model with a compliant barrier (four states). The
// parameters put the lanes on different sides at once.
TEST(Lanes, ModelFilesWithSwitchesEqualTheirScalarRunsBitForBit)
{
    if (!wide_lanes) GTEST_SKIP() << "this build has no SIMD lanes";
    for (const auto& [file, parameter, values] :
         std::vector<std::tuple<std::string, std::string, std::vector<double>>>{
             {"compliant_stop", "F", {0.5, 0.9, 1.2, 1.6, 2.0, 2.4, 3.0, 4.0, 5.0}},
             {"compliant_stop", "d", {0.3, 0.5, 0.8, 1.0, 1.3, 1.7, 2.2, 3.0, 4.0}},
             {"bilinear_oscillator", "F", {0.05, 0.1, 0.2, 0.3, 0.5, 0.8, 1.0, 1.5, 2.0}},
             {"rocking_block", "alpha", {0.12, 0.15, 0.2, 0.25, 0.3, 0.35, 0.4, 0.5, 0.6}},
             {"wake_compliant", "Ur", {14.0, 16.0, 17.5, 19.0, 20.5, 22.0, 23.5, 25.0, 26.0}}}) {
        SCOPED_TRACE(file + " " + parameter);
        const model m = test::example_model(file);
        ASSERT_TRUE(runs_in_lanes(m)) << "the model file's binary has no lanes of this build's width";
        ASSERT_GT(m.info().switches.size(), 0U);
        const auto models = file_models(m, parameter, values);
        for_each_method(60, 30, 0.0, [&](const protocol_options& po) {
            const auto together = simulate_many(models, std::vector<Eigen::VectorXd>(models.size(), m.initial_state()), po,
                                                lane_width);
            long crossings = 0;
            for (std::size_t j = 0; j < models.size(); ++j) {
                expect_same_run(simulate(models[j], m.initial_state(), po), together[j], "job " + std::to_string(j));
                crossings += together[j].stats.switchings;
            }
            EXPECT_GT(crossings, 0);
        });
    }
    // With a reset where the motion leaves the stop (a jump at the crossing).
    const model f = test::example_model("compliant_stop");
    std::string text = test::example_text("compliant_stop");
    const std::string when = "when = \"y - d\"\n";
    ASSERT_NE(text.find(when), std::string::npos);
    text.replace(text.find(when), when.size(), when + "reset = { v = \"0.8*v\" }\ndirection = \"down\"\n");
    const model r = model::from_toml(text, "compliant_stop_reset.toml");
    ASSERT_TRUE(runs_in_lanes(r));
    const auto models = file_models(r, "F", {0.5, 0.9, 1.2, 1.6, 2.0, 2.4, 3.0, 4.0, 5.0});
    for_each_method(60, 30, 0.0, [&](const protocol_options& po) {
        expect_lanes_equal_scalar(models, std::vector<Eigen::VectorXd>(models.size(), r.initial_state()), po);
    });
}

// A model file of a dimension with no fixed-size states in this build (states sized at run
// time) and a C++ definition reached through its table run one job at a time, with their own
// bits.
TEST(Lanes, ModelsWithoutTableLanesRunOneJobAtATime)
{
    const std::string copies = R"toml(
name = "five"
description = "a forced oscillator at a stop beside a free damped one"
state = [{ name = "x1" }, { name = "x2" }, { name = "x3" }, { name = "x4" }, { name = "phi" }]
initial_state = [0.5, 1, 0.5, 0.2, 0]
[parameters]
k = { default = 1.0, meaning = "stiffness", above = 0 }
[derivatives]
x1 = "x2"
x2 = "-k*x1 - 0.1*x2 + 0.6*cos(phi)"
x3 = "x4"
x4 = "-x3 - 0.1*x4"
phi = "1.3"
[[surfaces]]
name = "stop"
gap = "0.8 - x1"
reset = { x2 = "-0.7*x2" }
[[sections]]
name = "top"
when = "x2"
direction = "up"
)toml";
    const model f = model::from_toml(copies, "five.toml");
    EXPECT_FALSE(runs_in_lanes(f));
    EXPECT_EQ(resolve_batch(f, 0), 1);
    EXPECT_THROW((void)resolve_batch(f, -1), input_error);
    protocol_options po;
    po.transient_impacts = 5;
    po.record_points = 10;
    const model g = f.with_parameter(0, 1.3);
    const auto many = simulate_many({f, g}, {f.initial_state(), f.initial_state()}, po, 8);
    expect_same_run(simulate(f, f.initial_state(), po), many[0], "five states");
    expect_same_run(simulate(g, f.initial_state(), po), many[1], "five states, k = 1.3");

    // A C++ definition reached through its function table leaves the table's lanes empty.
    const model d = model::from_definition<two_sided_impact_oscillator>();
    EXPECT_FALSE(runs_in_lanes(d));
    EXPECT_EQ(resolve_batch(d, 0), 1);
    const model d2 = d.with_parameter(d.info().parameter_index("a"), 2.0);
    const auto both = simulate_many({d, d2}, {d.initial_state(), d.initial_state()}, po, 8);
    expect_same_run(simulate(d2, d.initial_state(), po), both[1], "C++ definition, a = 2");
    EXPECT_EQ(resolve_batch(model::builtin("wake_impact"), 1), 1);
}

// The job commands: the default batch (lanes) and --batch 1 give the same cells and points.
TEST(Lanes, MapSweepAndBasinsDoNotDependOnTheBatch)
{
    const model m = model::builtin("wake_impact");
    map_options mo;
    mo.x = {m.info().parameter_index("Ur"), grid_values(14.0, 24.0, 5)};
    mo.y = {m.info().parameter_index("sigma"), grid_values(-0.2, -0.05, 3)};
    mo.protocol.transient_impacts = 60;
    mo.protocol.record_points = 40;
    job_options one, lanes_opt;
    one.batch = 1;
    one.threads = lanes_opt.threads = 2;
    const auto a = map2d(m, mo, one), b = map2d(m, mo, lanes_opt);
    EXPECT_EQ(a.jobs.batch, 1);
    EXPECT_EQ(b.jobs.batch, runs_in_lanes(m) ? lane_width : 1);
    ASSERT_EQ(a.cells.size(), b.cells.size());
    for (std::size_t k = 0; k < a.cells.size(); ++k) {
        EXPECT_EQ(a.cells[k].label.label, b.cells[k].label.label) << k;
        EXPECT_EQ(a.cells[k].steps, b.cells[k].steps) << k;
        EXPECT_TRUE(same_bits(a.cells[k].label.closure, b.cells[k].label.closure)) << k;
    }

    sweep_options so;
    so.parameter = m.info().parameter_index("Ur");
    so.values = grid_values(20.0, 25.0, 11);
    so.protocol = mo.protocol;
    const auto sa = sweep(m, so, one), sb = sweep(m, so, lanes_opt);
    ASSERT_EQ(sa.points.size(), sb.points.size());
    for (std::size_t k = 0; k < sa.points.size(); ++k) {
        EXPECT_EQ(sa.points[k].label.label, sb.points[k].label.label) << k;
        expect_same_series(sa.points[k].points, sb.points[k].points, "sweep point " + std::to_string(k));
    }

    basins_options bo;
    bo.x_state = 2;
    bo.y_state = 3;
    bo.x_values = grid_values(-2.0, 2.0, 4);
    bo.y_values = grid_values(-1.0, 1.0, 3);
    bo.protocol = mo.protocol;
    const auto ba = basins(m, bo, one), bb = basins(m, bo, lanes_opt);
    ASSERT_EQ(ba.cells.size(), bb.cells.size());
    for (std::size_t k = 0; k < ba.cells.size(); ++k) {
        EXPECT_EQ(ba.cells[k].label.label, bb.cells[k].label.label) << k;
        EXPECT_EQ(ba.cells[k].attractor, bb.cells[k].attractor) << k;
        EXPECT_EQ(ba.cells[k].steps, bb.cells[k].steps) << k;
    }
}

}  // namespace

namespace {

// The other built-ins: forcing through cos and a section through sin (lane by lane with the
// standard library), two surfaces.
TEST(Lanes, ForcedOscillatorsEqualTheirScalarRuns)
{
    for (const char* name : {"forced_impact_oscillator", "two_sided_impact_oscillator"}) {
        const model m = model::builtin(name);
        if (!runs_in_lanes(m)) GTEST_SKIP() << "this build has no SIMD lanes";
        SCOPED_TRACE(name);
        const int p = 1;  // the second parameter: the forcing frequency or amplitude
        std::vector<model> models;
        const double v0 = m.parameters()[static_cast<std::size_t>(p)];
        for (int k = 0; k < lane_width + 2; ++k) models.push_back(m.with_parameter(p, v0 * (0.8 + 0.05 * k)));
        protocol_options po;
        po.transient_impacts = 40;
        po.record_points = 30;
        expect_lanes_equal_scalar(models, std::vector<Eigen::VectorXd>(models.size(), m.initial_state()), po);
    }
}

}  // namespace

namespace {

// The strobe section sin(theta) of a forced oscillator with no forcing and a fast phase
// (omega = 6 ... 15 times the natural frequency): nothing in the vector field limits the step
// to the phase's time scale, so the flow takes back the steps on which sin(theta) is not
// resolved (hybrid/flow.hpp, integrate/event_resolution.hpp), in lanes as alone. Every
// crossing is where it must be, t = 2 pi k / omega, and every lane equals its run alone.
TEST(Lanes, StepsTakenBackForAnUnresolvedSectionEqualTheScalarRuns)
{
    const model m = model::builtin("forced_impact_oscillator");
    if (!runs_in_lanes(m)) GTEST_SKIP() << "this build has no SIMD lanes";
    const int omega = m.info().parameter_index("omega"), force = m.info().parameter_index("F");
    std::vector<model> models;
    std::vector<double> omegas;
    for (int k = 0; k < lane_width + 2; ++k) {
        omegas.push_back(6.0 + 9.0 * k / (lane_width + 1));
        models.push_back(m.with_parameter(omega, omegas.back()).with_parameter(force, 0.0));
    }
    Eigen::VectorXd x0(3);
    x0 << 0.9, -2.0, 0.0;
    protocol_options po;
    po.transient_impacts = 0;
    po.record_points = 30;
    po.section = section_choice::crossings(2);
    expect_lanes_equal_scalar(models, std::vector<Eigen::VectorXd>(models.size(), x0), po);
    for (std::size_t j = 0; j < models.size(); ++j) {
        const simulation s = simulate(models[j], x0, po);
        ASSERT_EQ(s.points.size(), 30u);
        EXPECT_GT(s.stats.rejected, 0) << "no step was taken back at omega = " << omegas[j];
        const double first = std::round(s.points.t(0) * omegas[j] / (2.0 * M_PI));
        for (std::size_t k = 0; k < s.points.size(); ++k)
            EXPECT_NEAR(s.points.t(k), 2.0 * M_PI * (first + static_cast<double>(k)) / omegas[j], 1e-9)
                << "omega = " << omegas[j] << ", crossing " << k;
    }
}

}  // namespace

// Many-job analyses: the grid, the hand-over between branch points, attractor identification
// (synthetic, and the paper's coexisting P1 and P2 at Ur = 14.9), and the journal: a run
// stopped and resumed, or split in shards, equals one uninterrupted run; a damaged or foreign
// journal is refused with a message.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

#include <nlohmann/json.hpp>

#include "test_support.hpp"
#include "vimpact/analysis/attractor.hpp"
#include "vimpact/analysis/basins.hpp"
#include "vimpact/analysis/map.hpp"
#include "vimpact/analysis/sweep.hpp"
#include "io/json_codec.hpp"
#include "vimpact/core/input_error.hpp"
#include "vimpact/core/value_grid.hpp"

using namespace vimpact;
namespace fs = std::filesystem;

namespace {

TEST(Grid, EndsExactAndEvenlySpaced)
{
    const auto v = grid_values(12.0, 25.0, 27);
    ASSERT_EQ(v.size(), 27u);
    EXPECT_EQ(v.front(), 12.0);
    EXPECT_EQ(v.back(), 25.0);
    EXPECT_EQ(v[2], 13.0);
    EXPECT_EQ(grid_values(1.0, 2.0, 1), std::vector<double>{1.0});
    EXPECT_THROW((void)grid_values(1.0, 2.0, 0), input_error);
    EXPECT_THROW((void)grid_values(0.0, 1.0, 1'000'000'000'000L), input_error);
}

TEST(Grid, ARangeGivesTheValuesOfTheFormulaFromItsEndsAndCountAlone)
{
    // Value i = a + i (b - a)/(n - 1), the last exactly b: computed here, term by term.
    const double a = 12.0, b = 25.0;
    for (const long n : {1L, 2L, 27L, 131L}) {
        const value_grid g = value_grid::range(a, b, n);
        ASSERT_EQ(g.size(), static_cast<std::size_t>(n));
        for (long i = 0; i < n; ++i) {
            const double expected = n == 1 ? a : (i == n - 1 ? b : a + static_cast<double>(i) * (b - a) / static_cast<double>(n - 1));
            EXPECT_EQ(g[static_cast<std::size_t>(i)], expected) << n << " " << i;
        }
        EXPECT_EQ(g.values(), grid_values(a, b, n));
    }
    // A hundred million values: three numbers, any value at once.
    const value_grid big = value_grid::range(0.0, 1.0, 100'000'000);
    EXPECT_EQ(big.size(), 100'000'000u);
    EXPECT_EQ(big.back(), 1.0);
    EXPECT_EQ(big[50'000'000], 50'000'000.0 * (1.0 - 0.0) / 99'999'999.0);
    EXPECT_LE(sizeof(big), 128u);
    // The journal's spec: the ends and the count, not the values.
    EXPECT_EQ(detail::to_json(big).dump(), R"({"from":0.0,"n":100000000,"to":1.0})");
    EXPECT_EQ(detail::to_json(value_grid{1.0, 2.5}).dump(), "[1.0,2.5]");
    EXPECT_THROW((void)value_grid::range(0.0, 1.0, 0), input_error);
    EXPECT_THROW((void)value_grid::range(0.0, 1.0, 100'000'001), input_error);
    EXPECT_THROW((void)value_grid::range(0.0, INFINITY, 3), input_error);
    // Mapped (an SI speed to Ur): each value is the map of the given one, and the map is named.
    const value_grid u = value_grid::range(3.0, 6.0, 7).mapped([](double v) { return v / 0.24; }, "U / 0.24");
    for (std::size_t i = 0; i < u.size(); ++i) EXPECT_EQ(u[i], u.given(i) / 0.24);
    EXPECT_EQ(detail::to_json(u).dump(), R"({"from":3.0,"map":"U / 0.24","n":7,"to":6.0})");
}

// A state the moved barrier now lies above is put on it and, moving into it, reflected by the
// surface's reset (an impact: ydot -> -r ydot).
TEST(Grid, ContinueFromPutsAStateBeyondAMovedSurfaceOntoIt)
{
    const model m = test::with(model{}, "sigma", -0.1);
    const Eigen::Vector4d above(0.05, -0.3, 0.2, 0.1);
    EXPECT_EQ(continue_from(m, above), above);
    const Eigen::Vector4d below(-0.12, -0.3, 0.2, 0.1);
    const Eigen::VectorXd moved = continue_from(m, below);
    EXPECT_EQ(moved[0], -0.1);
    EXPECT_DOUBLE_EQ(moved[1], 0.8 * 0.3);
    EXPECT_EQ(moved[2], 0.2);
    EXPECT_EQ(violated_surface(m, moved), -1);
    // Two stops: beyond the left one at x = -d, moving left.
    const model two = model::builtin("two_sided_impact_oscillator");
    const Eigen::VectorXd back = continue_from(two, Eigen::Vector3d(-1.2, -0.5, 0.3));
    EXPECT_EQ(back[0], -1.0);
    EXPECT_DOUBLE_EQ(back[1], 0.4);
}

std::vector<Eigen::Vector3d> cycle(std::initializer_list<Eigen::Vector3d> pts, int repeats, int shift = 0)
{
    std::vector<Eigen::Vector3d> base(pts), out;
    for (int i = 0; i < repeats * static_cast<int>(base.size()); ++i)
        out.push_back(base[static_cast<std::size_t>((i + shift) % static_cast<int>(base.size()))]);
    return out;
}

TEST(Attractors, PhaseShiftedCyclesAreOneAttractorDistantOnesTwo)
{
    const Eigen::Vector3d a{0.1, 0.2, 0.3}, b{0.4, -0.5, 0.6}, c{-0.7, 0.8, 0.9};
    attractor_catalogue cat({.tolerance = 1e-6});
    EXPECT_EQ(cat.identify(make_signature("P2", 2, cycle({a, b}, 10))), 0);
    EXPECT_EQ(cat.identify(make_signature("P2", 2, cycle({a, b}, 10, 1))), 0);  // other phase
    const Eigen::Vector3d nudge{5e-7, 0.0, 0.0};
    EXPECT_EQ(cat.identify(make_signature("P2", 2, cycle({a + nudge, b}, 10))), 0);  // within tolerance
    EXPECT_EQ(cat.identify(make_signature("P2", 2, cycle({a + 4 * nudge, b}, 10))), 1);  // outside it
    EXPECT_EQ(cat.identify(make_signature("P2", 2, cycle({a, c}, 10))), 2);
    EXPECT_EQ(cat.identify(make_signature("P3", 3, cycle({a, b, c}, 10))), 3);
    EXPECT_EQ(cat.identify(make_signature("P1", 1, cycle({a}, 10))), 4);
    EXPECT_EQ(cat.entries()[0].members, 3);
}

TEST(Attractors, AperiodicByRegionAndFailuresByOutcome)
{
    std::vector<Eigen::Vector3d> cloud1, cloud2, cloud3;
    for (int i = 0; i < 200; ++i) {
        const double s = std::sin(1.7 * i), t = std::cos(2.3 * i);
        cloud1.emplace_back(s, t, s * t);
        cloud2.emplace_back(0.99 * s, t, s * t);  // the same region, another sample
        cloud3.emplace_back(s + 3.0, t, s * t);   // elsewhere
    }
    attractor_catalogue cat;
    EXPECT_EQ(cat.identify(make_signature("aperiodic", 0, cloud1)), 0);
    EXPECT_EQ(cat.identify(make_signature("aperiodic", 0, cloud2)), 0);
    EXPECT_EQ(cat.identify(make_signature("aperiodic", 0, cloud3)), 1);
    const std::vector<Eigen::Vector3d> none;
    EXPECT_EQ(cat.identify(make_signature("step_limit", -1, none)), 2);
    EXPECT_EQ(cat.identify(make_signature("step_limit", -1, none)), 2);
    EXPECT_EQ(cat.identify(make_signature("non_finite", -1, none)), 3);
}

// The paper (Fig. 2c, 3): P1 and P2 coexist at Ur = 14.9. Restarting on either attractor at
// another phase gives the same id; the two attractors get different ids.
TEST(Attractors, CoexistingP1AndP2OfThePaperModel)
{
    const model m = test::paper(14.9);
    const Eigen::Vector4d to_p2(0.0, 0.0, 0.0, 0.1), to_p1(0.14090909090909096, -0.2, 0.0, 0.1);
    const protocol_options po;
    const auto r2 = run_and_classify(m, to_p2, po, 1e-8);
    const auto r1 = run_and_classify(m, to_p1, po, 1e-8);
    ASSERT_EQ(r2.label.label, "P2");
    ASSERT_EQ(r1.label.label, "P1");
    auto signature = [&](const Eigen::VectorXd& x0) {
        const auto r = run_and_classify(m, x0, po, 1e-8);
        return signature_of(m, r.run, r.label);
    };
    attractor_catalogue cat;
    EXPECT_EQ(cat.identify(signature(to_p2)), 0);
    EXPECT_EQ(cat.identify(signature(to_p1)), 1);
    EXPECT_EQ(cat.identify(signature(r2.run.points.x(1))), 0);
    EXPECT_EQ(cat.identify(signature(r1.run.final_state)), 1);
    EXPECT_EQ(cat.entries().size(), 2u);
}

// ---- the journal ---------------------------------------------------------------------------

struct temp_dir {
    fs::path path;
    temp_dir()
    {
        std::random_device rd;
        path = fs::temp_directory_path() / ("vimpact-journal-test-" + std::to_string(rd()));
        fs::create_directories(path);
    }
    ~temp_dir() { fs::remove_all(path); }
};

sweep_options short_sweep()
{
    sweep_options o;
    o.parameter = model{}.info().parameter_index("Ur");
    o.values = grid_values(14.0, 20.0, 12);
    o.protocol.transient_impacts = 60;
    o.protocol.record_points = 20;
    o.start = sweep_start::follow;
    o.direction = sweep_direction::both;
    return o;
}

void expect_same(const sweep_result& a, const sweep_result& b)
{
    ASSERT_EQ(a.points.size(), b.points.size());
    for (std::size_t k = 0; k < a.points.size(); ++k) {
        EXPECT_EQ(a.points[k].value, b.points[k].value);
        EXPECT_EQ(a.points[k].label.label, b.points[k].label.label);
        EXPECT_EQ(a.points[k].points.values(), b.points[k].points.values());
        EXPECT_EQ(a.points[k].final_state, b.points[k].final_state);
    }
}

// The short sweep journaled in `j.journal` and stopped once 7 jobs are done (then `j` has no
// stop flag or progress sink again).
sweep_result stopped_after_seven(const model& m, job_options& j)
{
    std::atomic<bool> stop{false};
    j.stop = &stop;
    j.progress = [&](long done, long) {
        if (done >= 7) stop.store(true);
    };
    auto r = sweep(m, short_sweep(), j);
    j.stop = nullptr;
    j.progress = nullptr;
    return r;
}

TEST(Journal, ASweepOverARangeEqualsTheSweepOverItsValuesAndItsSpecHoldsTheRange)
{
    const model m;
    sweep_options o;
    o.parameter = m.info().parameter_index("Ur");
    o.protocol.transient_impacts = 60;
    o.protocol.record_points = 20;
    o.values = value_grid::range(14.0, 20.0, 7);
    std::vector<double> listed;
    for (long i = 0; i < 7; ++i) listed.push_back(i == 6 ? 20.0 : 14.0 + static_cast<double>(i) * 6.0 / 6.0);
    sweep_options l = o;
    l.values = listed;
    temp_dir dir;
    job_options j;
    j.threads = 2;
    j.journal = dir.path / "run.jobs";
    const sweep_result by_range = sweep(m, o, j);
    expect_same(by_range, sweep(m, l));
    std::ifstream in(*j.journal / "spec.json");
    const auto spec = nlohmann::json::parse(in);
    EXPECT_EQ(spec.at("values"), nlohmann::json::parse(R"({"from":14.0,"n":7,"to":20.0})"));
}

TEST(Journal, AStoppedRunResumedEqualsAnUninterruptedOne)
{
    const model m;
    const auto whole = sweep(m, short_sweep());
    ASSERT_TRUE(whole.jobs.complete());
    temp_dir dir;
    job_options j;
    j.journal = dir.path / "run.jobs";
    const auto first = stopped_after_seven(m, j);
    EXPECT_TRUE(first.jobs.stopped);
    EXPECT_FALSE(first.jobs.complete());
    EXPECT_GE(first.jobs.done, 7);
    // Without resume a journal of a whole run is refused (it would be resumed by mistake).
    EXPECT_THROW((void)sweep(m, short_sweep(), j), input_error);
    j.resume = true;
    const auto rest = sweep(m, short_sweep(), j);
    ASSERT_TRUE(rest.jobs.complete());
    EXPECT_EQ(rest.jobs.resumed, first.jobs.done);
    expect_same(rest, whole);
}

TEST(Journal, ShardsMeetInTheJournal)
{
    const model m;
    const auto whole = sweep(m, short_sweep());
    temp_dir dir;
    job_options j;
    j.journal = dir.path / "run.jobs";
    j.shard = {0, 2};
    const auto one = sweep(m, short_sweep(), j);
    EXPECT_FALSE(one.jobs.complete());
    j.shard = {1, 2};
    const auto two = sweep(m, short_sweep(), j);
    ASSERT_TRUE(two.jobs.complete());  // the last shard has every job
    expect_same(two, whole);
}

TEST(Journal, AnotherRunsOrADamagedJournalIsRefused)
{
    const model m;
    temp_dir dir;
    job_options j;
    j.journal = dir.path / "run.jobs";
    j.shard = {0, 2};
    (void)sweep(m, short_sweep(), j);
    auto other = short_sweep();
    other.protocol.record_points = 21;
    try {
        (void)sweep(m, other, j);
        FAIL() << "a journal of another run was accepted";
    } catch (const input_error& e) {
        EXPECT_NE(std::string(e.what()).find("belongs to a different run"), std::string::npos) << e.what();
    }
    {
        std::ofstream(*j.journal / "shard-0-of-2.jsonl", std::ios::app) << "{\"job\":1}\n";
    }
    j.shard = {1, 2};
    try {
        (void)sweep(m, short_sweep(), j);
        FAIL() << "a damaged journal was accepted";
    } catch (const input_error& e) {
        EXPECT_NE(std::string(e.what()).find("is damaged at line"), std::string::npos) << e.what();
    }
    fs::remove(*j.journal / "spec.json");
    try {
        (void)sweep(m, short_sweep(), j);
        FAIL() << "a journal without spec.json was accepted";
    } catch (const input_error& e) {
        EXPECT_NE(std::string(e.what()).find("has no spec.json"), std::string::npos) << e.what();
    }
}

// A process killed inside a journal write leaves a torn last line: a resume drops it, cuts it
// from the file before appending (so no line of the file is glued to it), and loses no whole line.
TEST(Journal, ATornLastLineIsCutAndEveryWholeLineKept)
{
    const model m;
    const auto whole = sweep(m, short_sweep());
    temp_dir dir;
    job_options j;
    j.journal = dir.path / "run.jobs";
    ASSERT_TRUE(stopped_after_seven(m, j).jobs.stopped);
    const fs::path file = *j.journal / "shard-0-of-1.jsonl";
    auto lines_of = [&] {
        std::ifstream in(file);
        std::vector<std::string> v;
        for (std::string l; std::getline(in, l);) v.push_back(l);
        return v;
    };
    const auto before = lines_of();
    ASSERT_GE(before.size(), 7u);
    std::ofstream(file, std::ios::app) << before[1].substr(0, before[1].size() / 2);  // torn
    j.resume = true;
    const auto rest = sweep(m, short_sweep(), j);
    ASSERT_TRUE(rest.jobs.complete());
    EXPECT_EQ(rest.jobs.resumed, static_cast<long>(before.size()));
    expect_same(rest, whole);
    const auto after = lines_of();
    ASSERT_EQ(after.size(), static_cast<std::size_t>(rest.jobs.jobs));
    EXPECT_TRUE(std::equal(before.begin(), before.end(), after.begin()));
    for (const auto& l : after) EXPECT_FALSE(nlohmann::json::parse(l, nullptr, false).is_discarded()) << l;
}

// One process at a time appends to a shard's file: a second one (a resume started while the
// interrupted run still ends) is refused before it reads or cuts anything.
TEST(Journal, ASecondWriterOfAShardIsRefusedWhileTheFirstRuns)
{
    const model m;
    const auto whole = sweep(m, short_sweep());
    temp_dir dir;
    job_options j;
    j.journal = dir.path / "run.jobs";
    j.threads = 1;
    std::string refusal;
    bool tried = false;
    j.progress = [&](long done, long) {
        if (done < 3 || tried) return;
        tried = true;
        job_options again;
        again.journal = j.journal;
        again.resume = true;
        try {
            (void)sweep(m, short_sweep(), again);
            refusal = "(accepted)";
        } catch (const input_error& e) {
            refusal = e.what();
        }
    };
    const auto first = sweep(m, short_sweep(), j);
    ASSERT_TRUE(tried);
    EXPECT_NE(refusal.find("shard-0-of-1.jsonl is being written by another process"), std::string::npos) << refusal;
    ASSERT_TRUE(first.jobs.complete());
    expect_same(first, whole);
}

// The result of a many-job analysis does not depend on the thread count (maps and basins too).
TEST(Journal, ResultsDoNotDependOnTheThreadCount)
{
    const model m;
    map_options mo;
    mo.x = {m.info().parameter_index("Ur"), grid_values(15.0, 22.0, 4)};
    mo.y = {m.info().parameter_index("sigma"), grid_values(-0.2, -0.1, 3)};
    mo.protocol.transient_impacts = 40;
    mo.protocol.record_points = 16;
    mo.grazing = true;
    job_options one, two;
    one.threads = 1;
    two.threads = 2;
    const auto a = map2d(m, mo, one), b = map2d(m, mo, two);
    ASSERT_EQ(a.cells.size(), 12u);
    for (std::size_t k = 0; k < a.cells.size(); ++k) EXPECT_EQ(a.cells[k].label.label, b.cells[k].label.label);
    EXPECT_EQ(a.grazing_axis, 1);
    ASSERT_EQ(a.grazing_values.size(), 4u);
    for (std::size_t k = 0; k < 4; ++k) EXPECT_EQ(a.grazing_values[k], b.grazing_values[k]);
}

}  // namespace

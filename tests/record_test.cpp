// Records described once (core/record.hpp): the journal line, the table row and its schema
// all follow from one description, so each is checked here against what the record holds and
// against the naming rules the documentation states, field by field.
#include <cmath>
#include <limits>

#include "test_support.hpp"
#include "io/record_json.hpp"
#include "vimpact/analysis/basins.hpp"
#include "vimpact/analysis/clearance.hpp"
#include "vimpact/analysis/response.hpp"
#include "vimpact/analysis/stability_sweep.hpp"
#include "vimpact/analysis/sweep.hpp"
#include "vimpact/io/record_table.hpp"

namespace vimpact {
namespace {

constexpr double inf = std::numeric_limits<double>::infinity();
constexpr double nan = std::numeric_limits<double>::quiet_NaN();

sweep_point awkward_point()
{
    sweep_point p;
    p.branch = 1;
    p.value = 0.1 + 0.2;  // not a short decimal
    p.label = {"P3", 3, 7, {4, 3}, 1.25e-11, false};
    p.status = outcome::chattering;
    p.points = state_series(2);
    Eigen::VectorXd x(2);
    x << -0.0, 1.0 / 3.0;
    p.points.push_back(1.5, x);
    x << inf, 5e-324;
    p.points.push_back(2.5, x);
    p.final_state.resize(2);
    p.final_state << nan, -inf;
    p.grazing = {0.75, nan};
    p.stats.steps = 123456789012L;
    p.stats.impacts_by_surface = {9, 8};
    p.stats.h_min = 1e-300;
    p.statistics.impacts = 7;
    p.statistics.velocity_max = 2.0 / 3.0;
    p.statistics.excursion_by_surface = {0.5, -0.25};
    return p;
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

TEST(Records, SweepPointJournalLineReadsBackBitForBit)
{
    const sweep_point p = awkward_point();
    // Through the text of the line, as a journal stores it.
    const auto text = detail::record_json(p).dump();
    const auto q = detail::record_from<sweep_point>(detail::json::parse(text));
    EXPECT_EQ(q.branch, p.branch);
    EXPECT_TRUE(same_bits(q.value, p.value));
    EXPECT_EQ(q.label.label, "P3");
    EXPECT_EQ(q.label.period, 3);
    EXPECT_EQ(q.label.impacts_per_period, 7);
    EXPECT_EQ(q.label.impacts_by_surface, (std::vector<long>{4, 3}));
    EXPECT_TRUE(same_bits(q.label.closure, 1.25e-11));
    EXPECT_FALSE(q.label.settled);
    EXPECT_EQ(q.status, outcome::chattering);
    ASSERT_EQ(q.points.size(), 2U);
    EXPECT_TRUE(same_bits(q.points.x(0, 0), -0.0));
    EXPECT_TRUE(same_bits(q.points.x(0, 1), 1.0 / 3.0));
    EXPECT_EQ(q.points.x(1, 0), inf);
    EXPECT_TRUE(same_bits(q.points.x(1, 1), 5e-324));
    EXPECT_EQ(q.points.t(1), 2.5);
    EXPECT_TRUE(std::isnan(q.final_state[0]));
    EXPECT_EQ(q.final_state[1], -inf);
    EXPECT_EQ(q.grazing[0], 0.75);
    EXPECT_TRUE(std::isnan(q.grazing[1]));
    EXPECT_EQ(q.stats.steps, 123456789012L);
    EXPECT_EQ(q.stats.impacts_by_surface, (std::vector<long>{9, 8}));
    EXPECT_TRUE(same_bits(q.stats.h_min, 1e-300));
    EXPECT_EQ(q.stats.h_max, 0.0);
    EXPECT_EQ(q.statistics.impacts, 7);
    EXPECT_TRUE(same_bits(q.statistics.velocity_max, 2.0 / 3.0));
    EXPECT_TRUE(std::isnan(q.statistics.velocity_min));
    EXPECT_EQ(q.statistics.excursion_by_surface, (std::vector<double>{0.5, -0.25}));
}

TEST(Records, AJournalLineWithoutAFieldIsDamage)
{
    auto j = detail::record_json(awkward_point());
    j["statistics"].erase("power");
    EXPECT_THROW((void)detail::record_from<sweep_point>(j), detail::json::exception);
}

// The naming rules of field::column, for a model with surfaces left and right that varies w
// with grazing values of d (the two-stop oscillator).
TEST(Records, TableColumnsFollowTheNamingRules)
{
    const table_context c{"w", "d", {"right", "left"}};
    const auto columns = record_columns<sweep_point>(c);
    std::vector<std::string> names;
    for (const auto& col : columns) names.push_back(col.name);
    const std::vector<std::string> first{"branch", "w", "label", "period", "impacts", "closure", "settled",
                                         "impacts_right", "impacts_left", "outcome", "d_graze_right", "d_graze_left",
                                         "impacts_recorded"};
    ASSERT_GE(names.size(), first.size());
    EXPECT_EQ(std::vector<std::string>(names.begin(), names.begin() + static_cast<long>(first.size())), first);
    EXPECT_EQ(names.back(), "excursion_left");
    // Neither series, state vectors nor counters are columns.
    for (const auto& n : names) {
        EXPECT_NE(n, "points");
        EXPECT_NE(n, "final_state");
        EXPECT_NE(n, "steps");
    }
    // One surface: a per-surface column without an explicit place is named by the field alone.
    const auto one = record_columns<sweep_point>({"w", "d", {"stop"}});
    EXPECT_TRUE(std::any_of(one.begin(), one.end(), [](const column_schema& s) { return s.name == "d_graze"; }));
    EXPECT_TRUE(std::any_of(one.begin(), one.end(), [](const column_schema& s) { return s.name == "impacts_stop"; }));
    // Without a grazing parameter its columns are left out.
    const auto none = record_columns<sweep_point>({"w", "", {"stop"}});
    EXPECT_EQ(none.size(), one.size() - 1);
}

// A per-switch field: a column per switch, NAME_SWITCH or the pattern's {switch}, even for one
// switch (a model may have a surface of the same field too), with the switch's index in the
// schema; none without switches.
TEST(Records, PerSwitchColumnsAreNamedAfterTheirSwitch)
{
    table_context c{"F", "d", {}};
    c.switches = {"contact", "heaviside#1"};
    std::vector<std::string> graze, margin;
    for (const auto& col : record_columns<response_point>(c)) {
        if (col.field == "switch_grazing") {
            graze.push_back(col.name);
            EXPECT_EQ(col.switch_index, static_cast<int>(graze.size()) - 1);
            EXPECT_EQ(col.surface, -1);
        }
        if (col.field == "switch_margin") margin.push_back(col.name);
    }
    EXPECT_EQ(graze, (std::vector<std::string>{"d_graze_contact", "d_graze_heaviside#1"}));
    EXPECT_EQ(margin, (std::vector<std::string>{"switch_margin_contact", "switch_margin_heaviside#1"}));
    c.switches = {"contact"};
    response_point p;
    p.switch_grazing = {2.5};
    const auto columns = record_columns<response_point>(c);
    const auto cells = record_cells(p, c);
    ASSERT_EQ(cells.size(), columns.size());
    for (std::size_t i = 0; i < columns.size(); ++i) {
        if (columns[i].name == "d_graze_contact") {
            EXPECT_EQ(cells[i], "2.5");
        }
        if (columns[i].name == "switch_margin_contact") {
            EXPECT_EQ(cells[i], format_double(std::numeric_limits<double>::quiet_NaN()));
        }
    }
    const auto none = record_columns<response_point>({"F", "d", {"stop"}});
    EXPECT_TRUE(std::none_of(none.begin(), none.end(), [](const column_schema& s) { return s.switch_index >= 0; }));
}

TEST(Records, EveryCellSitsUnderItsColumn)
{
    const table_context c{"w", "d", {"right", "left"}};
    const auto columns = record_columns<sweep_point>(c);
    const auto cells = record_cells(awkward_point(), c);
    ASSERT_EQ(cells.size(), columns.size());
    const auto at = [&](const std::string& name) {
        for (std::size_t i = 0; i < columns.size(); ++i)
            if (columns[i].name == name) return cells[i];
        ADD_FAILURE() << "no column " << name;
        return std::string();
    };
    EXPECT_EQ(at("w"), format_double(0.1 + 0.2));
    EXPECT_EQ(at("label"), "P3");
    EXPECT_EQ(at("settled"), "0");
    EXPECT_EQ(at("outcome"), "chattering");
    EXPECT_EQ(at("impacts_left"), "3");
    EXPECT_EQ(at("d_graze_right"), "0.75");
    EXPECT_EQ(at("d_graze_left"), "nan");
    EXPECT_EQ(at("impacts_recorded"), "7");
    EXPECT_EQ(at("excursion_right"), "0.5");
    // The schema types each column and says which field and group it holds.
    for (const auto& col : columns) {
        if (col.name == "settled") {
            EXPECT_EQ(col.type, "bool");
        }
        if (col.name == "impacts_left") {
            EXPECT_EQ(col.surface, 1);
        }
        if (col.name == "energy_per_impact") {
            EXPECT_EQ(col.group, "statistics");
            EXPECT_EQ(col.type, "float");
        }
    }
}

// A journal line read back and written again is the same text: no field is lost or rounded
// (every double is written as its shortest round trip, NaN and infinities included).
template <class R>
void expect_line_reads_back(const R& r)
{
    const auto text = detail::record_json(r).dump();
    EXPECT_EQ(detail::record_json(detail::record_from<R>(detail::json::parse(text))).dump(), text);
}

TEST(Records, ResponsePointJournalLineReadsBack)
{
    response_point p;
    p.curve = 2;
    p.value = 0.1 + 0.2;
    p.amplitude = inf;
    p.maximum = -0.0;
    p.minimum = 5e-324;
    p.grazing = {nan, -1.0 / 3.0};
    p.margin = {0.25, -inf};
    p.converged = true;
    p.status = outcome::time_limit;
    p.stats.steps = 42;
    expect_line_reads_back(p);
    const auto q = detail::record_from<response_point>(detail::record_json(p));
    EXPECT_EQ(q.curve, 2);
    EXPECT_TRUE(same_bits(q.maximum, -0.0));
    EXPECT_EQ(q.margin, p.margin);
    EXPECT_EQ(q.status, outcome::time_limit);
}

// response.csv's columns for the two-stop oscillator measuring x over w with grazing values of
// d: the documented names (docs/sweeps.md), the grazing columns left out without a parameter.
TEST(Records, ResponseColumnsNameTheVariableAndTheGrazingParameter)
{
    table_context c{"w", "d", {"right", "left"}, "x"};
    std::vector<std::string> names;
    for (const auto& col : record_columns<response_point>(c)) names.push_back(col.name);
    EXPECT_EQ(names, (std::vector<std::string>{"curve", "w", "amplitude", "x_max", "x_min", "d_graze_right",
                                               "d_graze_left", "margin_right", "margin_left", "frequency",
                                               "converged", "outcome"}));
    c.grazing.clear();
    EXPECT_EQ(record_columns<response_point>(c).size(), names.size() - 2);
}

TEST(Records, BasinCellJournalLineKeepsTheSignature)
{
    basin_cell b;
    b.admissible = true;
    b.label = {"P2", 2, 2, {1, 1}, 3e-12, true};
    b.steps = 99;
    b.signature.label = "P2";
    b.signature.period = 2;
    Eigen::VectorXd x(3);
    x << 0.1, -0.0, 1.0 / 7.0;
    b.signature.cycle = {x, -x};
    b.signature.lo = -x;
    b.signature.hi = x;
    // The basins' journal line is the cell and its signature (src/analysis/basins.cpp): the
    // cell's description holds no signature, so the group is checked on its own.
    expect_line_reads_back(b);
    expect_line_reads_back(b.signature);
    const auto s = detail::record_from<attractor_signature>(detail::record_json(b.signature));
    ASSERT_EQ(s.cycle.size(), 2U);
    EXPECT_TRUE(same_bits(s.cycle[0][1], -0.0));
    EXPECT_TRUE(s.cycle[1] == -x);
    EXPECT_TRUE(s.hi == x);
}

// The multipliers are complex and read back part by part, NaN and infinities included; the
// journal line of a whole point reads back to the same line.
TEST(Records, StabilitySweepPointsJournalLinesReadBackBitForBit)
{
    floquet_sweep_point f;
    f.value = 0.1 + 0.2;
    f.result.status = outcome::not_converged;
    f.result.label = "P2";
    f.result.period = 1.0 / 3.0;
    f.result.trivial_error = nan;
    f.result.max_nontrivial_modulus = inf;
    f.result.impacts_by_surface = {3, 0};
    f.result.multipliers = {{1.0, -0.0}, {nan, inf}, {-inf, 5e-324}};
    f.result.orbit_point.resize(2);
    f.result.orbit_point << -inf, 2.0 / 3.0;
    f.result.section_points = state_series(2);
    Eigen::VectorXd x(2);
    x << nan, -0.0;
    f.result.section_points.push_back(0.5, x);
    f.result.tangent_stats.steps = 123456789012L;
    expect_line_reads_back(f);
    const auto g = detail::record_from<floquet_sweep_point>(detail::json::parse(detail::record_json(f).dump()));
    EXPECT_TRUE(same_bits(g.value, f.value));
    EXPECT_EQ(g.result.status, outcome::not_converged);
    EXPECT_EQ(g.result.label, "P2");
    EXPECT_TRUE(same_bits(g.result.period, 1.0 / 3.0));
    EXPECT_TRUE(std::isnan(g.result.trivial_error));
    EXPECT_EQ(g.result.max_nontrivial_modulus, inf);
    EXPECT_EQ(g.result.impacts_by_surface, (std::vector<long>{3, 0}));
    ASSERT_EQ(g.result.multipliers.size(), 3U);
    EXPECT_EQ(g.result.multipliers[0].real(), 1.0);
    EXPECT_TRUE(same_bits(g.result.multipliers[0].imag(), -0.0));
    EXPECT_TRUE(std::isnan(g.result.multipliers[1].real()));
    EXPECT_EQ(g.result.multipliers[1].imag(), inf);
    EXPECT_EQ(g.result.multipliers[2].real(), -inf);
    EXPECT_TRUE(same_bits(g.result.multipliers[2].imag(), 5e-324));
    EXPECT_EQ(g.result.orbit_point[0], -inf);
    ASSERT_EQ(g.result.section_points.size(), 1U);
    EXPECT_TRUE(same_bits(g.result.section_points.x(0, 1), -0.0));
    EXPECT_EQ(g.result.tangent_stats.steps, 123456789012L);

    lyapunov_sweep_point l;
    l.value = -0.0;
    l.result.status = outcome::time_limit;
    l.result.exponents.resize(3);
    l.result.exponents << 0.1 + 0.2, -inf, nan;
    l.result.lle_standard_error = 5e-324;
    l.result.settled = false;
    l.result.impacts = 123456789012L;
    l.result.impacts_by_surface = {1, 2};
    l.result.misses = 7;
    l.result.sum_rule = inf;
    l.positive = true;
    expect_line_reads_back(l);
    const auto m = detail::record_from<lyapunov_sweep_point>(detail::json::parse(detail::record_json(l).dump()));
    EXPECT_TRUE(same_bits(m.value, -0.0));
    EXPECT_EQ(m.result.status, outcome::time_limit);
    ASSERT_EQ(m.result.exponents.size(), 3);
    EXPECT_TRUE(same_bits(m.result.exponents[0], 0.1 + 0.2));
    EXPECT_EQ(m.result.exponents[1], -inf);
    EXPECT_TRUE(std::isnan(m.result.exponents[2]));
    EXPECT_TRUE(same_bits(m.result.lle_standard_error, 5e-324));
    EXPECT_FALSE(m.result.settled);
    EXPECT_EQ(m.result.impacts, 123456789012L);
    EXPECT_EQ(m.result.impacts_by_surface, (std::vector<long>{1, 2}));
    EXPECT_EQ(m.result.misses, 7);
    EXPECT_EQ(m.result.sum_rule, inf);
    EXPECT_TRUE(m.positive);
}

// labels.csv and exponents.csv of the stability sweeps of the two-stop oscillator (states x,
// v, phi) over w: the documented columns (docs/stability.md); the multipliers and section
// points take none (tables of their own); exponents padded with NaN to the model's dimension.
TEST(Records, StabilitySweepColumnsAreTheDocumentedOnes)
{
    const table_context c{"w", "", {"right", "left"}, "", {"x", "v", "phi"}};
    const auto names = [](const std::vector<column_schema>& cols) {
        std::vector<std::string> out;
        for (const auto& col : cols) out.push_back(col.name);
        return out;
    };
    EXPECT_EQ(names(record_columns<floquet_sweep_point>(c)),
              (std::vector<std::string>{"w", "label", "period", "impacts", "trivial_error", "max_nontrivial_modulus",
                                        "closure", "outcome", "impacts_right", "impacts_left", "stable"}));
    const auto lc = record_columns<lyapunov_sweep_point>(c);
    EXPECT_EQ(names(lc), (std::vector<std::string>{"w", "lambda1", "lambda2", "lambda3", "lle_standard_error",
                                                   "settled", "impacts", "time", "misses", "outcome",
                                                   "impacts_right", "impacts_left", "positive"}));
    EXPECT_EQ(lc[3].state, 2);
    EXPECT_EQ(lc[3].field, "exponents");
    lyapunov_sweep_point l;
    l.result.exponents.resize(2);
    l.result.exponents << 0.5, -1.0;
    const auto cells = record_cells(l, c);
    ASSERT_EQ(cells.size(), lc.size());
    EXPECT_EQ(cells[1], format_double(0.5));
    EXPECT_EQ(cells[3], format_double(nan));
}

// The statistics that are one number each keep their documented names and order.
TEST(Records, ImpactStatisticsNamesAreTheDocumentedOnes)
{
    const std::vector<std::string> documented{"impacts_recorded", "duration", "impact_rate", "impact_velocity_min",
                                              "impact_velocity_mean", "impact_velocity_rms", "impact_velocity_max",
                                              "energy_per_impact", "power", "contact_fraction", "excursion"};
    const auto& names = impact_statistics_names();
    ASSERT_EQ(names.size(), documented.size());
    for (std::size_t i = 0; i < names.size(); ++i) EXPECT_EQ(names[i], documented[i]);
    impact_statistics s;
    s.impacts = 4;
    s.power = 0.5;
    const auto back = impact_statistics_from_values(impact_statistics_values(s));
    EXPECT_EQ(back.impacts, 4);
    EXPECT_EQ(back.power, 0.5);
    EXPECT_TRUE(std::isnan(back.velocity_mean));
}

// clearance.csv and chart.csv of the wake model (one surface, barrier) varying Ur with the
// gap parameter sigma: the columns docs/engineering.md lists, in its order after the lead
// columns (Ur and U), with the period label's and statistics' own columns among them.
TEST(Records, ClearanceColumnsAreTheDocumentedOnes)
{
    const table_context c{"Ur", "sigma", {"barrier"}};
    std::vector<std::string> names;
    for (const auto& col : record_columns<clearance_point>(c)) names.push_back(col.name);
    EXPECT_EQ(names, (std::vector<std::string>{"Ur", "sigma_graze", "clearance", "converged", "aperiodic_min",
                                               "aperiodic_max"}));
    names.clear();
    for (const auto& col : record_columns<clearance_cell>(c)) names.push_back(col.name);
    const std::vector<std::string> documented{"gap", "sigma", "label", "period", "impacts", "settled", "outcome"};
    auto at = names.begin();
    for (const auto& d : documented) {
        at = std::find(at, names.end(), d);
        EXPECT_NE(at, names.end()) << d << " missing or out of order";
    }
    for (const char* s : impact_statistics_names()) EXPECT_NE(std::find(names.begin(), names.end(), s), names.end()) << s;
}

// A clearance job's journal line: the point's record and its cells' (src/analysis/clearance.cpp).
TEST(Records, ClearanceRecordsReadBackBitForBit)
{
    clearance_point p;
    p.value = 0.1 + 0.2;
    p.grazing_value = -1.0 / 3.0;
    p.clearance = 1.0 / 3.0;
    p.converged = true;
    p.aperiodic_max = 5e-324;
    clearance_cell cell;
    cell.gap = 2.0 / 3.0;
    cell.gap_parameter_value = -2.0 / 3.0;
    cell.label = {"aperiodic", -1, 0, {0}, nan, false};
    cell.status = outcome::chattering;
    cell.statistics.velocity_max = 0.7;
    const auto q = detail::record_from<clearance_point>(detail::json::parse(detail::record_json(p).dump()));
    EXPECT_TRUE(same_bits(q.value, p.value));
    EXPECT_TRUE(same_bits(q.grazing_value, p.grazing_value));
    EXPECT_TRUE(same_bits(q.clearance, p.clearance));
    EXPECT_TRUE(q.converged);
    EXPECT_TRUE(std::isnan(q.aperiodic_min));
    EXPECT_TRUE(same_bits(q.aperiodic_max, 5e-324));
    const auto d = detail::record_from<clearance_cell>(detail::json::parse(detail::record_json(cell).dump()));
    EXPECT_TRUE(same_bits(d.gap, cell.gap));
    EXPECT_TRUE(same_bits(d.gap_parameter_value, cell.gap_parameter_value));
    EXPECT_EQ(d.label.label, "aperiodic");
    EXPECT_EQ(d.label.period, -1);
    EXPECT_EQ(d.status, outcome::chattering);
    EXPECT_EQ(d.statistics.velocity_max, 0.7);
}

}  // namespace
}  // namespace vimpact

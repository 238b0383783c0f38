// Options declared once (core/option.hpp): the declaration's ranges are what the library
// enforces, each end on the right side, and every default lies inside its range.
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "test_support.hpp"
#include "vimpact/analysis/basins.hpp"
#include "vimpact/analysis/clearance.hpp"
#include "vimpact/analysis/continuation.hpp"
#include "vimpact/analysis/correlation_dimension.hpp"
#include "vimpact/analysis/floquet.hpp"
#include "vimpact/analysis/grazing.hpp"
#include "vimpact/analysis/lyapunov.hpp"
#include "vimpact/analysis/map.hpp"
#include "vimpact/analysis/protocol_declaration.hpp"
#include "vimpact/analysis/response.hpp"
#include "vimpact/analysis/sweep.hpp"
#include "vimpact/integrate/runge_kutta.hpp"

namespace vimpact {
namespace {

// The numeric options of a declaration; each default must lie in its range.
struct numeric_keys {
    std::vector<std::string> keys;
    template <class T>
    void operator()(const option& o, const T& v)
    {
        if constexpr (std::is_arithmetic_v<T> && !std::is_same_v<T, bool>) {
            EXPECT_TRUE(o.range.admits(static_cast<double>(v))) << o.key << " default outside its range";
            keys.emplace_back(o.key);
        }
    }
    template <class E, std::size_t K>
    void operator()(const option&, const E&, const std::array<E, K>&)
    {
    }
};

// Sets option `key` just beyond its lower or upper end: the end itself when the end is open,
// one unit (a tenth, for a real) beyond it when closed. `done` stays false for an infinite end.
struct set_beyond {
    const std::string& key;
    bool high;
    bool done = false;
    template <class T>
    void operator()(const option& o, T& v)
    {
        if constexpr (std::is_arithmetic_v<T> && !std::is_same_v<T, bool>) {
            if (o.key != key) return;
            const double end = high ? o.range.upper : o.range.lower;
            if (!std::isfinite(end)) return;
            const bool open = !(high ? o.range.upper_inclusive : o.range.lower_inclusive);
            const double step = std::is_integral_v<T> ? 1.0 : 0.1;
            v = static_cast<T>(open ? end : (high ? end + step : end - step));
            done = true;
        }
    }
    template <class E, std::size_t K>
    void operator()(const option&, E&, const std::array<E, K>&)
    {
    }
};

// Every numeric option of O: its default passes, a value beyond either finite end is refused
// with an option_error naming the option by its key.
template <class O>
void check_every_end()
{
    numeric_keys p;
    const O defaults{};
    declare(p, defaults);
    EXPECT_NO_THROW(check_options(defaults));
    int refused = 0;
    for (const auto& key : p.keys) {
        for (const bool high : {false, true}) {
            O o{};
            set_beyond s{key, high};
            declare(s, o);
            if (!s.done) continue;
            try {
                check_options(o);
                ADD_FAILURE() << key << (high ? " above" : " below") << " its range was accepted";
            } catch (const option_error& e) {
                ++refused;
                EXPECT_EQ(e.key(), key);
                EXPECT_EQ(std::string(e.what()).rfind(key + " = ", 0), 0U) << e.what();
            }
        }
    }
    EXPECT_GT(refused, 0);
}

TEST(Options, LyapunovRefusesEveryEndOfItsDeclaration) { check_every_end<lyapunov_options>(); }
TEST(Options, FloquetRefusesEveryEndOfItsDeclaration) { check_every_end<floquet_options>(); }
TEST(Options, ContinuationRefusesEveryEndOfItsDeclaration) { check_every_end<continuation_options>(); }

// The library's own check of a continuation applies the declaration before it runs: a step
// count the arclength loop could not even start with is refused by its key.
TEST(Options, ContinuationValidateAppliesTheDeclaration)
{
    const model m = test::paper(14.0);
    continuation_options o;
    o.parameter = m.info().parameter_index("Ur");
    o.start = 14.0;
    o.end = 15.0;
    o.arclength.max_points = 1;  // a branch of one point has no tangent
    try {
        validate(m, o);
        ADD_FAILURE() << "max_points = 1 was accepted";
    } catch (const option_error& e) {
        EXPECT_EQ(e.key(), "max_points");
    }
}

// The protocol's options (transient, record, the tolerances, max_step, quiet_time, t_max), which
// every front end takes from the declaration: both ends of each checked by the library.
TEST(Options, ProtocolRefusesEveryEndOfItsDeclaration) { check_every_end<protocol_options>(); }

// The ranges the library enforced before the declaration (validate(protocol_options) and
// validate(integrator_options), written out by hand), each end a value on either side.
TEST(Options, ProtocolDeclarationKeepsTheRangesCheckedBefore)
{
    struct probe {
        const char* key;
        void (*set)(protocol_options&, double);
        double refused, admitted;
    };
    const probe probes[] = {
        {"rtol", [](protocol_options& o, double x) { o.flow.integration.rtol = x; }, 0.0, 1e-15},
        {"rtol", [](protocol_options& o, double x) { o.flow.integration.rtol = x; }, 1.0, 0.5},
        {"rtol", [](protocol_options& o, double x) { o.flow.integration.rtol = x; }, 5e-16, 1e-14},
        {"atol", [](protocol_options& o, double x) { o.flow.integration.atol = x; }, 1.0, 1e-300},
        {"atol", [](protocol_options& o, double x) { o.flow.integration.atol = x; }, 1e-301, 0.9},
        {"max_step", [](protocol_options& o, double x) { o.flow.integration.h_max = x; }, 0.0, 1e-3},
        {"transient", [](protocol_options& o, double x) { o.transient_impacts = static_cast<long>(x); }, -1.0, 0.0},
        {"transient", [](protocol_options& o, double x) { o.transient_impacts = static_cast<long>(x); }, 1e9 + 1, 1e9},
        {"record", [](protocol_options& o, double x) { o.record_points = static_cast<long>(x); }, 0.0, 1.0},
        {"record", [](protocol_options& o, double x) { o.record_points = static_cast<long>(x); }, 1e7 + 1, 1e7},
        {"quiet_time", [](protocol_options& o, double x) { o.quiet_time = x; }, 0.0, 1e-9},
        {"t_max", [](protocol_options& o, double x) { o.flow.t_max = x; }, -1.0, 1.0},
    };
    for (const auto& p : probes) {
        protocol_options o;
        p.set(o, p.admitted);
        EXPECT_NO_THROW(validate(o)) << p.key << " = " << p.admitted;
        p.set(o, p.refused);
        try {
            validate(o);
            ADD_FAILURE() << p.key << " = " << p.refused << " was accepted";
        } catch (const option_error& e) {
            EXPECT_EQ(e.key(), p.key) << e.what();
        }
    }
}

// check_options(o) refuses o with an option_error naming `key` and giving its range as `range`.
template <class O>
void expect_refused(const O& o, const std::string& key, const std::string& range)
{
    try {
        check_options(o);
        ADD_FAILURE() << key << " out of its range was accepted";
    } catch (const option_error& e) {
        EXPECT_EQ(e.key(), key);
        EXPECT_NE(std::string(e.what()).find(" is outside its valid range " + range), std::string::npos) << e.what();
    }
}

// A limit whose default is none (+inf) admits infinity, and only +inf: NaN and -inf are no
// limit at all. Its range reads (0, inf] in every message.
TEST(Options, InfiniteLimitsAreAdmittedAsNone)
{
    protocol_options o;
    EXPECT_EQ(o.flow.integration.h_max, std::numeric_limits<double>::infinity());
    o.quiet_time = o.flow.t_max = std::numeric_limits<double>::infinity();
    EXPECT_NO_THROW(check_options(o));
    for (const double bad : {std::nan(""), -std::numeric_limits<double>::infinity()}) {
        protocol_options b;
        b.flow.integration.h_max = bad;
        expect_refused(b, "max_step", "(0, inf]");
    }
}

// The hold band unset is the method's (none is never checked); set, it must lie in [0, 1),
// and the integrator's own check (grazing's, the systems') is the same declaration.
TEST(Options, HoldBandUnsetIsTheMethodsAndSetIsInItsRange)
{
    protocol_options o;
    EXPECT_FALSE(o.flow.integration.hold_band.has_value());
    EXPECT_NO_THROW(check_options(o));
    EXPECT_EQ(effective_hold_band(o.flow.integration, integration_method::dopri5), dopri5<1>::default_hold_band);
    EXPECT_EQ(effective_hold_band(o.flow.integration, integration_method::dop853), dop853<1>::default_hold_band);
    for (const double good : {0.0, 0.5, 0.999}) {
        o.flow.integration.hold_band = good;
        EXPECT_NO_THROW(check_options(o)) << good;
        EXPECT_EQ(effective_hold_band(o.flow.integration, integration_method::dopri5), good);
    }
    for (const double bad : {-0.1, 1.0, std::nan("")}) {
        o.flow.integration.hold_band = bad;
        expect_refused(o, "hold_band", "[0, 1)");
        integrator_options in;
        in.hold_band = bad;
        EXPECT_THROW(validate(in), option_error) << bad;
    }
}

TEST(Options, SweepRefusesEveryEndOfItsDeclaration) { check_every_end<sweep_options>(); }
TEST(Options, MapRefusesEveryEndOfItsDeclaration) { check_every_end<map_options>(); }
TEST(Options, BasinsRefusesEveryEndOfItsDeclaration) { check_every_end<basins_options>(); }
TEST(Options, GrazingRefusesEveryEndOfItsDeclaration) { check_every_end<grazing_options>(); }
TEST(Options, ResponseRefusesEveryEndOfItsDeclaration) { check_every_end<response_options>(); }
TEST(Options, ClearanceRefusesEveryEndOfItsDeclaration) { check_every_end<clearance_options>(); }
TEST(Options, DimensionRefusesEveryEndOfItsDeclaration) { check_every_end<dimension_options>(); }

// The option_error of `call`, whose key must be `key`: the analysis checked its declaration
// before computing anything.
template <class Call>
void refuses_key(const std::string& key, Call&& call)
{
    try {
        call();
        ADD_FAILURE() << key << " out of range was accepted";
    } catch (const option_error& e) {
        EXPECT_EQ(e.key(), key) << e.what();
    }
}

// Each grid analysis checks its declared options at its entry (the front ends check none), so
// a value outside the ranges the analyses needed before the declarations (a period tolerance
// > 0, a match tolerance > 0, a transient time >= 0, a block of >= 1 minima) is refused.
TEST(Options, GridAnalysesCheckTheirDeclarationsAtTheirEntry)
{
    const model m = test::paper(16.0);
    const int ur = m.info().parameter_index("Ur"), sigma = m.info().parameter_index("sigma");
    sweep_options s;
    s.parameter = ur;
    s.values = value_grid::range(15.0, 16.0, 2);
    s.period_tolerance = 0.0;
    refuses_key("tol", [&] { (void)sweep(m, s); });
    map_options mo;
    mo.x = {ur, value_grid::range(15.0, 16.0, 2)};
    mo.y = {sigma, value_grid::range(-0.16, -0.15, 2)};
    mo.period_tolerance = -1e-8;
    refuses_key("tol", [&] { (void)map2d(m, mo); });
    basins_options b;
    b.x_values = value_grid::range(-0.1, 0.1, 2);
    b.y_values = value_grid::range(-0.1, 0.1, 2);
    b.match.tolerance = 0.0;
    refuses_key("match_tol", [&] { (void)basins(m, b); });
    response_options r;
    r.parameter = ur;
    r.values = value_grid::range(15.0, 16.0, 2);
    r.grazing.transient_time = -1.0;
    refuses_key("transient_time", [&] { (void)response(m, r); });
    grazing_options g;
    g.block = 0;
    refuses_key("block", [&] { (void)grazing(m, test::paper_ic(), g); });
    clearance_options c;
    c.parameter = ur;
    c.values = value_grid::range(15.0, 16.0, 2);
    c.grazing.transient_time = -1.0;
    refuses_key("transient_time", [&] { (void)clearance(m, c); });
    c.grazing.transient_time = 10.0;
    c.period_tolerance = 0.0;
    refuses_key("tol", [&] { (void)clearance(m, c); });
}

// The paper's r0 = 1e-4 and t0 = pi are the defaults; the ends the analysis needs hold.
TEST(Options, LyapunovDeclaresThePapersDefaultsAndTheNeededEnds)
{
    lyapunov_options o;
    EXPECT_EQ(o.r0, 1e-4);
    EXPECT_EQ(o.t0, std::numbers::pi);
    o.r0 = 1.0;  // a deviation as large as the state is not a tangent vector
    EXPECT_THROW(check_options(o), option_error);
    o = {};
    o.impacts = 0;  // an average over nothing
    EXPECT_THROW(check_options(o), option_error);
    o = {};
    o.t0 = std::numeric_limits<double>::infinity();
    EXPECT_THROW(check_options(o), option_error);
}

TEST(Options, OptionErrorsKeepTheKeyForEachFrontEnd)
{
    const option_error e("p0_time", " = 0 is outside its valid range > 0");
    EXPECT_STREQ(e.what(), "p0_time = 0 is outside its valid range > 0");
    EXPECT_EQ(command_line_key(e.key()) + e.detail(), "--p0-time = 0 is outside its valid range > 0");
}

}  // namespace
}  // namespace vimpact

// Models: the built-ins' hand-written derivatives against automatic differentiation and
// finite differences, the function table against the native model, parameters and ranges.
#include <gtest/gtest.h>

#include <random>

#include "test_support.hpp"
#include "vimpact/core/input_error.hpp"
#include "vimpact/model/builtin/forced_impact_oscillator.hpp"
#include "vimpact/model/builtin/two_sided_impact_oscillator.hpp"
#include "vimpact/model/builtin/wake_impact.hpp"
#include "vimpact/model/model.hpp"
#include "vimpact/model/model_phrases.hpp"
#include "vimpact/model/native_model.hpp"
#include "vimpact/model/table_model.hpp"

using namespace vimpact;

namespace {

using test::defaults;
using test::max_abs_diff;
using test::random_vec;

// The wake model with every hand-written derivative removed: automatic differentiation only.
struct wake_ad_only {
    static constexpr auto name = wake_impact::name;
    static constexpr auto description = wake_impact::description;
    static constexpr auto state = wake_impact::state;
    static constexpr auto parameters = wake_impact::parameters;
    static constexpr auto surfaces = wake_impact::surfaces;
    static constexpr auto sections = wake_impact::sections;
    wake_impact w;
    explicit wake_ad_only(std::span<const double> p) : w(p) {}
    template <class T>
    vec_t<T, 4> derivatives(const vec_t<T, 4>& x) const { return w.derivatives(x); }
    template <class T>
    T gap(int i, const vec_t<T, 4>& x) const { return w.gap(i, x); }
    template <class T>
    vec_t<T, 4> reset(int i, const vec_t<T, 4>& x) const { return w.reset(i, x); }
    template <class T>
    T section(int k, const vec_t<T, 4>& x) const { return w.section(k, x); }
    template <class T>
    vec_t<T, 4> sticking_derivatives(int i, const vec_t<T, 4>& x) const { return w.sticking_derivatives(i, x); }
    template <class T>
    T release(int i, const vec_t<T, 4>& x) const { return w.release(i, x); }
    vec<4> rest(int i, const vec<4>& x) const { return w.rest(i, x); }
};

// Central differences of a vector function, column by column.
template <int N, class F>
mat<N> fd_jacobian(F&& f, const vec<N>& x, double h = 1e-6)
{
    mat<N> J;
    for (int j = 0; j < N; ++j) {
        vec<N> a = x, b = x;
        a[j] += h;
        b[j] -= h;
        J.col(j) = (f(a) - f(b)) / (2.0 * h);
    }
    return J;
}

}  // namespace

TEST(Model, WakeHandWrittenDerivativesEqualAutomaticOnes)
{
    const auto p = defaults<wake_impact>();
    const native_model<wake_impact> hand(p);
    const native_model<wake_ad_only> ad(p);
    std::mt19937 gen(1);
    for (int trial = 0; trial < 20; ++trial) {
        const vec<4> x = random_vec<4>(gen), u = random_vec<4>(gen), w = random_vec<4>(gen);
        EXPECT_LT(max_abs_diff(hand.jacobian(x), ad.jacobian(x)), 1e-14);
        EXPECT_LT(max_abs_diff(hand.second_derivative(x, u, w), ad.second_derivative(x, u, w)), 1e-14);
        EXPECT_NEAR(hand.divergence(x), ad.divergence(x), 1e-14);
        EXPECT_LT(max_abs_diff(hand.gap_gradient(0, x), ad.gap_gradient(0, x)), 1e-15);
        EXPECT_LT(max_abs_diff(hand.gap_hessian(0, x), ad.gap_hessian(0, x)), 1e-15);
        EXPECT_LT(max_abs_diff(hand.reset_jacobian(0, x), ad.reset_jacobian(0, x)), 1e-15);
        EXPECT_LT(max_abs_diff(hand.reset_second_derivative(0, x, u, w), ad.reset_second_derivative(0, x, u, w)), 1e-15);
        EXPECT_LT(max_abs_diff(hand.section_gradient(0, x), ad.section_gradient(0, x)), 1e-15);
        EXPECT_LT(max_abs_diff(hand.release_gradient(0, x), ad.release_gradient(0, x)), 1e-15);
    }
}

TEST(Model, AutomaticJacobiansEqualFiniteDifferences)
{
    std::mt19937 gen(2);
    const native_model<two_sided_impact_oscillator> m(defaults<two_sided_impact_oscillator>());
    const native_model<forced_impact_oscillator> f(defaults<forced_impact_oscillator>());
    for (int trial = 0; trial < 10; ++trial) {
        const vec<3> x = random_vec<3>(gen, 2.0);
        const mat<3> fd = fd_jacobian<3>([&](const vec<3>& y) { return m.rhs(y); }, x);
        EXPECT_LT(max_abs_diff(m.jacobian(x), fd), 1e-9);
        const mat<3> fdf = fd_jacobian<3>([&](const vec<3>& y) { return f.rhs(y); }, x);
        EXPECT_LT(max_abs_diff(f.jacobian(x), fdf), 1e-9);
        // The second derivative along u, w against differences of the Jacobian.
        const vec<3> u = random_vec<3>(gen), w = random_vec<3>(gen);
        const double h = 1e-6;
        const vec<3> d2 = (m.jacobian(vec<3>(x + h * u)) * w - m.jacobian(vec<3>(x - h * u)) * w) / (2.0 * h);
        EXPECT_LT(max_abs_diff(m.second_derivative(x, u, w), d2), 1e-8);
        for (int i = 0; i < 2; ++i) {
            const vec<3> g = fd_jacobian<3>([&](const vec<3>& y) { return vec<3>::Constant(m.gap(i, y)); }, x).row(0);
            EXPECT_LT(max_abs_diff(m.gap_gradient(i, x), g), 1e-9);
            const mat<3> R = fd_jacobian<3>([&](const vec<3>& y) { return m.reset(i, y); }, x);
            EXPECT_LT(max_abs_diff(m.reset_jacobian(i, x), R), 1e-9);
        }
        const vec<3> s = fd_jacobian<3>([&](const vec<3>& y) { return vec<3>::Constant(m.section(0, y)); }, x).row(0);
        EXPECT_LT(max_abs_diff(m.section_gradient(0, x), s), 1e-9);
    }
}

namespace {
// A curved wall: a gap with a nonzero Hessian.
struct curved {
    static constexpr std::string_view name = "curved", description = "a circular wall";
    static constexpr std::array<state_variable, 2> state{{{"q1"}, {"q2"}}};
    static constexpr std::array<parameter, 1> parameters{{{"R", 2.0}}};
    static constexpr std::array<impact_surface, 1> surfaces{{{"wall"}}};
    static constexpr std::array<poincare_section, 0> sections{};
    double R;
    explicit curved(std::span<const double> p) : R(p[0]) {}
    template <class T>
    vec_t<T, 2> derivatives(const vec_t<T, 2>& x) const { return {x[1], -x[0]}; }
    template <class T>
    T gap(int, const vec_t<T, 2>& x) const
    {
        using std::exp;
        using std::sin;
        return R * R - x[0] * x[0] - x[1] * x[1] * exp(sin(x[0]));
    }
    template <class T>
    vec_t<T, 2> reset(int, const vec_t<T, 2>& x) const { return x; }
    template <class T>
    T section(int, const vec_t<T, 2>& x) const { return x[0]; }
};
}  // namespace

TEST(Model, HessianOfANonlinearGapEqualsFiniteDifferencesOfItsGradient)
{
    const std::array<double, 1> p{2.0};
    const native_model<curved> m(p);
    std::mt19937 gen(3);
    for (int trial = 0; trial < 10; ++trial) {
        const vec<2> x = random_vec<2>(gen);
        const mat<2> fd = fd_jacobian<2>([&](const vec<2>& y) { return m.gap_gradient(0, y); }, x);
        EXPECT_LT(max_abs_diff(m.gap_hessian(0, x), fd), 1e-8);
        EXPECT_LT(max_abs_diff(m.gap_hessian(0, x), m.gap_hessian(0, x).transpose()), 1e-15);
    }
}

TEST(Model, FunctionTableCallsEqualTheNativeModel)
{
    const model m = model::builtin("wake_impact").with_parameter(0, 21.5);
    ASSERT_EQ(m.dim(), 4);
    const table_model<4> t(m.table(), m.context());
    const native_model<wake_impact> n(m.parameters());
    std::mt19937 gen(4);
    for (int trial = 0; trial < 5; ++trial) {
        const vec<4> x = random_vec<4>(gen), u = random_vec<4>(gen), w = random_vec<4>(gen);
        EXPECT_EQ(t.rhs(x), n.rhs(x));
        EXPECT_EQ(t.jacobian(x), n.jacobian(x));
        EXPECT_EQ(t.second_derivative(x, u, w), n.second_derivative(x, u, w));
        EXPECT_EQ(t.gap(0, x), n.gap(0, x));
        EXPECT_EQ(t.reset(0, x), n.reset(0, x));
        EXPECT_EQ(t.reset_jacobian(0, x), n.reset_jacobian(0, x));
        EXPECT_EQ(t.section(1, x), n.section(1, x));
        EXPECT_EQ(t.sticking_rhs(0, x), n.sticking_rhs(0, x));
        EXPECT_EQ(t.release(0, x), n.release(0, x));
        EXPECT_EQ(t.rest(0, x), n.rest(0, x));
    }
    EXPECT_EQ(t.section_direction(0), crossing::down);
    EXPECT_EQ(t.section_direction(1), crossing::up);
    EXPECT_TRUE(t.sticks(0));
}

TEST(Model, InfoDescribesTheBuiltIns)
{
    const model m;
    EXPECT_EQ(m.name(), "wake_impact");
    EXPECT_EQ(m.info().state_names(), "y, ydot, x, xdot");
    EXPECT_EQ(m.info().parameter_index("sigma"), 1);
    EXPECT_EQ(m.info().parameter_index("nope"), -1);
    EXPECT_EQ(m.info().section_names(), "maxima, minima");
    EXPECT_EQ(m.info().surfaces.at(0).name, "barrier");
    EXPECT_EQ(m.initial_state(), Eigen::Vector4d(0, 0, 0, 0.1));
    const int facchinetti = m.info().preset_index("facchinetti");
    ASSERT_GE(facchinetti, 0);
    EXPECT_EQ(m.with_preset(facchinetti).parameter(m.info().parameter_index("CL0")), 0.3);
    const model two = model::builtin("two_sided_impact_oscillator");
    EXPECT_EQ(two.info().surface_names(), "right, left");
    EXPECT_GT(two.info().state.at(2).period, 6.28);
    EXPECT_THROW((void)model::builtin("nope"), input_error);
}

TEST(Model, ParametersOutsideTheirRangeAreRefusedWithTheirRange)
{
    const model m;
    try {
        (void)m.with_parameter(m.info().parameter_index("r"), 1.5);
        FAIL() << "r = 1.5 accepted";
    } catch (const input_error& e) {
        EXPECT_STREQ(e.what(), "parameter r = 1.5 is outside its valid range [0, 1] (coefficient of restitution)");
    }
    EXPECT_THROW((void)m.with_parameter(0, 0.0), input_error);              // Ur > 0
    EXPECT_THROW((void)m.with_parameter(0, std::nan("")), input_error);
    EXPECT_NO_THROW((void)m.with_parameter(1, -0.2));
    EXPECT_TRUE(m == model::builtin("wake_impact"));
    EXPECT_FALSE(m == m.with_parameter(1, -0.2));
}

// Names to indices for the front ends, in the order docs/model.md lists the wake model's
// parameters (Ur, sigma, r, A, ...) and state (y, ydot, x, xdot); a name the model lacks is
// refused naming the input and what the model has.
TEST(ModelPhrases, NamesAreIndicesOrRefusalsThatNameTheInput)
{
    const auto m = vimpact::model::builtin("wake_impact");
    EXPECT_EQ(vimpact::parameter_index(m, "Ur", "--param"), 0);
    EXPECT_EQ(vimpact::parameter_index(m, "A", "--param"), 3);
    EXPECT_EQ(vimpact::state_index(m, "x", "--x"), 2);
    try {
        (void)vimpact::parameter_index(m, "Q", "--param");
        ADD_FAILURE() << "Q accepted";
    } catch (const vimpact::input_error& e) {
        EXPECT_EQ(std::string(e.what()).rfind("unknown parameter 'Q' for --param (model wake_impact has Ur, sigma, r, A", 0), 0u)
            << e.what();
    }
    try {
        (void)vimpact::state_index(m, "v", "x");
        ADD_FAILURE() << "v accepted";
    } catch (const vimpact::input_error& e) {
        EXPECT_EQ(std::string(e.what()), "x: 'v' is not one of y, ydot, x, xdot (the state of model wake_impact)");
    }
}

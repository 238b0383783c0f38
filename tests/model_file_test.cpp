// Model files: the example files against the built-ins they restate, symbolic derivatives
// against finite differences, exact constants, one message per class of bad file, the cache,
// the compiler requirement, the JSON path, model libraries, the bounds on what a file can make
// the symbolic stage and the compiler do, the cache's safety, and stopping a compilation.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <sys/wait.h>
#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <numbers>
#include <optional>
#include <random>
#include <set>
#include <sstream>
#include <thread>

#include <ginac/ginac.h>

#include "model_file_detail.hpp"
#include "test_support.hpp"
#include "vimpact/core/cancelled.hpp"
#include "vimpact/core/input_error.hpp"
#include "vimpact/io/build_info.hpp"
#include "vimpact/model/abi.h"
#include "vimpact/model/builtin/two_sided_impact_oscillator.hpp"
#include "vimpact/model/builtin/wake_impact.hpp"
#include "vimpact/model/model.hpp"
#include "vimpact/model/model_file.hpp"
#include "vimpact/model/table_model.hpp"

using namespace vimpact;
namespace fs = std::filesystem;

#if defined(__SANITIZE_ADDRESS__)
// CLN (GiNaC's number library, which libvimpact links) allocates a string when it is loaded
// and never frees it; LeakSanitizer would fail every process of this program for it. GiNaC's
// own parser was seen (once, in CI) to leave 40 bytes allocated inside libginac behind a
// refused expression, with no frame of ours on the allocation's stack.
extern "C" const char* __lsan_default_suppressions() { return "leak:libcln.so\nleak:libginac.so\n"; }
#endif

namespace {

// Every compiled model of this test program goes to a fresh cache directory.
class cache_environment : public ::testing::Environment {
public:
    void SetUp() override
    {
        char pattern[] = "/tmp/vimpact-model-file-test-XXXXXX";
        ASSERT_NE(::mkdtemp(pattern), nullptr);
        dir = pattern;
        ::setenv("VIMPACT_CACHE_DIR", pattern, 1);
    }
    void TearDown() override
    {
        std::error_code ec;
        fs::remove_all(dir, ec);
    }
    static inline fs::path dir;
};
[[maybe_unused]] auto* const environment = ::testing::AddGlobalTestEnvironment(new cache_environment);

const std::string source_dir = VIMPACT_SOURCE_DIR;

// Sets an environment variable for one scope.
class scoped_env {
public:
    scoped_env(const char* name, const std::string& value) : m_name(name)
    {
        if (const char* old = std::getenv(name)) m_old = old;
        ::setenv(name, value.c_str(), 1);
    }
    ~scoped_env()
    {
        if (m_old) ::setenv(m_name, m_old->c_str(), 1);
        else ::unsetenv(m_name);
    }
    scoped_env(const scoped_env&) = delete;
    scoped_env& operator=(const scoped_env&) = delete;

private:
    const char* m_name;
    std::optional<std::string> m_old;
};

using test::random_vec;

// |a - b| within `rel` of the largest entry of b (and of 1), by plain loops (Eigen's AVX-512
// reductions of small matrices trip false -Wmaybe-uninitialized errors in GCC 12).
template <class A, class B>
::testing::AssertionResult close(const A& a, const B& b, double rel = 5e-14)
{
    double scale = 1.0, diff = 0.0;
    for (Eigen::Index i = 0; i < b.rows(); ++i)
        for (Eigen::Index j = 0; j < b.cols(); ++j) {
            scale = std::max(scale, std::abs(b(i, j)));
            diff = std::max(diff, std::abs(a(i, j) - b(i, j)));
        }
    if (diff <= rel * scale) return ::testing::AssertionSuccess();
    std::ostringstream s;
    s << "difference " << diff << " > " << rel << " * " << scale << "\n" << a << "\nvs\n" << b;
    return ::testing::AssertionFailure() << s.str();
}
::testing::AssertionResult close(double a, double b, double rel = 5e-14)
{
    return close(Eigen::Matrix<double, 1, 1>(a), Eigen::Matrix<double, 1, 1>(b), rel);
}

// The message of the input_error that compiling `text` throws.
std::string error_of(const std::string& text, const std::string& source = "bad.toml")
{
    try {
        (void)compile_model_text(text, source);
    } catch (const input_error& e) {
        return e.what();
    } catch (const std::exception& e) {
        ADD_FAILURE() << "not an input_error: " << e.what();
        return {};
    }
    ADD_FAILURE() << "no error for:\n" << text;
    return {};
}

std::string replaced(std::string text, const std::string& from, const std::string& to)
{
    const auto pos = text.find(from);
    EXPECT_NE(pos, std::string::npos) << from;
    if (pos != std::string::npos) text.replace(pos, from.size(), to);
    return text;
}

std::string read_text(const fs::path& p)
{
    std::ifstream in(p);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

// The two-sided oscillator, short: the base of the bad files.
const std::string two_sided = R"toml(
name = "two_sided"
state = ["x", "v", "phi"]
[parameters]
zeta = 0.05
a = 1.0
w = 1.2
d = 1.0
r = { default = 0.8, min = 0, max = 1 }
[derivatives]
x = "v"
v = "-2*zeta*v - x + a*cos(phi)"
phi = "w"
[angles]
phi = "2*pi"
[[surfaces]]
name = "right"
gap = "d - x"
reset = { v = "-r*v" }
[[surfaces]]
name = "left"
gap = "x + d"
reset = { v = "-r*v" }
[[sections]]
name = "strobe"
when = "sin(phi)"
direction = "up"
)toml";

// Every function of the two tables agrees at random states.
template <int N>
void expect_same_functions(const model& file, const model& builtin, std::mt19937& gen, double scale)
{
    const table_model<N> f(file.table(), file.context());
    const table_model<N> b(builtin.table(), builtin.context());
    ASSERT_EQ(f.surface_count(), b.surface_count());
    ASSERT_EQ(f.section_count(), b.section_count());
    for (int trial = 0; trial < 40; ++trial) {
        const vec<N> x = random_vec<N>(gen, scale), u = random_vec<N>(gen), w = random_vec<N>(gen);
        EXPECT_TRUE(close(f.rhs(x), b.rhs(x)));
        EXPECT_TRUE(close(f.jacobian(x), b.jacobian(x)));
        EXPECT_TRUE(close(f.second_derivative(x, u, w), b.second_derivative(x, u, w)));
        EXPECT_TRUE(close(f.divergence(x), b.divergence(x)));
        for (int i = 0; i < b.surface_count(); ++i) {
            EXPECT_TRUE(close(f.gap(i, x), b.gap(i, x)));
            EXPECT_TRUE(close(f.gap_gradient(i, x), b.gap_gradient(i, x)));
            EXPECT_TRUE(close(f.gap_hessian(i, x), b.gap_hessian(i, x)));
            EXPECT_TRUE(close(f.reset(i, x), b.reset(i, x)));
            EXPECT_TRUE(close(f.reset_jacobian(i, x), b.reset_jacobian(i, x)));
            EXPECT_TRUE(close(f.reset_second_derivative(i, x, u, w), b.reset_second_derivative(i, x, u, w)));
            EXPECT_EQ(f.sticks(i), b.sticks(i));
            EXPECT_TRUE(close(f.sticking_rhs(i, x), b.sticking_rhs(i, x)));
            EXPECT_TRUE(close(f.release(i, x), b.release(i, x)));
            EXPECT_TRUE(close(f.release_gradient(i, x), b.release_gradient(i, x)));
            EXPECT_TRUE(close(f.rest(i, x), b.rest(i, x)));
        }
        for (int k = 0; k < b.section_count(); ++k) {
            EXPECT_TRUE(close(f.section(k, x), b.section(k, x)));
            EXPECT_TRUE(close(f.section_gradient(k, x), b.section_gradient(k, x)));
            EXPECT_EQ(f.section_direction(k), b.section_direction(k));
        }
    }
}

void expect_same_info(const model_info& f, const model_info& b)
{
    EXPECT_EQ(f.name, b.name);
    EXPECT_EQ(f.description, b.description);
    ASSERT_EQ(f.state.size(), b.state.size());
    for (std::size_t j = 0; j < b.state.size(); ++j) {
        EXPECT_EQ(f.state[j].name, b.state[j].name);
        EXPECT_EQ(f.state[j].meaning, b.state[j].meaning);
        EXPECT_EQ(f.state[j].unit, b.state[j].unit);
        EXPECT_EQ(f.state[j].period, b.state[j].period) << f.state[j].name;
    }
    EXPECT_EQ(f.initial_state, b.initial_state);
    ASSERT_EQ(f.parameters.size(), b.parameters.size());
    for (std::size_t k = 0; k < b.parameters.size(); ++k) {
        const auto& p = f.parameters[k];
        const auto& q = b.parameters[k];
        EXPECT_EQ(p.name, q.name);
        EXPECT_EQ(p.meaning, q.meaning);
        EXPECT_EQ(p.unit, q.unit);
        EXPECT_EQ(p.default_value, q.default_value) << p.name;
        EXPECT_EQ(p.range.lower, q.range.lower) << p.name;
        EXPECT_EQ(p.range.upper, q.range.upper) << p.name;
        EXPECT_EQ(p.range.lower_inclusive, q.range.lower_inclusive) << p.name;
        EXPECT_EQ(p.range.upper_inclusive, q.range.upper_inclusive) << p.name;
    }
    ASSERT_EQ(f.surfaces.size(), b.surfaces.size());
    for (std::size_t i = 0; i < b.surfaces.size(); ++i) {
        EXPECT_EQ(f.surfaces[i].name, b.surfaces[i].name);
        EXPECT_EQ(f.surfaces[i].meaning, b.surfaces[i].meaning);
        EXPECT_EQ(f.surfaces[i].sticks, b.surfaces[i].sticks);
    }
    ASSERT_EQ(f.sections.size(), b.sections.size());
    for (std::size_t k = 0; k < b.sections.size(); ++k) {
        EXPECT_EQ(f.sections[k].name, b.sections[k].name);
        EXPECT_EQ(f.sections[k].meaning, b.sections[k].meaning);
        EXPECT_EQ(f.sections[k].direction, b.sections[k].direction);
    }
    ASSERT_EQ(f.presets.size(), b.presets.size());
    for (std::size_t k = 0; k < b.presets.size(); ++k) {
        EXPECT_EQ(f.presets[k].name, b.presets[k].name);
        EXPECT_EQ(f.presets[k].meaning, b.presets[k].meaning);
        EXPECT_EQ(f.presets[k].values, b.presets[k].values);
    }
}

// Parameter sets inside every range: the defaults scaled by factors in [0.5, 1.5], and r,
// whose range is [0, 1], drawn from it.
std::vector<double> random_parameters(const model_info& info, std::mt19937& gen)
{
    std::uniform_real_distribution<double> factor(0.5, 1.5), unit(0.0, 1.0);
    std::vector<double> p;
    for (const auto& q : info.parameters) p.push_back(q.name == "r" ? unit(gen) : q.default_value * factor(gen));
    return p;
}

// The source the cache holds for the model named `name` (empty when there is none).
std::string generated_source(const std::string& name)
{
    for (const auto& e : fs::directory_iterator(cache_environment::dir))
        if (e.path().filename().string().starts_with(name + "-") && e.path().extension() == ".cpp")
            return read_text(e.path());
    return {};
}

}  // namespace

// ---- (a) the example files restate the built-ins

TEST(ModelFile, WakeImpactFileEqualsTheBuiltIn)
{
    const model file = model::from_file(source_dir + "/examples/models/wake_impact.toml");
    const model builtin = model::builtin("wake_impact");
    expect_same_info(file.info(), builtin.info());
    EXPECT_EQ(file.info().parameters[9].default_value, wake_impact::paper_CL0);
    EXPECT_EQ(file.info().source, source_dir + "/examples/models/wake_impact.toml");
    EXPECT_NE(file.info().identity, builtin.info().identity);
    std::mt19937 gen(11);
    expect_same_functions<4>(file, builtin, gen, 1.5);
    expect_same_functions<4>(file.with_preset(1), builtin.with_preset(1), gen, 1.5);
    for (int set = 0; set < 5; ++set) {
        const auto p = random_parameters(builtin.info(), gen);
        expect_same_functions<4>(file.with_parameters(p), builtin.with_parameters(p), gen, 1.5);
    }
}

// The same model as the equations read (bench/models/wake_impact_natural.toml): the parameter
// groups inside the equations, no derived quantities, the acceleration written twice. Its
// parts that depend on the parameters only are computed once per parameter set (hoisted), the
// acceleration once per call, and every function still equals the hand-written built-in's,
// for random parameter sets too.
TEST(ModelFile, NaturallyWrittenWakeModelEqualsTheBuiltIn)
{
    const model file = model::from_file(source_dir + "/bench/models/wake_impact_natural.toml");
    const model builtin = model::builtin("wake_impact");
    std::mt19937 gen(13);
    expect_same_functions<4>(file, builtin, gen, 1.5);
    for (int set = 0; set < 5; ++set) {
        const auto p = random_parameters(builtin.info(), gen);
        expect_same_functions<4>(file.with_parameters(p), builtin.with_parameters(p), gen, 1.5);
    }
    // No division is left in the vector field or its Jacobian: (1/(St*Ur))^2, 2*xi/(St*Ur),
    // gamma/mu and CL0/(16*pi^2*St^2*mu) are computed in vimpact_create.
    const std::string code = generated_source("wake_impact_natural");
    ASSERT_FALSE(code.empty());
    const auto body = [&](const std::string& function) {
        const auto at = code.find(function + "(const ");  // its definition
        return at == std::string::npos ? std::string() : code.substr(at, code.find("\n}\n", at) - at);
    };
    for (const char* f : {"vimpact_rhs", "vimpact_jacobian"}) {
        ASSERT_FALSE(body(f).empty()) << f;
        EXPECT_EQ(body(f).find('/'), std::string::npos) << body(f);
    }
    EXPECT_NE(body("vimpact_create").find('/'), std::string::npos);
    // The acceleration, written again in the wake equation (scaled by 16 where GiNaC keeps it),
    // is computed once: the wake's component reads it from the cylinder's, out[1].
    const std::string rhs = body("vimpact_rhs");
    const auto wake = rhs.find("out[3] = ");
    ASSERT_NE(wake, std::string::npos) << rhs;
    EXPECT_NE(rhs.find("out[1]", wake + 9), std::string::npos) << rhs;
}

TEST(ModelFile, TwoSidedOscillatorFileEqualsTheBuiltIn)
{
    const model file = model::from_file(source_dir + "/examples/models/two_sided_impact_oscillator.toml");
    const model builtin = model::builtin("two_sided_impact_oscillator");
    expect_same_info(file.info(), builtin.info());
    EXPECT_EQ(file.info().state[2].period, 2.0 * std::numbers::pi);
    std::mt19937 gen(12);
    expect_same_functions<3>(file, builtin, gen, 4.0);
    for (int set = 0; set < 5; ++set) {
        const auto p = random_parameters(builtin.info(), gen);
        expect_same_functions<3>(file.with_parameters(p), builtin.with_parameters(p), gen, 4.0);
    }
}

// ---- (b) symbolic derivatives of a nonlinear model against finite differences

namespace {

const std::string nonlinear = R"toml(
name = "nonlinear_check"
state = ["x", "y", "z"]
[parameters]
k = 1.3
c = { default = 0.4, min = 0 }
[derived]
k2 = "k^2 + c"
[expressions]
q = "tanh(x*y) + abs(z - 0.1)"
[derivatives]
x = "y*z - k*sin(x)^2 + q"
y = "pow(abs(x) + 1, 1.5) - c*y^3 + exp(-z^2) + (x + y)^2"
z = "x*y/(1 + z^2) + log(2 + cos(y)) + sqrt(1 + x^2)*k2 - atan(y)*cosh(z)"
[[surfaces]]
name = "curve"
gap = "1.5 - x^2 - 0.5*y^2 + tanh(z)*x + abs(y)*z"
reset = { x = "x - 0.1*y^2", y = "-c*y + 0.2*x*z^2", z = "z + sin(x*y)" }
[surfaces.sticking]
release = "x*y - z^3 + abs(x)"
derivatives = { x = "0" }
rest = { x = "x*0.5" }
[[sections]]
name = "s"
when = "x*cos(z) - y^2 + pow(1 + z^2, x)"
direction = "both"
)toml";

template <class F>
mat<3> fd_jacobian(F&& f, const vec<3>& x, double h = 1e-6)
{
    mat<3> J;
    for (int j = 0; j < 3; ++j) {
        vec<3> a = x, b = x;
        a[j] += h;
        b[j] -= h;
        J.col(j) = (f(a) - f(b)) / (2.0 * h);
    }
    return J;
}

vec<3> scalar3(double v) { return vec<3>::Constant(v); }

// A random state away from the kinks of abs in the model above.
vec<3> smooth_state(std::mt19937& gen)
{
    for (;;) {
        const vec<3> x = random_vec<3>(gen);
        if (std::abs(x[0]) > 0.05 && std::abs(x[1]) > 0.05 && std::abs(x[2] - 0.1) > 0.05) return x;
    }
}

}  // namespace

TEST(ModelFile, SymbolicDerivativesEqualFiniteDifferences)
{
    const model m = model::from_toml(nonlinear, "nonlinear.toml");
    const table_model<3> t(m.table(), m.context());
    std::mt19937 gen(13);
    const double tol = 1e-7;
    for (int trial = 0; trial < 30; ++trial) {
        const vec<3> x = smooth_state(gen), u = random_vec<3>(gen), w = random_vec<3>(gen);
        const double h = 1e-6;
        EXPECT_TRUE(close(t.jacobian(x), fd_jacobian([&](const vec<3>& y) { return t.rhs(y); }, x), tol));
        const vec<3> d2 = (t.jacobian(vec<3>(x + h * u)) * w - t.jacobian(vec<3>(x - h * u)) * w) / (2.0 * h);
        EXPECT_TRUE(close(t.second_derivative(x, u, w), d2, tol));
        EXPECT_TRUE(close(t.second_derivative(x, u, w), t.second_derivative(x, w, u), 1e-15));
        EXPECT_TRUE(close(t.divergence(x), t.jacobian(x).trace(), 1e-15));

        const vec<3> g = fd_jacobian([&](const vec<3>& y) { return scalar3(t.gap(0, y)); }, x).row(0);
        EXPECT_TRUE(close(t.gap_gradient(0, x), g, tol));
        EXPECT_TRUE(close(t.gap_hessian(0, x), fd_jacobian([&](const vec<3>& y) { return t.gap_gradient(0, y); }, x), tol));
        EXPECT_TRUE(close(t.gap_hessian(0, x), mat<3>(t.gap_hessian(0, x).transpose()), 0.0));

        EXPECT_TRUE(close(t.reset_jacobian(0, x), fd_jacobian([&](const vec<3>& y) { return t.reset(0, y); }, x), tol));
        const vec<3> r2 = (t.reset_jacobian(0, vec<3>(x + h * u)) * w - t.reset_jacobian(0, vec<3>(x - h * u)) * w) / (2.0 * h);
        EXPECT_TRUE(close(t.reset_second_derivative(0, x, u, w), r2, tol));

        const vec<3> s = fd_jacobian([&](const vec<3>& y) { return scalar3(t.section(0, y)); }, x).row(0);
        EXPECT_TRUE(close(t.section_gradient(0, x), s, tol));
        const vec<3> rel = fd_jacobian([&](const vec<3>& y) { return scalar3(t.release(0, y)); }, x).row(0);
        EXPECT_TRUE(close(t.release_gradient(0, x), rel, tol));

        // The constrained field replaces x' only; rest halves x only.
        const vec<3> f = t.rhs(x), fs = t.sticking_rhs(0, x), r = t.rest(0, x);
        EXPECT_EQ(fs[0], 0.0);
        EXPECT_EQ(fs[1], f[1]);
        EXPECT_EQ(fs[2], f[2]);
        EXPECT_EQ(r[0], 0.5 * x[0]);
        EXPECT_EQ(r[1], x[1]);
        EXPECT_EQ(r[2], x[2]);
    }
    // In the field, abs(x) and abs(z - 0.1) are switches (their sides held by a flow, the
    // state's away from one); the gap's and release's abs(y) and abs(x) stay functions, whose
    // derivative is csgn, 0 at the kink (not 0/0).
    const auto& switches = m.info().switches;
    ASSERT_EQ(switches.size(), 2U);
    EXPECT_EQ(switches[0].name, "abs#1");
    EXPECT_EQ(switches[0].meaning, "the sign of x, from abs() in derivatives.y");
    EXPECT_EQ(switches[1].name, "abs#2");
    EXPECT_EQ(switches[1].meaning, "the sign of z - 0.1, from abs() in derivatives.x");
    const vec<3> kink(0.3, 0.0, 0.1);
    const mat<3> J = t.jacobian(kink);
    for (int i = 0; i < 9; ++i) EXPECT_TRUE(std::isfinite(J.data()[i]));
    EXPECT_EQ(J(0, 2), 1.0);  // d/dz of y*z + abs(z - 0.1) at z = 0.1: y + side = 0 + 1
    EXPECT_EQ(t.gap_gradient(0, kink)[1], 0.0);  // d/dy of -y^2/2 + abs(y)*z at y = 0: csgn(0) z = 0
}

TEST(ModelFile, IntegerPowersAreMultiplicationsAndConstantsAreExactDoubles)
{
    const std::string text = R"toml(
name = "exact_constants"
state = ["x", "y", "z"]
[parameters]
p = 0.1
[derivatives]
x = "0.1"
y = "x^2 + (x + y)^3 + x^(-2) + (1 + z)^(-3) + sqrt(y) + y^1.5 + 1/sqrt(z)"
z = "1e-7 + 2.5e3*x + 0.30000000000000004*y + 1/3"
[angles]
z = "pi/3"
)toml";
    const model m = model::from_toml(text, "exact.toml");
    const table_model<3> t(m.table(), m.context());
    const vec<3> x(0.7, 0.4, 0.9);
    const vec<3> f = t.rhs(x);
    EXPECT_EQ(f[0], 0.1);  // bit for bit the C++ literal
    EXPECT_EQ(m.info().parameters[0].default_value, 0.1);
    EXPECT_EQ(m.info().state[2].period, std::numbers::pi / 3.0);
    const double y = 0.7 * 0.7 + (0.7 + 0.4) * (0.7 + 0.4) * (0.7 + 0.4) + 1.0 / (0.7 * 0.7) +
                     1.0 / ((1.9) * (1.9) * (1.9)) + std::sqrt(0.4) + 0.4 * std::sqrt(0.4) + 1.0 / std::sqrt(0.9);
    EXPECT_TRUE(close(f[1], y, 1e-15));
    EXPECT_TRUE(close(f[2], 1e-7 + 2.5e3 * 0.7 + 0.30000000000000004 * 0.4 + 1.0 / 3.0, 1e-15));

    // The generated source calls pow() for none of these powers.
    const std::string code = generated_source("exact_constants");
    ASSERT_FALSE(code.empty());
    EXPECT_EQ(code.find("pow("), std::string::npos) << code;
    EXPECT_NE(code.find("x[0]*x[0]"), std::string::npos);
}

// GiNaC's parser, which reads the expressions, takes a sign right after an operator to apply
// to the rest of the expression, so model files refuse that form (the next test). This test
// shows which reading the installed GiNaC makes: if it reads x - -y + z right, the refusal
// (check_syntax in src/model_file_symbolic.cpp) may be dropped.
TEST(ModelFile, GinacParserMisreadsASignRightAfterAnOperator)
{
    const GiNaC::realsymbol x("x"), y("y"), z("z");
    GiNaC::parser reader(GiNaC::symtab{{"x", x}, {"y", y}, {"z", z}}, true);
    const GiNaC::ex e = reader("x - -y + z");
    const bool misread = (e - (x + y - z)).expand().is_zero(), right = (e - (x + y + z)).expand().is_zero();
    EXPECT_TRUE(misread || right) << e;
    std::cout << "GiNaC " << GINACLIB_MAJOR_VERSION << "." << GINACLIB_MINOR_VERSION << "." << GINACLIB_MICRO_VERSION
              << (misread ? " misreads x - -y + z as x + y - z: model files keep refusing a sign after an operator\n"
                          : " reads x - -y + z right: the refusal of a sign after an operator may be dropped\n");
}

TEST(ModelFile, ASignRightAfterAnOperatorIsRefusedWithTheFix)
{
    const auto message = [&](const std::string& expression) {
        return error_of(replaced(two_sided, "x = \"v\"", "x = \"" + expression + "\""));
    };
    const std::string key = "model file bad.toml: derivatives.x: ", why = " (a sign right after an operator is ambiguous)";
    EXPECT_EQ(message("v^-2 + x"), key + "write v^(-2), not v^-2" + why);
    EXPECT_EQ(message("v**-2"), key + "write v**(-2), not v**-2" + why);
    EXPECT_EQ(message("x - -v + phi"), key + "write x - (-v), not x - -v" + why);
    EXPECT_EQ(message("2*-x"), key + "write 2*(-x), not 2*-x" + why);
    EXPECT_EQ(message("x/-v^2*phi"), key + "write x/(-v^2), not x/-v^2" + why);
    EXPECT_EQ(message("v + +x"), key + "write v + (+x), not v + +x" + why);
    EXPECT_EQ(message("--v + x"), key + "write -(-v), not --v" + why);
    EXPECT_EQ(message("(x + -v)"), key + "write x + (-v), not x + -v" + why);
    EXPECT_EQ(message("cos(phi)*-sin(x)"), key + "write cos(phi)*(-sin(x)), not cos(phi)*-sin(x)" + why);
    EXPECT_EQ(message("(x + v)^-(phi - 1)"), key + "write (x + v)^(-(phi - 1)), not (x + v)^-(phi - 1)" + why);
    EXPECT_EQ(message("pow(x, 2*-v)"), key + "write 2*(-v), not 2*-v" + why);
    // With nothing after the sign, what follows is the error.
    EXPECT_EQ(message("v^-"), key + "cannot read 'v^-': the expression ends too early");
    EXPECT_EQ(message("(v*-)"), key + "cannot read '(v*-)': unexpected ')'");
}

// The accepted forms, evaluated by the generated code against C++: signs where an expression
// starts, precedence, nested parentheses, every function, names GiNaC would take for its own
// constants (I, Euler), and the exact constants.
TEST(ModelFile, ExpressionsMeanWhatTheyMeanInCpp)
{
    using fn = double (*)(double, double, double);
    const std::vector<std::pair<std::string, fn>> cases = {
        {"x^(-2) + y", [](double x, double y, double) { return 1.0 / (x * x) + y; }},
        {"x - (-y) + z", [](double x, double y, double z) { return x + y + z; }},
        {"-x^2 + y", [](double x, double y, double) { return -(x * x) + y; }},
        {"2*(-x) + y", [](double x, double y, double) { return -2.0 * x + y; }},
        {"-x*y + z - x/y*z", [](double x, double y, double z) { return -x * y + z - x / y * z; }},
        {"+x - y - z + x*y", [](double x, double y, double z) { return x - y - z + x * y; }},
        {"x/(-y)*z - (-x)^3", [](double x, double y, double z) { return x / -y * z + x * x * x; }},
        {"-2^2*x + 2^3*x**2 - 2^(-1)", [](double x, double, double) { return -4.0 * x + 8.0 * x * x - 0.5; }},
        {"-(x - (-(y - (-z))))", [](double x, double y, double z) { return -(x + y + z); }},
        {"((x + y)*(-(z - x)))/(-(-y))", [](double x, double y, double z) { return (x + y) * (x - z) / y; }},
        {"pow(-x, 2) + pow(y, -1)", [](double x, double y, double) { return x * x + 1.0 / y; }},
        {"(x - y)^2*(y - x)^3", [](double x, double y, double) { return std::pow(x - y, 2) * std::pow(y - x, 3); }},
        {"sin(x) + cos(y) + tan(z)", [](double x, double y, double z) { return std::sin(x) + std::cos(y) + std::tan(z); }},
        {"asin(x/4) + acos(-y/4) + atan(z)",
         [](double x, double y, double z) { return std::asin(x / 4) + std::acos(-y / 4) + std::atan(z); }},
        {"sinh(x) + cosh(y) + tanh(-z)", [](double x, double y, double z) { return std::sinh(x) + std::cosh(y) - std::tanh(z); }},
        {"exp(-x) + log(y) + sqrt(z)", [](double x, double y, double z) { return std::exp(-x) + std::log(y) + std::sqrt(z); }},
        {"abs(-x) + abs(y - 3)", [](double x, double y, double) { return x + std::abs(y - 3.0); }},
        {"pow(x, y) + pow(z, 0.5) + z^1.5", [](double x, double y, double z) { return std::pow(x, y) + std::sqrt(z) + z * std::sqrt(z); }},
        {"I*x + Euler - u_1*z", [](double x, double, double z) { return 2.0 * x + 0.5 - 3.0 * z; }},
        {"0.1*x + 1e-3 - .5e1 + 2*pi", [](double x, double, double) { return 0.1 * x + 1e-3 - 5.0 + 2.0 * std::numbers::pi; }},
    };
    std::string text = "name = \"signs\"\nstate = [\"x\", \"y\", \"z\"]\n[parameters]\nI = 2.0\nEuler = 0.5\nu_1 = 3\n"
                       "[derivatives]\nx = \"0.1\"\ny = \"2*pi\"\nz = \"-x\"\n";
    for (std::size_t i = 0; i < cases.size(); ++i)
        text += "[[surfaces]]\nname = \"s" + std::to_string(i) + "\"\ngap = \"" + cases[i].first + "\"\nreset = {}\n";
    const model m = model::from_toml(text, "signs.toml");
    const table_model<3> t(m.table(), m.context());
    for (const vec<3>& x : {vec<3>(0.7, 1.3, 2.1), vec<3>(1.9, 0.4, 0.6), vec<3>(2.5, 3.1, 0.25)}) {
        const vec<3> f = t.rhs(x);
        EXPECT_EQ(f[0], 0.1);                    // bit for bit the C++ literal
        EXPECT_EQ(f[1], 2 * std::numbers::pi);  // and C++'s 2*pi
        EXPECT_EQ(f[2], -x[0]);
        for (std::size_t i = 0; i < cases.size(); ++i)
            EXPECT_TRUE(close(t.gap(static_cast<int>(i), x), cases[i].second(x[0], x[1], x[2]), 1e-14))
                << cases[i].first << " at " << x.transpose();
    }
}

// ---- (c) bad files: one input_error naming the key

TEST(ModelFile, SyntaxErrorNamesTheLine)
{
    const std::string e = error_of("name = \"a\"\nstate = [\"x\"\n[parameters]\n");
    EXPECT_TRUE(e.starts_with("model file bad.toml: line ")) << e;
}

TEST(ModelFile, MissingKey)
{
    EXPECT_EQ(error_of(replaced(two_sided, "[derivatives]\nx = \"v\"\nv = \"-2*zeta*v - x + a*cos(phi)\"\nphi = \"w\"\n", "")),
              "model file bad.toml: missing key 'derivatives'");
    EXPECT_EQ(error_of(replaced(two_sided, "gap = \"d - x\"\n", "")), "model file bad.toml: missing key 'surfaces[0].gap'");
}

TEST(ModelFile, UnknownKeyAtTopLevel)
{
    const std::string e = error_of("bogus = 1\n" + two_sided);
    EXPECT_TRUE(e.starts_with("model file bad.toml: unknown key 'bogus' (valid: name, description, state,")) << e;
}

TEST(ModelFile, UnknownNestedKey)
{
    EXPECT_EQ(error_of(replaced(two_sided, "gap = \"x + d\"\nreset", "gap = \"x + d\"\nresett")),
              "model file bad.toml: unknown key 'surfaces[1].resett' (valid: name, meaning, gap, reset, sticking)");
    EXPECT_EQ(error_of(replaced(two_sided, "r = { default = 0.8,", "r = { default = 0.8, mni = 0,")),
              "model file bad.toml: unknown key 'parameters.r.mni' (valid: default, meaning, unit, min, max, above, below)");
}

TEST(ModelFile, UnknownSymbol)
{
    EXPECT_EQ(error_of(replaced(two_sided, "-2*zeta*v", "-2*zet*v"), "two.toml"),
              "model file two.toml: derivatives.v: unknown symbol 'zet' (state: x, v, phi; parameters: zeta, a, w, d, r)");
}

TEST(ModelFile, UnknownFunction)
{
    const std::string e = error_of(replaced(two_sided, "when = \"sin(phi)\"", "when = \"sinc(phi)\""));
    EXPECT_TRUE(e.starts_with("model file bad.toml: sections[0].when: unknown function 'sinc' (functions: sin, cos,")) << e;
    EXPECT_NE(error_of(replaced(two_sided, "cos(phi)", "cos(phi, 2)")).find("derivatives.v: cos takes 1 argument, got 2"),
              std::string::npos);
}

TEST(ModelFile, MissingDerivative)
{
    EXPECT_EQ(error_of(replaced(two_sided, "phi = \"w\"\n[angles]", "[angles]")),
              "model file bad.toml: derivatives: no equation for state variable 'phi'");
}

TEST(ModelFile, DerivativeOfAnUnknownVariable)
{
    EXPECT_EQ(error_of(replaced(two_sided, "phi = \"w\"\n[angles]", "phi = \"w\"\nq = \"1\"\n[angles]")),
              "model file bad.toml: derivatives.q: 'q' is not a state variable (state: x, v, phi)");
}

TEST(ModelFile, ResetOfAnUnknownVariable)
{
    EXPECT_EQ(error_of(replaced(two_sided, "reset = { v = \"-r*v\" }", "reset = { q = \"-r*v\" }")),
              "model file bad.toml: surfaces[0].reset.q: 'q' is not a state variable (state: x, v, phi)");
}

TEST(ModelFile, BadDirection)
{
    EXPECT_EQ(error_of(replaced(two_sided, "direction = \"up\"", "direction = \"sideways\"")),
              "model file bad.toml: sections[0].direction: 'sideways' is not a direction (valid: up, down, both)");
}

TEST(ModelFile, AnglePeriodMustBeAPositiveConstant)
{
    EXPECT_EQ(error_of(replaced(two_sided, "phi = \"2*pi\"", "phi = \"2*pi*w\"")),
              "model file bad.toml: angles.phi: 'w' is a parameter: a period must be a constant, such as 2*pi");
    EXPECT_EQ(error_of(replaced(two_sided, "phi = \"2*pi\"", "phi = \"-2*pi\"")),
              "model file bad.toml: angles.phi: the period must be a positive number, got -6.283185307179586");
    EXPECT_EQ(error_of(replaced(two_sided, "phi = \"2*pi\"", "phi = 0")),
              "model file bad.toml: angles.phi: the period must be a positive number, got 0");
    EXPECT_EQ(error_of(replaced(two_sided, "phi = \"2*pi\"", "q = \"2*pi\"")),
              "model file bad.toml: angles.q: 'q' is not a state variable (state: x, v, phi)");
}

TEST(ModelFile, DuplicateNames)
{
    EXPECT_EQ(error_of(replaced(two_sided, "zeta = 0.05", "x = 0.05")),
              "model file bad.toml: parameters.x: the name 'x' is already used for a state variable");
    EXPECT_EQ(error_of(replaced(two_sided, "name = \"left\"", "name = \"right\"")),
              "model file bad.toml: surfaces[1].name: a surface named 'right' is already declared");
    EXPECT_EQ(error_of(replaced(two_sided, "[derivatives]", "[derived]\nd = \"2*a\"\n[derivatives]")),
              "model file bad.toml: derived.d: the name 'd' is already used for a parameter");
}

TEST(ModelFile, ReservedNames)
{
    const std::string e = error_of(replaced(two_sided, "state = [\"x\", \"v\", \"phi\"]", "state = [\"x\", \"v\", \"pi\"]"));
    EXPECT_TRUE(e.starts_with("model file bad.toml: state[2]: 'pi' is reserved")) << e;
    const std::string f = error_of(replaced(two_sided, "zeta = 0.05", "sin = 0.05"));
    EXPECT_TRUE(f.starts_with("model file bad.toml: parameters.sin: 'sin' is reserved")) << f;
    const std::string g = error_of(replaced(two_sided, "zeta = 0.05", "2zeta = 0.05"));
    EXPECT_NE(g.find("'2zeta' is not a valid name"), std::string::npos) << g;
}

TEST(ModelFile, DerivedCycle)
{
    EXPECT_EQ(error_of(replaced(two_sided, "[derivatives]", "[derived]\nb = \"2*c\"\nc = \"a + b\"\n[derivatives]")),
              "model file bad.toml: derived.b: circular definition (b -> c -> b)");
    EXPECT_EQ(error_of(replaced(two_sided, "[derivatives]", "[expressions]\nf = \"g*x\"\ng = \"f\"\n[derivatives]")),
              "model file bad.toml: expressions.f: circular definition (f -> g -> f)");
    EXPECT_EQ(error_of(replaced(two_sided, "[derivatives]", "[derived]\nb = \"2*x\"\n[derivatives]")),
              "model file bad.toml: derived.b: 'x' is a state variable: derived quantities depend on the parameters only");
}

TEST(ModelFile, DefaultOutsideItsRange)
{
    EXPECT_EQ(error_of(replaced(two_sided, "default = 0.8", "default = 2")),
              "model file bad.toml: parameters.r: the default 2 is outside the range [0, 1]");
    EXPECT_EQ(error_of(replaced(two_sided, "min = 0, max = 1", "min = 1, below = 1")),
              "model file bad.toml: parameters.r: the range [1, 1) is empty");
    EXPECT_EQ(error_of(replaced(two_sided, "min = 0, max = 1", "min = 0, above = 1")),
              "model file bad.toml: parameters.r: give min (a closed bound) or above (an open one), not both");
}

TEST(ModelFile, TooManyStateVariables)
{
    const int n = max_model_dimension + 1;
    std::ostringstream text, derivatives, expected;
    text << "name = \"big\"\nstate = [";
    for (int j = 0; j < n; ++j) {
        text << (j > 0 ? ", " : "") << "\"x" << j << "\"";
        derivatives << "x" << j << " = \"0\"\n";
    }
    text << "]\n[parameters]\n[derivatives]\n" << derivatives.str();
    expected << "model file bad.toml has " << n << " state variables; vimpact runs models with 1 to " << n - 1;
    const std::string e = error_of(text.str());
    EXPECT_TRUE(e.starts_with(expected.str())) << e;
}

TEST(ModelFile, StickingWithoutRelease)
{
    EXPECT_EQ(error_of(replaced(two_sided, "gap = \"d - x\"\nreset = { v = \"-r*v\" }",
                                "gap = \"d - x\"\nreset = { v = \"-r*v\" }\nsticking = { rest = { v = \"0\" } }")),
              "model file bad.toml: missing key 'surfaces[0].sticking.release'");
}

TEST(ModelFile, OtherBadExpressionsAndValues)
{
    const auto message = [&](const std::string& from, const std::string& to) {
        return error_of(replaced(two_sided, from, to));
    };
    EXPECT_EQ(message("x = \"v\"", "x = \"v +\""), "model file bad.toml: derivatives.x: cannot read 'v +': the expression ends too early");
    EXPECT_EQ(message("x = \"v\"", "x = \"v^2^3\""),
              "model file bad.toml: derivatives.x: cannot read 'v^2^3': a^b^c is ambiguous: write (a^b)^c or a^(b^c)");
    EXPECT_EQ(message("x = \"v\"", "x = \"v # 2\""),
              "model file bad.toml: derivatives.x: unexpected character '#' in 'v # 2' (expressions use numbers, names, "
              "+ - * / ^, parentheses and functions)");
    EXPECT_EQ(message("x = \"v\"", "x = \"2v\""),
              "model file bad.toml: derivatives.x: malformed number '2v' in '2v' (write 2*x for a product)");
    EXPECT_EQ(message("x = \"v\"", "x = \"v/(1 - 1)\""), "model file bad.toml: derivatives.x: cannot evaluate 'v/(1 - 1)': division by zero");
    EXPECT_EQ(message("x = \"v\"", "x = \"sqrt(-1)*v\""),
              "model file bad.toml: derivatives.x: the expression has no real value (a constant such as sqrt(-1) or log(-2) is complex)");
    EXPECT_EQ(message("x = \"v\"", "x = \"sin\""), "model file bad.toml: derivatives.x: 'sin' is a function: write sin(...)");
    EXPECT_EQ(message("x = \"v\"", "x = \"v(2)\""),
              "model file bad.toml: derivatives.x: 'v' is not a function (write v*(...) for a product)");
    EXPECT_EQ(message("x = \"v\"", "x = \"(v\""), "model file bad.toml: derivatives.x: unbalanced '(' in '(v'");
    EXPECT_EQ(message("x = \"v\"", "x = \"\""), "model file bad.toml: derivatives.x: empty expression");
    EXPECT_EQ(message("x = \"v\"", "x = [1]"),
              "model file bad.toml: derivatives.x: expected an expression (a string such as \"-r*v\", or a number), got an array");
    EXPECT_EQ(message("state = [\"x\", \"v\", \"phi\"]", "state = \"x\""), "model file bad.toml: state: expected an array, got a string");
    EXPECT_EQ(message("state = [\"x\", \"v\", \"phi\"]", "state = [\"x\", \"v\", \"phi\"]\ninitial_state = [1, 2]"),
              "model file bad.toml: initial_state: needs 3 numbers (x, v, phi), got 2");
    EXPECT_EQ(message("zeta = 0.05", "zeta = 1979-05-27"), "model file bad.toml: parameters.zeta: dates and times have no meaning in a model file");
    EXPECT_EQ(message("zeta = 0.05", "zeta = \"0.05\""),
              "model file bad.toml: parameters.zeta: expected a default value or a table {default, meaning, unit, min, max, above, "
              "below}, got a string");
    EXPECT_EQ(error_of(two_sided + "[presets]\nhigh = { rr = 0.5 }\n"),
              "model file bad.toml: presets.high.rr: 'rr' is not a parameter (parameters: zeta, a, w, d, r; or meaning = \"...\")");
    EXPECT_EQ(error_of(two_sided + "[presets]\nhigh = { r = 1.5 }\n"),
              "model file bad.toml: presets.high.r: 1.5 is outside the range of r ([0, 1])");
}

TEST(ModelFile, DerivedValueThatIsNotFiniteRefusesTheParameters)
{
    const std::string text = replaced(two_sided, "[derivatives]", "[derived]\ninv = \"1/(a - 1)\"\n[derivatives]");
    const auto code = compile_model_text(text, "derived.toml");
    try {
        (void)model::with_defaults(code);
        ADD_FAILURE() << "no error";
    } catch (const input_error& e) {
        EXPECT_EQ(std::string(e.what()), "model two_sided refuses its parameters: derived quantity inv = inf is not finite");
    }
    const model m(code, {0.05, 3.0, 1.2, 1.0, 0.8});  // a = 3: inv = 1/2
    EXPECT_EQ(m.parameter(1), 3.0);
}

// ---- (d) the cache: the same model is compiled once

namespace {

// A compiler that counts its runs and hands over to the real one.
fs::path counting_compiler(const fs::path& dir)
{
    const fs::path script = dir / "counting-c++";
    std::ofstream(script) << "#!/bin/sh\necho run >> '" << (dir / "runs").string() << "'\nexec c++ \"$@\"\n";
    ::chmod(script.c_str(), 0755);
    return script;
}

int runs(const fs::path& dir)
{
    std::ifstream in(dir / "runs");
    int n = 0;
    for (std::string line; std::getline(in, line);) ++n;
    return n;
}

}  // namespace

TEST(ModelFile, SecondLoadOfTheSameTextRunsNoCompiler)
{
    const fs::path dir = cache_environment::dir / "counting";
    fs::create_directories(dir);
    const scoped_env cxx("CXX", counting_compiler(dir).string());
    const std::string text = replaced(two_sided, "name = \"two_sided\"", "name = \"cached_once\"");
    const model first = model::from_toml(text, "first.toml");
    EXPECT_EQ(runs(dir), 1);
    fs::path so;
    for (const auto& e : fs::directory_iterator(cache_environment::dir))
        if (e.path().filename().string().starts_with("cached_once-") && e.path().extension() == ".so") so = e.path();
    ASSERT_FALSE(so.empty());
    const auto mtime = fs::last_write_time(so);
    // Other symbolic work in between must not change the generated source.
    (void)compile_model_text(nonlinear, "nonlinear.toml");
    const int after_other = runs(dir);
    const model second = model::from_toml(text, "second.toml");
    EXPECT_EQ(runs(dir), after_other);
    EXPECT_EQ(fs::last_write_time(so), mtime);
    EXPECT_EQ(first.info().identity, second.info().identity);
    EXPECT_EQ(second.info().source, "second.toml");
    EXPECT_TRUE(first == second);
}

namespace {
// Sums inside products and powers, in every position GiNaC may flip their sign.
const std::string tangled = R"toml(
name = "tangled"
state = ["a", "b", "c", "d"]
[parameters]
p = 1.5
q = -0.5
r = 2
[expressions]
s1 = "a - b + 2*c"
s2 = "q*d - p*a + 3"
s3 = "(a - c)*(b - d)*(c - a)"
[derivatives]
a = "p*s1*s2 - q*(b - a)^3 + (d - c)^(-1) + sin(r*(a - b))"
b = "s3/(1 + (a - d)^2) - (q - p)*(c - b)*sqrt(1 + (b - c)^2)"
c = "exp(-(a - b)*(c - d)) + cos(p*(d - a))*(b - a)^5 + (2*a - 4*b)*(6*c - 3*d)"
d = "(s1 - s2)^2*(s2 - s1)^3 + tanh(q*(b - a))/(r*(c - d) - 1)^2"
[[surfaces]]
name = "w"
gap = "(a - b)*(c - d) + 1"
reset = { a = "(b - a)*q", d = "-(c - d)^3" }
[[sections]]
name = "s"
when = "(a - b)*(d - c)"
direction = "up"
)toml";
}  // namespace

// The cache key hashes the headers the generated code's fused steps and lanes include (a changed stage
// code must compile a new entry): every header the compiler reads for that #include (-MM: all
// but the system ones) must be in the list it hashes. (The list may hold more: a header named
// under an #if the compiler skips.)
TEST(ModelFile, CacheKeyCoversEveryHeaderOfTheFusedSteps)
{
    const fs::path dir = cache_environment::dir / "includes";
    fs::create_directories(dir);
    const fs::path src = dir / "fused.cpp", deps = dir / "fused.d";
    std::ofstream(src) << "#include \"vimpact/integrate/fused_lanes.hpp\"\n";
    const fs::path include = fs::path(std::string(vimpact::source_include_dir()));
    const char* cxx = std::getenv("CXX");  // the compiler model files are built with
    const std::string command = std::string(cxx && *cxx ? cxx : "c++") + " -std=c++20 -MM -I'" + include.string() + "' -isystem '" +
                                std::string(vimpact::eigen_include_dir()) + "' -MF '" + deps.string() + "' '" +
                                src.string() + "'";
    ASSERT_EQ(std::system(command.c_str()), 0) << command;
    std::set<std::string> compiler;
    std::ifstream in(deps);
    for (std::string word; in >> word;) {
        const fs::path p = fs::path(word).lexically_normal();
        const std::string relative = p.lexically_relative(include).generic_string();
        if (p.is_absolute() && relative.starts_with("vimpact/")) compiler.insert(relative);
    }
    const auto hashed = model_file_detail::vimpact_includes(include, "vimpact/integrate/fused_lanes.hpp");
    ASSERT_TRUE(hashed.has_value());
    std::set<std::string> names;
    for (const auto& h : *hashed) {
        names.insert(h.name);
        EXPECT_FALSE(h.text.empty()) << h.name;
    }
    for (const auto& c : compiler) EXPECT_TRUE(names.count(c)) << c << " is read by the compiler but not hashed";
    EXPECT_GE(compiler.size(), 8U);  // fused_lanes, lanes, fused_step, runge_kutta, lane_ops, state, dense_output, dop853_tableau
    EXPECT_FALSE(model_file_detail::vimpact_includes(include, "vimpact/no_such_header.hpp").has_value());
}

// The scanner behind that list: quoted "vimpact/..." includes, with any spacing, depth first in
// the order written, each once (b.hpp includes a.hpp back); a name in a comment after an
// angle-bracket include is not one; a named header that is missing makes the list unusable.
TEST(ModelFile, IncludeScannerFollowsQuotedVimpactIncludesOnly)
{
    const fs::path dir = cache_environment::dir / "scanner";
    fs::create_directories(dir / "vimpact");
    std::ofstream(dir / "vimpact/a.hpp") << "#pragma once\n#include <vector> // \"vimpact/none.hpp\"\n"
                                            "#include \"vimpact/b.hpp\"\n  #  include   \"vimpact/c.hpp\"\n"
                                            "#include \"other/d.hpp\"\n";
    std::ofstream(dir / "vimpact/b.hpp") << "#include \"vimpact/a.hpp\"\n#include \"vimpact/c.hpp\"\n";
    std::ofstream(dir / "vimpact/c.hpp") << "int c;\n";
    const auto found = model_file_detail::vimpact_includes(dir, "vimpact/a.hpp");
    ASSERT_TRUE(found.has_value());
    std::vector<std::string> names;
    for (const auto& h : *found) names.push_back(h.name);
    EXPECT_EQ(names, (std::vector<std::string>{"vimpact/a.hpp", "vimpact/b.hpp", "vimpact/c.hpp"}));
    EXPECT_EQ(found->back().text, "int c;\n");
    std::ofstream(dir / "vimpact/c.hpp") << "#include \"vimpact/missing.hpp\"\n";
    EXPECT_FALSE(model_file_detail::vimpact_includes(dir, "vimpact/a.hpp").has_value());
}

// GiNaC's internal order changes with the addresses of a process: the test runs itself in
// fresh processes (as a child, with VIMPACT_TEST_CHILD_CACHE set, it only compiles).
TEST(ModelFile, GeneratedSourceIsTheSameInEveryProcess)
{
    if (const char* child = std::getenv("VIMPACT_TEST_CHILD_CACHE")) {
        const scoped_env cache("VIMPACT_CACHE_DIR", child);
        (void)compile_model_text(tangled, "tangled.toml");
        (void)model::from_file(source_dir + "/examples/models/wake_impact.toml");
        (void)model::from_file(source_dir + "/bench/models/wake_impact_natural.toml");  // hoisted parts
        return;
    }
    const fs::path dir = cache_environment::dir / "processes";
    fs::create_directories(dir);
    const std::string self = fs::read_symlink("/proc/self/exe").string();
    for (int run = 0; run < 3; ++run) {
        const std::string command = "VIMPACT_TEST_CHILD_CACHE='" + dir.string() + "' '" + self +
                                    "' --gtest_filter=ModelFile.GeneratedSourceIsTheSameInEveryProcess > /dev/null 2>&1";
        ASSERT_EQ(std::system(command.c_str()), 0) << command;
    }
    // The parent, after all the symbolic work of the other tests, makes the same source too.
    {
        const scoped_env cache("VIMPACT_CACHE_DIR", dir.string());
        (void)compile_model_text(tangled, "tangled.toml");
    }
    int sources = 0;
    for (const auto& e : fs::directory_iterator(dir)) sources += e.path().extension() == ".cpp" ? 1 : 0;
    EXPECT_EQ(sources, 3);
}

TEST(ModelFile, ConcurrentCompilationsOfTheSameModelAllSucceed)
{
    const std::string text = replaced(two_sided, "name = \"two_sided\"", "name = \"raced\"");
    std::vector<std::thread> threads;
    std::vector<std::string> identities(4), errors(4);
    for (std::size_t k = 0; k < 4; ++k)
        threads.emplace_back([&, k] {
            try {
                identities[k] = compile_model_text(text, "raced.toml")->info.identity;
            } catch (const std::exception& e) {
                errors[k] = e.what();
            }
        });
    for (auto& t : threads) t.join();
    for (std::size_t k = 0; k < 4; ++k) {
        EXPECT_EQ(errors[k], "");
        EXPECT_EQ(identities[k], identities[0]);
    }
    for (const auto& e : fs::directory_iterator(cache_environment::dir))
        EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos) << e.path();
}

// ---- (e) no compiler

TEST(ModelFile, MissingCompilerIsAClearError)
{
    const scoped_env cxx("CXX", "/nonexistent/bin/c++");
    const std::string text = replaced(two_sided, "name = \"two_sided\"", "name = \"no_compiler\"");
    EXPECT_EQ(error_of(text, "nocc.toml"),
              "model file nocc.toml needs a C++ compiler to be compiled to native code: none found "
              "(CXX=/nonexistent/bin/c++ is not an executable program; set CXX or install g++)");
}

TEST(ModelFile, CompilerFailureNamesTheKeptSource)
{
    const fs::path dir = cache_environment::dir / "failing";
    fs::create_directories(dir);
    const fs::path script = dir / "failing-c++";
    std::ofstream(script) << "#!/bin/sh\necho 'model.cpp:1:1: error: this compiler refuses everything' >&2\nexit 1\n";
    ::chmod(script.c_str(), 0755);
    const scoped_env cxx("CXX", script.string());
    const std::string text = replaced(two_sided, "name = \"two_sided\"", "name = \"refused\"");
    const std::string e = error_of(text, "refused.toml");
    EXPECT_TRUE(e.starts_with("model file refused.toml: the C++ compiler " + script.string() +
                              " failed (exit code 1): model.cpp:1:1: error: this compiler refuses everything "
                              "(the generated source is kept in "))
        << e;
    const std::string kept = e.substr(e.rfind("kept in ") + 8, e.size() - e.rfind("kept in ") - 9);
    EXPECT_TRUE(fs::exists(kept)) << kept;
    EXPECT_NE(read_text(kept).find("vimpact_model(void)"), std::string::npos);
}

// ---- (f) the JSON path

TEST(ModelFile, JsonDescriptionEqualsTheTomlFile)
{
    const auto json = nlohmann::ordered_json::parse(R"json({
        "name": "two_sided_impact_oscillator",
        "description": "a harmonically forced linear oscillator x'' + 2 zeta x' + x = a cos(phi), phi' = w, between rigid stops at x = -d and x = d",
        "state": [{"name": "x", "meaning": "displacement"},
                  {"name": "v", "meaning": "velocity"},
                  {"name": "phi", "meaning": "forcing phase", "unit": "rad"}],
        "initial_state": [0, 0, 0],
        "parameters": {
            "zeta": {"default": 0.05, "meaning": "damping ratio", "min": 0.0},
            "a": {"default": 1, "meaning": "forcing amplitude"},
            "w": {"meaning": "forcing frequency / natural frequency", "default": 1.2, "above": 0},
            "d": {"default": 1.0, "meaning": "half the clearance between the stops", "above": 0},
            "r": {"default": 0.8, "meaning": "coefficient of restitution", "min": 0, "max": 1.0}
        },
        "derivatives": {"phi": "w", "x": "v", "v": "-2*zeta*v - x + a*cos(phi)"},
        "angles": {"phi": "2*pi"},
        "surfaces": [
            {"name": "right", "meaning": "stop at x = d", "gap": "d - x", "reset": {"v": "-r*v"}},
            {"name": "left", "meaning": "stop at x = -d", "gap": "x + d", "reset": {"v": "-r*v"}}
        ],
        "sections": [{"name": "strobe", "direction": "up", "when": "sin(phi)",
                      "meaning": "once per forcing period: sin(phi) = 0, increasing (phi = 0 mod 2 pi)"}]
    })json");
    const model from_json(compile_model_json(json, "<dict>"), std::vector<double>{0.05, 1.0, 1.2, 1.0, 0.8});
    const model from_toml = model::from_file(source_dir + "/examples/models/two_sided_impact_oscillator.toml");
    EXPECT_EQ(from_json.info().identity, from_toml.info().identity);
    EXPECT_EQ(from_json.info().source, "<dict>");
    expect_same_info(from_json.info(), from_toml.info());
    const table_model<3> a(from_json.table(), from_json.context()), b(from_toml.table(), from_toml.context());
    std::mt19937 gen(14);
    for (int trial = 0; trial < 10; ++trial) {
        const vec<3> x = random_vec<3>(gen, 3.0), u = random_vec<3>(gen), w = random_vec<3>(gen);
        EXPECT_EQ(a.rhs(x), b.rhs(x));
        EXPECT_EQ(a.jacobian(x), b.jacobian(x));
        EXPECT_EQ(a.second_derivative(x, u, w), b.second_derivative(x, u, w));
        EXPECT_EQ(a.gap(1, x), b.gap(1, x));
        EXPECT_EQ(a.section_gradient(0, x), b.section_gradient(0, x));
    }
    // A .json file loads like a .toml file.
    const fs::path file = cache_environment::dir / "two_sided.json";
    std::ofstream(file) << json.dump(2);
    EXPECT_EQ(load_model_code(file)->info.identity, from_toml.info().identity);
    EXPECT_EQ(error_of("name = 3"), "model file bad.toml: name: expected a string, got a number");
    try {
        (void)compile_model_json(nlohmann::ordered_json::array(), "<dict>");
        ADD_FAILURE();
    } catch (const input_error& e) {
        EXPECT_TRUE(std::string(e.what()).starts_with("model file <dict>: expected a table of keys")) << e.what();
    }
}

// ---- (g) shared libraries exporting a C++ model

TEST(ModelFile, LibraryExportingACppDefinitionLoads)
{
    const fs::path dir = cache_environment::dir / "plugin";
    fs::create_directories(dir);
    const fs::path src = dir / "plugin.cpp", lib = dir / "libtwo_sided.so";
    std::ofstream(src) << "#include <vimpact/model/export.hpp>\n"
                          "#include <vimpact/model/builtin/two_sided_impact_oscillator.hpp>\n"
                          "VIMPACT_EXPORT_MODEL(vimpact::two_sided_impact_oscillator)\n";
    const std::string command = "c++ -std=c++20 -O1 -fPIC -shared -I'" + source_dir + "/include' -I/usr/include/eigen3 -o '" +
                                lib.string() + "' '" + src.string() + "'";
    ASSERT_EQ(std::system(command.c_str()), 0) << command;

    const auto code = load_model_library(lib);
    EXPECT_EQ(code->info.source, lib.string());
    EXPECT_TRUE(code->info.identity.starts_with("two_sided_impact_oscillator-")) << code->info.identity;
    EXPECT_NE(code->library, nullptr);
    const model plugin = model::with_defaults(code);
    const model builtin = model::builtin("two_sided_impact_oscillator");
    expect_same_info(plugin.info(), builtin.info());
    std::mt19937 gen(15);
    expect_same_functions<3>(plugin, builtin, gen, 3.0);
    // load_model_code and model::from_file dispatch on the extension; the same bytes have the same identity.
    EXPECT_EQ(model::from_file(lib).info().identity, code->info.identity);

    // A shared library without the entry point, and files that are neither.
    const fs::path empty_src = dir / "empty.cpp", empty = dir / "libempty.so";
    std::ofstream(empty_src) << "extern \"C\" int nothing_here() { return 0; }\n";
    ASSERT_EQ(std::system(("c++ -fPIC -shared -o '" + empty.string() + "' '" + empty_src.string() + "'").c_str()), 0);
    try {
        (void)load_model_code(empty);
        ADD_FAILURE();
    } catch (const input_error& e) {
        EXPECT_EQ(std::string(e.what()), "model library " + empty.string() +
                                             " does not export vimpact_model() (a C++ model library is built with "
                                             "VIMPACT_EXPORT_MODEL from vimpact/model/export.hpp)");
    }
    EXPECT_THROW((void)load_model_code(dir / "missing.toml"), input_error);
    EXPECT_THROW((void)load_model_code(src), input_error);

    // A library of another interface version (its fused step would return the error norm where
    // this version reads its square): refused, with the versions named.
    const fs::path old_src = dir / "old_abi.cpp", old_lib = dir / "libold_abi.so";
    std::ofstream(old_src) << "#include <vimpact/model/abi.h>\n"
                              "static vimpact_model_table table{VIMPACT_MODEL_ABI_VERSION - 1};\n"
                              "extern \"C\" const vimpact_model_table* vimpact_model() { return &table; }\n";
    ASSERT_EQ(std::system(("c++ -fPIC -shared -I'" + source_dir + "/include' -o '" + old_lib.string() + "' '" +
                           old_src.string() + "'")
                              .c_str()),
              0);
    try {
        (void)load_model_code(old_lib);
        ADD_FAILURE();
    } catch (const input_error& e) {
        EXPECT_EQ(std::string(e.what()), "model library " + old_lib.string() + " was built for model ABI version " +
                                             std::to_string(VIMPACT_MODEL_ABI_VERSION - 1) +
                                             "; this vimpact loads version " +
                                             std::to_string(VIMPACT_MODEL_ABI_VERSION) + " (rebuild it)");
    }
}

// ---- (h) bounds on what a file can make the compiler do

namespace {

// The two-sided oscillator under another name (a model of its own in the cache), with its
// forcing shifted by `shift`: rhs at the origin (phase 0) is (0, a + shift, w) = (0, 1 + shift, 1.2).
std::string shifted_model(const std::string& name, int shift)
{
    return replaced(replaced(two_sided, "name = \"two_sided\"", "name = \"" + name + "\""),
                    "v = \"-2*zeta*v - x + a*cos(phi)\"", "v = \"-2*zeta*v - x + a*cos(phi) + " + std::to_string(shift) + "\"");
}

// The error of `text` and how long it took to come.
std::pair<std::string, double> timed_error(const std::string& text)
{
    const auto start = std::chrono::steady_clock::now();
    std::string e = error_of(text);
    return {e, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()};
}

std::string nested(int depth, const std::string& inside)
{
    return std::string(static_cast<std::size_t>(depth), '(') + inside + std::string(static_cast<std::size_t>(depth), ')');
}

}  // namespace

// 8000 parentheses overflowed the stack of GiNaC's parser (SIGSEGV); the depth is bounded on
// the text, a named expression counting with its own depth where it is used.
TEST(ModelFile, NestingIsBoundedBeforeGinacReadsIt)
{
    const std::string deep = replaced(two_sided, "x = \"v\"", "x = \"" + nested(8000, "v") + "\"");
    const auto [e, seconds] = timed_error(deep);
    EXPECT_EQ(e, "model file bad.toml: derivatives.x: the expression nests more than " + std::to_string(model_file_detail::max_nesting) +
                     " levels deep (parentheses and calls); GiNaC reads and differentiates by recursion");
    EXPECT_LT(seconds, 3.0);
    // At the bound it is read: x' = v.
    const int limit = model_file_detail::max_nesting;
    const model at_limit = model::from_toml(replaced(shifted_model("nested", 0), "x = \"v\"", "x = \"" + nested(limit, "v") + "\""));
    EXPECT_EQ(table_model<3>(at_limit.table(), at_limit.context()).rhs(vec<3>(0.0, 2.5, 0.0))[0], 2.5);
    EXPECT_EQ(error_of(replaced(two_sided, "x = \"v\"", "x = \"" + nested(limit + 1, "v") + "\"")),
              "model file bad.toml: derivatives.x: the expression nests more than " + std::to_string(limit) +
                  " levels deep (parentheses and calls); GiNaC reads and differentiates by recursion");
    // A chain e1 = (e0 + x), e2 = (e1 + x), ...: each link 2 levels deeper, and its use in
    // x' = eN one more. At the bound (2 N + 1 = 249), x' = v + N x; with one link more x' is
    // refused, with two the link that crosses the bound.
    const auto chain = [&](int links) {
        std::string s = "[expressions]\ne0 = \"v\"\n";
        for (int i = 1; i <= links; ++i) s.append("e").append(std::to_string(i)).append(" = \"(e").append(std::to_string(i - 1)).append(" + x)\"\n");
        return replaced(replaced(shifted_model("chained", 0), "x = \"v\"", "x = \"e" + std::to_string(links) + "\""),
                        "[derivatives]", s + "[derivatives]");
    };
    const int links = (limit - 1) / 2;
    const model linked = model::from_toml(chain(links));
    EXPECT_EQ(table_model<3>(linked.table(), linked.context()).rhs(vec<3>(1.0, 0.5, 0.0))[0], 0.5 + links);
    const std::string deeper = ": the expression nests more than " + std::to_string(limit) +
                               " levels deep (with the named expressions it uses); GiNaC reads and differentiates by "
                               "recursion";
    EXPECT_EQ(error_of(chain(links + 1)), "model file bad.toml: derivatives.x" + deeper);
    EXPECT_EQ(error_of(chain(links + 2)), "model file bad.toml: expressions.e" + std::to_string(links + 2) + deeper);
}

// 2^(2^40)*x made GiNaC compute a number of 2^40 bits (memory grew to 6.5 GB); a constant's
// size is checked before GiNaC computes it, however it is reached.
TEST(ModelFile, ExactConstantsAreBoundedBeforeTheyAreComputed)
{
    const std::string message = ": an exact constant of the expression would have more than " +
                                std::to_string(model_file_detail::max_constant_bits) +
                                " bits (such as 2^(2^40)); constants are computed exactly before they are rounded to "
                                "doubles";
    for (const std::string& v : {std::string("2^(2^40)*x"), std::string("(sqrt(2)*v)^(2^40)"), std::string("((3/2)^(1/3))^(2^50)"),
                                 "x*1" + std::string(30000, '0')}) {
        const auto [e, seconds] = timed_error(replaced(two_sided, "x = \"v\"", "x = \"" + v + "\""));
        EXPECT_EQ(e, "model file bad.toml: derivatives.x" + message) << v;
        EXPECT_LT(seconds, 3.0) << v;
    }
    // Doubling through named expressions: c0 = (1 + 2^-1000)^30, about 1 as a double, is
    // exactly (2^1000 + 1)^30 / 2^30000, 60,031 bits; its square is refused.
    const std::string doubling = replaced(
        two_sided, "[derivatives]",
        "[expressions]\nc0 = \"(1 + 2^(-1000))^30\"\nc1 = \"c0*c0\"\nc2 = \"c1*c1\"\n[derivatives]");
    EXPECT_EQ(error_of(replaced(doubling, "x = \"v\"", "x = \"c2*v\"")), "model file bad.toml: expressions.c1" + message);
    // Constants as large as a double holds are fine: 2^1000 = 1.0715...e301.
    const model big = model::from_toml(replaced(shifted_model("big_constant", 0), "x = \"v\"", "x = \"2^1000*v/2^999\""));
    EXPECT_EQ(table_model<3>(big.table(), big.context()).rhs(vec<3>(0.0, 1.5, 0.0))[0], 3.0);
}

// A chain of named expressions that uses each link twice doubles the written-out code at each
// link (at 14 links the compiler was given 118 MB); the size of the code is bounded before
// the derivatives are taken.
TEST(ModelFile, GeneratedCodeIsBoundedBeforeItGrows)
{
    const auto chain = [&](int links) {
        std::string s = "[expressions]\ne0 = \"v + x\"\n";
        for (int i = 1; i <= links; ++i) {
            const std::string p = std::string("e").append(std::to_string(i - 1));
            s.append("e").append(std::to_string(i)).append(" = \"").append(p).append("^2 + sin(").append(p).append(") - x\"\n");
        }
        return replaced(replaced(two_sided, "x = \"v\"", "x = \"e" + std::to_string(links) + "\""), "[derivatives]",
                        s + "[derivatives]");
    };
    std::ostringstream limit;
    limit << model_file_detail::max_code_terms;
    for (const int links : {14, 40}) {
        const auto [e, seconds] = timed_error(chain(links));
        EXPECT_TRUE(e.starts_with("model file bad.toml: ")) << e;
        EXPECT_NE(e.find(" would make the generated code too large: more than " + limit.str() + " operations written out"),
                  std::string::npos)
            << e;
        EXPECT_LT(seconds, 10.0) << links;
    }
    // Far past the bound, the link that crosses it is named, as soon as it is read.
    EXPECT_TRUE(timed_error(chain(40)).first.starts_with("model file bad.toml: expressions.e"));
    // A short chain compiles.
    (void)compile_model_text(replaced(chain(3), "name = \"two_sided\"", "name = \"short_chain\""), "short.toml");
}

// A NUL in a string ended the C string the generated code holds: the meaning was cut short.
TEST(ModelFile, NulInAStringIsRefused)
{
    EXPECT_EQ(error_of(replaced(two_sided, "state = [\"x\", \"v\", \"phi\"]",
                                "state = [{ name = \"x\", meaning = \"dis\\u0000placement\" }, \"v\", \"phi\"]")),
              "model file bad.toml: state[0].meaning: the string contains a NUL character (\\u0000)");
    EXPECT_EQ(error_of(replaced(two_sided, "name = \"two_sided\"", "name = \"two_sided\"\ndescription = \"a\\u0000b\"")),
              "model file bad.toml: description: the string contains a NUL character (\\u0000)");
}

// ---- (i) the cache's safety: a private directory, entries checked before they are opened

namespace {

// A fresh cache directory, private (as one of ours would be), selected for one scope.
class scoped_cache {
public:
    explicit scoped_cache(const std::string& name) : m_dir(cache_environment::dir / name)
    {
        fs::remove_all(m_dir);
        fs::create_directories(m_dir);
        fs::permissions(m_dir, fs::perms::owner_all);
        m_env.emplace("VIMPACT_CACHE_DIR", m_dir.string());
    }
    const fs::path& dir() const { return m_dir; }

private:
    fs::path m_dir;
    std::optional<scoped_env> m_env;
};

// The files of the entries of model `name` in `dir` (NAME-KEY.so, .sha256, .cpp).
std::vector<fs::path> entry_files(const fs::path& dir, const std::string& name, const std::string& ext)
{
    std::vector<fs::path> found;
    for (const auto& e : fs::directory_iterator(dir)) {
        const std::string f = e.path().filename().string();
        if (f.starts_with(name + "-") && e.path().extension() == ext && f.find(".tmp-") == std::string::npos)
            found.push_back(e.path());
    }
    return found;
}

fs::path the_entry(const fs::path& dir, const std::string& name, const std::string& ext = ".so")
{
    const auto found = entry_files(dir, name, ext);
    EXPECT_EQ(found.size(), 1U) << name << ext;
    return found.empty() ? fs::path() : found.front();
}

// Compiles `text` in a child process, so that this process never maps the entry: the tests
// below damage it, which would break a mapping of their own (and a truncated mapped file
// raises SIGBUS in the process that reads it, which is the failure they guard against).
void compile_elsewhere(const std::string& text)
{
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        int code = 0;
        try {
            (void)compile_model_text(text, "child.toml");
        } catch (...) {
            code = 1;
        }
        ::_exit(code);
    }
    int status = 0;
    ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << status;
}

// Replaces a file by a copy of another (a new file renamed over it, as a cp to a temporary
// and mv would: the old file's bytes are never changed in place).
void replace_file(const fs::path& target, const fs::path& with)
{
    const fs::path tmp = target.string() + ".replacing";
    fs::copy_file(with, tmp, fs::copy_options::overwrite_existing);
    fs::permissions(tmp, fs::perms::owner_read | fs::perms::owner_write);
    fs::rename(tmp, target);
}

// A shared library whose constructor writes `marker`: what a planted library would run.
fs::path planted_library(const fs::path& dir, const fs::path& marker)
{
    const fs::path src = dir.parent_path() / (dir.filename().string() + "-planted.cpp");
    const fs::path lib = dir.parent_path() / (dir.filename().string() + "-planted.so");
    std::ofstream(src) << "#include <cstdio>\n"
                          "__attribute__((constructor)) static void planted() {\n"
                          "    if (FILE* f = std::fopen(\""
                       << marker.string()
                       << "\", \"w\")) { std::fputs(\"ran\", f); std::fclose(f); }\n}\n";
    const std::string command = "c++ -shared -fPIC -o '" + lib.string() + "' '" + src.string() + "'";
    EXPECT_EQ(std::system(command.c_str()), 0) << command;
    return lib;
}

double forcing_at_origin(const model& m)
{
    const table_model<3> t(m.table(), m.context());
    return t.rhs(vec<3>(0.0, 0.0, 0.0))[1];
}

bool no_temporaries(const fs::path& dir)
{
    for (const auto& e : fs::directory_iterator(dir))
        if (e.path().filename().string().find(".tmp-") != std::string::npos) return false;
    return true;
}

}  // namespace

// A library planted under an entry's name, with the entry's own record beside it or with
// another's, is never opened (its constructor would write the marker): the entry is compiled
// again and is the model it should be.
TEST(ModelCache, PlantedLibraryIsNeverLoaded)
{
    const std::string text = shifted_model("planted", 3);
    fs::path stem;
    {
        const scoped_cache cache("planted-first");
        compile_elsewhere(text);
        stem = the_entry(cache.dir(), "planted").stem();
    }
    const scoped_cache cache("planted");
    const fs::path marker = cache.dir().parent_path() / "planted-marker";
    fs::remove(marker);
    const fs::path lib = planted_library(cache.dir(), marker);
    // Planted before the model was ever compiled here, with a record of another library.
    replace_file(cache.dir() / (stem.string() + ".so"), lib);
    std::ofstream(cache.dir() / (stem.string() + ".sha256")) << "vimpact model cache entry\nkey " << stem.string().substr(8)
                                                               << "\nlibrary sha256 " << std::string(64, '0') << "\n";
    fs::permissions(cache.dir() / (stem.string() + ".sha256"), fs::perms::owner_read | fs::perms::owner_write);
    EXPECT_EQ(forcing_at_origin(model::from_toml(text, "planted.toml")), 4.0);
    EXPECT_FALSE(fs::exists(marker));
    // Planted over a good entry, whose record stays.
    const scoped_cache again("planted-again");
    compile_elsewhere(text);
    replace_file(the_entry(again.dir(), "planted"), lib);
    EXPECT_EQ(forcing_at_origin(model::from_toml(text, "planted.toml")), 4.0);
    EXPECT_FALSE(fs::exists(marker));
    EXPECT_TRUE(no_temporaries(again.dir()));
}

// A truncated entry (a full disk, an interrupted copy) crashed every process that loaded it
// with SIGBUS; now it fails its check and is compiled again.
TEST(ModelCache, TruncatedEntryIsCompiledAgain)
{
    const scoped_cache cache("truncated");
    const std::string text = shifted_model("truncated", 5);
    compile_elsewhere(text);
    const fs::path so = the_entry(cache.dir(), "truncated");
    const auto size = fs::file_size(so);
    fs::resize_file(so, size / 2);
    EXPECT_EQ(forcing_at_origin(model::from_toml(text, "truncated.toml")), 6.0);
    EXPECT_EQ(fs::file_size(the_entry(cache.dir(), "truncated")), size);
}

// A model loaded twice, the second time from the cache through a descriptor of another number
// (the dynamic loader then keeps that descriptor's /proc/self/fd name as an alias of the
// library), then other models, each loaded from a descriptor of that same number: each is
// itself, not the first model again (which a Python session met as a model file that ran
// with another model's equations). Every entry is compiled in a child first, so that each
// load here is a cache hit opening the same descriptors, one number up while `shift` holds
// the lowest free one.
TEST(ModelCache, ModelsLoadedAfterAnAliasedOneAreThemselves)
{
    const scoped_cache cache("aliases");
    const std::string first = shifted_model("aliased", 1);
    compile_elsewhere(first);
    for (int k = 0; k < 4; ++k) compile_elsewhere(shifted_model("after_" + std::to_string(k), 100 + k));
    struct shift {
        int fd = ::open("/dev/null", O_RDONLY | O_CLOEXEC);
        ~shift() { ::close(fd); }
    };
    const model a = model::from_toml(first, "aliased.toml");
    {
        const shift s;
        EXPECT_EQ(forcing_at_origin(model::from_toml(first, "aliased.toml")), 2.0);
    }
    for (int k = 0; k < 4; ++k) {
        const shift s;
        const std::string name = "after_" + std::to_string(k);
        EXPECT_EQ(forcing_at_origin(model::from_toml(shifted_model(name, 100 + k), name + ".toml")), 101.0 + k) << name;
    }
    EXPECT_EQ(forcing_at_origin(a), 2.0);
}

// Another model's entry copied over this one's (the library alone, or with its record) is not
// loaded in its place: the model is this one, as compiled in a fresh cache.
TEST(ModelCache, EntryCopiedOverAnotherModelIsCompiledAgain)
{
    const std::string a = shifted_model("copied_a", 10), b = shifted_model("copied_b", 20);
    for (const bool with_record : {false, true}) {
        const scoped_cache cache(with_record ? "copied-with-record" : "copied");
        compile_elsewhere(a);
        compile_elsewhere(b);
        replace_file(the_entry(cache.dir(), "copied_b"), the_entry(cache.dir(), "copied_a"));
        if (with_record)
            replace_file(the_entry(cache.dir(), "copied_b", ".sha256"), the_entry(cache.dir(), "copied_a", ".sha256"));
        const model m = model::from_toml(b, "b.toml");
        EXPECT_EQ(forcing_at_origin(m), 21.0) << with_record;
        const scoped_cache fresh(with_record ? "copied-fresh-2" : "copied-fresh");
        const model reference = model::from_toml(b, "b.toml");
        const table_model<3> t(m.table(), m.context()), r(reference.table(), reference.context());
        std::mt19937 gen(37);
        for (int trial = 0; trial < 10; ++trial) {
            const vec<3> x = random_vec<3>(gen, 3.0);
            EXPECT_EQ(t.rhs(x), r.rhs(x));
        }
    }
}

// Where others may write, a library could be planted: a cache directory writable by its
// group or by all is refused, naming it, before anything in it is opened.
TEST(ModelCache, DirectoryWritableByOthersIsRefused)
{
    for (const auto mode : {fs::perms::owner_all | fs::perms::group_all | fs::perms::others_all,
                            fs::perms::owner_all | fs::perms::group_all}) {
        const scoped_cache cache("shared");
        fs::permissions(cache.dir(), mode);
        const std::string e = error_of(shifted_model("shared", 1), "shared.toml");
        const std::string mode_text = mode == (fs::perms::owner_all | fs::perms::group_all) ? "0770" : "0777";
        EXPECT_EQ(e, "model file shared.toml: the model cache directory " + cache.dir().string() +
                         " is writable by other users (mode " + mode_text +
                         "), who could plant code in it: make it private (chmod 700 " + cache.dir().string() +
                         ") or set VIMPACT_CACHE_DIR");
        EXPECT_TRUE(entry_files(cache.dir(), "shared", ".so").empty());
    }
}

// An entry of another user (only root can make one here) and a link in place of an entry are
// refused, naming them; so is a cache directory of another user.
TEST(ModelCache, EntryOfAnotherUserOrALinkIsRefused)
{
    const std::string text = shifted_model("foreign", 2);
    {
        const scoped_cache cache("link");
        compile_elsewhere(text);
        const fs::path so = the_entry(cache.dir(), "foreign");
        const fs::path real = cache.dir().parent_path() / "link-target.so";
        fs::rename(so, real);
        fs::create_symlink(real, so);
        EXPECT_EQ(error_of(text, "foreign.toml"),
                  "model file foreign.toml: the model cache entry " + so.string() +
                      " is a symbolic link, so it is not loaded: remove it (the cache holds only your own files)");
    }
    if (::geteuid() != 0) GTEST_SKIP() << "only root can give a file to another user";
    const scoped_cache cache("foreign");
    compile_elsewhere(text);
    const fs::path so = the_entry(cache.dir(), "foreign");
    ASSERT_EQ(::chown(so.c_str(), 65534, 65534), 0);
    EXPECT_EQ(error_of(text, "foreign.toml"),
              "model file foreign.toml: the model cache entry " + so.string() +
                  " belongs to another user (uid 65534), so it is not loaded: remove it (the cache holds only your "
                  "own files)");
    ASSERT_EQ(::chown(cache.dir().c_str(), 65534, 65534), 0);
    EXPECT_EQ(error_of(text, "foreign.toml"),
              "model file foreign.toml: the model cache directory " + cache.dir().string() +
                  " belongs to another user (uid 65534), who could plant code in it: use a directory of your own (set "
                  "VIMPACT_CACHE_DIR)");
}

// What the cache creates is private: the directory (and a missing parent) 0700, the source,
// the library and its record 0600, whatever the umask.
TEST(ModelCache, WhatTheCacheCreatesIsPrivate)
{
    const fs::path parent = cache_environment::dir / "private-parent";
    fs::remove_all(parent);
    const fs::path dir = parent / "cache";
    const scoped_env env("VIMPACT_CACHE_DIR", dir.string());
    const mode_t old_umask = ::umask(0);
    (void)compile_model_text(shifted_model("private", 4), "private.toml");
    ::umask(old_umask);
    const auto mode = [](const fs::path& p) {
        struct stat st {};
        EXPECT_EQ(::lstat(p.c_str(), &st), 0) << p;
        return st.st_mode & 07777;
    };
    EXPECT_EQ(mode(parent), 0700U);
    EXPECT_EQ(mode(dir), 0700U);
    for (const char* ext : {".so", ".sha256", ".cpp"}) EXPECT_EQ(mode(the_entry(dir, "private", ext)), 0600U) << ext;
}

// A relative cache directory is one directory wherever it is used, and its name reaches the
// compiler as no option: VIMPACT_CACHE_DIR=-odd gave the compiler "-odd/NAME.cpp", which it
// took for an option.
TEST(ModelCache, RelativeDirectoryThatLooksLikeAnOption)
{
    const fs::path cwd = cache_environment::dir / "odd-cwd";
    fs::remove_all(cwd);
    fs::create_directories(cwd);
    const fs::path old = fs::current_path();
    fs::current_path(cwd);
    std::string error;
    double forcing = 0.0;
    try {
        const scoped_env env("VIMPACT_CACHE_DIR", "-odd");
        forcing = forcing_at_origin(model::from_toml(shifted_model("odd", 6), "odd.toml"));
    } catch (const std::exception& e) {
        error = e.what();
    }
    fs::current_path(old);
    EXPECT_EQ(error, "");
    EXPECT_EQ(forcing, 7.0);
    EXPECT_EQ(entry_files(cwd / "-odd", "odd", ".so").size(), 1U);
}

// A compiler that writes something else than a shared library is named as such (this said
// "file too short", dlopen's word for it).
TEST(ModelCache, CompilerOutputThatIsNoLibraryIsNamed)
{
    const scoped_cache cache("garbage");
    const fs::path script = cache.dir().parent_path() / "garbage-c++";
    std::ofstream(script) << "#!/bin/sh\nwhile [ $# -gt 0 ]; do\n  if [ \"$1\" = -o ]; then shift; echo garbage > \"$1\"; fi\n"
                             "  shift\ndone\nexit 0\n";
    ::chmod(script.c_str(), 0755);
    const scoped_env cxx("CXX", script.string());
    EXPECT_EQ(error_of(shifted_model("garbage", 1), "garbage.toml"),
              "model file garbage.toml: the C++ compiler " + script.string() +
                  " did not produce a loadable shared library (it wrote a file that is not an ELF shared object; "
                  "CXX selects the compiler)");
    EXPECT_TRUE(no_temporaries(cache.dir()));
    EXPECT_TRUE(entry_files(cache.dir(), "garbage", ".so").empty());
}

// ---- (j) stopping a compilation

namespace {

// Whether a process runs (a zombie has ended).
bool process_runs(pid_t pid)
{
    std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
    std::string line;
    if (!std::getline(stat, line)) return false;
    const auto close_paren = line.rfind(')');
    return close_paren != std::string::npos && close_paren + 2 < line.size() && line[close_paren + 2] != 'Z';
}

// A compiler that writes its pid to `pid_file` and sleeps (as a child, in its process group).
fs::path sleeping_compiler(const fs::path& dir, const fs::path& pid_file)
{
    const fs::path script = dir / "sleeping-c++";
    std::ofstream(script) << "#!/bin/sh\necho $$ > '" << pid_file.string() << ".tmp'\nmv '" << pid_file.string() << ".tmp' '"
                          << pid_file.string() << "'\nsleep 60\n";
    ::chmod(script.c_str(), 0755);
    return script;
}

pid_t wait_for_pid(const fs::path& pid_file)
{
    for (int i = 0; i < 6000 && !fs::exists(pid_file); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    pid_t pid = 0;
    std::ifstream(pid_file) >> pid;
    return pid;
}

}  // namespace

// The cancel flag stops a compilation at once: the compiler is ended (its children too) and
// reaped, the temporaries are removed, and `cancelled` is thrown.
TEST(ModelCache, CancelStopsTheCompilerAtOnce)
{
    const scoped_cache cache("cancel");
    const fs::path pid_file = cache.dir().parent_path() / "cancel.pid";
    fs::remove(pid_file);
    const scoped_env cxx("CXX", sleeping_compiler(cache.dir().parent_path(), pid_file).string());
    std::atomic<bool> cancel{false};
    std::string outcome;
    std::thread work([&] {
        try {
            (void)compile_model_text(shifted_model("cancelled", 1), "cancelled.toml", &cancel);
            outcome = "loaded";
        } catch (const cancelled&) {
            outcome = "cancelled";
        } catch (const std::exception& e) {
            outcome = e.what();
        }
    });
    const pid_t compiler = wait_for_pid(pid_file);
    ASSERT_GT(compiler, 0);
    EXPECT_TRUE(process_runs(compiler));
    const auto start = std::chrono::steady_clock::now();
    cancel = true;
    work.join();
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_EQ(outcome, "cancelled");
    EXPECT_LT(seconds, 2.0);
    EXPECT_FALSE(process_runs(compiler));
    std::vector<std::string> left;
    for (const auto& e : fs::directory_iterator(cache.dir())) left.push_back(e.path().filename().string());
    EXPECT_TRUE(left.empty()) << left.front();
}

// The compiler dies with its caller, even one killed by SIGKILL; the temporaries that caller
// could not remove are removed by the next compilation.
TEST(ModelCache, CompilerDiesWithItsCaller)
{
    const scoped_cache cache("orphan");
    const fs::path pid_file = cache.dir().parent_path() / "orphan.pid";
    fs::remove(pid_file);
    const pid_t caller = ::fork();
    ASSERT_GE(caller, 0);
    if (caller == 0) {
        ::setenv("CXX", sleeping_compiler(cache.dir().parent_path(), pid_file).c_str(), 1);
        try {
            (void)compile_model_text(shifted_model("orphan", 1), "orphan.toml");
        } catch (...) {
        }
        ::_exit(0);
    }
    const pid_t compiler = wait_for_pid(pid_file);
    ASSERT_GT(compiler, 0);
    ::kill(caller, SIGKILL);
    int status = 0;
    ::waitpid(caller, &status, 0);
    bool runs = true;
    for (int i = 0; i < 200 && runs; ++i) {
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
        runs = process_runs(compiler);
    }
    EXPECT_FALSE(runs);
    EXPECT_FALSE(no_temporaries(cache.dir()));  // the killed caller's source
    (void)compile_model_text(shifted_model("after_orphan", 1), "after.toml");
    EXPECT_TRUE(no_temporaries(cache.dir()));
}

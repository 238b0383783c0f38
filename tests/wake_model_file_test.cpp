// The paper's model written as a model file (examples/models/wake_impact.toml), compiled to
// native code and run through the function table, against the built-in wake_impact and the
// paper: the grazing value of sigma at Ur = 25, the period labels of the paper's protocol,
// and Floquet multipliers. The file's equations are the built-in's; only the order of some
// floating-point operations may differ, so results agree to round-off amplified by the
// dynamics, and the labels exactly.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdio>
#include <string>

#include "example_models.hpp"
#include "test_support.hpp"
#include "vimpact/analysis/floquet.hpp"
#include "vimpact/analysis/grazing.hpp"
#include "vimpact/analysis/period.hpp"
#include "vimpact/analysis/protocol.hpp"

namespace {

using vimpact::model;
using vimpact::outcome;
using vimpact::test::paper_ic;
using vimpact::test::with;

model wake_file() { return vimpact::test::example_model("wake_impact"); }

// The file's model at Ur and sigma (its defaults are the paper preset).
model paper_file(double Ur, double sigma = -0.150298) { return with(with(wake_file(), "Ur", Ur), "sigma", sigma); }

}  // namespace

TEST(WakeModelFile, IsTheCompiledFileNotTheBuiltIn)
{
    const model m = wake_file();
    EXPECT_EQ(m.native(), vimpact::native_kind::none);
    EXPECT_EQ(m.dim(), 4);
    EXPECT_TRUE(m.info().surfaces.at(0).sticks);
    EXPECT_EQ(m.parameters(), model{}.parameters());  // the paper preset as defaults
}

// The paper's grazing value at Ur = 25: -0.150298 to its six printed digits, and the
// built-in's to round-off.
TEST(WakeModelFile, GrazingValueAtUr25IsThePapers)
{
    vimpact::grazing_options o;
    o.parameter = wake_file().info().parameter_index("sigma");
    const auto file = vimpact::grazing(paper_file(25.0), paper_ic(), o);
    const auto builtin = vimpact::grazing(vimpact::test::paper(25.0), paper_ic(), o);
    ASSERT_EQ(file.status, outcome::ok);
    ASSERT_TRUE(file.converged);
    ASSERT_TRUE(builtin.converged);
    const double f = file.surfaces.at(0).parameter_value, b = builtin.surfaces.at(0).parameter_value;
    EXPECT_NEAR(f, -0.150298, 5e-7);
    EXPECT_NEAR(f, b, 1e-12);
    std::printf("[ measured ] grazing sigma at Ur = 25: model file %.12f, built-in %.12f (difference %.1e)\n", f, b,
                f - b);
}

// The paper's labels (Fig. 2): P2 at Ur = 14.9 (from the paper's initial state; P1 coexists)
// and 16, P3 at 19, P4 at 21.5, with the default protocol (500 transient impacts, 200 maxima),
// the same from the file as from the built-in. The step counts of the two runs at Ur = 16 are
// printed for the benchmark (the same integrator on the same equations: equal or nearly).
TEST(WakeModelFile, PeriodLabelsAreThePapers)
{
    const vimpact::protocol_options opt;
    struct expectation {
        double Ur;
        const char* label;
    };
    for (const auto& e : {expectation{14.9, "P2"}, expectation{16.0, "P2"}, expectation{19.0, "P3"},
                          expectation{21.5, "P4"}}) {
        const auto file = vimpact::run_and_classify(paper_file(e.Ur), paper_ic(), opt, 1e-8);
        const auto builtin = vimpact::run_and_classify(vimpact::test::paper(e.Ur), paper_ic(), opt, 1e-8);
        ASSERT_EQ(file.run.status, outcome::ok) << "Ur " << e.Ur;
        EXPECT_EQ(file.label.label, e.label) << "Ur " << e.Ur;
        EXPECT_EQ(builtin.label.label, e.label) << "Ur " << e.Ur;
        EXPECT_EQ(file.label.impacts_per_period, builtin.label.impacts_per_period) << "Ur " << e.Ur;
        if (e.Ur == 16.0) {
            const long sf = file.run.stats.steps, sb = builtin.run.stats.steps;
            std::printf("[ measured ] Ur = 16, default protocol: model file %ld steps (%ld rejected, %ld rhs calls), "
                        "built-in %ld steps (%ld rejected, %ld rhs calls)\n",
                        sf, file.run.stats.rejected, file.run.stats.rhs_calls, sb, builtin.run.stats.rejected,
                        builtin.run.stats.rhs_calls);
            EXPECT_LE(std::abs(sf - sb), sb / 100) << "the same equations should take the same steps";
        }
    }
}

// Floquet multipliers at Ur = 16 (P2) and Ur = 14.9 (P2 from the paper's start): the file's
// within 1e-10 of the built-in's.
TEST(WakeModelFile, FloquetMultipliersEqualTheBuiltIns)
{
    for (double Ur : {16.0, 14.9}) {
        const auto file = vimpact::floquet(paper_file(Ur), paper_ic(), {});
        const auto builtin = vimpact::floquet(vimpact::test::paper(Ur), paper_ic(), {});
        ASSERT_EQ(file.status, outcome::ok) << "Ur " << Ur;
        ASSERT_EQ(builtin.status, outcome::ok) << "Ur " << Ur;
        EXPECT_EQ(file.label, builtin.label);
        ASSERT_EQ(file.multipliers.size(), 4u);
        ASSERT_EQ(builtin.multipliers.size(), 4u);
        double worst = 0.0;
        for (std::size_t i = 0; i < 4; ++i) worst = std::max(worst, std::abs(file.multipliers[i] - builtin.multipliers[i]));
        EXPECT_LE(worst, 1e-10) << "Ur " << Ur;
        EXPECT_LE(file.trivial_error, 1e-9) << "Ur " << Ur;
        EXPECT_NEAR(file.period, builtin.period, 1e-10) << "Ur " << Ur;
        std::printf("[ measured ] Ur = %g %s: model file multipliers within %.1e of the built-in's; |mu_trivial - 1| "
                    "= %.1e (file), %.1e (built-in)\n",
                    Ur, file.label.c_str(), worst, file.trivial_error, builtin.trivial_error);
    }
}

// The columns front ends write states and impacts under, and the output-target check that
// runs before any work.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "vimpact/core/input_error.hpp"
#include "vimpact/io/staged_output.hpp"
#include "vimpact/io/state_columns.hpp"

using namespace vimpact;
namespace fs = std::filesystem;

namespace {

std::vector<std::string> names(const std::vector<impact_column>& cols)
{
    std::vector<std::string> out;
    for (const auto& c : cols) out.push_back(c.name);
    return out;
}

}  // namespace

// A reset that puts the state on the surface (y -> sigma) leaves that variable as it was at the
// impact; the velocity it reverses gets a column before and after.
TEST(StateColumns, ImpactColumnsSplitWhatTheResetChanges)
{
    const model wake;
    EXPECT_EQ(state_columns(wake.info()), (std::vector<std::string>{"y", "ydot", "x", "xdot"}));
    const auto w = impact_columns(wake);
    EXPECT_EQ(names(w), (std::vector<std::string>{"y", "ydot_before", "ydot_after", "x", "xdot"}));
    EXPECT_EQ(w[1].variable, 1);
    EXPECT_FALSE(w[1].after);
    EXPECT_EQ(w[2].variable, 1);
    EXPECT_TRUE(w[2].after);
    EXPECT_EQ(names(impact_columns(model::builtin("two_sided_impact_oscillator"))),
              (std::vector<std::string>{"x", "v_before", "v_after", "phi"}));
    EXPECT_EQ(names(impact_columns(model::builtin("forced_impact_oscillator"))),
              (std::vector<std::string>{"y", "ydot_before", "ydot_after", "theta"}));
}

TEST(OutputTarget, RefusedBeforeAnythingIsCreated)
{
    const fs::path dir = fs::temp_directory_path() / ("vimpact_target_test_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    const fs::path file = dir / "file";
    std::ofstream(file) << "x\n";
    EXPECT_THROW(check_output_target(file), input_error);
    EXPECT_THROW(check_output_target(file / "sub" / "run"), input_error);
    EXPECT_NO_THROW(check_output_target(dir / "new" / "deeper" / "run"));
    EXPECT_NO_THROW(check_output_target(dir));
    EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);  // only the file
    try {
        check_output_target(file);
    } catch (const input_error& e) {
        EXPECT_NE(std::string(e.what()).find("not a directory"), std::string::npos) << e.what();
    }
    fs::remove_all(dir);
}

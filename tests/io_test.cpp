// Output primitives: numbers round-trip through text bit for bit; staged output is all or
// nothing.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

#include "vimpact/core/format.hpp"
#include "vimpact/io/csv_writer.hpp"
#include "vimpact/io/staged_output.hpp"

namespace fs = std::filesystem;

TEST(Format, ShortestRoundTripIsExact)
{
    std::mt19937_64 rng(42);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int i = 0; i < 10000; ++i) {
        const double x = u(rng) * std::pow(10.0, static_cast<int>(rng() % 40) - 20);
        EXPECT_EQ(std::stod(vimpact::format_double(x)), x);
    }
}

TEST(StagedOutput, NothingAppearsWithoutCommit)
{
    const fs::path dir = fs::temp_directory_path() / "vimpact_staged_test_a";
    fs::remove_all(dir);
    {
        vimpact::staged_output out(dir);
        vimpact::csv_writer w(out.file("a.csv"), {"x"});
        w.row({1.0});
        w.close();
        EXPECT_TRUE(fs::exists(out.staging_dir() / "a.csv"));
    }
    EXPECT_FALSE(fs::exists(dir));
    for (const auto& e : fs::directory_iterator(fs::temp_directory_path()))
        EXPECT_EQ(e.path().filename().string().find(".vimpact-staging-vimpact_staged_test_a"), std::string::npos);
}

TEST(StagedOutput, CommitMovesFilesIntoExistingDirectory)
{
    const fs::path dir = fs::temp_directory_path() / "vimpact_staged_test_b";
    fs::remove_all(dir);
    fs::create_directories(dir);
    std::ofstream(dir / "keep.txt") << "old";
    {
        vimpact::staged_output out(dir);
        vimpact::csv_writer w(out.file("a.csv"), {"x", "y"});
        w.row({0.1, 2.0});
        w.close();
        out.commit();
    }
    EXPECT_TRUE(fs::exists(dir / "a.csv"));
    EXPECT_TRUE(fs::exists(dir / "keep.txt"));
    std::ifstream in(dir / "a.csv");
    std::string header, row;
    std::getline(in, header);
    std::getline(in, row);
    EXPECT_EQ(header, "x,y");
    EXPECT_EQ(row, "0.1,2");
    fs::remove_all(dir);
}

// Output primitives: numbers round-trip through text bit for bit; staged output is all or
// nothing.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <numbers>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "io/json_codec.hpp"
#include "io/json_line.hpp"
#include "vimpact/core/format.hpp"
#include "vimpact/io/csv_writer.hpp"
#include "vimpact/io/model_info_json.hpp"
#include "vimpact/io/staged_output.hpp"
#include "vimpact/model/model.hpp"

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

// Journal lines are read by simdjson into the value nlohmann's own parser gives: the same
// types (non-negative integers unsigned, negative signed, other numbers doubles), the same
// digits (every double correctly rounded) and the same text when written again.
TEST(JsonLine, ReadsWhatNlohmannReads)
{
    const std::vector<std::string> lines = {
        R"({"job":1,"record":{"grazing":[],"label":{"closure":9.992007221626409e-15,"impacts":1,"label":"P2","settled":true},"statistics":{"values":[9.0,150.46680647601897,"nan",-0.0,6.322403519779272e-06,1e-300,4.9e-324,1.7976931348623157e308]},"status":"ok","steps":7048}})",
        R"([-9223372036854775808,18446744073709551615,0,-1,1.0,0.1,2.5e-8,"a\"b\\c\u00e9\n",null,false,{"":{}},[[],[[]]]])",
        R"({"z":1,"a":2,"m":{"k":[1,2,3]}})",
        "  3.141592653589793  ",
    };
    for (const auto& line : lines) {
        const auto fast = vimpact::detail::try_parse_json_line(line);
        ASSERT_TRUE(fast.has_value()) << line;
        const auto slow = nlohmann::json::parse(line);
        EXPECT_EQ(*fast, slow) << line;
        EXPECT_EQ(fast->dump(), slow.dump()) << line;
        std::function<void(const nlohmann::json&, const nlohmann::json&)> same_types = [&](const auto& a, const auto& b) {
            ASSERT_EQ(a.type(), b.type()) << a.dump() << " in " << line;
            if (a.is_structured())
                for (auto i = a.begin(), j = b.begin(); i != a.end(); ++i, ++j) same_types(*i, *j);
        };
        same_types(*fast, slow);
    }
    for (const std::string bad : {"", "{", R"({"job":1,})", "[1 2]", "nan", "{} {}"}) {
        EXPECT_FALSE(vimpact::detail::try_parse_json_line(bad).has_value()) << bad;
        EXPECT_THROW((void)vimpact::detail::parse_json_line(bad), std::runtime_error) << bad;
    }
}

// A job journal's spec records the hold band the run uses (integrator_options::hold_band):
// DOPRI5's default band appears, so a journal written before DOPRI5 held by default (no band
// in its spec) is not resumed with it; a band of 0 is not written, as before the option.
TEST(JsonCodec, ProtocolSpecRecordsTheHoldBandTheRunUses)
{
    using vimpact::integration_method;
    vimpact::protocol_options o;
    const auto band = [&o]() -> std::optional<double> {
        const auto j = vimpact::detail::to_json(o)["flow"]["integration"];
        if (!j.contains("hold_band")) return std::nullopt;
        return j["hold_band"].get<double>();
    };
    o.method = integration_method::dopri5;
    EXPECT_EQ(band(), 0.1);
    o.flow.integration.hold_band = 0.0;
    EXPECT_EQ(band(), std::nullopt);
    o.flow.integration.hold_band = 0.3;
    EXPECT_EQ(band(), 0.3);
    o.method = integration_method::dop853;
    EXPECT_EQ(band(), 0.3);
    o.flow.integration.hold_band.reset();
    EXPECT_EQ(band(), std::nullopt);
}

namespace vimpact {

// What the models declare, as docs/model.md documents them: the
// forced impact oscillator's state y, ydot and its forcing phase theta (period 2 pi), its
// restitution coefficient r in [0, 1] and frequency omega > 0; the wake model's start
// (0, 0, 0, 0.1) and Facchinetti's lift coefficient CL0 = 0.3 in its preset.
TEST(ModelInfoJson, SaysWhatTheModelsDeclare)
{
    const auto j = model_info_json(model::builtin("forced_impact_oscillator").info());
    ASSERT_EQ(j.at("state").size(), 3u);
    EXPECT_EQ(j["state"][2]["name"], "theta");
    EXPECT_DOUBLE_EQ(j["state"][2]["period"].get<double>(), 2 * std::numbers::pi);
    EXPECT_TRUE(j["state"][0]["period"].is_null());
    const auto parameter = [&](const std::string& name) {
        for (const auto& p : j.at("parameters"))
            if (p.at("name") == name) return p;
        ADD_FAILURE() << name;
        return nlohmann::json();
    };
    const auto r = parameter("r").at("range");
    EXPECT_EQ(r["lower"], 0.0);
    EXPECT_EQ(r["upper"], 1.0);
    EXPECT_TRUE(r["lower_inclusive"].get<bool>() && r["upper_inclusive"].get<bool>());
    EXPECT_EQ(r["text"], "[0, 1]");
    const auto omega = parameter("omega").at("range");
    EXPECT_FALSE(omega["lower_inclusive"].get<bool>());
    EXPECT_TRUE(omega["upper"].is_null());  // no upper bound: JSON has no infinity

    const model w = model::builtin("wake_impact");
    const auto jw = model_info_json(w.info());
    EXPECT_EQ(jw.at("initial_state"), nlohmann::json({0.0, 0.0, 0.0, 0.1}));
    ASSERT_EQ(jw.at("presets").size(), 2u);
    EXPECT_EQ(jw["presets"][1]["name"], "facchinetti");
    EXPECT_EQ(jw["presets"][1]["values"], nlohmann::json({{"CL0", 0.3}}));
    EXPECT_EQ(w.with_preset(1).parameter(w.info().parameter_index("CL0")), 0.3);
}

}  // namespace vimpact

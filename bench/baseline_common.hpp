// What the standalone C++ baselines of the work-precision diagram share (bench/baseline_plain.cpp,
// bench/baseline_odeint.cpp, bench/baseline_sundials.cpp): the paper preset, the two runs
// (the protocol, or every section point up to a fixed horizon), the command line and the
// output. Standard library only; the baselines do not use vimpact.
//
// Common options:
//   --ur U          reduced velocity (default 16)
//   --tol T         rtol = atol (default 1e-10)
//   --horizon H     record every section point with t <= H from t = 0 (no transient)
//                   instead of the protocol (discard 500 impacts, record 200 maxima)
//   --points FILE   write the recorded section points as CSV: t,y,v,x,w (%.17g)
//   --repeat N      run N times, report the median wall time
// Prints one JSON line: name, wall_s (median), wall_all, cpu_s (median of the process CPU time of
// each run: what a loaded machine does not inflate), steps, rejected, rhs_calls, impacts, points.
#pragma once
#include <algorithm>
#include <array>
#include <chrono>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace baseline {

// ---- paper preset ------------------------------------------------------------
constexpr double St = 0.2;
constexpr double xi = 0.0052;
constexpr double gamma_ = 0.8;
constexpr double mu = 1.19381;
constexpr double eps = 0.3;
constexpr double A = 12.0;
constexpr double bisect_tol = 1e-14;

struct problem {
    double ur = 16.0;
    double sigma = -0.150298;
    double r = 0.8;
    double tol = 1e-10;
    double horizon = 0.0;  // > 0: every section point with t <= horizon; 0: the protocol
    long discard_impacts = 500;
    std::size_t n_points = 200;
    std::string points_file;
    int repeat = 1;

    [[nodiscard]] double t_end() const { return horizon > 0.0 ? horizon : 1e9; }
    [[nodiscard]] double delta() const { return 1.0 / (St * ur); }
    [[nodiscard]] double alpha() const { return 2.0 * xi * delta() + gamma_ / mu; }
    [[nodiscard]] double M() const { return 0.05 / mu; }
};

struct section_point {
    double t;
    std::array<double, 4> X;
};

struct run_result {
    double wall_s = 0.0;
    long steps = 0;
    long rejected = 0;
    long rhs_calls = 0;
    long impacts = 0;
    std::vector<section_point> points;

    [[nodiscard]] bool recording(const problem& p) const { return p.horizon > 0.0 || impacts >= p.discard_impacts; }
    [[nodiscard]] bool done(const problem& p) const { return p.horizon <= 0.0 && points.size() >= p.n_points; }
};

using clock = std::chrono::steady_clock;
inline double seconds_since(clock::time_point t0)
{
    return std::chrono::duration<double>(clock::now() - t0).count();
}

inline std::optional<problem> parse(int argc, char** argv)
{
    problem p;
    for (int i = 1; i < argc; ++i) {
        const bool has = i + 1 < argc;
        if (has && !std::strcmp(argv[i], "--ur")) p.ur = std::atof(argv[++i]);
        else if (has && !std::strcmp(argv[i], "--tol")) p.tol = std::atof(argv[++i]);
        else if (has && !std::strcmp(argv[i], "--horizon")) p.horizon = std::atof(argv[++i]);
        else if (has && !std::strcmp(argv[i], "--points")) p.points_file = argv[++i];
        else if (has && !std::strcmp(argv[i], "--repeat")) p.repeat = std::atoi(argv[++i]);
        else {
            std::fprintf(stderr, "usage: %s [--ur U] [--tol T] [--horizon H] [--points FILE] [--repeat N]\n", argv[0]);
            return std::nullopt;
        }
    }
    if (p.repeat < 1 || !(p.tol > 0.0) || !(p.ur > 0.0)) {
        std::fprintf(stderr, "%s: --repeat >= 1, --tol > 0 and --ur > 0 are required\n", argv[0]);
        return std::nullopt;
    }
    return p;
}

// A program's --method M among `allowed` (the first is the default), then the common options;
// nullopt (and a message) when either is wrong.
inline std::optional<std::pair<std::string, problem>> parse_with_method(int argc, char** argv,
                                                                       const std::vector<std::string>& allowed)
{
    std::string method = allowed.front();
    std::vector<char*> rest;
    for (int i = 0; i < argc; ++i) {
        if (i > 0 && i + 1 < argc && std::strcmp(argv[i], "--method") == 0) method = argv[++i];
        else rest.push_back(argv[i]);
    }
    if (std::find(allowed.begin(), allowed.end(), method) == allowed.end()) {
        std::string names;
        for (const auto& a : allowed) names += (names.empty() ? "" : "|") + a;
        std::fprintf(stderr, "%s: --method %s\n", argv[0], names.c_str());
        return std::nullopt;
    }
    const auto p = parse(static_cast<int>(rest.size()), rest.data());
    if (!p) return std::nullopt;
    return std::make_pair(method, *p);
}

// Runs `run` p.repeat times and prints the JSON line; writes the last run's points.
template <class Run>
int report(const problem& p, const char* name, Run&& run)
{
    std::vector<double> walls, cpus;
    run_result res;
    for (int k = 0; k < p.repeat; ++k) {
        const std::clock_t c0 = std::clock();
        res = run();
        cpus.push_back(static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC);
        walls.push_back(res.wall_s);
    }
    auto median_of = [](std::vector<double> s) {
        std::sort(s.begin(), s.end());
        const std::size_t n = s.size();
        return n % 2 ? s[n / 2] : 0.5 * (s[n / 2 - 1] + s[n / 2]);
    };
    const double median = median_of(walls);
    if (!p.points_file.empty()) {
        std::FILE* f = std::fopen(p.points_file.c_str(), "w");
        if (!f) {
            std::perror(p.points_file.c_str());
            return 1;
        }
        std::fprintf(f, "t,y,v,x,w\n");
        for (const auto& q : res.points)
            std::fprintf(f, "%.17g,%.17g,%.17g,%.17g,%.17g\n", q.t, q.X[0], q.X[1], q.X[2], q.X[3]);
        std::fclose(f);
    }
    std::printf("{\"name\": \"%s\", \"wall_s\": %.9g, \"cpu_s\": %.9g, \"steps\": %ld, \"rejected\": %ld, "
                "\"rhs_calls\": %ld, \"impacts\": %ld, \"points\": %zu, \"wall_all\": [",
                name, median, median_of(cpus), res.steps, res.rejected, res.rhs_calls, res.impacts, res.points.size());
    for (std::size_t i = 0; i < walls.size(); ++i) std::printf("%s%.9g", i ? ", " : "", walls[i]);
    std::printf("]}\n");
    return 0;
}

}  // namespace baseline

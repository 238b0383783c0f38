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
// Prints one JSON line: name, wall_s (median), wall_all, steps, rejected, rhs_calls, impacts, points.
#pragma once
#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <string>
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

// Runs `run` p.repeat times and prints the JSON line; writes the last run's points.
template <class Run>
int report(const problem& p, const char* name, Run&& run)
{
    std::vector<double> walls;
    run_result res;
    for (int k = 0; k < p.repeat; ++k) {
        res = run();
        walls.push_back(res.wall_s);
    }
    std::vector<double> s = walls;
    std::sort(s.begin(), s.end());
    const std::size_t n = s.size();
    const double median = n % 2 ? s[n / 2] : 0.5 * (s[n / 2 - 1] + s[n / 2]);
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
    std::printf("{\"name\": \"%s\", \"wall_s\": %.9g, \"steps\": %ld, \"rejected\": %ld, \"rhs_calls\": %ld, "
                "\"impacts\": %ld, \"points\": %zu, \"wall_all\": [",
                name, median, res.steps, res.rejected, res.rhs_calls, res.impacts, res.points.size());
    for (std::size_t i = 0; i < walls.size(); ++i) std::printf("%s%.9g", i ? ", " : "", walls[i]);
    std::printf("]}\n");
    return 0;
}

}  // namespace baseline

// A discrete-event simulation of the MPI job loop's schedule (docs/distributed.md states the
// model): R ranks of T threads, rank 0 coordinating with the library's own job_dispenser (the
// same blocks, window and order as a real run), message latency L, and a coordinator that
// serves messages one at a time. Job costs come from a measured map (bench/job_costs.cpp):
// each job of the NX x NY target grid takes the cost of the measured cell it falls in
// ("upsampled": the expensive cells near the grazing line stay together, as in a real map), or
// a cost drawn at random from the measured ones ("resampled").
//   schedule_sim COSTS.csv NX NY R T [upsampled|resampled] [L_us] [msg_us] [RECORD] [BATCH] [SPEEDUP]
// RECORD: the coordinator's cost per result in us, or a file of journal lines to measure it on
// (measure_record_cost); BATCH: the jobs a thread takes at once (SIMD lanes; the hand-out rules
// of jobs/job_loop.hpp for that batch), SPEEDUP: the lanes' throughput over one job at a time
// (each job's measured cost divided by it). Defaults: 5 us, 1, 1.
// Prints one line of JSON: makespan, parallel efficiency (work / (R T makespan)), the
// coordinator's messages per second and its busy fraction, the largest reorder buffer.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <fstream>
#include <iostream>
#include <queue>
#include <random>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <filesystem>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "io/json_codec.hpp"
#include "io/json_line.hpp"
#include "vimpact/analysis/impact_statistics.hpp"
#include "vimpact/core/format.hpp"
#include "vimpact/io/csv_writer.hpp"

#include "jobs/job_dispenser.hpp"

namespace {

struct measured {
    long nx = 0, ny = 0;
    std::vector<double> cost;  // by job of the measured grid
};

measured read_costs(const std::string& path)
{
    std::ifstream in(path);
    std::string line;
    std::getline(in, line);  // job,ix,iy,Ur,sigma,label,seconds[,steps]
    measured m;
    while (std::getline(in, line)) {
        std::vector<std::string> f;
        std::stringstream ss(line);
        for (std::string x; std::getline(ss, x, ',');) f.push_back(x);
        const long ix = std::stol(f[1]), iy = std::stol(f[2]);
        m.nx = std::max(m.nx, ix + 1);
        m.ny = std::max(m.ny, iy + 1);
        m.cost.push_back(std::stod(f[6]));
    }
    return m;
}

// The coordinator's cost per received result, measured here on real journal lines (a map's,
// from a run of this build: bench/run_mpi_bench.sh makes them): what rank 0 does with every
// result from another rank, as the library and the command line do it: read the line
// (detail::parse_json_line), decode the map cell (the map's record: label, outcome, steps,
// impact statistics, grazing values), format its row of labels.csv (format_double, csv_writer's
// text_row) and append the journal line (the journal is flushed once per batch of 8).
double measure_record_cost(const std::string& lines_path)
{
    std::ifstream in(lines_path);
    std::vector<std::string> lines;
    for (std::string l; std::getline(in, l);)
        if (!l.empty()) lines.push_back(l);
    if (lines.empty()) throw std::runtime_error("no journal lines in " + lines_path);
    const auto dir = std::filesystem::temp_directory_path() / "vimpact_schedule_sim";
    std::filesystem::create_directories(dir);
    vimpact::csv_writer rows(dir / "labels.csv", std::vector<std::string>(20, "c"));
    std::FILE* journal = std::fopen((dir / "journal.jsonl").c_str(), "w");
    constexpr int n = 20000;
    long sum = 0;
    const auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < n; ++i) {
        const std::string& line = lines[static_cast<std::size_t>(i) % lines.size()];
        const auto j = vimpact::detail::parse_json_line(line);
        const auto& r = j.at("record");
        const auto label = vimpact::detail::label_from(r.at("label"));
        const auto status = vimpact::detail::outcome_from(r.at("status"));
        const long steps = r.at("steps").get<long>();
        const auto stats = vimpact::detail::statistics_from(r.at("statistics"));
        const auto grazing = vimpact::detail::numbers_from(r.at("grazing"));
        sum += steps + static_cast<long>(grazing.size());
        std::vector<std::string> cells{vimpact::format_double(14.0 + 1e-3 * i), vimpact::format_double(-0.16 + 1e-4 * i),
                                       label.label, std::to_string(label.period), std::to_string(label.impacts_per_period),
                                       label.settled ? "1" : "0", std::string(vimpact::to_string(status))};
        for (const long c : label.impacts_by_surface) cells.push_back(std::to_string(c));
        for (const double v : vimpact::impact_statistics_values(stats)) cells.push_back(vimpact::format_double(v));
        cells.resize(20, "0");
        rows.text_row(cells);
        std::fwrite(line.data(), 1, line.size(), journal);
        std::fputc('\n', journal);
        if (i % 8 == 7) std::fflush(journal);
    }
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() / n;
    std::fclose(journal);
    rows.close();
    std::filesystem::remove_all(dir);
    return sum > 0 ? s : s;
}

struct event {
    double t;
    int kind;  // 0 a job ends on a rank, 1 a message reaches the coordinator, 2 a grant reaches a rank
    int rank;
    long job;   // kind 0
    long want;  // kind 1
    std::vector<long> jobs;  // kind 1: results; kind 2: jobs
    bool operator>(const event& o) const { return t > o.t; }
};

}  // namespace

int main(int argc, char** argv)
{
    if (argc < 6) {
        std::cerr << "usage: schedule_sim COSTS.csv NX NY R T [upsampled|resampled] [L_us] [msg_us] [RECORD_us|LINES.jsonl]"
                     " [BATCH] [SPEEDUP]\n";
        return 2;
    }
    const measured m = read_costs(argv[1]);
    const long NX = std::atol(argv[2]), NY = std::atol(argv[3]), jobs = NX * NY;
    const int R = std::atoi(argv[4]);
    const long T = std::atol(argv[5]);
    const std::string mode = argc > 6 ? argv[6] : "upsampled";
    const double L = (argc > 7 ? std::atof(argv[7]) : 20.0) * 1e-6;
    const double c_msg = (argc > 8 ? std::atof(argv[8]) : 5.0) * 1e-6;
    const std::string record_arg = argc > 9 ? argv[9] : "5";
    const bool record_file = record_arg.find_first_not_of("0123456789.eE+-") != std::string::npos;
    const double c_rec = record_file ? measure_record_cost(record_arg) : std::atof(record_arg.c_str()) * 1e-6;
    const long B = argc > 10 ? std::max(1L, std::atol(argv[10])) : 1L;
    const double speedup = argc > 11 ? std::atof(argv[11]) : 1.0;
    const double c_grant = 0.2e-6;  // per job granted: a number on a line

    std::vector<double> cost(static_cast<std::size_t>(jobs));
    std::mt19937_64 rng(12345);
    std::uniform_int_distribution<std::size_t> pick(0, m.cost.size() - 1);
    double work = 0.0;
    for (long j = 0; j < jobs; ++j) {
        const long ix = j % NX * m.nx / NX, iy = j / NX * m.ny / NY;
        const double c = mode == "resampled" ? m.cost[pick(rng)] : m.cost[static_cast<std::size_t>(iy * m.nx + ix)];
        cost[static_cast<std::size_t>(j)] = c / speedup;
        work += c / speedup;
    }

    const long all_threads = static_cast<long>(R) * T;
    vimpact::job_dispenser dispenser({jobs, 0}, [](long) { return true; }, jobs,
                                     std::max(vimpact::ranks_window_per_thread, 2 * B) * all_threads, all_threads, 2, B);
    std::vector<char> arrived(static_cast<std::size_t>(jobs), 0);
    long next_undelivered = 0, buffered = 0, max_buffered = 0;

    struct rank_state {
        std::deque<long> queue;
        long running = 0;
        bool asked = false;
        long want = 0;  // at the coordinator
        std::vector<long> unsent;
        double work = 0.0;  // of the jobs done, for the mean that sets the capacity
        long done = 0;
        long batch = 1;
        [[nodiscard]] long capacity(long threads) const
        {
            return vimpact::rank_capacity(threads, done > 0 ? work / static_cast<double>(done) : 0.0, batch);
        }
    };
    std::vector<rank_state> ranks(static_cast<std::size_t>(R));
    for (auto& r : ranks) r.batch = B;
    std::priority_queue<event, std::vector<event>, std::greater<>> events;
    double coordinator_free = 0.0, busy = 0.0, end = 0.0;
    long messages = 0, done = 0;

    auto start_jobs = [&](int r, double t) {
        auto& s = ranks[static_cast<std::size_t>(r)];
        while (s.running < T && !s.queue.empty()) {
            const long j = s.queue.front();
            s.queue.pop_front();
            ++s.running;
            events.push({t + cost[static_cast<std::size_t>(j)], 0, r, j, 0, {}});
        }
    };
    auto held = [&](int r) {
        const auto& s = ranks[static_cast<std::size_t>(r)];
        return static_cast<long>(s.queue.size()) + s.running;
    };
    // The coordinator hands out after each thing it does: its own threads first, then the
    // ranks that asked (as run_jobs does), each grant a message of latency L.
    auto hand_out = [&](double t) {
        const long own_want = (B > 1 ? 3 : 2) * B * T - held(0);
        if (own_want >= std::max(B, T))
            for (const long j : dispenser.grant(own_want)) ranks[0].queue.push_back(j);
        start_jobs(0, t);
        for (int r = 1; r < R; ++r) {
            auto& s = ranks[static_cast<std::size_t>(r)];
            if (s.want <= 0) continue;
            auto g = dispenser.grant(s.want);
            if (g.empty()) continue;
            s.want = 0;
            const double cost_g = c_msg + c_grant * static_cast<double>(g.size());
            coordinator_free = std::max(coordinator_free, t) + cost_g;
            busy += cost_g;
            ++messages;
            events.push({coordinator_free + L, 2, r, 0, 0, std::move(g)});
        }
    };
    auto record = [&](long j) {
        arrived[static_cast<std::size_t>(j)] = 1;
        dispenser.completed(j);
        ++buffered;
        while (next_undelivered < jobs && arrived[static_cast<std::size_t>(next_undelivered)]) {
            ++next_undelivered;
            --buffered;
        }
        dispenser.delivered_below(next_undelivered);
        max_buffered = std::max(max_buffered, buffered);
        ++done;
    };

    for (int r = 1; r < R; ++r) {
        ranks[static_cast<std::size_t>(r)].asked = true;
        events.push({L, 1, r, 0, vimpact::rank_capacity(T, 0.0, B), {}});
    }
    hand_out(0.0);
    while (!events.empty()) {
        event e = events.top();
        events.pop();
        auto& s = ranks[static_cast<std::size_t>(e.rank)];
        if (e.kind == 0) {
            --s.running;
            if (e.rank == 0) {  // the coordinator's own thread: no message, the record's cost
                coordinator_free = std::max(coordinator_free, e.t) + c_rec;
                busy += c_rec;
                record(e.job);
                end = std::max(end, coordinator_free);
                hand_out(coordinator_free);
            } else {
                // As run_rank: results go with a request, or when half a capacity gathered.
                s.work += cost[static_cast<std::size_t>(e.job)];
                ++s.done;
                s.unsent.push_back(e.job);
                const long cap = s.capacity(T);
                long want = 0;
                if (!s.asked && held(e.rank) <= cap / 2) {
                    want = cap - held(e.rank);
                    s.asked = true;
                }
                const bool last = dispenser.exhausted() && held(e.rank) == 0;
                if (want > 0 || 2 * static_cast<long>(s.unsent.size()) >= cap || last)
                    events.push({e.t + L, 1, e.rank, 0, want, std::exchange(s.unsent, {})});
            }
            start_jobs(e.rank, e.t);
        } else if (e.kind == 1) {
            const double cost_m = c_msg + c_rec * static_cast<double>(e.jobs.size());
            coordinator_free = std::max(coordinator_free, e.t) + cost_m;
            busy += cost_m;
            ++messages;
            for (const long j : e.jobs) record(j);
            s.want += e.want;
            end = std::max(end, coordinator_free);
            hand_out(coordinator_free);
        } else {
            s.asked = false;
            for (const long j : e.jobs) s.queue.push_back(j);
            start_jobs(e.rank, e.t);
        }
    }
    if (done != jobs) {
        std::cerr << "schedule_sim: " << done << " of " << jobs << " jobs ran\n";
        return 1;
    }
    const nlohmann::json out = {{"ranks", R},
                                {"threads_per_rank", T},
                                {"jobs", jobs},
                                {"costs", mode},
                                {"latency_us", L * 1e6},
                                {"message_us", c_msg * 1e6},
                                {"record_us", c_rec * 1e6},
                                {"batch", B},
                                {"lanes_speedup", speedup},
                                {"work_s", work},
                                {"makespan_s", end},
                                {"ideal_s", work / static_cast<double>(all_threads)},
                                {"efficiency", work / (static_cast<double>(all_threads) * end)},
                                {"messages_per_s", static_cast<double>(messages) / end},
                                {"coordinator_busy", busy / end},
                                {"max_reorder_buffer", max_buffered}};
    std::cout << out.dump() << '\n';
    return 0;
}

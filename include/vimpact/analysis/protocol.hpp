#pragma once
// The simulation protocol (the paper's Section 3): run from an initial state, discard a
// transient of impacts, then record points on a section.
//
// Non-impacting runs (P0): if no impact happens for `quiet_time` time units, the orbit is
// taken to have settled away from every surface; the transient bookkeeping is dropped and the
// section points recorded from then on describe the surface-free steady state. The default,
// 2000 time units, is about 318 wake periods of the paper's model and far longer than the
// gaps between impacts of any impacting orbit we have seen (< 100).
#include <array>
#include <functional>
#include <optional>
#include <string>
#include <string_view>

#include <Eigen/Core>

#include "vimpact/analysis/impact_statistics.hpp"
#include "vimpact/core/names.hpp"
#include "vimpact/core/outcome.hpp"
#include "vimpact/core/state_series.hpp"
#include "vimpact/hybrid/flow_options.hpp"
#include "vimpact/hybrid/lanes_counts.hpp"
#include "vimpact/hybrid/run_stats.hpp"
#include "vimpact/model/model.hpp"

namespace vimpact {

enum class integration_method { dop853, dopri5 };

constexpr std::string_view to_string(integration_method m)
{
    return m == integration_method::dopri5 ? "dopri5" : "dop853";
}
inline constexpr std::array<integration_method, 2> all_integration_methods{integration_method::dop853,
                                                                         integration_method::dopri5};

// The step-size controller's hold band a run of `method` with these options uses: the one
// given, else the method's default (integrator_options::hold_band).
double effective_hold_band(const integrator_options& o, integration_method method);

// Where the protocol records its points: the crossings of one of the model's sections, or
// the states just after impacts (on one surface, or on every surface).
struct section_choice {
    enum class kind { crossing, impacts };
    kind type = kind::crossing;
    int index = 0;  // crossing: the section; impacts: the surface, -1 for every surface

    static section_choice crossings(int section) { return {kind::crossing, section}; }
    static section_choice impacts(int surface = -1) { return {kind::impacts, surface}; }
    friend bool operator==(const section_choice&, const section_choice&) = default;
};

// The name of a choice for `m`: a section's name, "impacts" or "impacts:SURFACE".
std::string section_choice_name(const model& m, const section_choice& s);
// The choice so named for `m` (section_choice_name's inverse); none when `m` has no such
// section or surface.
std::optional<section_choice> section_choice_named(const model& m, std::string_view name);
// Every name section_choice_named accepts for `m`, "maxima, minima, impacts, impacts:barrier",
// for messages.
std::string section_choice_names(const model& m);
// Where a run that names no choice records: the model's first section, or the impacts of a
// model that declares none.
section_choice default_section(const model& m);

// Throws input_error if the model has no such section or surface.
void validate(const model& m, const section_choice& s);

struct protocol_options {
    long transient_impacts = 500;
    long record_points = 200;
    section_choice section{};  // default: the model's first section
    double quiet_time = 2000.0;
    double sample_dt = 0.0;    // > 0: sample the recorded window every sample_dt (time series)
    // The time series' size limit: a run whose series reaches it, or whose sample_dt is too
    // small to advance the time, ends with the outcome sample_limit: a tiny sample_dt ends in
    // bounded memory (a million samples of a 4-dimensional state are 40 MB, about 100 MB of
    // CSV) instead of filling the machine.
    long max_samples = 1'000'000;
    // Integration, limits and the chattering rule; the analysis sets the surfaces and the
    // events itself.
    flow_options flow{.t_max = 1e6};
    integration_method method = integration_method::dop853;
};

// Throws input_error for options outside their valid ranges (the tolerances among them).
void validate(const protocol_options& o);
void validate(const integrator_options& o);

struct simulation {
    outcome status = outcome::ok;
    bool impacting = true;       // false: no impact for quiet_time (label P0)
    long transient_impacts = 0;  // impacts discarded
    double t_record_start = 0.0;
    // The end of the recorded window: the last recorded point's time, or where the run ended
    // otherwise (stats.t_final, the end of the integration step, may lie a little later).
    double t_record_end = 0.0;
    state_series points;         // the recorded section points
    impact_series impacts;       // the impacts of the recorded window
    impact_series switchings;    // the crossings of switching surfaces there (`surface`: the switch)
    state_series series;         // time series of the recorded window (sample_dt > 0)
    Eigen::VectorXd final_state;
    run_stats stats;
    // The recorded window, for its impact statistics: time in contact phases, and each
    // surface's largest gap (NaN for a surface whose gap was never sampled).
    double contact_time = 0.0;
    std::vector<double> max_gap;
    impact_statistics statistics;  // of the recorded window (analysis/impact_statistics.hpp)
};

// Runs the protocol on `m` from (0, x0). Throws input_error for invalid options or an
// inadmissible initial state; numerical trouble is reported in result.status.
simulation simulate(const model& m, const Eigen::VectorXd& x0, const protocol_options& o);

// One job of a protocol stream: a model, its initial state and the caller's key for it.
struct protocol_job {
    long key = 0;
    model m;
    Eigen::VectorXd x0;
};
// Gives the next job, or none for now (a later call may give more).
using protocol_source = std::function<std::optional<protocol_job>()>;
// Receives each job with its run, as the run ends.
using protocol_sink = std::function<void(protocol_job&&, simulation&&)>;

// The protocol for every job `next` gives, until it gives none while no job is running;
// each result goes to `done` as its run ends (not in the order given). Jobs whose model is
// `kind` with other parameter values share SIMD lanes, up to `width` at once (at most
// lane_width), when the model runs in lanes (runs_in_lanes); a lane whose run ends takes the
// next job. Every result is the one simulate() gives, bit for bit. Other jobs, and every job
// when width is 1, run one at a time. Returns how the lanes were used (zero without lanes).
// Throws input_error as simulate() does.
lanes_counts simulate_stream(const model& kind, const protocol_options& o, int width, const protocol_source& next,
                     const protocol_sink& done);

// The protocol for several jobs, models[j] from x0s[j] (simulate_stream), results in order.
std::vector<simulation> simulate_many(const std::vector<model>& models, const std::vector<Eigen::VectorXd>& x0s,
                                      const protocol_options& o, int batch);

// Whether the protocol runs of `m` can share SIMD lanes: a built-in model on a machine (and
// build) with SIMD registers of 4 doubles or more. Model files run one job at a time.
bool runs_in_lanes(const model& m);

// The jobs per batch of the job commands: `requested` (0: the SIMD width, lane_width), 1 when
// the model cannot run in lanes. Throws input_error outside [0, 1024].
int resolve_batch(const model& m, int requested);

}  // namespace vimpact

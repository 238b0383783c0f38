#pragma once
// How a computation ended: one type for every run and analysis. Expected numerical trouble is
// a value here, never an exception; bad input is an input_error, broken invariants assertions.
#include <optional>
#include <string_view>

namespace vimpact {

enum class outcome {
    ok,              // the requested stop condition was reached
    time_limit,      // t_max (or an averaging-time limit) reached before the stop condition
    step_limit,      // max_steps accepted steps reached
    impact_limit,    // max_impacts reached before the stop condition
    step_underflow,  // the step size fell below what the time resolution allows
    non_finite,      // the state or the vector field became NaN or infinite
    interrupted,     // the caller's cancel flag was set (Ctrl-C)
    chattering,      // impacts accumulate on a surface that declares no sticking phase
    sticking,        // a tangent analysis met a sticking phase (its tangent map is not implemented)
    aperiodic,       // a periodic orbit was required (Floquet) but none was found
    not_converged,   // Newton's method did not reach its tolerance
    inadmissible,    // the initial state lies beyond an impact surface
    sample_limit,    // the time series reached its sample limit (protocol_options::max_samples)
    sliding,         // the fields on both sides of a switching surface point into it (Filippov sliding)
};

inline constexpr outcome all_outcomes[] = {
    outcome::ok,         outcome::time_limit, outcome::step_limit,    outcome::impact_limit,
    outcome::step_underflow, outcome::non_finite, outcome::interrupted, outcome::chattering,
    outcome::sticking,   outcome::aperiodic,  outcome::not_converged, outcome::inadmissible,
    outcome::sample_limit, outcome::sliding,
};

constexpr std::string_view to_string(outcome o)
{
    switch (o) {
        case outcome::ok: return "ok";
        case outcome::time_limit: return "time_limit";
        case outcome::step_limit: return "step_limit";
        case outcome::impact_limit: return "impact_limit";
        case outcome::step_underflow: return "step_underflow";
        case outcome::non_finite: return "non_finite";
        case outcome::interrupted: return "interrupted";
        case outcome::chattering: return "chattering";
        case outcome::sticking: return "sticking";
        case outcome::aperiodic: return "aperiodic";
        case outcome::not_converged: return "not_converged";
        case outcome::inadmissible: return "inadmissible";
        case outcome::sample_limit: return "sample_limit";
        case outcome::sliding: return "sliding";
    }
    return "unknown";
}

constexpr std::optional<outcome> outcome_from_string(std::string_view s)
{
    for (const outcome o : all_outcomes)
        if (to_string(o) == s) return o;
    return std::nullopt;
}

}  // namespace vimpact

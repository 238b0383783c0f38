#pragma once
// How a run ended. Expected numerical trouble is a value here, never an exception.
#include <string_view>

namespace vimpact {

enum class outcome {
    ok,              // the requested stop condition was reached
    time_limit,      // t_max reached before the stop condition
    step_limit,      // max_steps accepted steps reached
    impact_limit,    // max_impacts reached before the stop condition
    step_underflow,  // the step size fell below what the time resolution allows
    non_finite,      // the state or the vector field became NaN or infinite
    interrupted,     // the caller's cancel flag was set (Ctrl-C)
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
    }
    return "unknown";
}

}  // namespace vimpact

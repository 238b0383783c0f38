#pragma once
// The checks every steppable system makes of its input, one wording for all three.
#include <cmath>
#include <string>

#include <Eigen/Core>

#include "vimpact/analysis/protocol.hpp"
#include "vimpact/core/format.hpp"
#include "vimpact/core/input_error.hpp"
#include "vimpact/hybrid/flow_options.hpp"
#include "vimpact/model/model.hpp"

namespace vimpact::detail {

inline void check_system_start(const model& m, const Eigen::VectorXd& x, double t)
{
    check_state_size(m, x.size(), "the initial state");
    if (!x.allFinite()) throw input_error("the initial state must be finite");
    if (!std::isfinite(t)) throw input_error("the initial time t = " + format_double(t) + " must be finite");
}

inline void check_system_flow(const flow_options& f, double max_return_time)
{
    validate(f.integration);
    if (!f.events.empty()) throw input_error("flow.events must be empty: a system watches its own section only");
    if (f.max_steps < 1) throw input_error("max_steps = " + std::to_string(f.max_steps) + " must be >= 1");
    if (!(max_return_time > 0.0))
        throw input_error("max_return_time = " + format_double(max_return_time) + " must be > 0");
}

// A time to advance to: finite, and not before the system's time.
inline void check_target_time(double t, double now)
{
    if (!std::isfinite(t) || t < now)
        throw input_error("t = " + format_double(t) + " is outside its valid range [" + format_double(now) +
                          ", inf) (the system's time onwards)");
}

inline void check_step_count(long n)
{
    if (n < 0) throw input_error("n = " + std::to_string(n) + " steps must be >= 0");
}

}  // namespace vimpact::detail

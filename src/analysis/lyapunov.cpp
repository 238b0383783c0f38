#include "vimpact/analysis/lyapunov.hpp"

#include <cmath>

#include "dispatch.hpp"
#include "vimpact/core/format.hpp"
#include "vimpact/model/model_phrases.hpp"

namespace vimpact {

void validate(const model& m, const lyapunov_options& o)
{
    validate(o.flow.integration);
    check_options(o);
    if (o.transient_impacts < 0) throw input_error("transient must be >= 0 impacts");
    // Each interval keeps its growth rates (the history), so the number of intervals bounds
    // both the memory and the time; the longest averaging is `time` when given, else max_time.
    constexpr double max_intervals = 2e6;
    const double horizon =
        static_cast<double>(o.warmup_intervals) * o.t0 + (o.time > 0.0 ? o.time : std::max(o.max_time, o.p0_time));
    if (horizon / o.t0 > max_intervals) {
        const double t0_min = (o.time > 0.0 ? o.time : std::max(o.max_time, o.p0_time)) /
                              (max_intervals - static_cast<double>(o.warmup_intervals));
        throw input_error("t0 = " + format_double(o.t0) + " would need more than 2e6 intervals over the averaging (" +
                          (o.time > 0.0 ? "time " + format_double(o.time) : "up to max_time " + format_double(o.max_time)) +
                          "): t0 must be >= " + format_double(t0_min) + (o.time > 0.0 ? "" : ", or give a shorter time"));
    }
    if (!(o.quiet_time > 0.0)) throw input_error("quiet_time must be > 0");
    if (o.record_points < 0) throw input_error("record must be >= 0 section points");
    if ((o.record_points > 0 || m.section_count() > 0) && (o.section < 0 || o.section >= std::max(1, m.section_count())))
        throw input_error("section " + std::to_string(o.section) + " does not exist (" + sections_it_has(m.info()) +
                          ")");
    if (o.record_points > 0 && m.section_count() == 0)
        throw input_error("model " + m.name() + " declares no section to record points on");
}

lyapunov_result lyapunov(const model& m, const Eigen::VectorXd& x0, const lyapunov_options& o)
{
    validate(m, o);
    check_state_size(m, x0.size(), "the initial state");
    return detail::with_engine(m, [&](const auto& em) { return detail::run_lyapunov(em, x0, o); });
}

}  // namespace vimpact

#include "vimpact/analysis/lyapunov.hpp"

#include <cmath>

#include "dispatch.hpp"
#include "vimpact/core/format.hpp"

namespace vimpact {

void validate(const model& m, const lyapunov_options& o)
{
    validate(o.flow.integration);
    if (!(o.r0 > 0.0) || !std::isfinite(o.r0) || o.r0 >= 1.0)
        throw input_error("r0 = " + format_double(o.r0) + " is outside its valid range (0, 1)");
    if (!(o.t0 > 0.0) || !std::isfinite(o.t0))
        throw input_error("t0 = " + format_double(o.t0) + " is outside its valid range (0, inf)");
    if (o.transient_impacts < 0) throw input_error("transient must be >= 0 impacts");
    if (o.warmup_intervals < 0) throw input_error("warmup must be >= 0 intervals");
    if (o.impacts < 1) throw input_error("impacts must be >= 1");
    if (!(o.time >= 0.0) || !std::isfinite(o.time)) throw input_error("time must be >= 0 and finite");
    if (!(o.max_time > 0.0) || !(o.p0_time > 0.0)) throw input_error("averaging time limits must be > 0");
    if (!(o.quiet_time > 0.0)) throw input_error("quiet_time must be > 0");
    if (o.record_points < 0) throw input_error("record must be >= 0 section points");
    if ((o.record_points > 0 || m.section_count() > 0) && (o.section < 0 || o.section >= std::max(1, m.section_count())))
        throw input_error("section " + std::to_string(o.section) + " does not exist (model " + m.name() + " has " +
                          m.info().section_names() + ")");
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

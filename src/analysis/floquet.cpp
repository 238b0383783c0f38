#include "vimpact/analysis/floquet.hpp"

#include <cmath>

#include "dispatch.hpp"
#include "vimpact/core/format.hpp"
#include "vimpact/model/model_phrases.hpp"

namespace vimpact {

void validate(const model& m, const floquet_options& o)
{
    validate(o.protocol);
    validate(m, o.protocol.section);
    validate(o.tangent_integration);
    if (o.protocol.section.type != section_choice::kind::crossing)
        throw option_error("section", ": Floquet analysis needs a section crossing, not the impacts (" +
                                          sections_it_has(m.info()) + ")");
    if (o.protocol.record_points < 2)
        throw option_error("record", " = " + std::to_string(o.protocol.record_points) +
                                         ": Floquet analysis needs at least 2 recorded section points");
    check_options(o);
    // A period of a few time units sampled at the bound is a few million samples; a smaller
    // step would only fill memory (and at 1e-300 never end).
    if (!(o.sample_dt == 0.0 || o.sample_dt >= 1e-6) || !std::isfinite(o.sample_dt))
        throw input_error("sample_dt must be 0 (no orbit samples) or in [1e-6, inf) (got " + format_double(o.sample_dt) +
                          ")");
    if (m.dim() < 2) throw input_error("Floquet analysis needs at least 2 state variables");
}

floquet_result floquet(const model& m, const Eigen::VectorXd& x0, const floquet_options& o)
{
    validate(m, o);
    check_state_size(m, x0.size(), "the initial state");
    return detail::with_engine(m, [&](const auto& em) { return detail::run_floquet(em, x0, o, m.info()); });
}

floquet_result floquet_from_point(const model& m, const Eigen::VectorXd& x_guess, int returns, const floquet_options& o)
{
    validate(m, o);
    check_state_size(m, x_guess.size(), "the orbit point");
    if (returns < 1) throw input_error("section returns must be >= 1 (got " + std::to_string(returns) + ")");
    return detail::with_engine(m, [&](const auto& em) { return detail::run_floquet_from_point(em, x_guess, returns, o); });
}

}  // namespace vimpact

#include "vimpact/system/hybrid_system.hpp"

#include <limits>

#include "dispatch.hpp"
#include "system/system_checks.hpp"
#include "system/system_engines.hpp"

namespace vimpact {

hybrid_system::hybrid_system(model m, const Eigen::VectorXd& x0, double t0, hybrid_system_options o)
    : m_model(std::move(m)), m_options(std::move(o))
{
    detail::check_system_flow(m_options.flow, std::numeric_limits<double>::infinity());
    reinit(x0, t0);
}

hybrid_system::hybrid_system(const hybrid_system& other)
    : m_model(other.m_model), m_options(other.m_options), m_impl(other.m_impl->clone())
{
}
hybrid_system& hybrid_system::operator=(const hybrid_system& other)
{
    if (this != &other) *this = hybrid_system(other);
    return *this;
}
hybrid_system::hybrid_system(hybrid_system&&) noexcept = default;
hybrid_system& hybrid_system::operator=(hybrid_system&&) noexcept = default;
hybrid_system::~hybrid_system() = default;

const Eigen::VectorXd& hybrid_system::state() const { return m_impl->x(); }
double hybrid_system::time() const { return m_impl->t(); }
outcome hybrid_system::status() const { return m_impl->status(); }
run_stats hybrid_system::stats() const { return m_impl->stats(); }
const impact_series& hybrid_system::impacts() const { return m_impl->impacts(); }
const impact_series& hybrid_system::switchings() const { return m_impl->switchings(); }
bool hybrid_system::in_contact() const { return m_impl->in_contact(); }

outcome hybrid_system::step() { return m_impl->step(); }

outcome hybrid_system::step(double dt)
{
    if (!(dt >= 0.0)) throw input_error("dt = " + format_double(dt) + " is outside its valid range [0, inf)");
    return advance_to(time() + dt);
}

outcome hybrid_system::advance_to(double t)
{
    detail::check_target_time(t, time());
    return m_impl->advance_to(t);
}

void hybrid_system::reinit(const Eigen::VectorXd& x, double t)
{
    detail::check_system_start(m_model, x, t);
    const detail::flow_system_spec spec{m_options.flow, m_options.method};
    m_impl = detail::with_engine(m_model, [&](const auto& em) { return detail::make_flow_system(em, spec, t, x); });
}

void hybrid_system::set_parameter(int i, double v)
{
    m_model = m_model.with_parameter(i, v);
    const Eigen::VectorXd x = state();
    reinit(x, time());
}

}  // namespace vimpact

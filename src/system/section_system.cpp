#include "vimpact/system/section_system.hpp"

#include "dispatch.hpp"
#include "system/system_checks.hpp"
#include "system/system_engines.hpp"

namespace vimpact {

section_system::section_system(model m, const Eigen::VectorXd& x0, double t0, section_system_options o)
    : m_model(std::move(m)), m_options(std::move(o)), m_section(m_options.section.value_or(default_section(m_model)))
{
    validate(m_model, m_section);
    detail::check_system_flow(m_options.flow, m_options.max_return_time);
    reinit(x0, t0);
}

section_system::section_system(const section_system& other)
    : m_model(other.m_model), m_options(other.m_options), m_section(other.m_section), m_impl(other.m_impl->clone())
{
}
section_system& section_system::operator=(const section_system& other)
{
    if (this != &other) *this = section_system(other);
    return *this;
}
section_system::section_system(section_system&&) noexcept = default;
section_system& section_system::operator=(section_system&&) noexcept = default;
section_system::~section_system() = default;

const Eigen::VectorXd& section_system::state() const { return m_impl->x(); }
double section_system::time() const { return m_impl->t(); }
outcome section_system::status() const { return m_impl->status(); }
run_stats section_system::stats() const { return m_impl->stats(); }
const impact_series& section_system::impacts() const { return m_impl->impacts(); }
const impact_series& section_system::switchings() const { return m_impl->switchings(); }

outcome section_system::step() { return m_impl->next_point(m_options.max_return_time); }

outcome section_system::step(long n)
{
    detail::check_step_count(n);
    for (long k = 0; k < n; ++k)
        if (step() != outcome::ok) break;
    return status();
}

void section_system::reinit(const Eigen::VectorXd& x, double t)
{
    detail::check_system_start(m_model, x, t);
    detail::flow_system_spec spec{m_options.flow, m_options.method};
    if (m_section.type == section_choice::kind::crossing) spec.section = m_section.index;
    else spec.impact_points = m_section.index;
    m_impl = detail::with_engine(m_model, [&](const auto& em) { return detail::make_flow_system(em, spec, t, x); });
}

void section_system::set_parameter(int i, double v)
{
    m_model = m_model.with_parameter(i, v);
    const Eigen::VectorXd x = state();
    reinit(x, time());
}

}  // namespace vimpact

#include "vimpact/system/tangent_system.hpp"

#include "dispatch.hpp"
#include "system/system_checks.hpp"
#include "system/system_engines.hpp"
#include "vimpact/model/model_phrases.hpp"

namespace vimpact {

namespace {

// The deviations' count: o.deviations, or the dimension for 0.
int deviation_count(const model& m, const tangent_system_options& o)
{
    if (o.deviations < 0 || o.deviations > m.dim())
        throw input_error("deviations = " + std::to_string(o.deviations) + " is outside its valid range [0, " +
                          std::to_string(m.dim()) + "] (0: " + std::to_string(m.dim()) + ", the state's dimension)");
    return o.deviations == 0 ? m.dim() : o.deviations;
}

void check_deviations(const model& m, int k, const Eigen::MatrixXd& w)
{
    if (w.rows() != m.dim() || w.cols() != k)
        throw input_error("the deviations must be a " + std::to_string(m.dim()) + " x " + std::to_string(k) +
                          " matrix (state dimension x deviations), got " + std::to_string(w.rows()) + " x " +
                          std::to_string(w.cols()));
    if (!w.allFinite()) throw input_error("the deviations must be finite");
}

}  // namespace

tangent_system::tangent_system(model m, const Eigen::VectorXd& x0, double t0, tangent_system_options o)
    : m_model(std::move(m)), m_options(std::move(o))
{
    if (m_options.section < -1 || m_options.section >= m_model.section_count())
        throw input_error("section " + std::to_string(m_options.section) + " does not exist (" +
                          sections_it_has(m_model.info()) + "; -1: continuous time)");
    detail::check_system_flow(m_options.flow, m_options.max_return_time);
    m_options.deviations = deviation_count(m_model, m_options);
    reinit(x0, t0);
}

tangent_system::tangent_system(const tangent_system& other)
    : m_model(other.m_model), m_options(other.m_options), m_impl(other.m_impl->clone())
{
}
tangent_system& tangent_system::operator=(const tangent_system& other)
{
    if (this != &other) *this = tangent_system(other);
    return *this;
}
tangent_system::tangent_system(tangent_system&&) noexcept = default;
tangent_system& tangent_system::operator=(tangent_system&&) noexcept = default;
tangent_system::~tangent_system() = default;

const Eigen::VectorXd& tangent_system::state() const { return m_impl->x(); }
double tangent_system::time() const { return m_impl->t(); }
const Eigen::MatrixXd& tangent_system::deviations() const { return m_impl->w(); }
outcome tangent_system::status() const { return m_impl->status(); }
run_stats tangent_system::stats() const { return m_impl->stats(); }

outcome tangent_system::step() { return m_impl->step(); }

outcome tangent_system::step(long n)
{
    detail::check_step_count(n);
    for (long k = 0; k < n; ++k)
        if (step() != outcome::ok) break;
    return status();
}

outcome tangent_system::advance_to(double t)
{
    if (discrete())
        throw input_error("advance_to: a tangent system on section " + std::to_string(m_options.section) +
                          " steps in discrete time (step(n)); section -1 gives continuous time");
    detail::check_target_time(t, time());
    return m_impl->advance_to(t);
}

void tangent_system::set_deviations(const Eigen::MatrixXd& w)
{
    check_deviations(m_model, m_options.deviations, w);
    m_impl->set_deviations(w);
}

void tangent_system::reinit(const Eigen::VectorXd& x, double t)
{
    reinit(x, t, Eigen::MatrixXd::Identity(m_model.dim(), m_options.deviations));
}

void tangent_system::reinit(const Eigen::VectorXd& x, double t, const Eigen::MatrixXd& w)
{
    detail::check_system_start(m_model, x, t);
    check_deviations(m_model, m_options.deviations, w);
    m_impl = detail::with_engine(m_model, [&](const auto& em) { return detail::make_tangent_engine(em, m_options, t, x, w); });
}

void tangent_system::set_parameter(int i, double v)
{
    m_model = m_model.with_parameter(i, v);
    const Eigen::VectorXd x = state();
    const Eigen::MatrixXd w = deviations();
    reinit(x, time(), w);
}

}  // namespace vimpact

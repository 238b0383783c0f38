// The steppable systems' engines (system_engines.hpp) on one engine model: included by the
// engine modules (src/instances/), whose table of functions (engine_instances.ipp) holds
// make_flow_system and make_tangent_engine.
#include "system/system_engines.hpp"

#include <optional>

#include "vimpact/engine/stepping.hpp"
#include "vimpact/model/builtin/forced_impact_oscillator.hpp"
#include "vimpact/model/builtin/two_sided_impact_oscillator.hpp"
#include "vimpact/model/builtin/wake_impact.hpp"
#include "vimpact/model/native_model.hpp"
#include "vimpact/model/table_model.hpp"
#include "vimpact/integrate/runge_kutta.hpp"
#include "vimpact/tangent/section_map.hpp"
#include "vimpact/tangent/variational.hpp"

namespace vimpact::detail {

// Moves the impacts (or crossings of switches) the flow reported up to time `until` from its
// record's `events` into `out`, as states of the model (the tangent flow's states hold more).
template <class Events, class Point>
void take_impacts(Events& events, double until, impact_series& out, Point&& point)
{
    while (!events.empty() && events.front().t <= until) {
        const auto& i = events.front();
        out.push_back(i.t, i.surface, point(i.pre), point(i.post));
        events.pop_front();
    }
}

// The flow's options for a system: the surfaces act, the section (if any) is watched.
template <engine_model Model>
flow_options system_flow(const Model& m, flow_options fo, int section)
{
    fo.surfaces = true;
    fo.events.clear();
    if (section >= 0) fo.events.push_back(flow_event::section(section, m.section_direction(section)));
    return fo;
}

template <engine_model EM, template <int> class Method>
class flow_system_on final : public flow_system {
public:
    static constexpr int N = EM::dim;

    flow_system_on(const EM& em, const flow_system_spec& s, double t, const vec<N>& x)
        : m_run(em, system_flow(em, s.flow, s.section), t, s.section >= 0 ? past_section(em, s.section, x) : x)
    {
        m_run.record().impact_points = s.impact_points;
        m_run.record().keep_switchings = true;
        m_impacts = impact_series(state_dim(em));
        m_switchings = impact_series(state_dim(em));
        m_t = t;
        m_x = to_dynamic(x);
    }
    [[nodiscard]] std::unique_ptr<flow_system> clone() const override { return std::make_unique<flow_system_on>(*this); }

    outcome step() override
    {
        clear_events();
        m_status = m_run.step();
        after_step();
        return m_status;
    }
    outcome advance_to(double t) override
    {
        clear_events();
        m_status = m_run.advance_to(t);
        after_step();
        return m_status;
    }
    outcome next_point(double max_flight) override
    {
        clear_events();
        auto& rec = m_run.record();
        while (rec.points.empty()) {
            if (m_status != outcome::ok) return m_status;
            if (m_run.t() - m_t > max_flight) return m_status = outcome::time_limit;
            m_status = m_run.step();
            if (rec.points.empty()) take_events(rec, m_run.t());
        }
        const auto p = rec.points.front();
        rec.points.pop_front();
        take_events(rec, p.t);
        m_t = p.t;
        assign_dynamic(p.x, m_x);
        return outcome::ok;  // the flow may have ended after this point: the next call says so
    }
    [[nodiscard]] run_stats stats() const override { return m_run.stats(); }
    [[nodiscard]] bool in_contact() const override { return m_run.flow().mode() == flow_mode::sticking; }

private:
    static constexpr auto identity = [](const vec<N>& v) { return v; };
    void clear_events()
    {
        m_impacts.clear();
        m_switchings.clear();
    }
    template <class Record>
    void take_events(Record& rec, double until)
    {
        take_impacts(rec.impacts, until, m_impacts, identity);
        take_impacts(rec.switchings, until, m_switchings, identity);
    }
    void after_step()
    {
        take_events(m_run.record(), m_run.t());
        m_t = m_run.t();
        assign_dynamic(m_run.x(), m_x);
    }

    engine::stepping_flow<EM, Method> m_run;
};

namespace instance {

template <class EM>
std::unique_ptr<flow_system> make_flow_system(const EM& em, const flow_system_spec& s, double t,
                                              const Eigen::VectorXd& x)
{
    const vec<EM::dim> xs = head_as<EM::dim>(x, state_dim(em));
    if (s.method == integration_method::dopri5) return std::make_unique<flow_system_on<EM, dopri5>>(em, s, t, xs);
    return std::make_unique<flow_system_on<EM, dop853>>(em, s, t, xs);
}

// The tangent flow without the divergence integral (nothing here reads it), with DOP853 as
// every tangent run of the library (engine_instances.ipp says why).
template <engine_model EM>
class tangent_engine_on final : public tangent_engine {
public:
    static constexpr int N = EM::dim;
    using VM = variational_model<EM, false>;

    tangent_engine_on(const EM& em, const tangent_system_options& o, double t, const vec<N>& x,
                      const Eigen::MatrixXd& w)
        : m_vm(em, impact_tangent::saltation), m_flow(system_flow(em, o.flow, o.section)), m_section(o.section),
          m_max_flight(o.max_return_time)
    {
        m_flow.integration = VM::integration_options(o.flow.integration);
        start(t, x, w);
    }
    [[nodiscard]] std::unique_ptr<tangent_engine> clone() const override
    {
        return std::make_unique<tangent_engine_on>(*this);
    }

    outcome step() override
    {
        if (m_status != outcome::ok) return m_status;
        m_run->record().impacts.clear();  // only the states matter here
        if (m_section < 0) {
            m_status = checked(m_run->step());
            publish(m_run->t(), m_run->x());
            return m_status;
        }
        auto& rec = m_run->record();
        while (rec.points.empty()) {
            if (m_status != outcome::ok) return m_status;
            if (m_run->t() - m_t > m_max_flight) return m_status = outcome::time_limit;
            m_status = checked(m_run->step());
        }
        const auto p = rec.points.front();
        rec.points.pop_front();
        publish(p.t, p.x);
        // Projected along the flow onto the section (tangent/section_map.hpp's header).
        const vec<N> xc = VM::point(p.x);
        const vec<N> F = m_vm.base().rhs(xc);
        const vec<N> g = m_vm.base().section_gradient(m_section, xc);
        m_w = (mat<N>::Identity(xc.size(), xc.size()) - F * g.transpose() / g.dot(F)) * m_w;
        return outcome::ok;
    }
    outcome advance_to(double t) override
    {
        if (m_status != outcome::ok) return m_status;
        m_run->record().impacts.clear();
        m_status = checked(m_run->advance_to(t));
        publish(m_run->t(), m_run->x());
        return m_status;
    }
    void set_deviations(const Eigen::MatrixXd& w) override
    {
        m_before.add(m_run->stats());
        start(m_t, vec<N>(m_x), w);
    }
    [[nodiscard]] run_stats stats() const override
    {
        run_stats s = m_before;
        s.add(m_run->stats());
        return s;
    }

private:
    void start(double t, const vec<N>& x, const Eigen::MatrixXd& w)
    {
        // Element by element: Eigen's block copies between fixed and dynamic sizes trip false
        // -Warray-bounds errors in GCC 12 for N = 1.
        mat<N> Y = mat<N>::Zero(x.size(), x.size());
        for (Eigen::Index j = 0; j < w.cols(); ++j)
            for (Eigen::Index i = 0; i < x.size(); ++i) Y(i, j) = w(i, j);
        const vec<N> xs = m_section >= 0 ? past_section(m_vm.base(), m_section, x) : x;
        m_run.emplace(m_vm, m_flow, t, VM::pack(xs, Y, 0.0));
        m_t = t;
        m_x = to_dynamic(x);
        m_w = w;
        m_status = outcome::ok;
    }
    // Read in place, element by element (as start() says why), into the vectors already there.
    void publish(double t, const typename VM::state& X)
    {
        m_t = t;
        const auto Y = VM::matrix_view(X);
        assign_dynamic(X.head(Y.rows()), m_x);
        for (Eigen::Index j = 0; j < m_w.cols(); ++j)
            for (Eigen::Index i = 0; i < Y.rows(); ++i) m_w(i, j) = Y(i, j);
    }
    // The tangent map of a contact phase is not implemented (variational.hpp).
    [[nodiscard]] outcome checked(outcome o) const
    {
        return o == outcome::ok && m_run->flow().sticking_phases() > 0 ? outcome::sticking : o;
    }

    VM m_vm;
    flow_options m_flow;
    int m_section;
    double m_max_flight;
    std::optional<engine::stepping_flow<VM, dop853>> m_run;
    run_stats m_before;  // of the tangent flows before the last start
};

template <class EM>
std::unique_ptr<tangent_engine> make_tangent_engine(const EM& em, const tangent_system_options& o, double t,
                                                    const Eigen::VectorXd& x, const Eigen::MatrixXd& w)
{
    return std::make_unique<tangent_engine_on<EM>>(em, o, t, head_as<EM::dim>(x, state_dim(em)), w);
}

}  // namespace instance

}  // namespace vimpact::detail

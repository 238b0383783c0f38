#pragma once
// The section map and its Jacobian, and Newton shooting for its fixed points: the building
// blocks of Floquet analysis, reusable by a continuation solver.
//
// The section is Sigma = { v = 0, v decreasing } (the maxima of the impacting coordinate, the
// paper's Sigma). A point of Sigma is given by its section coordinates z: the state without
// the velocity component (which is 0 on Sigma). P^k(z) is the state at the k-th return to
// Sigma, through any impacts on the way.
//
// Jacobian. With Phi = dx(t)/dx0 at fixed t (flow STMs and impact jumps multiplied in order,
// integrated as the tangent part of variational_model) and the return time t(x0) fixed by
// v(x(t)) = 0, the derivative of the return point is
//   dx_end/dx0 = (I - F(x_end) e_v^T / F_v(x_end)) Phi
// and the section map's Jacobian is that matrix without the velocity row and column.
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <Eigen/LU>

#include "vimpact/analysis/protocol.hpp"
#include "vimpact/hybrid/flow.hpp"
#include "vimpact/stability/variational.hpp"

namespace vimpact {

template <class Model>
using section_point = vec<Model::dim - 1>;

// State on Sigma -> section coordinates (drop the velocity) and back.
template <class Model>
section_point<Model> to_section(const vec<Model::dim>& x)
{
    section_point<Model> z;
    for (int i = 0, k = 0; i < Model::dim; ++i)
        if (i != Model::velocity) z[k++] = x[i];
    return z;
}

template <class Model>
vec<Model::dim> from_section(const section_point<Model>& z)
{
    vec<Model::dim> x;
    for (int i = 0, k = 0; i < Model::dim; ++i) x[i] = (i == Model::velocity) ? 0.0 : z[k++];
    return x;
}

struct section_map_options {
    // Newton closes the orbit to 1e-11 only if the map itself is that accurate. t_max is the
    // flight time allowed for the requested returns; the section flags are set by the map.
    flow_options flow{.integration{.rtol = 1e-12, .atol = 1e-12}, .t_max = 1e4, .max_steps = 50'000'000};
    impact_tangent jump = impact_tangent::saltation;
    double sample_dt = 0.0;       // > 0: also sample the orbit (state part) every sample_dt
};

template <int N>
struct section_return {
    outcome status = outcome::ok;       // ok: the requested returns were reached
    long sticking_phases = 0;           // > 0: the tangent is not valid (see variational.hpp)
    vec<N> x0;
    vec<N> x_end;                       // state at the last return
    double time = 0.0;                  // return time
    long impacts = 0;                   // impacts before the last return
    mat<N> monodromy;                   // dx(time)/dx0, impacts included
    mat<N - 1> jacobian;                // D P^k in section coordinates
    double divergence_integral = 0.0;   // integral of div F over [0, time]
    double log_det_jumps = 0.0;         // sum of ln|det(jump)| over the impacts
    std::vector<impact_event<N>> impact_list;  // reference states at the impacts (t, pre, post)
    std::vector<timed_state<N>> samples;       // the orbit every sample_dt (if asked)
    run_stats stats;

    [[nodiscard]] bool valid() const { return status == outcome::ok && sticking_phases == 0; }
};

namespace detail {

template <class VModel>
class section_return_observer : public flow_observer {
public:
    static constexpr int N = VModel::base_dim;
    section_return_observer(const VModel& vm, int returns, double sample_dt, section_return<N>& out)
        : m_vm(vm), m_returns(returns), m_dt(sample_dt), m_out(out), m_next(sample_dt)
    {
    }
    [[nodiscard]] bool wants_segments() const { return m_dt > 0.0; }
    [[nodiscard]] bool reached() const { return m_seen >= m_returns; }
    [[nodiscard]] const typename VModel::state& end_state() const { return m_end; }

    // With sampling, the run goes on to the end of the step that holds the last return, so
    // that the step's interpolant is delivered (up to the return) before the stop.
    flow_control on_section(section_kind k, double t, const typename VModel::state& X)
    {
        if (k != section_kind::maximum || reached()) return flow_control::proceed;
        if (++m_seen < m_returns) return flow_control::proceed;
        m_end = X;
        m_out.time = t;
        return m_dt > 0.0 ? flow_control::proceed : flow_control::stop;
    }
    flow_control on_step_end(double)
    {
        if (!reached()) return flow_control::proceed;
        if (m_dt > 0.0) m_out.samples.push_back({m_out.time, VModel::point(m_end)});
        return flow_control::stop;
    }
    flow_control on_impact(double t, const typename VModel::state& pre, const typename VModel::state& post)
    {
        if (reached()) return flow_control::stop;  // after the last return, in its step
        const vec<N> x = VModel::point(pre);
        m_out.impact_list.push_back({t, x, VModel::point(post)});
        ++m_out.impacts;
        const mat<N> jump = impact_jump_matrix(m_vm.base(), x, m_vm.jump());
        m_out.log_det_jumps += std::log(std::abs(jump.determinant()));
        return flow_control::proceed;
    }
    template <class X>
    void on_stick(double, const X&)
    {
        if (!reached()) ++m_out.sticking_phases;
    }
    template <class D>
    void on_segment(const D& d, double ta, double tb, flow_mode)
    {
        if (reached()) tb = std::min(tb, m_out.time);
        while (m_next < tb) {
            if (m_next >= ta) m_out.samples.push_back({m_next, VModel::point(d.value(m_next))});
            m_next = static_cast<double>(++m_index) * m_dt;
        }
    }

private:
    const VModel& m_vm;
    int m_returns;
    double m_dt;
    section_return<N>& m_out;
    int m_seen = 0;
    typename VModel::state m_end;
    double m_next;  // the sample at t = 0 is the start point itself
    long m_index = 1;
};

}  // namespace detail

// P^returns from x0 (on Sigma: x0[velocity] == 0) with the tangent. Time starts at 0.
template <template <int> class Method = dop853, tangent_model Model>
section_return<Model::dim> section_map(const Model& model, const vec<Model::dim>& x0, int returns,
                                       const section_map_options& opt = {})
{
    constexpr int N = Model::dim;
    if (returns < 1) throw input_error("section returns must be >= 1 (got " + std::to_string(returns) + ")");
    using VM = variational_model<Model>;
    const VM vm(model, opt.jump);
    flow_options fo = opt.flow;
    fo.integration = VM::integration_options(opt.flow.integration);
    fo.track_maxima = true;
    fo.track_minima = false;
    hybrid_flow<VM, Method> flow(vm, fo);
    section_return<N> out;
    out.x0 = x0;
    flow.start(0.0, VM::pack(x0, mat<N>::Identity(), 0.0));
    if (opt.sample_dt > 0.0) out.samples.push_back({0.0, x0});
    detail::section_return_observer<VM> obs(vm, returns, opt.sample_dt, out);
    out.status = flow.run(obs);
    out.stats = flow.stats();
    if (out.status == outcome::ok && !obs.reached()) out.status = outcome::time_limit;
    if (out.status != outcome::ok) {
        out.x_end = VM::point(flow.x());
        out.monodromy = VM::matrix(flow.x());
        out.jacobian.setConstant(std::numeric_limits<double>::quiet_NaN());
        return out;
    }
    const auto& X = obs.end_state();
    out.x_end = VM::point(X);
    out.monodromy = VM::matrix(X);
    out.divergence_integral = VM::divergence_integral(X);
    const vec<N> F = model.rhs(out.x_end);
    mat<N> proj = mat<N>::Identity();
    proj -= F * vec<N>::Unit(Model::velocity).transpose() / F[Model::velocity];
    const mat<N> D = proj * out.monodromy;
    for (int i = 0, ri = 0; i < N; ++i) {
        if (i == Model::velocity) continue;
        for (int j = 0, rj = 0; j < N; ++j) {
            if (j == Model::velocity) continue;
            out.jacobian(ri, rj++) = D(i, j);
        }
        ++ri;
    }
    return out;
}

// ---- Newton shooting ---------------------------------------------------------------------

struct shooting_options {
    section_map_options map{};
    double tolerance = 1e-11;   // closure |P^k(z) - z|_inf to reach
    int max_iterations = 20;
};

enum class shooting_status { converged, not_converged, flow_failed, sticking };

constexpr const char* to_string(shooting_status s)
{
    switch (s) {
        case shooting_status::converged: return "converged";
        case shooting_status::not_converged: return "not_converged";
        case shooting_status::flow_failed: return "flow_failed";
        case shooting_status::sticking: return "sticking";
    }
    return "unknown";
}

template <int N>
struct periodic_orbit {
    shooting_status status = shooting_status::not_converged;
    vec<N> x;                       // the refined point on Sigma
    int returns = 0;
    double initial_closure = std::numeric_limits<double>::quiet_NaN();
    double closure = std::numeric_limits<double>::quiet_NaN();  // |P^k(z) - z|_inf at x
    int iterations = 0;
    section_return<N> map;          // P^k at x, with the saltation tangent
    long map_evaluations = 0;
};

// Fixed point of P^returns near x_guess by Newton's method on P^k(z) - z = 0, with step
// halving when the closure does not decrease. The result carries the last map evaluation
// (monodromy, period, impacts) at the returned point.
template <template <int> class Method = dop853, tangent_model Model>
periodic_orbit<Model::dim> find_periodic_orbit(const Model& model, const vec<Model::dim>& x_guess,
                                               int returns, const shooting_options& opt = {})
{
    constexpr int N = Model::dim;
    constexpr int K = N - 1;
    if (!(opt.tolerance > 0.0)) throw input_error("Newton tolerance must be > 0");
    if (opt.max_iterations < 0) throw input_error("Newton iterations must be >= 0");
    section_map_options mo = opt.map;
    mo.jump = impact_tangent::saltation;
    periodic_orbit<N> orb;
    orb.returns = returns;
    auto residual_of = [&](const section_return<N>& r, const vec<N>& x) {
        return vec<K>(to_section<Model>(state_difference(model, r.x_end, x)));
    };
    auto evaluate = [&](const vec<N>& x) {
        ++orb.map_evaluations;
        return section_map<Method>(model, x, returns, mo);
    };
    vec<N> x = x_guess;
    x[Model::velocity] = 0.0;
    section_return<N> r = evaluate(x);
    auto failed = [&](const section_return<N>& e) {
        orb.status = e.sticking_phases > 0 ? shooting_status::sticking : shooting_status::flow_failed;
        orb.x = x;
        orb.map = e;
        return orb;
    };
    if (!r.valid()) return failed(r);
    vec<K> res = residual_of(r, x);
    double norm = res.cwiseAbs().maxCoeff();
    orb.initial_closure = norm;
    for (int it = 0; it < opt.max_iterations && norm > opt.tolerance; ++it) {
        const mat<K> A = r.jacobian - mat<K>::Identity();
        const vec<K> step = A.fullPivLu().solve(-res);
        if (!step.allFinite()) break;
        bool improved = false;
        double lambda = 1.0;
        for (int halving = 0; halving < 10; ++halving, lambda *= 0.5) {
            const vec<N> xt = from_section<Model>(vec<K>(to_section<Model>(x) + lambda * step));
            if (!(model.guard(xt) > 0.0)) continue;  // a trial point beyond the barrier
            section_return<N> rt = evaluate(xt);
            if (!rt.valid()) continue;
            const vec<K> rest = residual_of(rt, xt);
            const double nt = rest.cwiseAbs().maxCoeff();
            if (nt < norm) {
                x = xt;
                r = std::move(rt);
                res = rest;
                norm = nt;
                improved = true;
                break;
            }
        }
        orb.iterations = it + 1;
        if (!improved) break;
    }
    orb.x = x;
    orb.closure = norm;
    orb.map = std::move(r);
    orb.status = norm <= opt.tolerance ? shooting_status::converged : shooting_status::not_converged;
    return orb;
}

}  // namespace vimpact

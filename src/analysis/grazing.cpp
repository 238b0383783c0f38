#include "vimpact/analysis/grazing.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "dispatch.hpp"
#include "vimpact/core/format.hpp"
#include "vimpact/integrate/tangent_integration.hpp"

namespace vimpact {

namespace {

// States to probe a model's functions at: the initial state and a few spread around it.
std::vector<Eigen::VectorXd> probe_states(const model& m)
{
    std::vector<Eigen::VectorXd> out{m.initial_state()};
    for (int k = 1; k <= 3; ++k) {
        Eigen::VectorXd x = m.initial_state();
        for (int j = 0; j < x.size(); ++j) x[j] += 0.1 * k * (j % 2 == 0 ? 1.0 : -1.0) + 0.013 * j;
        out.push_back(std::move(x));
    }
    return out;
}

bool same_bits(const Eigen::VectorXd& a, const Eigen::VectorXd& b)
{
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), sizeof(double) * static_cast<std::size_t>(a.size())) == 0;
}

Eigen::VectorXd field_at(const model& m, const Eigen::VectorXd& x)
{
    Eigen::VectorXd f(m.dim());
    m.table().rhs(m.context(), x.data(), f.data());
    return f;
}

double gap_at(const model& m, int i, const Eigen::VectorXd& x) { return m.table().gap(m.context(), i, x.data()); }
double switching_at(const model& m, int k, const Eigen::VectorXd& x)
{
    return m.table().switching(m.context(), k, x.data());
}

// The model with parameter p moved a little (within its range), or nullopt.
std::optional<model> nudged(const model& m, int p)
{
    const double v = m.parameter(p);
    const double d = 1e-3 * std::max(1.0, std::abs(v));
    for (const double w : {v + d, v - d}) {
        try {
            return m.with_parameter(p, w);
        } catch (const input_error&) {
        }
    }
    return std::nullopt;
}

bool enters_field(const model& m, const model& moved, const std::vector<Eigen::VectorXd>& states)
{
    for (const auto& x : states)
        if (!same_bits(field_at(m, x), field_at(moved, x))) return true;
    return false;
}

// The parameters that change value(model, x) without entering the vector field (at the probe
// states, on their sides of the switches).
template <class Value>
std::vector<int> moving_parameters(const model& m, Value value)
{
    std::vector<int> out;
    const auto states = probe_states(m);
    for (int p = 0; p < static_cast<int>(m.parameters().size()); ++p) {
        const auto moved = nudged(m, p);
        if (!moved || enters_field(m, *moved, states)) continue;
        bool moves = false;
        for (const auto& x : states) moves = moves || value(m, x) != value(*moved, x);
        if (moves) out.push_back(p);
    }
    return out;
}

// The value of `parameter` with value(model, x*) = target: Newton's method in P with
// central-difference slopes, exact in one or two steps for a function affine in P; the slope
// error only slows the last digits. NaN when the function does not depend on P or the root
// leaves the parameter's range.
template <class Value>
double parameter_root(const model& m, int parameter, const Eigen::VectorXd& x_star, double target, Value value)
{
    constexpr double nan = std::numeric_limits<double>::quiet_NaN();
    if (x_star.size() != m.dim() || !x_star.allFinite()) return nan;
    const auto offset = [&](const model& mm) { return value(mm, x_star) - target; };
    double P = m.parameter(parameter);
    double g = offset(m);
    for (int it = 0; it < 40 && g != 0.0; ++it) {
        const double h = 1e-6 * std::max(1.0, std::abs(P));
        double slope = nan;
        try {
            slope = (offset(m.with_parameter(parameter, P + h)) - offset(m.with_parameter(parameter, P - h))) / (2.0 * h);
        } catch (const input_error&) {
            return nan;
        }
        if (!(slope != 0.0) || !std::isfinite(slope)) return nan;
        const double next = P - g / slope;
        double g_next = nan;
        try {
            g_next = offset(m.with_parameter(parameter, next));
        } catch (const input_error&) {
            return nan;
        }
        if (next == P || std::abs(g_next) >= std::abs(g)) {
            if (std::abs(g_next) < std::abs(g)) P = next;
            break;
        }
        P = next;
        g = g_next;
    }
    return P;
}

}  // namespace

void validate(const grazing_options& o)
{
    validate(o.integration);
    check_options(o);
}

std::vector<int> gap_parameters(const model& m, int surface)
{
    return moving_parameters(m, [surface](const model& mm, const Eigen::VectorXd& x) { return gap_at(mm, surface, x); });
}

std::vector<int> switch_parameters(const model& m, int k)
{
    return moving_parameters(m, [k](const model& mm, const Eigen::VectorXd& x) { return switching_at(mm, k, x); });
}

int first_gap_parameter(const model& m)
{
    for (int i = 0; i < m.surface_count(); ++i) {
        const auto g = gap_parameters(m, i);
        if (!g.empty()) return g.front();
    }
    return -1;
}

int first_grazing_parameter(const model& m)
{
    if (const int p = first_gap_parameter(m); p >= 0) return p;
    for (int k = 0; k < static_cast<int>(m.info().switches.size()); ++k) {
        const auto w = switch_parameters(m, k);
        if (!w.empty()) return w.front();
    }
    return -1;
}

int surface_moved_by(const model& m, int parameter)
{
    for (int i = 0; i < m.surface_count(); ++i) {
        const auto g = gap_parameters(m, i);
        if (std::find(g.begin(), g.end(), parameter) != g.end()) return i;
    }
    return -1;
}

int switch_moved_by(const model& m, int parameter)
{
    for (int k = 0; k < static_cast<int>(m.info().switches.size()); ++k) {
        const auto w = switch_parameters(m, k);
        if (std::find(w.begin(), w.end(), parameter) != w.end()) return k;
    }
    return -1;
}

double switch_side_at(const model& m, int k, const Eigen::VectorXd& x)
{
    // The flow's rule (hybrid_flow::pin_sides_at): where h = 0, the side the field goes to.
    const double h = switching_at(m, k, x);
    if (h != 0.0) return h > 0.0 ? 1.0 : -1.0;
    Eigen::VectorXd g(m.dim());
    m.table().switching_gradient(m.context(), k, x.data(), g.data());
    return g.dot(field_at(m, x)) >= 0.0 ? 1.0 : -1.0;
}

double switch_rest_gap(const model& m, int k, double side) { return side * switching_at(m, k, m.initial_state()); }

double switch_parameter_for_gap(const model& m, int k, int parameter, const Eigen::VectorXd& x, double side,
                                double target)
{
    return parameter_root(m, parameter, x, target,
                          [k, side](const model& mm, const Eigen::VectorXd& y) { return side * switching_at(mm, k, y); });
}

double rest_gap(const model& m, int surface) { return gap_at(m, surface, m.initial_state()); }

double grazing_parameter_value(const model& m, int surface, int parameter, const Eigen::VectorXd& x_star)
{
    return parameter_for_gap(m, surface, parameter, x_star, 0.0);
}

double parameter_for_gap(const model& m, int surface, int parameter, const Eigen::VectorXd& x_star, double target)
{
    return parameter_root(m, parameter, x_star, target,
                          [surface](const model& mm, const Eigen::VectorXd& x) { return gap_at(mm, surface, x); });
}

double switch_grazing_parameter_value(const model& m, int k, int parameter, const Eigen::VectorXd& x_star)
{
    return parameter_root(m, parameter, x_star, 0.0,
                          [k](const model& mm, const Eigen::VectorXd& x) { return switching_at(mm, k, x); });
}

grazing_options job_grazing_options(const integrator_options& protocol_integration, double transient_time)
{
    grazing_options go;
    go.integration = tangent_integration(protocol_integration);
    go.transient_time = transient_time;
    return go;
}

void validate(const model& m, const grazing_options& o)
{
    validate(o);
    const int W = static_cast<int>(m.info().switches.size());
    if (m.surface_count() == 0 && W == 0)
        throw input_error("model " + m.name() + " has no impact surface or switch to graze");
    if (o.response_variable >= m.dim()) throw input_error("response variable index out of range");
    if (o.parameter < 0) {
        if (o.parameter != -1 && o.parameter != each_surface_gap_parameter)
            throw input_error("grazing parameter index out of range");
        return;
    }
    if (o.parameter >= static_cast<int>(m.parameters().size())) throw input_error("parameter index out of range");
    const auto& name = m.info().parameters[static_cast<std::size_t>(o.parameter)].name;
    const auto moved = nudged(m, o.parameter);
    if (moved && enters_field(m, *moved, probe_states(m)))
        throw input_error("parameter " + name + " enters the vector field of model " + m.name() +
                          ": a grazing value is one of a parameter that only moves a surface");
    for (int i = 0; i < m.surface_count(); ++i) {
        const auto g = gap_parameters(m, i);
        if (std::find(g.begin(), g.end(), o.parameter) != g.end()) return;
    }
    for (int k = 0; k < W; ++k) {
        const auto g = switch_parameters(m, k);
        if (std::find(g.begin(), g.end(), o.parameter) != g.end()) return;
    }
    throw input_error("parameter " + name + " moves no surface or switch of model " + m.name() +
                      ": a grazing value is one of a parameter that moves a surface or a switch");
}

grazing_result grazing(const model& m, const Eigen::VectorXd& x0, const grazing_options& o)
{
    validate(m, o);
    check_state_size(m, x0.size(), "the initial state");
    if (!x0.allFinite()) throw input_error("initial state must be finite");
    auto res = detail::with_engine(m, [&](const auto& em) { return detail::run_grazing(em, x0, o); });
    for (int i = 0; i < m.surface_count(); ++i) {
        auto& s = res.surfaces[static_cast<std::size_t>(i)];
        if (o.parameter >= 0) {
            s.parameter = o.parameter;
        } else if (o.parameter == each_surface_gap_parameter) {
            const auto own = gap_parameters(m, i);
            if (!own.empty()) s.parameter = own.front();
        }
        if (s.parameter >= 0 && s.x.size() == m.dim()) s.parameter_value = grazing_parameter_value(m, i, s.parameter, s.x);
    }
    for (int k = 0; k < static_cast<int>(res.switches.size()); ++k) {
        auto& s = res.switches[static_cast<std::size_t>(k)];
        if (o.parameter >= 0) {
            s.parameter = o.parameter;
        } else if (o.parameter == each_surface_gap_parameter) {
            const auto own = switch_parameters(m, k);
            if (!own.empty()) s.parameter = own.front();
        }
        if (s.parameter >= 0 && s.x.size() == m.dim())
            s.parameter_value = switch_grazing_parameter_value(m, k, s.parameter, s.x);
    }
    return res;
}

bool parameter_enters_field(const model& m, int parameter)
{
    const auto moved = nudged(m, parameter);
    return moved && enters_field(m, *moved, probe_states(m));
}

}  // namespace vimpact

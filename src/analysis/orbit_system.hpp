#pragma once
// The periodic-orbit equations G(z, p) = 0 of a model family as an arclength system
// (arclength.hpp): unknowns u = (z, p_1, ..., p_m), the chart coordinates of the orbit's
// section point followed by the m continued parameters. G_z comes from the tangent flow,
// G_p by central differences of the map in each parameter (one-sided at the end of a
// parameter's valid range).
#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "arclength.hpp"
#include "vimpact/analysis/continuation.hpp"
#include "vimpact/analysis/orbit_map.hpp"
#include "vimpact/model/model.hpp"

namespace vimpact::detail {

// Where a grazing happens on an orbit: a surface and a time window around the grazing
// minimum (or the impact that replaces it), clear of the orbit's other impacts.
struct grazing_window {
    int surface = 0;
    double from = 0.0, until = 0.0;
};

class orbit_system {
public:
    orbit_system(model base, std::vector<int> parameters, orbit_map_request request)
        : m_base(std::move(base)), m_parameters(std::move(parameters)), m_request(std::move(request))
    {
    }

    [[nodiscard]] int chart_size() const { return m_base.dim() - 1; }
    [[nodiscard]] int parameter_count() const { return static_cast<int>(m_parameters.size()); }
    [[nodiscard]] const model& base() const { return m_base; }
    [[nodiscard]] const std::vector<int>& parameters() const { return m_parameters; }
    [[nodiscard]] const orbit_map_request& request() const { return m_request; }
    [[nodiscard]] int returns() const { return m_request.returns; }

    // The same equations with other returns or absent surfaces.
    [[nodiscard]] orbit_system with_returns(int k) const;
    // Surface w.surface absent in the time window of w (from the orbit's section point).
    [[nodiscard]] orbit_system with_absent(const grazing_window& w) const;

    // The model at the parameters of u (throws input_error outside their valid ranges).
    [[nodiscard]] model model_at(const Eigen::VectorXd& u) const;
    // The map at u (status inadmissible for parameters outside their valid range); with
    // forced_surface >= 0 an impact forced on it at forced_time (orbit_map_request).
    [[nodiscard]] orbit_map_value map(const Eigen::VectorXd& u, bool tangent, int forced_surface = -1,
                                      double forced_time = 0.0) const;
    // G at u, with [G_z G_p] when `jacobian`.
    [[nodiscard]] arc_eval operator()(const Eigen::VectorXd& u, bool jacobian) const;
    // dG/dp_j at u by a central difference of the map, its step scaled to the orbit's distance
    // to grazing (`centre`: the map at u); NaN-filled when the map fails on both sides.
    [[nodiscard]] Eigen::VectorXd parameter_derivative(const Eigen::VectorXd& u, int j,
                                                       const orbit_map_value& centre) const;

    [[nodiscard]] arc_system as_function() const
    {
        return [this](const Eigen::VectorXd& u, bool jac) { return (*this)(u, jac); };
    }

    [[nodiscard]] long tangent_maps() const { return m_tangent_maps; }
    [[nodiscard]] long plain_maps() const { return m_plain_maps; }

    // The point of the section with chart coordinates z (the chart's solve for x_c).
    [[nodiscard]] continuation_point to_point(const arc_point& p) const;

private:
    model m_base;
    std::vector<int> m_parameters;
    orbit_map_request m_request;
    mutable long m_tangent_maps = 0;
    mutable long m_plain_maps = 0;
};

// The orbits with an impact on a surface forced at a time t_i, the surface absent around it
// otherwise (orbit_map_request::forced_surface): unknowns (z, p, t_i), equations G = 0 and the
// gap at t_i = 0. The family of orbits with that impact is smooth through the grazing orbit
// (impact velocity 0) in these unknowns, where the section map's Jacobian grows like 1 / v:
// a continuation follows it a few steps off the grazing onto the impacting family.
class forced_system {
public:
    forced_system(const orbit_system& orbits, const grazing_window& w) : m_orbits(orbits.with_absent(w)), m_surface(w.surface)
    {
    }
    [[nodiscard]] const orbit_system& orbits() const { return m_orbits; }
    [[nodiscard]] orbit_map_value map(const Eigen::VectorXd& u) const;
    [[nodiscard]] arc_eval operator()(const Eigen::VectorXd& u, bool jacobian) const;
    [[nodiscard]] arc_system as_function() const
    {
        return [this](const Eigen::VectorXd& u, bool jac) { return (*this)(u, jac); };
    }

private:
    orbit_system m_orbits;
    int m_surface;
};

// The window around time t of an orbit for surface i: a quarter of the time to the nearest
// other impact on either side (a quarter period when there is none).
grazing_window window_around(const orbit_map_value& o, int i, double t);

// The grazing test function: the smallest gap minimum of the window's surface inside the
// window, with the surface absent there (negative: the orbit crosses the surface). None when
// the window holds no minimum.
std::optional<double> grazing_test(const orbit_map_value& o, const grazing_window& w);
// That minimum itself (its time, surface and gap).
std::optional<gap_minimum_record> grazing_minimum(const orbit_map_value& o, const grazing_window& w);

// The test function of a switch's grazing: the extremum of switching function k on the orbit
// that lies nearest 0, signed. It goes through 0 where the orbit starts or stops crossing the
// switch there (the flow is continuous: no window, nothing absent). None without one.
std::optional<double> nearest_switch_extremum(const orbit_map_value& o, int k);

// Both maps ok with the same impacts in the same order: a difference between them is smooth.
bool same_impacts(const orbit_map_value& a, const orbit_map_value& b);

// The nontrivial multipliers of a point inside the unit circle.
bool stable_multipliers(const std::vector<std::complex<double>>& section_multipliers);

}  // namespace vimpact::detail

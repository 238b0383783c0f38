#pragma once
// Grazing: where the attracting surface-free orbit just touches each impact surface, and the
// switch-free orbit each switching surface.
//
// The surface-free flow (every surface off) runs past a transient; the minima of each gap
// g_i along the orbit (zeros of g_i' going up) are located on the interpolant, and the
// smallest over consecutive blocks of minima is compared until two blocks agree within
// `tolerance`. That smallest gap is the surface's grazing margin: the orbit clears the
// surface by it (a negative margin: the free orbit would cross the surface).
//
// In a parameter P that moves the surface without entering the vector field (the paper's
// sigma, the stops' d), the grazing value P_graze solves g_i(x*, P) = 0 at the state x* of
// the minimum: a barrier just on the admissible side of it is never hit, one just beyond it is.
// For a gap affine in P (y - sigma, d - x) it is exact: sigma_graze is the minimum of y.
//
// Switches the same way: the switch-free flow holds the sides of the start (the field of
// those sides throughout, no crossing sought), and the minima of each distance side * h_k
// give the switch's margin: positive, the orbit stays on its side; negative, it would cross.
// A grazing value of a parameter that moves the switch's function without entering the field
// of the held side (the stop's position d of a compliant stop) solves h_k(x*, P) = 0.
//
// The same run measures the surface-free response of one state variable (lock-in curves):
// its largest and smallest extremum over the last block and its mean angular frequency from
// the times of its minima, 2 pi (n - 1) / (t_n - t_1).
#include <atomic>
#include <limits>
#include <vector>

#include <Eigen/Core>

#include "vimpact/analysis/protocol.hpp"
#include "vimpact/core/option.hpp"

namespace vimpact {

// grazing_options::parameter: for each surface, its own first gap parameter (gap_parameters):
// sigma for the paper's barrier, d for both stops; none for a surface that has none.
inline constexpr int each_surface_gap_parameter = -2;

struct grazing_options {
    integrator_options integration{.rtol = 1e-12, .atol = 1e-12};
    integration_method method = integration_method::dop853;
    double transient_time = 1000.0;
    int block = 16;              // minima per block
    double tolerance = 1e-11;    // agreement of successive block minima
    double t_max = 1e5;
    // >= 0: also the grazing value of this parameter, for every surface;
    // each_surface_gap_parameter: of each surface's own; -1: none.
    int parameter = -1;
    int response_variable = -1;  // >= 0: also the response of this state variable
    const std::atomic<bool>* cancel = nullptr;  // see flow_options::cancel
};

// The options of the surface-free run a user sets by name (core/option.hpp); the integration
// is the run's (rtol, atol, method), the parameter resolved by each front end.
template <class V, record_of<grazing_options> O>
void declare(V& v, O& o)
{
    v(option{"transient_time", "time discarded before minima count", at_least(0.0)}, o.transient_time);
    v(option{"tol", "agreement of successive block minima", above(0.0)}, o.tolerance);
    v(option{"block", "minima per block", at_least(1.0)}, o.block);
    v(option{"t_max", "give up (not converged, outcome time_limit) at this time", above(0.0)}, o.t_max);
}

struct surface_grazing {
    bool converged = false;
    int parameter = -1;          // the parameter of parameter_value, -1 when none
    double margin = std::numeric_limits<double>::quiet_NaN();           // smallest gap on the orbit
    double change = std::numeric_limits<double>::quiet_NaN();           // last block-to-block change
    double parameter_value = std::numeric_limits<double>::quiet_NaN();  // P_graze (parameter >= 0)
    double t = 0.0;              // time of the minimum
    Eigen::VectorXd x;           // state at the minimum
    long minima = 0;
};

struct grazing_result {
    outcome status = outcome::ok;
    bool converged = false;  // every surface and switch converged
    std::vector<surface_grazing> surfaces;
    std::vector<surface_grazing> switches;  // of the switching surfaces
    // The response of grazing_options::response_variable over the last block.
    double response_max = std::numeric_limits<double>::quiet_NaN();
    double response_min = std::numeric_limits<double>::quiet_NaN();
    double response_omega = std::numeric_limits<double>::quiet_NaN();
    run_stats stats;
};

void validate(const grazing_options& o);
// Also: the model has a surface, the parameter moves one without entering the vector field.
void validate(const model& m, const grazing_options& o);

// Throws input_error for bad options, or a parameter that enters the vector field or does not
// move any surface.
grazing_result grazing(const model& m, const Eigen::VectorXd& x0, const grazing_options& o);

// The parameters that move surface i without entering the vector field: the candidates for a
// grazing value (sigma for the paper's barrier, d for the two stops).
std::vector<int> gap_parameters(const model& m, int surface);

// The parameters that move switch k's function without entering the vector field (at the
// probe states, on their sides): the candidates for a switch's grazing value.
std::vector<int> switch_parameters(const model& m, int k);
// P_graze of switch k at x*: the value of `parameter` with h_k(x*, P) = 0 (NaN as above).
double switch_grazing_parameter_value(const model& m, int k, int parameter, const Eigen::VectorXd& x_star);

// The first parameter that moves any surface without entering the vector field, -1 if none.
int first_gap_parameter(const model& m);
// first_gap_parameter, else the first that moves a switch (switch_parameters), -1 if none: the
// default grazing parameter of a sweep's grazing line and of a response.
int first_grazing_parameter(const model& m);
// The first surface that `parameter` moves (gap_parameters), -1 if none.
int surface_moved_by(const model& m, int parameter);
// The first switch that `parameter` moves (switch_parameters), -1 if none.
int switch_moved_by(const model& m, int parameter);
// The side of switch k at x, as the flow takes it at a start: the sign of h_k(x), and where
// h_k = 0 the side the field goes to.
double switch_side_at(const model& m, int k, const Eigen::VectorXd& x);
// rest_gap of switch k: side * h_k at the model's initial state.
double switch_rest_gap(const model& m, int k, double side);
// The value of `parameter` with side * h_k(x, P) = target: the distance `target` on the side
// `side` of switch k (NaN as for grazing_parameter_value).
double switch_parameter_for_gap(const model& m, int k, int parameter, const Eigen::VectorXd& x, double side,
                                double target);
// The gap of surface i at the model's initial state, its rest state (for the paper's barrier
// y - sigma at y = 0: -sigma): the distance to the surface that SI gaps and clearances measure.
double rest_gap(const model& m, int surface);

// Whether changing the parameter changes the vector field (probed at a few states around the
// model's initial state; a parameter that only moves surfaces does not).
bool parameter_enters_field(const model& m, int parameter);

// P_graze of surface i at the state x*: the value of `parameter` with g_i(x*, P) = 0 (NaN if
// the surface does not depend on it or the root leaves the parameter's range).
double grazing_parameter_value(const model& m, int surface, int parameter, const Eigen::VectorXd& x_star);
// The value of `parameter` with g_i(x, P) = gap (the same root finder; NaN as above).
double parameter_for_gap(const model& m, int surface, int parameter, const Eigen::VectorXd& x, double gap);

// The tolerances of a grazing run inside a job (a sweep's grazing line, a response point): the
// caller's, never looser than 1e-12, since the grazing value is wanted to about 1e-9.
grazing_options job_grazing_options(const integrator_options& protocol_integration,
                                    double transient_time = grazing_options{}.transient_time);

}  // namespace vimpact

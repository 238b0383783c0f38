#pragma once
// The options of the adaptive step-size control, apart from the integrator itself
// (integrate/adaptive_integrator.hpp), so that option and result types can name them without
// the Runge-Kutta machinery.
#include <limits>
#include <optional>

namespace vimpact {

struct integrator_options {
    double rtol = 1e-10;
    double atol = 1e-10;
    double h_max = std::numeric_limits<double>::infinity();
    double h_init = 0.0;   // 0: estimated from the vector field (Hairer's algorithm)
    double safety = 0.9;
    double factor_min = 0.2;
    double factor_max = 10.0;
    // Proportional-integral step control (integrate/step_control.hpp; Hairer's DOPRI5 uses
    // 0.04): damps the accept/reject oscillation of a purely proportional controller (measured
    // on the paper's model with DOP853 at 1e-10: 8 % fewer trial steps than beta = 0).
    // 0: proportional.
    double pi_beta = 0.04;
    // Hold band: an accepted step whose error norm lies in [hold_band, 1] keeps the step size
    // (integrate/step_control.hpp). In [0, 1); 0: off, the controller acts on every step;
    // none: the method's default_hold_band (DOPRI5 0.1, DOP853 0). Its cost and accuracy:
    // docs/performance.md, "The hold band".
    std::optional<double> hold_band = std::nullopt;
};

}  // namespace vimpact

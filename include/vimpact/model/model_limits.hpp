#pragma once
// How large a model may be.

namespace vimpact {

// The largest state dimension accepted: a tangent run (Floquet, Lyapunov, the tangent system)
// carries N + N^2 doubles per state, 8 MB per state vector at N = 1000 and a dozen such
// vectors per Runge-Kutta step.
inline constexpr int max_model_dimension = 1000;

}  // namespace vimpact

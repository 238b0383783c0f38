#pragma once
// The parts of the extension module _vimpact, one per source file.
#include <pybind11/pybind11.h>

namespace vimpact::python {

void bind_models(pybind11::module_& m);     // _Model: the library's model handle
void bind_runs(pybind11::module_& m);       // _simulate, _period, _grazing
void bind_jobs(pybind11::module_& m);       // _sweep, _map, _basins, _response (the job loop)
void bind_stability(pybind11::module_& m);  // _floquet, _lyapunov and their sweeps
void bind_dimension(pybind11::module_& m);  // _dimension
void bind_continuation(pybind11::module_& m);  // _continuation
void bind_units(pybind11::module_& m);      // _SIUnits: SI inputs and outputs
void bind_systems(pybind11::module_& m);    // _HybridSystem, _SectionSystem, _TangentSystem

}  // namespace vimpact::python

#pragma once
// Parts of the library that some runs only need are modules of their own, loaded the first
// time a run needs them: libvimpact_symbolic.so (GiNaC: reading model files),
// libvimpact_mpi.so (MPI: a run launched as several ranks) and each engine model's analyses,
// libvimpact_engine_MODEL.so (engine_instances.hpp). A run of a built-in model in one process
// loads that model's module only; none is loaded at start-up.
namespace vimpact::detail {

// The address of `symbol` in the module `file`, which lies beside libvimpact.so (the build
// directory, an install's library directory, a Python package's vimpact/). The module is
// loaded once and stays loaded. Throws std::runtime_error naming the file when it cannot be
// loaded: an incomplete installation, not bad input.
void* module_symbol(const char* file, const char* symbol);

}  // namespace vimpact::detail

// How this process was launched (MPI's launchers announce the ranks in the environment), and
// MPI_COMM_WORLD as the ranks of a many-job run (jobs/job_ranks.hpp) from the module
// libvimpact_mpi.so (src/modules/mpi.cpp), loaded only by a process launched as several ranks.
#include "vimpact/jobs/job_ranks.hpp"

#include <cstdlib>
#include <mutex>

#include "vimpact/core/input_error.hpp"

#include "core/load_module.hpp"

namespace vimpact {

namespace {

long env_long(const char* name)
{
    const char* v = std::getenv(name);
    if (!v || !*v) return -1;
    char* end = nullptr;
    const long n = std::strtol(v, &end, 10);
    return end && *end == '\0' ? n : -1;
}

// The number of ranks an MPI launcher announced in the environment (Open MPI's mpirun, and
// the PMI of MPICH's mpiexec and of srun), or -1 when none did.
long announced_size()
{
    for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "MPI_LOCALNRANKS"})
        if (const long n = env_long(name); n >= 1) return n;
    // srun --mpi=pmix announces ranks only through PMIx; the task count is Slurm's.
    if (std::getenv("PMIX_RANK")) return env_long("SLURM_NTASKS") >= 1 ? env_long("SLURM_NTASKS") : 1;
    return -1;
}

}  // namespace

bool built_with_mpi()
{
#ifdef VIMPACT_HAVE_MPI
    return true;
#else
    return false;
#endif
}

bool launched_as_mpi_ranks() { return announced_size() > 1; }

int launched_rank()
{
    for (const char* name : {"OMPI_COMM_WORLD_RANK", "PMI_RANK", "PMIX_RANK"})
        if (const long r = env_long(name); r >= 0) return static_cast<int>(r);
    return 0;
}

#ifdef VIMPACT_HAVE_MPI

std::shared_ptr<job_ranks> mpi_world_ranks()
{
    static std::mutex mutex;
    static std::weak_ptr<job_ranks> world;
    const std::lock_guard lock(mutex);
    if (announced_size() <= 1) return nullptr;
    if (auto w = world.lock()) return w->size() > 1 ? w : nullptr;
    using make_ranks = job_ranks* (*)();
    const auto make = reinterpret_cast<make_ranks>(detail::module_symbol("libvimpact_mpi.so", "vimpact_mpi_world_ranks_v1"));
    std::shared_ptr<job_ranks> w(make());
    world = w;
    return w->size() > 1 ? w : nullptr;
}

#else

std::shared_ptr<job_ranks> mpi_world_ranks()
{
    if (launched_as_mpi_ranks())
        throw input_error("this vimpact was built without MPI (CMake option VIMPACT_MPI, and an MPI library such as "
                          "Debian's libopenmpi-dev), so its " + std::to_string(announced_size()) +
                          " ranks would each run the whole job: run one process, with --threads or --shard");
    return nullptr;
}

#endif

}  // namespace vimpact

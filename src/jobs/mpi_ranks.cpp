// MPI_COMM_WORLD as the ranks of a many-job run (jobs/job_ranks.hpp). Only the thread that
// initialised MPI calls it (MPI_THREAD_FUNNELED): the job loop's coordinating thread; the
// computing threads never do.
#include "vimpact/jobs/job_ranks.hpp"

#include <chrono>
#include <cstdlib>
#include <list>
#include <mutex>
#include <stdexcept>
#include <thread>

#include "vimpact/core/input_error.hpp"

#ifdef VIMPACT_HAVE_MPI
// The C interface only: the deprecated C++ bindings would be linked otherwise.
#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>
#endif

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

namespace {

class mpi_ranks final : public job_ranks {
public:
    mpi_ranks()
    {
        int initialised = 0, finalised = 0;
        MPI_Initialized(&initialised);
        MPI_Finalized(&finalised);
        if (finalised) throw std::runtime_error("MPI was finalised already in this process");
        if (!initialised) {
            int provided = 0;
            MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
            m_owns = true;
        }
        MPI_Comm_dup(MPI_COMM_WORLD, &m_comm);
        MPI_Comm_rank(m_comm, &m_rank);
        MPI_Comm_size(m_comm, &m_size);
        MPI_Comm node;
        MPI_Comm_split_type(m_comm, MPI_COMM_TYPE_SHARED, m_rank, MPI_INFO_NULL, &node);
        MPI_Comm_size(node, &m_local);
        MPI_Comm_free(&node);
    }
    ~mpi_ranks() override
    {
        flush();
        MPI_Comm_free(&m_comm);
        if (m_owns) MPI_Finalize();
    }
    mpi_ranks(const mpi_ranks&) = delete;
    mpi_ranks& operator=(const mpi_ranks&) = delete;

    [[nodiscard]] int rank() const override { return m_rank; }
    [[nodiscard]] int size() const override { return m_size; }
    [[nodiscard]] int local_size() const override { return m_local; }

    void send(int to, int tag, std::string bytes) override
    {
        reap();
        auto& p = m_pending.emplace_back();
        p.bytes = std::move(bytes);
        MPI_Isend(p.bytes.data(), static_cast<int>(p.bytes.size()), MPI_CHAR, to, tag, m_comm, &p.request);
    }

    std::optional<rank_message> receive() override
    {
        reap();
        int flag = 0;
        MPI_Message handle;
        MPI_Status status;
        MPI_Improbe(MPI_ANY_SOURCE, MPI_ANY_TAG, m_comm, &flag, &handle, &status);
        if (!flag) return std::nullopt;
        int count = 0;
        MPI_Get_count(&status, MPI_CHAR, &count);
        rank_message m;
        m.from = status.MPI_SOURCE;
        m.tag = status.MPI_TAG;
        m.bytes.resize(static_cast<std::size_t>(count));
        MPI_Mrecv(m.bytes.data(), count, MPI_CHAR, &handle, MPI_STATUS_IGNORE);
        return m;
    }

    void flush() override
    {
        // Polled with pauses: a blocking wait spins a core inside Open MPI.
        while (reap() > 0) std::this_thread::sleep_for(std::chrono::microseconds(200));
    }

private:
    struct pending {
        std::string bytes;
        MPI_Request request = MPI_REQUEST_NULL;
    };

    // Frees the sends that have left; returns how many have not.
    std::size_t reap()
    {
        for (auto it = m_pending.begin(); it != m_pending.end();) {
            int done = 0;
            MPI_Test(&it->request, &done, MPI_STATUS_IGNORE);
            it = done ? m_pending.erase(it) : std::next(it);
        }
        return m_pending.size();
    }

    MPI_Comm m_comm = MPI_COMM_NULL;
    int m_rank = 0, m_size = 1, m_local = 1;
    bool m_owns = false;
    std::list<pending> m_pending;  // a list: the buffers must not move while they are sent
};

}  // namespace

std::shared_ptr<job_ranks> mpi_world_ranks()
{
    static std::mutex mutex;
    static std::weak_ptr<job_ranks> world;
    const std::lock_guard lock(mutex);
    if (announced_size() <= 1) return nullptr;
    if (auto w = world.lock()) return w->size() > 1 ? w : nullptr;
    auto w = std::make_shared<mpi_ranks>();
    world = w;
    return w->size() > 1 ? std::shared_ptr<job_ranks>(w) : nullptr;
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

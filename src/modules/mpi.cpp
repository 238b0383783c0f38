// MPI_COMM_WORLD as the ranks of a many-job run (jobs/job_ranks.hpp): a module of its own
// (libvimpact_mpi.so), loaded by mpi_world_ranks() only in a process that an MPI launcher
// started as one of several ranks, so that no other run loads the MPI library. Only the thread
// that initialised MPI calls it (MPI_THREAD_FUNNELED): the job loop's coordinating thread; the
// computing threads never do.
#include <chrono>
#include <list>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>

// The C interface only: the deprecated C++ bindings would be linked otherwise.
#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>

#include "vimpact/jobs/job_ranks.hpp"

namespace vimpact {

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

}  // namespace vimpact

// The module's entry (core/load_module.hpp): a new handle on MPI_COMM_WORLD, owned by the caller.
extern "C" vimpact::job_ranks* vimpact_mpi_world_ranks_v1() { return new vimpact::mpi_ranks(); }

#pragma once
// The processes of one many-job run (MPI ranks): how the job loop (jobs/job_loop.hpp) talks
// to the others. Rank 0 coordinates: it hands out jobs, receives every result and delivers
// them in job order; the other ranks compute what they are given. Messages are byte strings
// with a tag, sent without blocking and received by polling, so that no rank spins in the
// MPI library while its threads compute.
//
// The interface names no MPI type: the library is linked with MPI when it is built with it
// (CMake option VIMPACT_MPI), and a test can connect ranks inside one process.
#include <memory>
#include <optional>
#include <string>

namespace vimpact {

struct rank_message {
    int from = 0;
    int tag = 0;
    std::string bytes;
};

class job_ranks {
public:
    virtual ~job_ranks() = default;
    [[nodiscard]] virtual int rank() const = 0;
    [[nodiscard]] virtual int size() const = 0;
    // Ranks sharing this machine (the default thread count divides its cores among them).
    [[nodiscard]] virtual int local_size() const { return 1; }
    // Queues a message; it leaves while the caller goes on.
    virtual void send(int to, int tag, std::string bytes) = 0;
    // A message that has arrived for this rank, if any; never waits.
    virtual std::optional<rank_message> receive() = 0;
    // Waits until every message this rank sent has left.
    virtual void flush() = 0;
};

// Whether this library was built with MPI.
bool built_with_mpi();

// Whether this process was started by an MPI launcher (mpirun, mpiexec, srun) as one of
// several ranks, as its environment says.
bool launched_as_mpi_ranks();
// This process's rank as the launcher announced it (0 when none did): before MPI starts, for
// messages that only rank 0 should print.
int launched_rank();

// The ranks of MPI_COMM_WORLD, MPI initialised on the first call and finalised when the last
// handle goes; null when the process was not launched as one of several ranks. Throws
// input_error when it was but the library was built without MPI.
std::shared_ptr<job_ranks> mpi_world_ranks();

}  // namespace vimpact

#pragma once
// A many-job run's list of jobs: how many, which continue from which (chains), and which
// belong to one shard of the run.
#include <string>

#include "vimpact/core/input_error.hpp"

namespace vimpact {

// Shard i/n owns every chain c with c % n == i (for independent jobs, every n-th job); n
// processes with i = 0..n-1 together compute every job exactly once.
struct shard_spec {
    long index = 0;
    long count = 1;

    [[nodiscard]] bool owns_chain(long chain) const { return chain % count == index; }
};

// Chained jobs (a parameter sweep that follows its branch): job j starts from the result of
// job j - chains. With chains = 2 an upward and a downward sweep interleave and run in parallel.
struct job_schedule {
    long jobs = 0;
    long chains = 0;  // 0: independent jobs; c > 0: job j continues from job j - c

    [[nodiscard]] bool chained() const { return chains > 0; }
    [[nodiscard]] long chain_of(long job) const { return chained() ? job % chains : job; }
    [[nodiscard]] long predecessor(long job) const { return chained() && job >= chains ? job - chains : -1; }
};

inline void validate(const shard_spec& s)
{
    if (s.count < 1 || s.index < 0 || s.index >= s.count)
        throw input_error("shard " + std::to_string(s.index) + "/" + std::to_string(s.count) +
                          " is invalid (need 0 <= i < n, n >= 1)");
}

}  // namespace vimpact

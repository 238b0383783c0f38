#pragma once
// The protocol runs of a job runner's stream (jobs/job_loop.hpp) for the analyses whose jobs
// may start beyond a surface (sweep, basins): such a job is not run, it is handed back at once
// with a record saying so, and the job source is asked again.
#include <optional>
#include <utility>

#include "vimpact/analysis/protocol.hpp"
#include "jobs/job_loop.hpp"

namespace vimpact::detail {

// make(job) -> protocol_job; inadmissible(protocol_job&&): the job whose initial state lies
// beyond a surface.
template <class Make, class Inadmissible>
protocol_source admissible_jobs(job_source next, Make make, Inadmissible inadmissible)
{
    return [next = std::move(next), make, inadmissible]() -> std::optional<protocol_job> {
        for (;;) {
            const std::optional<long> job = next();
            if (!job) return std::nullopt;
            protocol_job pj = make(*job);
            if (violated_surface(pj.m, pj.x0) < 0) return pj;
            inadmissible(std::move(pj));
        }
    };
}

}  // namespace vimpact::detail

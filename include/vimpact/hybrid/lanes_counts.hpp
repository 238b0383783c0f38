#pragma once
// What a run of jobs in SIMD lanes did (hybrid/flow_lanes.hpp): how its lanes were used.

namespace vimpact {

struct lanes_counts {
    long lane_trials = 0;  // trials of all the lanes together
    long steps_alone = 0;  // steps lanes took on their own at a list's end (few lanes busy)
};

}  // namespace vimpact

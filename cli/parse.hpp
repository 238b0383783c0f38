#pragma once
// Text to values for the options: numbers, lists, ranges, shards. Every function throws
// input_error naming the option (`what`) and the text it could not read.
#include <string>
#include <utility>
#include <vector>

#include "vimpact/core/value_grid.hpp"
#include "vimpact/jobs/job_schedule.hpp"

namespace vimpact::cli {

double parse_number(const std::string& text, const std::string& what);
long parse_count(const std::string& text, const std::string& what);  // an integer >= 0
std::vector<std::string> split(const std::string& text, char sep);
std::vector<double> parse_numbers(const std::string& text, const std::string& what);  // "1,2,3"

// "a:b:n": n values from a to b inclusive, as a range (never enumerated).
value_grid parse_range(const std::string& text, const std::string& what);

// "NAME:a:b:n": a name and its values.
struct named_range {
    std::string name;
    value_grid values;
};
named_range parse_named_range(const std::string& text, const std::string& what);

shard_spec parse_shard(const std::string& text);  // "I/N", 0 <= I < N

// "KEY=VALUE,KEY=VALUE": the pairs in order (the keys are the caller's to check).
std::vector<std::pair<std::string, double>> parse_pairs(const std::string& text, const std::string& what);

}  // namespace vimpact::cli

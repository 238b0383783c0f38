// The ranks of one many-job run agree on what they run (journal.hpp, check_same_run): ranks
// started with different options would otherwise merge their results into one run, silently.
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <thread>

#include "journal.hpp"
#include "jobs/job_loop.hpp"

namespace vimpact::detail {

namespace {

// "model/parameters/A" for the pointer "/model/parameters/A".
std::string key_of(const std::string& pointer) { return pointer.empty() ? "the run" : pointer.substr(1); }

std::string shown(const json& spec, const std::string& pointer)
{
    const json::json_pointer p(pointer);
    if (!spec.contains(p)) return "absent";
    std::string text = spec.at(p).dump();
    constexpr std::size_t longest = 60;
    if (text.size() > longest) text = text.substr(0, longest) + "...";
    return text;
}

// The first differences between rank 0's spec and another's: "key (a on rank 0, b on rank r)".
std::string differences(const json& own, const json& other, int rank)
{
    const json patch = json::diff(own, other);
    std::string text;
    std::size_t named = 0;
    for (const auto& op : patch) {
        if (named == 3) {
            text += ", ...";
            break;
        }
        const std::string pointer = op.at("path").get<std::string>();
        text += (named++ ? "; " : "") + key_of(pointer) + ": " + shown(own, pointer) + " on rank 0, " +
                shown(other, pointer) + " on rank " + std::to_string(rank);
    }
    return text;
}

void pause() { std::this_thread::sleep_for(std::chrono::microseconds(500)); }

}  // namespace

std::string spec_hash(const json& spec)
{
    std::uint64_t h = 1469598103934665603ULL;
    for (const unsigned char ch : spec.dump()) {
        h ^= ch;
        h *= 1099511628211ULL;
    }
    char buf[17];
    std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
    return buf;
}

void check_same_run(job_ranks& ranks, const json& spec)
{
    const std::string own = spec_hash(spec);
    if (ranks.rank() != 0) {
        ranks.send(0, tag_spec, own + "\n" + spec.dump());
        for (;;) {
            if (auto m = ranks.receive()) {
                if (m->tag == tag_same) return;
                if (m->tag == tag_abort) std::rethrow_exception(failure_from(m->bytes, 0));
            }
            pause();
        }
    }
    // The others wait for the answer before they send anything else: only specs arrive here.
    std::string mismatch;
    for (int got = 0; got < ranks.size() - 1;) {
        auto m = ranks.receive();
        if (!m) {
            pause();
            continue;
        }
        if (m->tag != tag_spec) continue;
        ++got;
        const auto nl = m->bytes.find('\n');
        if (m->bytes.substr(0, nl) == own || !mismatch.empty()) continue;
        const json other = json::parse(m->bytes.substr(nl + 1), nullptr, false);
        mismatch = "MPI rank " + std::to_string(m->from) + " was started with another run than rank 0 (" +
                   (other.is_discarded() ? std::string("its spec is unreadable") : differences(spec, other, m->from)) +
                   "): start every rank with the same command and options";
    }
    if (!mismatch.empty()) {
        const auto e = std::make_exception_ptr(input_error(mismatch));
        abort_ranks(ranks, e);
        std::rethrow_exception(e);
    }
    for (int r = 1; r < ranks.size(); ++r) ranks.send(r, tag_same, {});
}

}  // namespace vimpact::detail

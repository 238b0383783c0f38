#include "vimpact/analysis/protocol.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "dispatch.hpp"
#include "vimpact/analysis/protocol_declaration.hpp"
#include "vimpact/core/format.hpp"
#include "vimpact/integrate/runge_kutta.hpp"
#include "vimpact/model/model_phrases.hpp"

namespace vimpact {

std::string section_choice_name(const model& m, const section_choice& s)
{
    if (s.type == section_choice::kind::crossing) return m.info().sections.at(static_cast<std::size_t>(s.index)).name;
    if (s.index < 0) return "impacts";
    return "impacts:" + m.info().surfaces.at(static_cast<std::size_t>(s.index)).name;
}

std::optional<section_choice> section_choice_named(const model& m, std::string_view name)
{
    constexpr std::string_view impacts = "impacts";
    const auto& info = m.info();
    if (name == impacts) return section_choice::impacts();
    if (name.starts_with(impacts) && name.size() > impacts.size() && name[impacts.size()] == ':') {
        const int i = info.surface_index(name.substr(impacts.size() + 1));
        if (i >= 0) return section_choice::impacts(i);
        return std::nullopt;
    }
    const int k = info.section_index(name);
    if (k >= 0) return section_choice::crossings(k);
    return std::nullopt;
}

std::string section_choice_names(const model& m)
{
    const auto& info = m.info();
    std::string s = info.section_names();
    s += s.empty() ? "impacts" : ", impacts";
    for (const auto& surface : info.surfaces) {
        s += ", impacts:";
        s += surface.name;
    }
    return s;
}

section_choice default_section(const model& m)
{
    return m.section_count() > 0 ? section_choice::crossings(0) : section_choice::impacts();
}

double effective_hold_band(const integrator_options& o, integration_method method)
{
    return o.hold_band.value_or(method == integration_method::dopri5 ? dopri5<1>::default_hold_band
                                                                     : dop853<1>::default_hold_band);
}

void validate(const model& m, const section_choice& s)
{
    if (s.type == section_choice::kind::crossing) {
        if (s.index < 0 || s.index >= m.section_count())
            throw input_error(m.section_count() == 0
                                  ? "model " + m.name() + " declares no section: use the impacts"
                                  : "section " + std::to_string(s.index) + " does not exist (" +
                                        sections_it_has(m.info()) + ")");
    } else if (s.index >= m.surface_count()) {
        throw input_error("surface " + std::to_string(s.index) + " does not exist (" + surfaces_it_has(m.info()) + ")");
    }
}

void validate(const integrator_options& in) { check_options(in); }

void validate(const protocol_options& o)
{
    check_options(o);  // the declared options (analysis/protocol_declaration.hpp)
    if (!(o.sample_dt >= 0.0) || !std::isfinite(o.sample_dt)) throw input_error("sample_dt must be >= 0 and finite");
    if (o.max_samples < 1)
        throw input_error("max_samples must be >= 1 (got " + std::to_string(o.max_samples) + ")");
}

bool runs_in_lanes(const model& m)
{
    if constexpr (!wide_lanes) return false;
    return detail::with_engine(m, [](const auto& em) { return detail::lanes_ready(em); });
}

int resolve_batch(const model& m, int requested)
{
    if (requested < 0 || requested > 1024)
        throw input_error("batch = " + std::to_string(requested) + " is outside its valid range [0, 1024] (0: the SIMD width)");
    if (!runs_in_lanes(m)) return 1;
    return requested == 0 ? lane_width : requested;
}

lanes_counts simulate_stream(const model& kind, const protocol_options& o, int width, const protocol_source& next,
                             const protocol_sink& done)
{
    validate(o);
    validate(kind, o.section);
    // A job of another model runs alone, at once; the source is then asked again.
    auto lanes_job = [&]() -> std::optional<protocol_job> {
        for (;;) {
            std::optional<protocol_job> j = next();
            if (!j || j->m.code() == kind.code()) {
                if (j) check_state_size(kind, j->x0.size(), "the initial state");
                return j;
            }
            simulation s = simulate(j->m, j->x0, o);
            done(std::move(*j), std::move(s));
        }
    };
    if (width > 1 && runs_in_lanes(kind)) {
        std::optional<lanes_counts> counts = detail::with_engine(kind, [&](const auto& em) -> std::optional<lanes_counts> {
            using EM = std::decay_t<decltype(em)>;
            if constexpr (detail::lanes_engine<EM>)
                return detail::run_simulate_lanes<EM>(o, width, lanes_job, [&](protocol_job&& j, simulation&& s) {
                    s.statistics = compute_impact_statistics(j.m, s);
                    done(std::move(j), std::move(s));
                });
            else return std::nullopt;  // runs_in_lanes says it cannot happen; one at a time below
        });
        if (counts) return *counts;
    }
    while (std::optional<protocol_job> j = next()) {
        simulation s = simulate(j->m, j->x0, o);
        done(std::move(*j), std::move(s));
    }
    return {};
}

std::vector<simulation> simulate_many(const std::vector<model>& models, const std::vector<Eigen::VectorXd>& x0s,
                                      const protocol_options& o, int batch)
{
    if (models.size() != x0s.size()) throw std::invalid_argument("simulate_many: one initial state per model");
    std::vector<simulation> out(models.size());
    if (models.empty()) return out;
    for (std::size_t k = 0; k < models.size(); ++k) check_state_size(models[k], x0s[k].size(), "the initial state");
    std::size_t given = 0;
    simulate_stream(
        models[0], o, models.size() > 1 ? batch : 1,
        [&]() -> std::optional<protocol_job> {
            if (given == models.size()) return std::nullopt;
            const std::size_t k = given++;
            return protocol_job{static_cast<long>(k), models[k], x0s[k]};
        },
        [&](protocol_job&& j, simulation&& s) { out[static_cast<std::size_t>(j.key)] = std::move(s); });
    return out;
}

simulation simulate(const model& m, const Eigen::VectorXd& x0, const protocol_options& o)
{
    validate(o);
    validate(m, o.section);
    check_state_size(m, x0.size(), "the initial state");
    simulation r = detail::with_engine(m, [&](const auto& em) { return detail::run_simulate(em, x0, o); });
    r.statistics = compute_impact_statistics(m, r);
    return r;
}

}  // namespace vimpact

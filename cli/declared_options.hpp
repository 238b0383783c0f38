#pragma once
// The options an options struct declares (core/option.hpp) as options of a command: --key
// (underscores as hyphens), the declaration's help with the default and the valid range, the
// value written straight into the struct. The library checks the ranges when the analysis
// runs (an option_error, which main() reports under the option's command-line name), so a
// command adds an analysis' options with one call and checks none of them itself.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>

#include "vimpact/core/format.hpp"
#include "vimpact/core/names.hpp"
#include "vimpact/core/option.hpp"

namespace vimpact::cli {

namespace detail {

// A declaration's help as the command line's help texts read: a capital first.
inline std::string sentence(std::string_view help)
{
    std::string s(help);
    if (!s.empty() && s[0] >= 'a' && s[0] <= 'z') s[0] = static_cast<char>(s[0] - 'a' + 'A');
    return s;
}

struct option_adder {
    CLI::App& app;

    template <class T>
    void operator()(const option& o, T& v) const
    {
        std::string help = sentence(o.help);
        if constexpr (std::is_same_v<T, bool>) {
            // A switch: --key turns on one that is off by default, --no-key turns off one that is on.
            if (v)
                app.add_flag_callback("--no-" + command_line_key(o.key).substr(2), [&v] { v = false; },
                                      help + " (on by default; this turns it off)");
            else
                app.add_flag(command_line_key(o.key), v, help);
        } else {
            app.add_option(command_line_key(o.key), v, help + " (default " + format_double(static_cast<double>(v)) +
                                                            range_note(o) + ")");
        }
    }

    // Unset by default (none: the library chooses, as the help says); a value given sets it.
    template <class T>
    void operator()(const option& o, std::optional<T>& v) const
    {
        app.add_option_function<T>(
            command_line_key(o.key), [&v](const T& x) { v = x; },
            sentence(o.help) + " (default " + (v ? format_double(static_cast<double>(*v)) : "none") + range_note(o) + ")");
    }

    // A count users write as 1e8 (pairs): read as a number, then it must be a whole one in range.
    void operator()(const option& o, std::uint64_t& v) const
    {
        app.add_option_function<double>(
            command_line_key(o.key),
            [&v, o](double x) {
                if (x != std::floor(x) || !o.range.admits(x) || x >= 0x1p64)
                    throw option_error(o.key, " = " + format_double(x) + " is not a whole number in its valid range " +
                                                  o.range.text());
                v = static_cast<std::uint64_t>(x);
            },
            sentence(o.help) + " (default " + format_double(static_cast<double>(v)) + range_note(o) + ")");
    }

    static std::string range_note(const option& o) { return o.range.bounded() ? "; " + o.range.text() : std::string(); }

    template <class E, std::size_t K>
    void operator()(const option& o, E& v, const std::array<E, K>& all) const
    {
        const std::string key = command_line_key(o.key);
        app.add_option_function<std::string>(
            key, [&v, all, key](const std::string& text) { v = parse_name(text, all, key); },
            sentence(o.help) + " (default " + std::string(to_string(v)) + "; one of " + name_list(all) + ")");
    }
};

// The declared options' values as run.json and config.toml record them, by key (an
// enumeration by name; a limit that is none, +inf or unset, left out), those `keep` admits.
struct settings_writer {
    nlohmann::json& j;
    bool (*keep)(std::string_view key);
    template <class T>
    void operator()(const option& o, const T& v) const
    {
        if constexpr (std::is_floating_point_v<T>)
            if (!std::isfinite(v)) return;
        if (keep(o.key)) j[std::string(o.key)] = v;
    }
    template <class T>
    void operator()(const option& o, const std::optional<T>& v) const
    {
        if (v) (*this)(o, *v);
    }
    template <class E, std::size_t K>
    void operator()(const option& o, const E& v, const std::array<E, K>&) const
    {
        if (keep(o.key)) j[std::string(o.key)] = std::string(to_string(v));
    }
};

}  // namespace detail

template <class O>
nlohmann::json declared_settings(const O& o, bool (*keep)(std::string_view) = [](std::string_view) { return true; })
{
    nlohmann::json j = nlohmann::json::object();
    const detail::settings_writer w{j, keep};
    declare(w, o);
    return j;
}

// One option declared on its own (period_tolerance_option), bound to `v`.
template <class T>
void add_declared_option(CLI::App& app, const option& o, T& v)
{
    detail::option_adder{app}(o, v);
}

// Adds every option `o` declares to `app`, bound to o's members.
template <class O>
void add_declared_options(CLI::App& app, O& o)
{
    detail::option_adder a{app};
    declare(a, o);
}

}  // namespace vimpact::cli

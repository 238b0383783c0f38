#pragma once
// An analysis' options declared once. Each options struct has one function beside it,
//   template <class V, class O> void declare(V& v, O& o)   (O: the struct, const or not)
// calling v(option{key, help, range}, o.member) for every option a user sets, and
// v(option{key, help}, o.member, all_values) for an enumeration (its values by name). The key is the
// option's name everywhere (the command line's --key with '_' written '-', Python's keyword,
// a config file's key), the default is the member's value in a default-constructed struct,
// and the range is checked here, once, by check_options: the front ends add the options and
// their help from the declaration and never check a value themselves.
//
// A member std::optional<double> is an option that may be unset (none: the library chooses);
// its range applies when it is set. A limit whose default is none, +inf, declares its range
// with or_infinite (core/value_range.hpp): (a, inf] admits infinity itself.
//
// An option out of its range is an option_error, an input_error that keeps the key apart from
// the message, so that each front end names the option as its user writes it (see key_text).
#include <array>
#include <cmath>
#include <concepts>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>

#include "vimpact/core/format.hpp"
#include "vimpact/core/input_error.hpp"
#include "vimpact/core/record.hpp"
#include "vimpact/core/value_range.hpp"

namespace vimpact {

struct option {
    std::string_view key;
    std::string_view help;
    value_range range;  // of a number; an enumeration names its values instead

    constexpr option(std::string_view key_, std::string_view help_, value_range range_ = {})
        : key(key_), help(help_), range(range_)
    {
    }
};

// A bad value of the option `key`: what() reads "KEY = VALUE is outside its valid range ..."
// in Python's form; the command line writes --KEY (key_text).
class option_error : public input_error {
public:
    option_error(std::string_view key, std::string detail)
        : input_error(std::string(key) + detail), m_key(key), m_detail(std::move(detail))
    {
    }
    [[nodiscard]] const std::string& key() const { return m_key; }
    [[nodiscard]] const std::string& detail() const { return m_detail; }

private:
    std::string m_key, m_detail;
};

// The option as the command line writes it: --key with '_' as '-'.
inline std::string command_line_key(std::string_view key)
{
    std::string s = "--" + std::string(key);
    for (char& c : s)
        if (c == '_') c = '-';
    return s;
}

namespace detail {

struct option_checker {
    template <class E, std::size_t K>
    void operator()(const option&, const E&, const std::array<E, K>&) const
    {
    }
    template <class T>
    void operator()(const option& o, const T& v) const
    {
        if constexpr (std::is_arithmetic_v<T> && !std::is_same_v<T, bool>) {
            const double x = static_cast<double>(v);
            // An integer as typed (2000000000, not 2e+09).
            const std::string shown = std::is_integral_v<T> ? std::to_string(v) : format_double(x);
            if (!o.range.admits(x))
                throw option_error(o.key, " = " + shown + " is outside its valid range " + o.range.text());
        }
    }
    // Unset: the library's choice, nothing to check.
    template <class T>
    void operator()(const option& o, const std::optional<T>& v) const
    {
        if (v) (*this)(o, *v);
    }
};

}  // namespace detail

// One option's value in its range, or its option_error (a front end checking a value where it
// reads it, a config file's, to name the file).
template <class T>
void check_option(const option& o, const T& v)
{
    detail::option_checker{}(o, v);
}

// Every declared option of `o` in its range, or the option_error of the first that is not.
template <class O>
void check_options(const O& o)
{
    detail::option_checker c;
    declare(c, o);
}

}  // namespace vimpact

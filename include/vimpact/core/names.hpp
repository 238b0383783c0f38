#pragma once
// Enumerations by name: what a front end reads from a user (a command-line option, a keyword
// argument) turned into the library's value, with one message for every bad name. `what` is
// the front end's spelling of the input ("--tdm", "tdm"); the library knows none.
#include <array>
#include <string>
#include <string_view>

#include "vimpact/core/input_error.hpp"

namespace vimpact {

// "a, b, c": the names of every value, for messages.
template <class E, std::size_t K>
std::string name_list(const std::array<E, K>& all)
{
    std::string s;
    for (const E e : all) s += (s.empty() ? "" : ", ") + std::string(to_string(e));
    return s;
}

// The value named `text`; throws input_error "<what> 'text' is not one of a, b, c".
template <class E, std::size_t K>
E parse_name(std::string_view text, const std::array<E, K>& all, std::string_view what)
{
    for (const E e : all)
        if (to_string(e) == text) return e;
    throw input_error(std::string(what) + " '" + std::string(text) + "' is not one of " + name_list(all));
}

}  // namespace vimpact

#pragma once
// Shortest round-trip text for doubles: what we print can be read back bit for bit.
#include <charconv>
#include <string>

namespace vimpact {

inline std::string format_double(double x)
{
    char buf[32];
    auto [end, ec] = std::to_chars(buf, buf + sizeof buf, x);
    (void)ec;
    return std::string(buf, end);
}

}  // namespace vimpact

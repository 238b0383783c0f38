#include "parse.hpp"

#include <charconv>
#include <cmath>

#include "vimpact/analysis/sweep.hpp"
#include "vimpact/core/input_error.hpp"

namespace vimpact::cli {

double parse_number(const std::string& text, const std::string& what)
{
    double v = 0.0;
    const char* b = text.data();
    const char* e = b + text.size();
    while (b < e && *b == ' ') ++b;
    while (e > b && e[-1] == ' ') --e;
    if (b < e && *b == '+') ++b;
    auto [p, ec] = std::from_chars(b, e, v);
    if (ec != std::errc() || p != e || b == e) throw input_error("malformed number '" + text + "' for " + what);
    if (!std::isfinite(v)) throw input_error(what + " must be finite (got '" + text + "')");
    return v;
}

long parse_count(const std::string& text, const std::string& what)
{
    const double v = parse_number(text, what);
    if (v < 0 || v != std::floor(v) || v > 1e15)
        throw input_error(what + " must be an integer >= 0 (got '" + text + "')");
    return static_cast<long>(v);
}

std::vector<std::string> split(const std::string& text, char sep)
{
    std::vector<std::string> parts;
    std::size_t start = 0;
    for (;;) {
        const auto at = text.find(sep, start);
        parts.push_back(text.substr(start, at == std::string::npos ? std::string::npos : at - start));
        if (at == std::string::npos) break;
        start = at + 1;
    }
    return parts;
}

std::vector<double> parse_numbers(const std::string& text, const std::string& what)
{
    std::vector<double> out;
    for (const auto& item : split(text, ',')) out.push_back(parse_number(item, what));
    return out;
}

value_grid parse_range(const std::string& text, const std::string& what)
{
    const auto parts = split(text, ':');
    if (parts.size() != 3) throw input_error(what + " '" + text + "' must be a:b:n (from a to b, n points)");
    const double a = parse_number(parts[0], what + " start");
    const double b = parse_number(parts[1], what + " end");
    const double n = parse_number(parts[2], what + " points");
    if (n < 1 || n != std::floor(n) || n > 1e7)
        throw input_error(what + " '" + text + "': n must be an integer in [1, 1e7]");
    return value_grid::range(a, b, static_cast<long>(n));
}

named_range parse_named_range(const std::string& text, const std::string& what)
{
    const auto colon = text.find(':');
    if (colon == std::string::npos || colon == 0) throw input_error(what + " '" + text + "' must be NAME:a:b:n");
    return {text.substr(0, colon), parse_range(text.substr(colon + 1), what)};
}

shard_spec parse_shard(const std::string& text)
{
    const auto slash = text.find('/');
    const std::string what = "--shard '" + text + "'";
    if (slash == std::string::npos) throw input_error(what + " must be I/N with 0 <= I < N");
    const double i = parse_number(text.substr(0, slash), "--shard I");
    const double n = parse_number(text.substr(slash + 1), "--shard N");
    if (i != std::floor(i) || n != std::floor(n) || n < 1 || i < 0 || i >= n)
        throw input_error(what + " must be I/N with integers 0 <= I < N");
    return {static_cast<long>(i), static_cast<long>(n)};
}

std::vector<std::pair<std::string, double>> parse_pairs(const std::string& text, const std::string& what)
{
    std::vector<std::pair<std::string, double>> out;
    for (const auto& item : split(text, ',')) {
        const auto eq = item.find('=');
        if (eq == std::string::npos || eq == 0) throw input_error(what + " expects KEY=VALUE,... (got '" + item + "')");
        const std::string key = item.substr(0, eq);
        out.emplace_back(key, parse_number(item.substr(eq + 1), what + " " + key));
    }
    return out;
}

}  // namespace vimpact::cli

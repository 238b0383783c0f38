#pragma once
// One line of JSON (a journal line: a job's record) read into a JSON value, fast.
//
// The coordinating rank of a distributed run reads every result that another rank sends, a
// journal line each, and a resume reads every line of its journal: at a thousand ranks that is
// 100 000 lines a second for one core. nlohmann's parser takes about 7 us for a map cell's
// 440 bytes, most of it converting numbers; simdjson (Debian's libsimdjson-dev) parses the
// line in under 1 us, and building the same JSON value from its result about 3 us more. The
// value is the one nlohmann::json::parse gives: the same types (non-negative integers
// unsigned, negative ones signed, every other number a double, correctly rounded), keys and
// order, so the records' decoders (io/json_codec.hpp) read it unchanged.
#include <optional>
#include <string_view>

#include <nlohmann/json.hpp>

namespace vimpact::detail {

// The value of `text`, or nullopt when it is not one valid JSON value.
std::optional<nlohmann::json> try_parse_json_line(std::string_view text);
// The same, throwing std::runtime_error for invalid text.
nlohmann::json parse_json_line(std::string_view text);

}  // namespace vimpact::detail

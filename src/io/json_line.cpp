#include "json_line.hpp"

#include <cstdint>
#include <stdexcept>
#include <string>

#include <simdjson.h>

namespace vimpact::detail {

namespace {

using nlohmann::json;

json to_nlohmann(simdjson::dom::element e)
{
    switch (e.type()) {
        case simdjson::dom::element_type::ARRAY: {
            json a = json::array();
            const simdjson::dom::array items = e.get_array().value_unsafe();
            for (const simdjson::dom::element x : items) a.push_back(to_nlohmann(x));
            return a;
        }
        case simdjson::dom::element_type::OBJECT: {
            json o = json::object();
            const simdjson::dom::object fields = e.get_object().value_unsafe();
            auto& members = o.get_ref<json::object_t&>();
            for (const auto kv : fields) members.emplace_hint(members.end(), std::string(kv.key), to_nlohmann(kv.value));
            return o;
        }
        case simdjson::dom::element_type::INT64: {
            const std::int64_t v = e.get_int64().value_unsafe();
            // nlohmann reads a non-negative integer as unsigned.
            if (v >= 0) return static_cast<std::uint64_t>(v);
            return v;
        }
        case simdjson::dom::element_type::UINT64: return e.get_uint64().value_unsafe();
        case simdjson::dom::element_type::DOUBLE: return e.get_double().value_unsafe();
        case simdjson::dom::element_type::STRING: return std::string(e.get_string().value_unsafe());
        case simdjson::dom::element_type::BOOL: return e.get_bool().value_unsafe();
        case simdjson::dom::element_type::NULL_VALUE: return nullptr;
    }
    return nullptr;
}

}  // namespace

std::optional<nlohmann::json> try_parse_json_line(std::string_view text)
{
    // A parser keeps its buffers between lines: one per thread (no state that a result
    // depends on).
    thread_local simdjson::dom::parser parser;
    simdjson::dom::element root;
    if (parser.parse(text.data(), text.size(), true).get(root) != simdjson::SUCCESS) return std::nullopt;
    return to_nlohmann(root);
}

nlohmann::json parse_json_line(std::string_view text)
{
    auto j = try_parse_json_line(text);
    if (!j) throw std::runtime_error("invalid JSON line: " + std::string(text.substr(0, 80)));
    return std::move(*j);
}

}  // namespace vimpact::detail

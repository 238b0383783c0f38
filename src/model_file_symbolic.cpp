// The library's side of the module libvimpact_symbolic.so (src/modules/symbolic.cpp): the
// stage-2 functions of model files, which need GiNaC, forwarded to the module, loaded on the
// first call.
#include <cmath>

#include "core/load_module.hpp"
#include "model_file_detail.hpp"
#include "vimpact/core/format.hpp"

namespace vimpact::model_file_detail {

namespace {

const symbolic_module& symbolic()
{
    using entry = const symbolic_module* (*)();
    static const symbolic_module* const module =
        reinterpret_cast<entry>(detail::module_symbol("libvimpact_symbolic.so", "vimpact_symbolic_v1"))();
    return *module;
}

}  // namespace

std::string generate_source(const description& d, const std::string& where, const std::atomic<bool>* cancel)
{
    return symbolic().generate_source(d, where, cancel);
}

bool is_reserved_name(std::string_view name) { return symbolic().is_reserved_name(name); }

std::string function_list() { return symbolic().function_list(); }

std::string number_text(double v)
{
    if (v == std::trunc(v) && std::fabs(v) < 9007199254740992.0) return std::to_string(static_cast<long long>(v));
    return format_double(v);
}

}  // namespace vimpact::model_file_detail

#include <cstring>
#include <stdexcept>
#include <string>

#include "core/load_module.hpp"
#include "engine_instances.hpp"

namespace vimpact::detail {

const void* engine_table(const std::string& file, const char* model)
{
    using entry = const void* (*)();
    const void* table = reinterpret_cast<entry>(module_symbol(file.c_str(), "vimpact_engine_v1"))();
    // engine_functions is standard-layout: its first member, the model's name, is at its start.
    const char* its_model = *static_cast<const char* const*>(table);
    if (std::strcmp(its_model, model) != 0)
        throw std::runtime_error(file + " was compiled for another model than its name says: this vimpact is not "
                                        "completely built or installed");
    return table;
}

}  // namespace vimpact::detail

// Placeholder while the model-file compiler is written (replaced before merge).
#include "vimpact/model/model_file.hpp"

#include "vimpact/core/input_error.hpp"

namespace vimpact {

std::shared_ptr<const model_code> load_model_code(const std::filesystem::path& path)
{
    throw input_error("model files are not supported yet: " + path.string());
}
std::shared_ptr<const model_code> compile_model_text(std::string_view, std::string_view source)
{
    throw input_error("model files are not supported yet: " + std::string(source));
}
std::shared_ptr<const model_code> load_model_library(const std::filesystem::path& path)
{
    throw input_error("model libraries are not supported yet: " + path.string());
}

}  // namespace vimpact

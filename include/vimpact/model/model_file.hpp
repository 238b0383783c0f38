#pragma once
// Loading models from files: a model file (TOML: equations as expressions, differentiated
// symbolically with GiNaC and compiled to native code with the machine's C++ compiler, once,
// cached by content hash) or a shared library that exports vimpact_model()
// (model/export.hpp). docs/model-files.md describes the file format; the same description
// as JSON (a .json file, or Python's dict) takes the same path.
//
// The cache directory is $VIMPACT_CACHE_DIR, else $XDG_CACHE_HOME/vimpact, else
// ~/.cache/vimpact; the compiler is $CXX, else c++. Every problem with a file is an
// input_error of one line that names the file, the key and the problem.
//
// `cancel`, when given, is polled while the model is differentiated and compiled: once it is
// set the work stops (the compiler is ended, its temporary files removed) and `cancelled`
// (vimpact/core/cancelled.hpp) is thrown.
#include <atomic>
#include <filesystem>
#include <memory>
#include <string_view>

#include <nlohmann/json.hpp>

#include "vimpact/model/model.hpp"

namespace vimpact {

// A .toml (or .json) model file, or a shared library (.so, or any ELF file).
std::shared_ptr<const model_code> load_model_code(const std::filesystem::path& path,
                                                  const std::atomic<bool>* cancel = nullptr);

// What load_model_code makes of a file: a model file it compiles from equations, or a shared
// library whose code it runs as it is (a caller that must not run native code it was not
// handed directly, e.g. one named in a config file, asks first). Throws input_error as
// load_model_code does for a file that is neither, or none.
enum class model_file_kind { model_text, model_json, shared_library };
model_file_kind model_file_kind_of(const std::filesystem::path& path);

// The text of a model file; `source` names it in messages.
std::shared_ptr<const model_code> compile_model_text(std::string_view text, std::string_view source,
                                                     const std::atomic<bool>* cancel = nullptr);

// The same description as a JSON tree with the file's keys (what Python's dict constructor
// sends); object keys in declaration order.
std::shared_ptr<const model_code> compile_model_json(const nlohmann::ordered_json& description,
                                                     std::string_view source,
                                                     const std::atomic<bool>* cancel = nullptr);

// A shared library exporting vimpact_model().
std::shared_ptr<const model_code> load_model_library(const std::filesystem::path& path);

}  // namespace vimpact

#pragma once
// The stages of the model-file compiler (src/model_file.cpp has the format and the overview):
//   describe()        a JSON tree -> a checked description (keys, types, names, ranges)
//   generate_source() the description -> C++ source of a function table (GiNaC: parsing,
//                     symbolic derivatives, printing), in the module libvimpact_symbolic.so
//                     (src/modules/symbolic.cpp), loaded with the first model file
//   compile_cached()  the source -> a loaded shared library (compiler run, cache, dlopen)
// Every stage throws input_error("<where>: ...") for a problem of the file, and `cancelled`
// once the caller's cancel flag is set (polled between symbolic steps and while the compiler
// runs).
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "vimpact/model/abi.h"
#include "vimpact/model/spec.hpp"

namespace vimpact::model_file_detail {

// An expression as the file writes it, and the key it was written under (for messages).
struct expression_text {
    std::string key;   // "derivatives.v", "surfaces[1].reset.v"
    std::string text;  // "-2*zeta*v - x + a*cos(phi)"
};

struct state_decl {
    std::string name, meaning, unit;
    std::optional<expression_text> period;  // from [angles]
};

struct parameter_decl {
    std::string name, meaning, unit;
    double default_value = 0.0;
    value_range range;
};

// A derived quantity or a named expression.
struct named_expression {
    std::string name;
    expression_text expr;
};

// A new value for one state variable (reset, rest, constrained field).
struct assignment {
    int index = 0;  // the state variable
    expression_text expr;
};

struct sticking_decl {
    std::vector<assignment> rest, derivatives;
    expression_text release;
};

struct surface_decl {
    std::string name, meaning;
    expression_text gap;
    std::vector<assignment> reset;
    std::optional<sticking_decl> sticking;
};

struct section_decl {
    std::string name, meaning;
    expression_text when;
    crossing direction = crossing::down;
};

// A switching surface: the field changes where `when` changes sign (side(NAME), on(NAME) in
// the expressions); `reset` applies at the crossings in `direction`.
struct switch_decl {
    std::string name, meaning;
    expression_text when;
    std::vector<assignment> reset;
    crossing direction = crossing::both;
};

struct preset_decl {
    std::string name, meaning;
    std::vector<std::pair<int, double>> values;  // (parameter index, value)
};

struct description {
    std::string name, description;
    std::vector<state_decl> state;
    std::vector<double> initial_state;  // dim numbers
    std::vector<parameter_decl> parameters;
    std::vector<named_expression> derived, expressions;
    std::vector<expression_text> derivatives;  // one per state variable, in state order
    std::vector<surface_decl> surfaces;
    std::vector<section_decl> sections;
    std::vector<switch_decl> switches;
    std::vector<preset_decl> presets;
};

// `where` is the message prefix, "model file two.toml".
description describe(const nlohmann::ordered_json& tree, const std::string& where);

// Everything that defines the model, in one fixed form: equal for equal models whatever the
// spelling of the input (TOML or JSON, integer or float literals, order of optional keys).
nlohmann::ordered_json canonical_json(const description& d);

// The C++ source of the model's function table, prefixed with the ABI header. Refuses a file
// whose expressions nest deeper than max_nesting, whose exact constants grow beyond
// max_constant_bits, or whose generated code (the expressions and their derivatives, written
// out) would exceed max_code_terms, naming the key, before the work grows.
std::string generate_source(const description& d, const std::string& where,
                            const std::atomic<bool>* cancel = nullptr);

// The bounds generate_source enforces (docs/model-files.md states them).
inline constexpr int max_nesting = 250;              // parentheses, calls and named expressions
inline constexpr long max_constant_bits = 65536;     // numerator and denominator of an exact constant
inline constexpr double max_code_terms = 5.0e5;      // operations in all the printed expressions

// A loaded model library and its table.
struct loaded_library {
    std::shared_ptr<void> handle;  // dlclose on release
    const vimpact_model_table* table = nullptr;
};

// Compiles `source` into the cache (or finds it there) and loads it (model_file_cache.cpp has
// the cache's rules).
loaded_library compile_cached(const std::string& source, const std::string& model_name, const std::string& where,
                              const std::atomic<bool>* cancel = nullptr);

// A file descriptor that is closed with its owner.
class unique_fd {
public:
    unique_fd() = default;
    explicit unique_fd(int fd) : m_fd(fd) {}
    unique_fd(unique_fd&& o) noexcept : m_fd(o.release()) {}
    unique_fd& operator=(unique_fd&& o) noexcept;
    unique_fd(const unique_fd&) = delete;
    unique_fd& operator=(const unique_fd&) = delete;
    ~unique_fd();
    [[nodiscard]] int get() const { return m_fd; }
    [[nodiscard]] bool valid() const { return m_fd >= 0; }
    int release()
    {
        const int fd = m_fd;
        m_fd = -1;
        return fd;
    }

private:
    int m_fd = -1;
};

// The outcome of a compiler run.
struct compiler_run {
    int status = 0;      // as waitpid gives it
    std::string output;  // what it wrote to stdout and stderr (the first MB)
};

// Runs `program` with `args` (args[0] is its name as given) in the directory `dir_fd`, with
// /dev/null as input and its output captured, until it ends; once *cancel is set, ends it
// and everything it started, and throws `cancelled`. The compiler dies with its caller too.
compiler_run run_compiler(const std::string& program, const std::vector<std::string>& args, int dir_fd,
                          const std::atomic<bool>* cancel);

// The headers of include_dir that `root` (a path relative to it) brings into a compilation:
// root, then each header it includes as "vimpact/...", depth first, each once, in the order
// met, with their text. Their names and text are part of the cache key, so a changed header
// (stage code, the lanes' bit operations) compiles a new entry. nullopt when one is missing.
struct header_text {
    std::string name;  // relative to the include directory: "vimpact/core/state.hpp"
    std::string text;
};
std::optional<std::vector<header_text>> vimpact_includes(const std::filesystem::path& include_dir,
                                                         const std::string& root);

// dlopen + vimpact_model() + ABI check; `what` names the library in messages.
loaded_library open_library(const std::filesystem::path& path, const std::string& what);

// The same for the file open as `fd` (through /proc/self/fd, so that the file loaded is the
// one checked): the cache's entries.
loaded_library open_library_fd(int fd, const std::string& what);

// FNV-1a, 64 bits; `h` chains several pieces.
inline constexpr std::uint64_t fnv_offset = 14695981039346656037ULL;
std::uint64_t fnv1a(std::string_view bytes, std::uint64_t h = fnv_offset);
std::string hex64(std::uint64_t h);

// The names an expression may not use for itself: the functions and `pi`.
bool is_reserved_name(std::string_view name);
std::string function_list();  // "sin, cos, ..." for messages

// A number as an expression's text, the same for 1 and 1.0.
std::string number_text(double v);

// What the module libvimpact_symbolic.so gives: the functions above that need GiNaC.
struct symbolic_module {
    std::string (*generate_source)(const description&, const std::string&, const std::atomic<bool>*);
    bool (*is_reserved_name)(std::string_view);
    std::string (*function_list)();
};

}  // namespace vimpact::model_file_detail

#pragma once
// vimpact::model: any impacting system with its parameter values, the one type every
// analysis takes. A model is a small immutable value; copies share the loaded code.
//
//   model::builtin("wake_impact")          the paper's model (also model{}), and the others
//                                          of builtin_names()
//   model::from_file("my.toml")            a model file, compiled to native code once
//   model::from_file("libmine.so")         a shared library exporting a C++ model
//   model::from_definition<D>()            a C++ definition compiled into the caller
//                                          (defined in model/export.hpp)
//
// Parameters are set by index (with_parameter) after a front end has looked the name up in
// info(); every value is range-checked, so a model always holds a valid parameter set.
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "vimpact/model/abi.h"
#include "vimpact/model/model_info.hpp"
#include "vimpact/model/model_limits.hpp"

namespace vimpact {

// The built-ins the library compiles the analyses for directly (the others run through their
// function table).
enum class native_kind { none, wake_impact, forced_impact_oscillator, two_sided_impact_oscillator };

// The code of a model: its table, its description, and what keeps the code loaded.
struct model_code {
    const vimpact_model_table* table = nullptr;
    model_info info;
    native_kind native = native_kind::none;
    std::shared_ptr<void> library;  // dlopen handle of a model file or plugin; null otherwise
};

class model {
public:
    // The paper's model with its default parameters.
    model();
    model(std::shared_ptr<const model_code> code, std::vector<double> parameters);

    static model builtin(std::string_view name);
    static std::vector<std::string> builtin_names();
    // A .toml model file (compiled with the machine's C++ compiler, cached by content) or a
    // shared library exporting vimpact_model(). Throws input_error naming the problem.
    static model from_file(const std::filesystem::path& path);
    // A model file's text (source names where it came from, for messages).
    static model from_toml(std::string_view text, std::string_view source = "<string>");
    // A loaded function table, e.g. the one of a definition (model/export.hpp).
    static model from_table(const vimpact_model_table& table, std::string_view source,
                            native_kind native = native_kind::none);
    template <class D>
    static model from_definition();

    [[nodiscard]] const model_info& info() const { return m_code->info; }
    [[nodiscard]] const std::string& name() const { return m_code->info.name; }
    [[nodiscard]] int dim() const { return m_code->info.dim(); }
    [[nodiscard]] int surface_count() const { return static_cast<int>(m_code->info.surfaces.size()); }
    [[nodiscard]] int section_count() const { return static_cast<int>(m_code->info.sections.size()); }
    [[nodiscard]] const std::vector<double>& parameters() const { return m_parameters; }
    [[nodiscard]] double parameter(int i) const { return m_parameters.at(static_cast<std::size_t>(i)); }
    [[nodiscard]] Eigen::VectorXd initial_state() const;

    // One parameter's value against its range (and not subnormal) alone: what every copy
    // below checks first, for a caller that reads values one by one (a config file).
    static void check_parameter(const parameter_info& p, double value);

    // Copies with changed parameters; throw input_error for a value outside its range.
    [[nodiscard]] model with_parameter(int index, double value) const;
    [[nodiscard]] model with_parameters(std::span<const double> values) const;
    [[nodiscard]] model with_preset(int preset) const;  // defaults, then the preset's values

    // What the engine calls.
    [[nodiscard]] const vimpact_model_table& table() const { return *m_code->table; }
    [[nodiscard]] const void* context() const { return m_context.get(); }
    [[nodiscard]] native_kind native() const { return m_code->native; }
    [[nodiscard]] const std::shared_ptr<const model_code>& code() const { return m_code; }

    // Same code and parameters.
    friend bool operator==(const model& a, const model& b);

    // A model of `code` at its default parameters.
    static model with_defaults(std::shared_ptr<const model_code> code);

private:
    std::shared_ptr<const model_code> m_code;
    std::vector<double> m_parameters;
    std::shared_ptr<void> m_context;
};

// The state dimensions the library's analyses are compiled for with fixed-size states (besides
// the built-ins, the fast path); a model file or plugin of any other dimension up to
// max_model_dimension runs on states sized at run time (table_model<Eigen::Dynamic>).
const std::vector<int>& engine_dimensions();

// Throws input_error naming `what`, its dimension and the limit unless 1 <= dim <= max_model_dimension.
void check_engine_dimension(int dim, std::string_view what);

// The first surface a state lies beyond (gap < 0, or 0 and decreasing), -1 if none: a state
// is admissible when none.
int violated_surface(const model& m, const Eigen::VectorXd& x);

// The message for a state of the wrong size: "<what> needs 4 numbers (y, ydot, x, xdot), got 3".
void check_state_size(const model& m, Eigen::Index size, std::string_view what);

}  // namespace vimpact

#pragma once
// What a model says about itself at run time: names, meanings, units, parameter defaults and
// ranges, surfaces, sections, presets. Front ends name inputs with it; the library never
// looks a parameter up by name inside a loop.
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "vimpact/model/abi.h"
#include "vimpact/model/spec.hpp"

namespace vimpact {

struct state_variable_info {
    std::string name, meaning, unit;
    double period = 0.0;  // > 0: a phase
};

struct parameter_info {
    std::string name, meaning, unit;
    double default_value = 0.0;
    value_range range;
};

struct surface_info {
    std::string name, meaning;
    bool sticks = false;
};

struct section_info {
    std::string name, meaning;
    crossing direction = crossing::down;
};

// A switching surface (model/spec.hpp, switching_surface): the crossings in `direction`
// apply its reset, if it has one.
struct switch_info {
    std::string name, meaning;
    crossing direction = crossing::both;
};

struct preset_info {
    std::string name, meaning;
    std::vector<std::pair<int, double>> values;  // (parameter index, value)
};

struct model_info {
    std::string name, description;
    std::string source;    // "built-in", or the file it was loaded from
    std::string identity;  // equal identities, equal models: the name of a built-in, a content hash otherwise
    std::vector<state_variable_info> state;
    std::vector<parameter_info> parameters;
    std::vector<surface_info> surfaces;
    std::vector<section_info> sections;
    std::vector<switch_info> switches;
    std::vector<preset_info> presets;
    std::vector<double> initial_state;

    [[nodiscard]] int dim() const { return static_cast<int>(state.size()); }
    // Index by name, or -1.
    [[nodiscard]] int state_index(std::string_view name) const;
    [[nodiscard]] int parameter_index(std::string_view name) const;
    [[nodiscard]] int surface_index(std::string_view name) const;
    [[nodiscard]] int section_index(std::string_view name) const;
    [[nodiscard]] int preset_index(std::string_view name) const;
    // "y, ydot, x, xdot" and the like, for messages.
    [[nodiscard]] std::string state_names() const;
    [[nodiscard]] std::string parameter_names() const;
    [[nodiscard]] std::string surface_names() const;
    [[nodiscard]] std::string section_names() const;
    [[nodiscard]] std::string preset_names() const;
    [[nodiscard]] bool has_angles() const;
};

// The coordinates of a state for distances between recorded states (attractor signatures,
// correlation dimension): every state variable as it is, except that a phase x with period p
// becomes the pair s cos(x / s), s sin(x / s), s = p / 2 pi, named NAME_cos and NAME_sin, so
// that states a period apart are the same point and small differences keep their size.
std::vector<std::string> coordinate_names(const model_info& m);
// Writes coordinate_names(m).size() numbers.
void state_coordinates(const model_info& m, const double* x, double* out);

// The information in a function table (source and identity are the caller's to fill).
model_info info_from_table(const vimpact_model_table& t);

}  // namespace vimpact

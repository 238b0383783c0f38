/* The binary interface of a compiled model: what a model file compiles to and what a C++
 * model exports from a shared library (VIMPACT_EXPORT_MODEL, model/export.hpp). The library
 * loads it with dlopen and calls vimpact_model() once; the table it returns describes the
 * model and holds the functions the integrator calls.
 *
 * Conventions: states are arrays of `dim` doubles; matrices are column-major dim x dim; a
 * context is created from the parameter values (in declared order, already range-checked)
 * and passed to every function; surfaces i and sections k count from 0. Second derivatives
 * are bilinear forms D2f(x)[u, w]. Plain C, so that the generated code compiles in well under
 * a second and the layout does not depend on a compiler's C++ ABI. */
#ifndef VIMPACT_MODEL_ABI_H
#define VIMPACT_MODEL_ABI_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

#define VIMPACT_MODEL_ABI_VERSION 7

enum vimpact_crossing { VIMPACT_CROSSING_DOWN = 0, VIMPACT_CROSSING_UP = 1, VIMPACT_CROSSING_BOTH = 2 };

typedef struct vimpact_model_table {
    int abi_version; /* VIMPACT_MODEL_ABI_VERSION */
    int dim, parameter_count, surface_count, section_count, preset_count;
    const char* name;
    const char* description;

    const char* const* state_names;
    const char* const* state_meanings;
    const char* const* state_units;
    const double* state_periods;          /* > 0: a phase, compared modulo this period */
    const double* initial_state;          /* may be NULL: zeros */

    const char* const* parameter_names;
    const char* const* parameter_meanings;
    const char* const* parameter_units;
    const double* parameter_defaults;
    const double* parameter_lower;        /* -inf: none */
    const double* parameter_upper;        /* +inf: none */
    const int* parameter_bounds_closed;   /* bit 0: lower bound included, bit 1: upper */

    const char* const* surface_names;
    const char* const* surface_meanings;
    const int* surface_sticks;            /* nonzero: the surface declares a contact phase */

    const char* const* section_names;
    const char* const* section_meanings;
    const int* section_directions;        /* enum vimpact_crossing */

    /* presets: name, meaning and a list of (parameter index, value) pairs each */
    const char* const* preset_names;
    const char* const* preset_meanings;
    const int* preset_sizes;
    const int* preset_parameters;         /* concatenated */
    const double* preset_values;          /* concatenated */

    /* Returns NULL and writes a message to `error` if the parameters are refused. */
    void* (*create)(const double* parameters, char* error, size_t error_size);
    void (*destroy)(void* context);

    void (*rhs)(const void* c, const double* x, double* f);
    void (*jacobian)(const void* c, const double* x, double* J);
    void (*second_derivative)(const void* c, const double* x, const double* u, const double* w, double* out);
    double (*divergence)(const void* c, const double* x);

    double (*gap)(const void* c, int i, const double* x);
    void (*gap_gradient)(const void* c, int i, const double* x, double* out);
    void (*gap_hessian)(const void* c, int i, const double* x, double* out);
    void (*reset)(const void* c, int i, const double* x, double* out);
    void (*reset_jacobian)(const void* c, int i, const double* x, double* out);
    void (*reset_second_derivative)(const void* c, int i, const double* x, const double* u, const double* w,
                                    double* out);

    double (*section)(const void* c, int k, const double* x);
    void (*section_gradient)(const void* c, int k, const double* x, double* out);

    /* contact phases (called only for surfaces with surface_sticks[i] != 0) */
    void (*sticking_rhs)(const void* c, int i, const double* x, double* f);
    double (*release)(const void* c, int i, const double* x);
    void (*release_gradient)(const void* c, int i, const double* x, double* out);
    void (*rest)(const void* c, int i, const double* x, double* out);

    /* Optional (NULL: the library calls rhs once per stage): one trial Runge-Kutta step of the
     * free vector field with the field compiled in (integrate/fused_step.hpp); method 0 is
     * DOP853, 1 DOPRI5. `stages` is the caller's method, carried from a step to its interpolant:
     * the library's fixed-size method object of the model's dimension (integrate/fused_step.hpp,
     * its stages alone: 16 * dim doubles for DOP853, 7 * dim for DOPRI5), aligned as Eigen
     * aligns it. Returns the squared scaled error norm (ABI version 3; the norm itself
     * in version 2), writes x_new and f_new = F(x_new). */
    double (*step)(const void* c, int method, const double* x, const double* f, double h, double rtol, double atol,
                   double* x_new, double* f_new, double* stages);
    /* The interpolant of the last accepted step: 7 * dim coefficients (DOP853), 4 * dim (DOPRI5). */
    void (*dense)(const void* c, int method, double t0, double h, const double* x0, const double* x1, double* stages,
                  double* coefficients);
    /* Optional (NULL: the library calls gap, gap_gradient, section and section_gradient): every
     * gap and section at x in one call, as (value, rate) pairs, the rate being grad . f for the
     * given field value f: gaps[2 i], gaps[2 i + 1] and sections[2 k], sections[2 k + 1]. The
     * flow samples each step end with it. */
    void (*samples)(const void* c, const double* x, const double* f, double* gaps, double* sections);

    /* Nonzero: the gap (section function) is affine in the state, so the integrator's error
     * control resolves it on every step; the flow checks every other one on each step (ABI
     * version 4). NULL: none is. */
    const int* surface_affine;
    const int* section_affine;

    /* Optional (NULL: the jobs of this model run one at a time): SIMD lanes (ABI version 5),
     * several jobs of the model stepped at once, each lane with the bits it gets alone (the
     * library's core/lanes.hpp). A lanes value is `lanes_width` doubles, one per lane; a vector
     * of them is dim such values in a row (x[i * lanes_width + lane]). `contexts` holds every
     * lane's context, a context being `context_size` doubles: contexts[k * lanes_width + lane].
     * The library uses them only when lanes_width is its own and the table has `step` and
     * `dense` (a lane's interpolant is built by `dense`, as after a fused step). */
    int lanes_width;
    int context_size;
    /* One trial Runge-Kutta step of the free field in every lane (method as for `step`): the
     * step sizes h, x_new, f_new, the stages (the library's method object in lanes, which is
     * its stages alone: 16 * dim lanes values for DOP853, 7 * dim for DOPRI5), and each lane's
     * squared scaled error norm err2 (one lanes value). */
    void (*lanes_step)(const double* contexts, int method, const double* x, const double* f, const double* h,
                       double rtol, double atol, double* x_new, double* f_new, double* stages, double* err2);
    /* Gap i or section k (one lanes value) and its gradient (dim lanes values) in every lane. */
    void (*lanes_gap)(const double* contexts, int i, const double* x, double* out);
    void (*lanes_gap_gradient)(const double* contexts, int i, const double* x, double* out);
    void (*lanes_section)(const double* contexts, int k, const double* x, double* out);
    void (*lanes_section_gradient)(const double* contexts, int k, const double* x, double* out);
    /* Every gap, then every section, then every switch (ABI version 7), at x in one call:
     * their values (surface_count + section_count + switch_count lanes values) and gradients
     * (dim lanes values each, in the same order). A switch's value is side * h_k, its gradient
     * side * grad h_k: positive on the side the lane is on. */
    void (*lanes_points)(const double* contexts, const double* x, double* values, double* gradients);

    /* Switching surfaces (ABI version 6; switch_count 0: none, and the rest may be NULL): the
     * field changes where a switching function h_k changes sign, the state going on
     * continuously unless the switch's reset applies (model/spec.hpp, switching_surface). The
     * functions of a context read the sides the context holds once pinned, the sides of the
     * state before (h_k >= 0: +1). A side set is a bit mask: bit k set for side -1 of switch k.
     * The library pins only its own copies of a context (copy_context, released by destroy),
     * one per flow, never the context it created. */
    int switch_count;
    const char* const* switch_names;
    const char* const* switch_meanings;
    const int* switch_directions;         /* enum vimpact_crossing: the crossings the reset applies at */
    const int* switch_affine;             /* nonzero: h_k is affine in the state */
    double (*switching)(const void* c, int k, const double* x);
    void (*switching_gradient)(const void* c, int k, const double* x, double* out);
    void* (*copy_context)(const void* c);
    void (*pin_sides)(void* c, unsigned long long negative);
    unsigned long long (*sides_at)(const void* c, const double* x);
    /* Crossing switch k at x (context pinned): its side changes; out is the state after it.
     * Returns nonzero when the switch's reset applied (out is then its image of x). */
    int (*cross)(void* c, int k, const double* x, double* out);
    /* The Jacobian of switch k's reset at x, on the context's (pinned) sides. */
    void (*switch_reset_jacobian)(const void* c, int k, const double* x, double* out);
    /* The lanes of a model with switches (ABI version 7; NULL: its jobs run one at a time).
     * Every lanes function reads each lane's sides from its context, which the library keeps
     * pinned (a flow's own copy, context_size doubles, pinned flag and sides included): side *
     * h_k in every lane. */
    void (*lanes_switching)(const double* contexts, int k, const double* x, double* out);
} vimpact_model_table;

/* The one symbol a model library exports. */
typedef const vimpact_model_table* (*vimpact_model_entry)(void);
#define VIMPACT_MODEL_ENTRY "vimpact_model"

#ifdef __cplusplus
}
#endif

#endif

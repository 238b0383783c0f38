// Model files, stage 2: a checked description -> the C++ source of its function table. A
// module of its own, libvimpact_symbolic.so (core/load_module.hpp): only a run with a model
// file loads GiNaC.
//
// Expressions are read by GiNaC's parser, after a scan of our own that gives the messages
// (unknown symbol, unknown function, wrong arity, bad character, syntax) and refuses a sign
// right after an operator, which GiNaC 1.8 misreads (expression_reader::check_syntax). A
// number literal becomes the exact value of the double nearest to it (a rational): GiNaC
// would make 0.1 a 17-digit float, while the generated code must carry the same double as
// a C++ literal 0.1, and constant folding in GiNaC is then exact. Every derivative of the
// table is taken symbolically and printed as C.
//
// Printing: GiNaC's C printer writes pow(b, 2.0) for integer powers of anything but a
// symbol and 17-digit scientific constants; our print context (c_printer) prints integer
// powers as multiplications, half-integer ones with sqrt, and every constant as the
// shortest decimal that reads back as the same double.
//
// Bounds (a model file is input, and GiNaC would follow it anywhere): GiNaC's parser and
// algorithms recurse along the nesting of an expression (8000 parentheses overflowed the
// stack), exact constants grow without limit (2^(2^40) asked for 2^40 bits), and a chain of
// named expressions that uses each link twice doubles the written-out code at each link
// (GiNaC shares the links; the printed C does not). So: the nesting depth is counted on the
// text before GiNaC reads it, a named expression counting with its own depth where it is
// used (max_nesting); numbers are bound to placeholder symbols while GiNaC parses, then
// substituted bottom-up, each power of constants checked before GiNaC computes it and each
// new constant after (max_constant_bits); and the size of every expression, written out, is
// measured on GiNaC's shared nodes, and that of each derivative bounded from above before it
// is taken, against one budget for the whole generated code (max_code_terms). Each refusal
// names the key, before the work that would grow.
//
// GiNaC is not thread-safe (reference counts are not atomic): the whole stage runs under
// one mutex.
#include <algorithm>
#include <array>
#include <cstring>
#include <cmath>
#include <functional>
#include <iterator>
#include <map>
#include <mutex>
#include <set>
#include <sstream>
#include <unordered_map>

#include <ginac/ginac.h>

#include "model_file_detail.hpp"
#include "vimpact/core/cancelled.hpp"
#include "vimpact/core/switch_sides.hpp"
#include "vimpact/core/format.hpp"
#include "vimpact/core/input_error.hpp"

namespace vimpact::detail {
extern const char* const model_abi_text;
}

// Our versions of abs and its sign: GiNaC differentiates abs(u) to u'*u/abs(u) (NaN at 0,
// and with a complex conjugate for symbols not declared real) and leaves csgn without a
// derivative; the generated code needs abs' = csgn and csgn' = 0 (almost everywhere).
namespace {
DECLARE_FUNCTION_1P(vimpact_abs)
DECLARE_FUNCTION_1P(vimpact_csgn)
DECLARE_FUNCTION_1P(vimpact_heaviside)
DECLARE_FUNCTION_2P(vimpact_min)
DECLARE_FUNCTION_2P(vimpact_max)
}  // namespace
unsigned vimpact_abs_SERIAL::serial = 0;
unsigned vimpact_csgn_SERIAL::serial = 0;
unsigned vimpact_heaviside_SERIAL::serial = 0;
unsigned vimpact_min_SERIAL::serial = 0;
unsigned vimpact_max_SERIAL::serial = 0;

namespace vimpact::model_file_detail {

// GiNaC finds a context's parent by the name the macros stringify: unqualified, as GiNaC
// registers its own.
using GiNaC::print_csrc_double;

// The C printer of generated code (outside the anonymous namespace: GiNaC needs its default
// constructor, which nothing here calls).
class c_printer : public print_csrc_double {
    GINAC_DECLARE_PRINT_CONTEXT(c_printer, print_csrc_double)
public:
    c_printer(std::ostream& os, std::set<int>& used_powers) : print_csrc_double(os), powers(&used_powers) {}
    std::set<int>* powers = nullptr;  // integer powers printed with a helper function
};
c_printer::c_printer() : print_csrc_double(std::cout) {}
GINAC_IMPLEMENT_PRINT_CONTEXT(c_printer, print_csrc_double)

namespace {

using GiNaC::ex;
using GiNaC::ex_to;
using GiNaC::is_a;

// How GiNaC's parser makes a function call: it tells a reader from the serial number of a
// GiNaC function by the pointer's low bit (parser.cpp, dispatch_reader_fcn), so a reader
// must sit at an even address, which optimized code gives but -O0 or -Os need not.
template <const unsigned& serial>
[[gnu::aligned(4)]] ex read_call(const GiNaC::exvector& a)
{
    return GiNaC::function(serial, a);
}
[[gnu::aligned(4)]] ex read_sqrt(const GiNaC::exvector& a) { return GiNaC::sqrt(a[0]); }
[[gnu::aligned(4)]] ex read_pow(const GiNaC::exvector& a) { return GiNaC::pow(a[0], a[1]); }

struct function_spec {
    std::string_view name;
    std::size_t arity;
    GiNaC::reader_func read;
};
// The functions an expression may call (abs is read as vimpact_abs, sgn as vimpact_csgn).
// The kinks and jumps (abs, sgn, heaviside, min, max) of the state in a vector field become
// switches (generator::switchify).
constexpr std::array<function_spec, 18> functions{{
    {"sin", 1, read_call<GiNaC::sin_SERIAL::serial>},
    {"cos", 1, read_call<GiNaC::cos_SERIAL::serial>},
    {"tan", 1, read_call<GiNaC::tan_SERIAL::serial>},
    {"asin", 1, read_call<GiNaC::asin_SERIAL::serial>},
    {"acos", 1, read_call<GiNaC::acos_SERIAL::serial>},
    {"atan", 1, read_call<GiNaC::atan_SERIAL::serial>},
    {"sinh", 1, read_call<GiNaC::sinh_SERIAL::serial>},
    {"cosh", 1, read_call<GiNaC::cosh_SERIAL::serial>},
    {"tanh", 1, read_call<GiNaC::tanh_SERIAL::serial>},
    {"exp", 1, read_call<GiNaC::exp_SERIAL::serial>},
    {"log", 1, read_call<GiNaC::log_SERIAL::serial>},
    {"sqrt", 1, read_sqrt},
    {"abs", 1, read_call<vimpact_abs_SERIAL::serial>},
    {"sgn", 1, read_call<vimpact_csgn_SERIAL::serial>},
    {"heaviside", 1, read_call<vimpact_heaviside_SERIAL::serial>},
    {"min", 2, read_call<vimpact_min_SERIAL::serial>},
    {"max", 2, read_call<vimpact_max_SERIAL::serial>},
    {"pow", 2, read_pow},
}};

const function_spec* find_function(std::string_view name)
{
    for (const auto& f : functions)
        if (f.name == name) return &f;
    return nullptr;
}

// "sin, cos, ..." for messages.
std::string functions_text()
{
    std::string s;
    for (const auto& f : functions) s += (s.empty() ? "" : ", ") + std::string(f.name);
    return s;
}

// ---- GiNaC set-up: our functions and the C printer

ex abs_eval(const ex& a)
{
    if (is_a<GiNaC::numeric>(a)) return GiNaC::abs(ex_to<GiNaC::numeric>(a));
    return vimpact_abs(a).hold();
}
ex abs_derivative(const ex& a, unsigned) { return vimpact_csgn(a); }
void abs_print_c(const ex& a, const GiNaC::print_context& c)
{
    c.s << "fabs(";
    a.print(c);
    c.s << ")";
}
ex csgn_eval(const ex& a)
{
    if (is_a<GiNaC::numeric>(a) && ex_to<GiNaC::numeric>(a).is_real()) return ex_to<GiNaC::numeric>(a).csgn();
    return vimpact_csgn(a).hold();
}
ex csgn_derivative(const ex&, unsigned) { return 0; }
void csgn_print_c(const ex& a, const GiNaC::print_context& c)
{
    c.s << "vimpact_csgn(";
    a.print(c);
    c.s << ")";
}
// heaviside(0) = 1, as on(NAME) is 1 where the switching function is 0.
ex heaviside_eval(const ex& a)
{
    if (is_a<GiNaC::numeric>(a) && ex_to<GiNaC::numeric>(a).is_real()) return ex_to<GiNaC::numeric>(a) >= 0 ? 1 : 0;
    return vimpact_heaviside(a).hold();
}
ex heaviside_derivative(const ex&, unsigned) { return 0; }
void heaviside_print_c(const ex& a, const GiNaC::print_context& c)
{
    c.s << "vimpact_heaviside(";
    a.print(c);
    c.s << ")";
}
bool real_numbers(const ex& a, const ex& b)
{
    return is_a<GiNaC::numeric>(a) && ex_to<GiNaC::numeric>(a).is_real() && is_a<GiNaC::numeric>(b) &&
           ex_to<GiNaC::numeric>(b).is_real();
}
ex min_eval(const ex& a, const ex& b)
{
    if (real_numbers(a, b)) return ex_to<GiNaC::numeric>(a) <= ex_to<GiNaC::numeric>(b) ? a : b;
    return vimpact_min(a, b).hold();
}
ex max_eval(const ex& a, const ex& b)
{
    if (real_numbers(a, b)) return ex_to<GiNaC::numeric>(a) >= ex_to<GiNaC::numeric>(b) ? a : b;
    return vimpact_max(a, b).hold();
}
// min(a, b) is a where b - a >= 0, max(a, b) is a where a - b >= 0: the same rule as the
// switches they become.
ex min_derivative(const ex& a, const ex& b, unsigned i)
{
    const ex first = vimpact_heaviside(b - a);
    return i == 0 ? first : 1 - first;
}
ex max_derivative(const ex& a, const ex& b, unsigned i)
{
    const ex first = vimpact_heaviside(a - b);
    return i == 0 ? first : 1 - first;
}
template <const char* name>
void binary_print_c(const ex& a, const ex& b, const GiNaC::print_context& c)
{
    c.s << name << "(";
    a.print(c);
    c.s << ", ";
    b.print(c);
    c.s << ")";
}
constexpr char min_c_name[] = "vimpact_min";
constexpr char max_c_name[] = "vimpact_max";

// The shortest decimal that reads back as the double nearest to the exact value.
std::string c_number(double v)
{
    std::string s = format_double(std::fabs(v));
    if (s.find_first_of(".e") == std::string::npos) s += ".0";
    return (v < 0.0 ? "-" : "") + s;
}

// x*x*x and the like, grouped as GiNaC does so that the compiler can share the squares.
std::string multiplication_chain(const std::string& b, int k)
{
    if (k == 1) return b;
    if (k == 2) return b + "*" + b;
    if (k % 2 == 1) return b + "*" + multiplication_chain(b, k - 1);
    const std::string half = multiplication_chain(b, k / 2);
    return "(" + half + ")*(" + half + ")";
}

constexpr int max_multiplied_power = 64;

void print_numeric(const GiNaC::numeric& n, const c_printer& c, unsigned) { c.s << c_number(n.to_double()); }

void print_constant(const GiNaC::constant& k, const c_printer& c, unsigned)
{
    if (!ex(k).is_equal(GiNaC::Pi)) throw std::logic_error("model file: unexpected constant in an expression");
    c.s << c_number(3.141592653589793);
}

// Sums and products are printed in a canonical form, because the cache needs the same
// source for the same model in every process, and GiNaC's form is not canonical: it orders
// the operands of sums and products by hash values that depend on the serial numbers of
// the symbols and on addresses (so on what the process did before, and on ASLR), and it
// makes a sum that is a factor of a product "unit normal" by the sign of whichever term
// comes first, so that p*(a - b) may be stored as -p*(b - a). The printer therefore sorts
// operands by their text and writes a sum inside a product (or an integer power of one)
// with the sign that gives the smaller text, moving the sign into the coefficient.
constexpr unsigned add_level = 40, mul_level = 50;  // GiNaC's precedences of add and mul

std::string printed(const ex& e, const c_printer& c, unsigned level)
{
    std::ostringstream s;
    e.print(c_printer(s, *c.powers), level);
    return s.str();
}

std::string_view unsigned_text(const std::string& t) { return std::string_view(t).substr(t.starts_with('-') ? 1 : 0); }

std::string joined_sum(std::vector<std::string> terms)
{
    std::sort(terms.begin(), terms.end(), [](const std::string& a, const std::string& b) {
        const auto ua = unsigned_text(a), ub = unsigned_text(b);
        return ua != ub ? ua < ub : a < b;
    });
    std::string s;
    for (const auto& t : terms) s += s.empty() || t.starts_with('-') ? t : "+" + t;
    return s;
}

std::vector<std::string> sum_terms(const ex& sum, const c_printer& c)
{
    std::vector<std::string> terms;
    for (std::size_t i = 0; i < sum.nops(); ++i) terms.push_back(printed(sum.op(i), c, add_level));
    return terms;
}

// The text of S or of -S, whichever is smaller, and whether it is -S. (Every term prints
// with its sign in front, so the terms of -S are those of S with the sign toggled.)
std::string canonical_sum(const ex& sum, const c_printer& c, bool& negated)
{
    std::vector<std::string> terms = sum_terms(sum, c), flipped;
    for (const auto& t : terms) flipped.push_back(t.starts_with('-') ? t.substr(1) : "-" + t);
    std::string plus = joined_sum(std::move(terms)), minus = joined_sum(std::move(flipped));
    negated = minus < plus;
    return negated ? minus : plus;
}

void print_add(const GiNaC::add& a, const c_printer& c, unsigned level)
{
    const std::string s = joined_sum(sum_terms(a, c));
    c.s << (level > 0 ? "(" + s + ")" : s);
}

// b^k, k > 0 an integer; `negative` when the text is that of (-b)^k with k odd (only if
// `sign_free`: a sum under a root keeps its sign).
std::string integer_power_text(const ex& b, int k, const c_printer& c, bool& negative, bool sign_free = true)
{
    negative = false;
    std::string base;
    if (is_a<GiNaC::add>(b) && sign_free) {
        bool negated = false;
        base = canonical_sum(b, c, negated);
        negative = negated && k % 2 == 1;
    } else if (is_a<GiNaC::symbol>(b)) {
        return "(" + multiplication_chain(ex_to<GiNaC::symbol>(b).get_name(), k) + ")";
    } else {
        base = printed(b, c, 0);
    }
    if (k == 1) return "(" + base + ")";
    c.powers->insert(k);
    return "vimpact_pow" + std::to_string(k) + "(" + base + ")";
}

std::string power_text(const GiNaC::power& p, const c_printer& c, bool& negative)
{
    negative = false;
    const ex b = p.op(0);
    const ex e = p.op(1);
    if (is_a<GiNaC::numeric>(e)) {
        const GiNaC::numeric& n = ex_to<GiNaC::numeric>(e);
        const GiNaC::numeric limit(max_multiplied_power);
        if (n.is_integer() && GiNaC::abs(n) <= limit) {
            const int k = n.to_int();
            // 1.0/t as a product with no numerator prints (print_mul), which GiNaC may make of it
            const std::string t = integer_power_text(b, std::abs(k), c, negative);
            return k < 0 ? "1.0/" + t : t;
        }
        if (n.is_rational() && n.denom() == GiNaC::numeric(2) && GiNaC::abs(n) <= limit) {
            const int k = n.numer().to_int();
            const int m = (std::abs(k) - 1) / 2;
            bool unused = false;
            const std::string root = "sqrt(" + printed(b, c, 0) + ")";
            const std::string t = m > 0 ? "(" + integer_power_text(b, m, c, unused, false) + "*" + root + ")" : root;
            return k < 0 ? "(1.0/" + t + ")" : t;
        }
    }
    return "pow(" + printed(b, c, 0) + "," + printed(e, c, 0) + ")";
}

void print_power(const GiNaC::power& p, const c_printer& c, unsigned)
{
    bool negative = false;
    const std::string t = power_text(p, c, negative);
    c.s << (negative ? "-" : "") << t;
}

void print_mul(const GiNaC::mul& m, const c_printer& c, unsigned)
{
    GiNaC::numeric coefficient(1);
    std::vector<std::string> numerator, denominator;
    for (std::size_t i = 0; i < m.nops(); ++i) {
        const ex f = m.op(i);
        bool negative = false;
        if (is_a<GiNaC::numeric>(f)) {
            coefficient = coefficient.mul(ex_to<GiNaC::numeric>(f));
        } else if (is_a<GiNaC::add>(f)) {
            numerator.push_back("(" + canonical_sum(f, c, negative) + ")");
        } else if (is_a<GiNaC::power>(f) && is_a<GiNaC::numeric>(f.op(1)) &&
                   ex_to<GiNaC::numeric>(f.op(1)).is_integer() && ex_to<GiNaC::numeric>(f.op(1)).is_negative()) {
            const int k = ex_to<GiNaC::numeric>(f.op(1)).to_int();
            denominator.push_back(-k <= max_multiplied_power ? integer_power_text(f.op(0), -k, c, negative)
                                                              : printed(GiNaC::pow(f.op(0), -f.op(1)), c, mul_level));
        } else if (is_a<GiNaC::power>(f)) {
            numerator.push_back(power_text(ex_to<GiNaC::power>(f), c, negative));
        } else {
            numerator.push_back(printed(f, c, mul_level));
        }
        if (negative) coefficient = coefficient.mul(GiNaC::numeric(-1));
    }
    std::sort(numerator.begin(), numerator.end());
    std::sort(denominator.begin(), denominator.end());
    std::string s;
    if (numerator.empty()) {
        s = coefficient.is_equal(GiNaC::numeric(1)) ? "1.0" : c_number(coefficient.to_double());
    } else {
        if (coefficient.is_equal(GiNaC::numeric(-1))) s = "-";
        else if (!coefficient.is_equal(GiNaC::numeric(1))) s = c_number(coefficient.to_double()) + "*";
        for (std::size_t i = 0; i < numerator.size(); ++i) s += (i ? "*" : "") + numerator[i];
    }
    for (const auto& d : denominator) s += "/" + d;
    c.s << s;
}

void set_up_ginac()
{
    static std::once_flag once;
    std::call_once(once, [] {
        vimpact_abs_SERIAL::serial = GiNaC::function::register_new(
            GiNaC::function_options("vimpact_abs", 1)
                .eval_func(abs_eval)
                .derivative_func(abs_derivative)
                .print_func<GiNaC::print_csrc>(abs_print_c));
        vimpact_csgn_SERIAL::serial = GiNaC::function::register_new(
            GiNaC::function_options("vimpact_csgn", 1)
                .eval_func(csgn_eval)
                .derivative_func(csgn_derivative)
                .print_func<GiNaC::print_csrc>(csgn_print_c));
        vimpact_heaviside_SERIAL::serial = GiNaC::function::register_new(
            GiNaC::function_options("vimpact_heaviside", 1)
                .eval_func(heaviside_eval)
                .derivative_func(heaviside_derivative)
                .print_func<GiNaC::print_csrc>(heaviside_print_c));
        vimpact_min_SERIAL::serial = GiNaC::function::register_new(
            GiNaC::function_options("vimpact_min", 2)
                .eval_func(min_eval)
                .derivative_func(min_derivative)
                .print_func<GiNaC::print_csrc>(binary_print_c<min_c_name>));
        vimpact_max_SERIAL::serial = GiNaC::function::register_new(
            GiNaC::function_options("vimpact_max", 2)
                .eval_func(max_eval)
                .derivative_func(max_derivative)
                .print_func<GiNaC::print_csrc>(binary_print_c<max_c_name>));
        GiNaC::set_print_func<GiNaC::numeric, c_printer>(print_numeric);
        GiNaC::set_print_func<GiNaC::constant, c_printer>(print_constant);
        GiNaC::set_print_func<GiNaC::power, c_printer>(print_power);
        GiNaC::set_print_func<GiNaC::add, c_printer>(print_add);
        GiNaC::set_print_func<GiNaC::mul, c_printer>(print_mul);
    });
}

// ex::map with a lambda (GiNaC takes a map_function).
template <class F>
struct mapping : GiNaC::map_function {
    F f;
    explicit mapping(F g) : f(std::move(g)) {}
    ex operator()(const ex& e) override { return f(e); }
};
template <class F>
ex map_operands(const ex& e, F f)
{
    mapping<F> m(std::move(f));
    return e.map(m);
}

// GiNaC's own abs and csgn (GiNaC may make them, e.g. sqrt(x^2) = abs(x)) -> ours.
struct use_our_abs : GiNaC::map_function {
    ex operator()(const ex& e) override
    {
        if (is_ex_the_function(e, GiNaC::abs)) return vimpact_abs(e.op(0).map(*this));
        if (is_ex_the_function(e, GiNaC::csgn)) return vimpact_csgn(e.op(0).map(*this));
        return e.map(*this);
    }
};

// ---- bounds

// Sizes of expressions as the printer writes them out: a subexpression counts at each of its
// uses, since the generated code does not share them. Memoized on GiNaC's nodes, which the
// expressions share (a named expression used twice is one node), so measuring is linear in
// the number of distinct nodes however large the written-out size. A measured node is kept
// alive by the memo, so that its address is not taken by another one.
class expression_sizes {
public:
    double size(const ex& e)
    {
        const auto* key = &ex_to<GiNaC::basic>(e);
        if (const auto it = m_size.find(key); it != m_size.end()) return it->second.value;
        double n = 1.0;
        for (std::size_t i = 0; i < e.nops(); ++i) n += size(e.op(i));
        m_size.emplace(key, memo{e, n});
        return n;
    }

    // An upper bound on size(e.diff(x)), from GiNaC's rules (the product rule repeats a
    // product once per factor that depends on x; a function's derivative holds its argument
    // a few times), without differentiating.
    double derivative_size(const ex& e, const GiNaC::symbol& x)
    {
        if (!m_variable.is_equal(x)) {
            m_derivative.clear();
            m_variable = x;
        }
        return derivative(e);
    }

private:
    struct memo {
        ex keep;
        double value;
    };

    double derivative(const ex& e)
    {
        const auto* key = &ex_to<GiNaC::basic>(e);
        if (const auto it = m_derivative.find(key); it != m_derivative.end()) return it->second.value;
        double d = 0.0;
        if (is_a<GiNaC::symbol>(e)) {
            d = e.is_equal(m_variable) ? 1.0 : 0.0;
        } else if (is_a<GiNaC::add>(e)) {
            for (std::size_t i = 0; i < e.nops(); ++i) d += derivative(e.op(i));
        } else if (is_a<GiNaC::mul>(e)) {
            for (std::size_t i = 0; i < e.nops(); ++i) {
                const ex f = e.op(i);
                if (const double df = derivative(f); df > 0.0) d += df + size(e) - size(f) + 1.0;
            }
        } else if (is_a<GiNaC::power>(e)) {
            const double db = derivative(e.op(0)), dc = derivative(e.op(1));
            if (db + dc > 0.0) {
                const double sb = size(e.op(0)), sc = size(e.op(1));
                d = is_a<GiNaC::numeric>(e.op(1)) ? db + sb + sc + 4.0 : db + dc + 2.0 * size(e) + sb + sc + 8.0;
            }
        } else if (is_a<GiNaC::function>(e)) {
            double args = 0.0, dargs = 0.0;
            for (std::size_t i = 0; i < e.nops(); ++i) {
                args += size(e.op(i));
                dargs += derivative(e.op(i));
            }
            if (dargs > 0.0) d = dargs + 4.0 * args + 8.0;
        }
        m_derivative.emplace(key, memo{e, d});
        return d;
    }

    std::unordered_map<const GiNaC::basic*, memo> m_size, m_derivative;
    ex m_variable;
};

// The bits of an exact constant: numerator and denominator (of both parts, if complex).
double constant_bits(const GiNaC::numeric& n)
{
    if (!n.is_real()) return constant_bits(n.real()) + constant_bits(n.imag());
    if (!n.is_rational()) return 64.0;
    const GiNaC::numeric d = n.denom();
    return static_cast<double>(n.numer().int_length()) + (d.is_equal(GiNaC::numeric(1)) ? 0.0 : d.int_length());
}

// The bits of the largest constant GiNaC computes when it evaluates b^x (x a number): a
// number raised, a product's factors raised one by one, a power's exponents multiplied.
double raised_bits(const ex& b, const GiNaC::numeric& x)
{
    if (!x.is_rational() || (x.is_integer() && GiNaC::abs(x) <= GiNaC::numeric(1))) return 0.0;
    if (is_a<GiNaC::numeric>(b)) {
        const auto& n = ex_to<GiNaC::numeric>(b);
        if (n.is_zero() || GiNaC::abs(n).is_equal(GiNaC::numeric(1))) return 0.0;
        return constant_bits(n) * std::fabs(x.to_double());
    }
    double most = 0.0;
    if (is_a<GiNaC::mul>(b))
        for (std::size_t i = 0; i < b.nops(); ++i) most = std::max(most, raised_bits(b.op(i), x));
    if (is_a<GiNaC::power>(b) && is_a<GiNaC::numeric>(b.op(1)))
        most = raised_bits(b.op(0), ex_to<GiNaC::numeric>(b.op(1)).mul(x));
    return most;
}

[[noreturn]] void constant_too_large(const std::string& where, const std::string& key)
{
    throw input_error(where + ": " + key + ": an exact constant of the expression would have more than " +
                      std::to_string(max_constant_bits) +
                      " bits (such as 2^(2^40)); constants are computed exactly before they are rounded to doubles");
}

// The new constants of a node just made (its own value, or its operands: a product's
// coefficient, a sum's constant term).
void check_constants(const ex& e, const std::string& where, const std::string& key)
{
    const auto check = [&](const ex& x) {
        if (is_a<GiNaC::numeric>(x) && constant_bits(ex_to<GiNaC::numeric>(x)) > static_cast<double>(max_constant_bits))
            constant_too_large(where, key);
    };
    check(e);
    if (is_a<GiNaC::add>(e) || is_a<GiNaC::mul>(e))
        for (std::size_t i = 0; i < e.nops(); ++i) check(e.op(i));
}

// The expression GiNaC parsed over placeholders, with their values put in from the leaves up:
// the constants' growth is checked at each node, before a power of constants is computed.
struct bounded_substitution : GiNaC::map_function {
    bounded_substitution(const std::map<std::string, ex>& v, const std::string& w, const std::string& k)
        : values(v), where(w), key(k)
    {
    }
    ex operator()(const ex& e) override
    {
        if (is_a<GiNaC::symbol>(e)) {
            const auto it = values.find(ex_to<GiNaC::symbol>(e).get_name());
            return it != values.end() ? it->second : e;
        }
        ex r;
        if (is_a<GiNaC::power>(e)) {
            const ex b = (*this)(e.op(0)), x = (*this)(e.op(1));
            if (is_a<GiNaC::numeric>(x) && raised_bits(b, ex_to<GiNaC::numeric>(x)) > static_cast<double>(max_constant_bits))
                constant_too_large(where, key);
            r = GiNaC::pow(b, x);
        } else {
            r = e.map(*this);
        }
        check_constants(r, where, key);
        return r;
    }
    const std::map<std::string, ex>& values;
    const std::string& where;
    const std::string& key;
};

[[noreturn]] void code_too_large(const std::string& where, const std::string& key, const std::string& what)
{
    std::ostringstream limit;
    limit << max_code_terms;
    throw input_error(where + ": " + key + ": " + what + " would make the generated code too large: more than " +
                      limit.str() +
                      " operations written out (a named expression is written out wherever it is used, with its "
                      "derivatives); simplify the equations, or write the model in C++ (docs/own-model.md)");
}

// ---- reading expressions

[[noreturn]] void fail(const std::string& where, const std::string& key, const std::string& message)
{
    throw input_error(where + ": " + key + ": " + message);
}

enum symbol_kind : unsigned { state_kind = 1, parameter_kind = 2, derived_kind = 4, expression_kind = 8, switch_kind = 16 };

// side(NAME) and on(NAME): the side of switch NAME (+1 or -1) and (1 + side) / 2. Not
// functions of an expression: their argument is a switch's name.
bool is_side_call(const std::string& name) { return name == "side" || name == "on"; }

const char* kind_name(unsigned k)
{
    switch (k) {
        case state_kind: return "a state variable";
        case parameter_kind: return "a parameter";
        case derived_kind: return "a derived quantity";
        case switch_kind: return "a switch";
        default: return "a named expression";
    }
}

struct token {
    enum kind_t { number, name, op, open, close, comma } kind;
    std::string text;
    std::size_t begin, end;  // where it is written in the expression
};

bool is_letter(char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_'; }
bool is_digit(char c) { return c >= '0' && c <= '9'; }

std::vector<token> tokenize(const expression_text& e, const std::string& where)
{
    std::vector<token> out;
    const std::string& s = e.text;
    std::size_t i = 0;
    while (i < s.size()) {
        const char c = s[i];
        if (c == ' ' || c == '\t' || c == '\n' || c == '\r') {
            ++i;
        } else if (is_digit(c) || (c == '.' && i + 1 < s.size() && is_digit(s[i + 1]))) {
            const std::size_t start = i;
            while (i < s.size() && is_digit(s[i])) ++i;
            if (i < s.size() && s[i] == '.') {
                ++i;
                while (i < s.size() && is_digit(s[i])) ++i;
            }
            if (i < s.size() && (s[i] == 'e' || s[i] == 'E')) {
                std::size_t j = i + 1;
                if (j < s.size() && (s[j] == '+' || s[j] == '-')) ++j;
                if (j < s.size() && is_digit(s[j])) {
                    i = j;
                    while (i < s.size() && is_digit(s[i])) ++i;
                }
            }
            if (i < s.size() && (is_letter(s[i]) || s[i] == '.'))
                fail(where, e.key, "malformed number '" + s.substr(start, i - start + 1) + "' in '" + s +
                                       "' (write 2*x for a product)");
            out.push_back({token::number, s.substr(start, i - start), start, i});
        } else if (is_letter(c)) {
            const std::size_t start = i;
            while (i < s.size() && (is_letter(s[i]) || is_digit(s[i]))) ++i;
            out.push_back({token::name, s.substr(start, i - start), start, i});
        } else if (c == '*' && i + 1 < s.size() && s[i + 1] == '*') {
            out.push_back({token::op, "^", i, i + 2});
            i += 2;
        } else if (c == '+' || c == '-' || c == '*' || c == '/' || c == '^') {
            out.push_back({token::op, std::string(1, c), i, i + 1});
            ++i;
        } else if (c == '(') {
            out.push_back({token::open, "(", i, i + 1});
            ++i;
        } else if (c == ')') {
            out.push_back({token::close, ")", i, i + 1});
            ++i;
        } else if (c == ',') {
            out.push_back({token::comma, ",", i, i + 1});
            ++i;
        } else {
            fail(where, e.key, "unexpected character '" + std::string(1, c) + "' in '" + s +
                                   "' (expressions use numbers, names, + - * / ^, parentheses and functions)");
        }
    }
    if (out.empty()) fail(where, e.key, "empty expression");
    return out;
}

// The exact value of the double nearest to a literal.
GiNaC::numeric literal_value(const std::string& text)
{
    if (text.find_first_of(".eE") == std::string::npos) return GiNaC::numeric(text.c_str());
    const double v = std::strtod(text.c_str(), nullptr);
    if (!std::isfinite(v)) throw std::range_error("the number " + text + " is out of the range of double");
    if (v == 0.0) return 0;
    int e = 0;
    const double m = std::frexp(v, &e);  // v = m 2^e, 0.5 <= m < 1
    const auto mantissa = static_cast<long>(std::ldexp(m, 53));
    return GiNaC::numeric(mantissa).mul(GiNaC::numeric(2).power(GiNaC::numeric(e - 53)));
}

bool is_sign(const token& t) { return t.kind == token::op && (t.text == "+" || t.text == "-"); }

// The index of the ')' that closes the '(' at tokens[open] (parentheses are balanced).
std::size_t closing(const std::vector<token>& tokens, std::size_t open)
{
    std::size_t depth = 0;
    for (std::size_t t = open;; ++t) {
        if (tokens[t].kind == token::open) ++depth;
        if (tokens[t].kind == token::close && --depth == 0) return t;
    }
}

// One past the operand that starts at tokens[i] (signs, a number, name, call or group, and
// a power of it), or i if none starts there.
std::size_t operand_end(const std::vector<token>& tokens, std::size_t i)
{
    // A loop, not a recursion, along a^b^...: a written chain may be longer than the stack.
    std::size_t end = i, j = i;
    for (;;) {
        while (j < tokens.size() && is_sign(tokens[j])) ++j;
        if (j == tokens.size()) return end;
        if (tokens[j].kind == token::name && j + 1 < tokens.size() && tokens[j + 1].kind == token::open) ++j;
        if (tokens[j].kind == token::open) j = closing(tokens, j);
        else if (tokens[j].kind != token::number && tokens[j].kind != token::name) return end;
        end = ++j;
        if (j == tokens.size() || tokens[j].kind != token::op || tokens[j].text != "^") return end;
        ++j;
    }
}

// The first token of the operand that ends with tokens[last].
std::size_t operand_start(const std::vector<token>& tokens, std::size_t last)
{
    if (tokens[last].kind != token::close) return last;
    std::size_t depth = 0, t = last;
    for (;; --t) {
        if (tokens[t].kind == token::close) ++depth;
        if (tokens[t].kind == token::open && --depth == 0) break;
    }
    return t > 0 && tokens[t - 1].kind == token::name ? t - 1 : t;
}

const GiNaC::prototype_table& function_readers()
{
    static const GiNaC::prototype_table readers = [] {
        GiNaC::prototype_table r;
        for (const auto& f : functions) r[{std::string(f.name), f.arity}] = f.read;
        return r;
    }();
    return readers;
}

struct named_symbol {
    unsigned kind;
    ex value;  // the symbol, or for a named expression its value once read
    bool ready = true;
    int nesting = 0;  // of a named expression: its own depth, which it brings where it is used
};

[[noreturn]] void too_deep(const std::string& where, const std::string& key, const std::string& what)
{
    fail(where, key, "the expression nests more than " + std::to_string(max_nesting) + " levels deep (" + what +
                         "); GiNaC reads and differentiates by recursion");
}

// What an expression may refer to, and why not when it may not.
struct expression_rules {
    unsigned allowed;
    const char* reason;  // "derived quantities depend on the parameters only"
};

class expression_reader {
public:
    explicit expression_reader(const std::string& where) : m_where(where) {}

    void add(const std::string& name, unsigned kind, ex value, bool ready = true)
    {
        m_names[name] = {kind, std::move(value), ready};
        m_order.push_back(name);
    }
    void set_value(const std::string& name, ex value, int nesting)
    {
        auto& n = m_names.at(name);
        n.value = std::move(value);
        n.ready = true;
        n.nesting = nesting;
    }

    // The depth of an expression: its parentheses (a call's too), and at each use of a named
    // expression 1 + that expression's depth.
    int nesting(const expression_text& e) const
    {
        const auto tokens = tokenize(e, m_where);
        int depth = 0, most = 0;
        for (const token& tk : tokens) {
            if (tk.kind == token::open) most = std::max(most, ++depth);
            else if (tk.kind == token::close) --depth;
            else if (tk.kind == token::name)
                if (const auto it = m_names.find(tk.text); it != m_names.end() && it->second.kind == expression_kind)
                    most = std::max(most, depth + 1 + it->second.nesting);
        }
        return most;
    }

    expression_sizes& sizes() const { return m_sizes; }

    // The names an expression uses, after checking every token.
    std::vector<std::string> names_used(const expression_text& e, const expression_rules& rules) const
    {
        std::vector<std::string> used;
        const auto tokens = tokenize(e, m_where);
        int depth = 0;
        for (std::size_t t = 0; t < tokens.size(); ++t) {
            const token& tk = tokens[t];
            // Before GiNaC's parser, which recurses once per level, sees the text.
            if (tk.kind == token::open && ++depth > max_nesting) too_deep(m_where, e.key, "parentheses and calls");
            if (tk.kind == token::close && --depth < 0) fail(m_where, e.key, "unbalanced ')' in '" + e.text + "'");
            if (tk.kind != token::name) continue;
            const bool call = t + 1 < tokens.size() && tokens[t + 1].kind == token::open;
            if (call && is_side_call(tk.text)) {
                check_side_call(e, tokens, t, rules);
                t += 3;  // past '(' NAME ')'
                continue;
            }
            if (call) {
                check_call(e, tokens, t);
                continue;
            }
            if (find_function(tk.text)) fail(m_where, e.key, "'" + tk.text + "' is a function: write " + tk.text + "(...)");
            if (tk.text == "pi") continue;
            const auto it = m_names.find(tk.text);
            if (it == m_names.end())
                fail(m_where, e.key, "unknown symbol '" + tk.text + "' (" + known_names(rules.allowed) + ")");
            if (it->second.kind == switch_kind)
                fail(m_where, e.key, "'" + tk.text + "' is a switch: write side(" + tk.text + ") or on(" + tk.text + ")");
            if (!(it->second.kind & rules.allowed))
                fail(m_where, e.key, "'" + tk.text + "' is " + kind_name(it->second.kind) + ": " + rules.reason);
            used.push_back(tk.text);
        }
        if (depth != 0) fail(m_where, e.key, "unbalanced '(' in '" + e.text + "'");
        return used;
    }

    ex read(const expression_text& e, const expression_rules& rules) const
    {
        (void)names_used(e, rules);
        if (nesting(e) > max_nesting) too_deep(m_where, e.key, "with the named expressions it uses");
        const auto tokens = tokenize(e, m_where);
        check_syntax(e, tokens);
        ex result;
        try {
            GiNaC::symtab operands;
            std::map<std::string, ex> values;
            const std::string text = ginac_text(tokens, operands, values, e.key);
            for (const auto& [name, value] : values) check_constants(value, m_where, e.key);
            GiNaC::parser reader(operands, true, function_readers());
            bounded_substitution substitute(values, m_where, e.key);
            result = substitute(reader(text));
        } catch (const input_error&) {
            throw;
        } catch (const GiNaC::parse_error& x) {
            fail(m_where, e.key, "cannot read '" + e.text + "': " + x.what());
        } catch (const std::exception& x) {
            fail(m_where, e.key, "cannot evaluate '" + e.text + "': " + evaluation_message(x.what()));
        }
        // Measured on the shared nodes first: the walks below follow every use.
        if (m_sizes.size(result) > max_code_terms) code_too_large(m_where, e.key, "the expression");
        use_our_abs ours;
        result = ours(result);
        check_translatable(result, e.key, m_where);
        return result;
    }

    // Every object of an expression must have a C translation with real, finite constants.
    static void check_translatable(const ex& e, const std::string& key, const std::string& where)
    {
        if (is_a<GiNaC::numeric>(e)) {
            const auto& n = ex_to<GiNaC::numeric>(e);
            if (!n.is_real())
                fail(where, key, "the expression has no real value (a constant such as sqrt(-1) or log(-2) is complex)");
            if (!std::isfinite(n.to_double()))
                fail(where, key, "a constant of the expression or of its derivatives is out of the range of double");
            return;
        }
        if (is_a<GiNaC::symbol>(e)) return;
        if (is_a<GiNaC::constant>(e)) {
            if (!e.is_equal(GiNaC::Pi)) fail(where, key, "unexpected constant in the expression");
            return;
        }
        if (is_a<GiNaC::function>(e)) {
            const std::string name = ex_to<GiNaC::function>(e).get_name();
            if (!name.starts_with("vimpact_") && !find_function(name))
                fail(where, key, "the function " + name + " cannot be compiled");
        } else if (!is_a<GiNaC::add>(e) && !is_a<GiNaC::mul>(e) && !is_a<GiNaC::power>(e)) {
            std::ostringstream s;
            s << e;
            fail(where, key, "cannot compile '" + s.str() + "'");
        }
        for (std::size_t i = 0; i < e.nops(); ++i) check_translatable(e.op(i), key, where);
    }

private:
    // The grammar, checked before GiNaC reads the text: GiNaC's messages would not name the
    // key, and its parser silently misreads a sign right after an operator as applying to
    // the rest of the expression (x^-2 + y as x^(-2 + y), x - -y + z as x + y - z). A sign is
    // therefore allowed only where an expression starts: first, after '(' and after ','.
    void check_syntax(const expression_text& e, const std::vector<token>& tokens) const
    {
        const auto cannot_read = [&](const std::string& why) {
            fail(m_where, e.key, "cannot read '" + e.text + "': " + why);
        };
        struct level {
            bool call;     // the arguments of a function, where ',' is allowed
            char last_op;  // the last binary operator at this level, for a^b^c
        };
        std::vector<level> levels{{false, 0}};
        bool operand = true;  // whether an operand comes next
        for (std::size_t t = 0; t < tokens.size(); ++t) {
            const token& tk = tokens[t];
            const auto unexpected = [&] { cannot_read("unexpected '" + tk.text + "'"); };
            if (operand) {
                if (tk.kind == token::number) {
                    operand = false;
                } else if (tk.kind == token::name) {
                    operand = t + 1 < tokens.size() && tokens[t + 1].kind == token::open;
                } else if (tk.kind == token::open) {
                    levels.push_back({t > 0 && tokens[t - 1].kind == token::name, 0});
                } else if (is_sign(tk)) {
                    if (t > 0 && tokens[t - 1].kind == token::op) refuse_sign(e, tokens, t);
                } else {
                    unexpected();
                }
            } else if (tk.kind == token::op) {
                if (tk.text == "^" && levels.back().last_op == '^')
                    cannot_read("a^b^c is ambiguous: write (a^b)^c or a^(b^c)");
                levels.back().last_op = tk.text[0];
                operand = true;
            } else if (tk.kind == token::close) {
                levels.pop_back();
            } else if (tk.kind == token::comma && levels.back().call) {
                levels.back().last_op = 0;
                operand = true;
            } else {
                unexpected();
            }
        }
        if (operand) cannot_read("the expression ends too early");
    }

    // The message for the sign at tokens[sign], with the fix written into the text as given:
    // "write x^(-2), not x^-2". (Without an operand after the sign, the next token is the
    // error.)
    void refuse_sign(const expression_text& e, const std::vector<token>& tokens, std::size_t sign) const
    {
        const std::size_t end = operand_end(tokens, sign);
        if (end == sign) return;
        const std::size_t op = sign - 1;
        const bool binary = op > 0 && (tokens[op - 1].kind == token::number || tokens[op - 1].kind == token::name ||
                                       tokens[op - 1].kind == token::close);
        const std::size_t from = tokens[binary ? operand_start(tokens, op - 1) : op].begin;
        const std::size_t at = tokens[sign].begin, to = tokens[end - 1].end;
        const std::string& s = e.text;
        fail(m_where, e.key, "write " + s.substr(from, at - from) + "(" + s.substr(at, to - at) + "), not " +
                                 s.substr(from, to - from) + " (a sign right after an operator is ambiguous)");
    }

    // The text GiNaC reads: every number and name becomes a placeholder (a0, a1, ...) that
    // the symbol table binds to its value, so GiNaC reads only the structure. Its lexer
    // would make 0.1 a 17-digit float and take the names I, Pi, Euler and Catalan for its
    // own constants.
    // The placeholders stay symbols while GiNaC parses (`values` holds what they stand for),
    // so that it computes nothing with the numbers before bounded_substitution checks it.
    std::string ginac_text(const std::vector<token>& tokens, GiNaC::symtab& operands,
                           std::map<std::string, ex>& values, const std::string& key) const
    {
        std::string text;
        for (std::size_t t = 0; t < tokens.size(); ++t) {
            const token& tk = tokens[t];
            const bool call = t + 1 < tokens.size() && tokens[t + 1].kind == token::open;
            if (tk.kind == token::name && call && is_side_call(tk.text)) {
                // side(NAME) or on(NAME), checked by names_used: one operand.
                const std::string placeholder = "a" + std::to_string(t);
                operands[placeholder] = GiNaC::symbol(placeholder);
                const ex side = m_names.at(tokens[t + 2].text).value;
                values[placeholder] = tk.text == "side" ? side : (1 + side) / 2;
                text += placeholder + " ";
                t += 3;
                continue;
            }
            if (tk.kind == token::number || (tk.kind == token::name && !call)) {
                const std::string placeholder = "a" + std::to_string(t);
                operands[placeholder] = GiNaC::symbol(placeholder);
                // An integer literal is exact: its digits count (log10(2) bits each) before it is read.
                if (tk.kind == token::number && tk.text.find_first_of(".eE") == std::string::npos &&
                    static_cast<double>(tk.text.size()) > static_cast<double>(max_constant_bits) * 0.30103 + 1.0)
                    constant_too_large(m_where, key);
                values[placeholder] = tk.kind == token::number ? ex(literal_value(tk.text))
                                      : tk.text == "pi"        ? ex(GiNaC::Pi)
                                                               : m_names.at(tk.text).value;
                text += placeholder + " ";
            } else {
                text += tk.text + " ";
            }
        }
        return text;
    }

    void check_side_call(const expression_text& e, const std::vector<token>& tokens, std::size_t t,
                         const expression_rules& rules) const
    {
        const std::string& f = tokens[t].text;
        if (!(t + 3 < tokens.size() && tokens[t + 2].kind == token::name && tokens[t + 3].kind == token::close))
            fail(m_where, e.key, f + "() takes the name of a switch: " + f + "(NAME) in '" + e.text + "'");
        const std::string& name = tokens[t + 2].text;
        const auto it = m_names.find(name);
        if (it == m_names.end() || it->second.kind != switch_kind)
            fail(m_where, e.key, "'" + name + "' is not a switch (" + f + "() takes the name of one: " + switch_names() + ")");
        if (!(rules.allowed & switch_kind))
            fail(m_where, e.key, f + "(" + name + ") is the side of a switch: " + rules.reason);
    }
    std::string switch_names() const
    {
        std::string list;
        for (const auto& name : m_order)
            if (m_names.at(name).kind == switch_kind) list += (list.empty() ? "" : ", ") + name;
        return list.empty() ? "the model has none" : "switches: " + list;
    }

    void check_call(const expression_text& e, const std::vector<token>& tokens, std::size_t t) const
    {
        const std::string& name = tokens[t].text;
        const function_spec* f = find_function(name);
        if (!f) {
            if (name == "pi" || m_names.count(name))
                fail(m_where, e.key, "'" + name + "' is not a function (write " + name + "*(...) for a product)");
            fail(m_where, e.key, "unknown function '" + name + "' (functions: " + functions_text() + ")");
        }
        // Count the arguments: commas at depth 1 until the matching parenthesis.
        std::size_t args = 0, depth = 0;
        bool empty = true;
        for (std::size_t u = t + 1; u < tokens.size(); ++u) {
            if (tokens[u].kind == token::open) {
                ++depth;
            } else if (tokens[u].kind == token::close) {
                if (--depth == 0) break;
            } else if (tokens[u].kind == token::comma && depth == 1) {
                ++args;
            }
            if (depth >= 1 && u > t + 1) empty = false;
        }
        if (!empty) ++args;
        if (args != f->arity)
            fail(m_where, e.key, name + " takes " + std::to_string(f->arity) + " argument" + (f->arity == 1 ? "" : "s") +
                                     ", got " + std::to_string(args) + " in '" + e.text + "'");
    }

    std::string known_names(unsigned allowed) const
    {
        std::string out;
        for (const unsigned k : {state_kind, parameter_kind, derived_kind, expression_kind}) {
            if (!(allowed & k)) continue;
            std::string list;
            for (const auto& name : m_order)
                if (m_names.at(name).kind == k) list += (list.empty() ? "" : ", ") + name;
            if (list.empty()) continue;
            const char* label = k == state_kind       ? "state"
                                : k == parameter_kind ? "parameters"
                                : k == derived_kind   ? "derived"
                                                      : "expressions";
            out += (out.empty() ? "" : "; ") + std::string(label) + ": " + list;
        }
        return out.empty() ? "no names may be used here, only numbers and pi" : out;
    }

    static std::string evaluation_message(const std::string& m)
    {
        if (m.find("division by zero") != std::string::npos) return "division by zero";
        if (m.find("log(0)") != std::string::npos || m.find("pole") != std::string::npos) return "a singular constant (such as log(0))";
        return m;
    }

    const std::string& m_where;
    std::map<std::string, named_symbol> m_names;
    std::vector<std::string> m_order;
    mutable expression_sizes m_sizes;
};

// A constant expression (an angle's period) in double arithmetic.
double evaluate_constant(const ex& e)
{
    if (is_a<GiNaC::numeric>(e)) return ex_to<GiNaC::numeric>(e).to_double();
    if (is_a<GiNaC::constant>(e)) return 3.141592653589793;
    if (is_a<GiNaC::add>(e)) {
        double s = 0.0;
        for (std::size_t i = 0; i < e.nops(); ++i) s += evaluate_constant(e.op(i));
        return s;
    }
    if (is_a<GiNaC::mul>(e)) {
        // A rational coefficient p/q as *p/q, so that pi/3 is the double of C++'s pi/3.0.
        double s = 1.0;
        GiNaC::numeric coefficient(1);
        for (std::size_t i = 0; i < e.nops(); ++i) {
            if (is_a<GiNaC::numeric>(e.op(i))) coefficient = coefficient.mul(ex_to<GiNaC::numeric>(e.op(i)));
            else s *= evaluate_constant(e.op(i));
        }
        return s * coefficient.numer().to_double() / coefficient.denom().to_double();
    }
    if (is_a<GiNaC::power>(e)) return std::pow(evaluate_constant(e.op(0)), evaluate_constant(e.op(1)));
    if (is_a<GiNaC::function>(e)) {
        const std::string name = ex_to<GiNaC::function>(e).get_name();
        const double a = evaluate_constant(e.op(0));
        if (name == "vimpact_min") return std::fmin(a, evaluate_constant(e.op(1)));
        if (name == "vimpact_max") return std::fmax(a, evaluate_constant(e.op(1)));
        static const std::map<std::string, double (*)(double)> f{
            {"sin", [](double v) { return std::sin(v); }},   {"cos", [](double v) { return std::cos(v); }},
            {"tan", [](double v) { return std::tan(v); }},   {"asin", [](double v) { return std::asin(v); }},
            {"acos", [](double v) { return std::acos(v); }}, {"atan", [](double v) { return std::atan(v); }},
            {"sinh", [](double v) { return std::sinh(v); }}, {"cosh", [](double v) { return std::cosh(v); }},
            {"tanh", [](double v) { return std::tanh(v); }}, {"exp", [](double v) { return std::exp(v); }},
            {"log", [](double v) { return std::log(v); }},   {"vimpact_abs", [](double v) { return std::fabs(v); }},
            {"vimpact_csgn", [](double v) { return v > 0.0 ? 1.0 : v < 0.0 ? -1.0 : 0.0; }},
            {"vimpact_heaviside", [](double v) { return v >= 0.0 ? 1.0 : 0.0; }},
        };
        if (const auto it = f.find(name); it != f.end()) return it->second(a);
    }
    return std::nan("");
}

// Order a set of definitions that may use each other (derived quantities, named
// expressions) so that each comes after what it uses; a cycle is an error.
std::vector<std::size_t> dependency_order(const std::vector<named_expression>& items,
                                          const std::vector<std::vector<std::string>>& uses, const std::string& where)
{
    const std::size_t n = items.size();
    std::map<std::string, std::size_t> index;
    for (std::size_t i = 0; i < n; ++i) index[items[i].name] = i;
    std::vector<int> state(n, 0);  // 0 new, 1 on the path, 2 done
    std::vector<std::size_t> order, path;
    std::function<void(std::size_t)> visit = [&](std::size_t i) {
        if (state[i] == 2) return;
        if (state[i] == 1) {
            std::string cycle;
            auto it = std::find(path.begin(), path.end(), i);
            for (; it != path.end(); ++it) cycle += items[*it].name + " -> ";
            fail(where, items[i].expr.key, "circular definition (" + cycle + items[i].name + ")");
        }
        state[i] = 1;
        path.push_back(i);
        for (const auto& name : uses[i])
            if (const auto it = index.find(name); it != index.end()) visit(it->second);
        path.pop_back();
        state[i] = 2;
        order.push_back(i);
    };
    for (std::size_t i = 0; i < n; ++i) visit(i);
    return order;
}

std::string c_string(std::string_view s)
{
    std::string out = "\"";
    for (const char ch : s) {
        const auto c = static_cast<unsigned char>(ch);
        if (c == '"' || c == '\\' || c == '?') {
            out += '\\';
            out += ch;
        } else if (c < 0x20 || c >= 0x7f) {
            const char digits[] = {'\\', static_cast<char>('0' + (c >> 6)), static_cast<char>('0' + ((c >> 3) & 7)),
                                   static_cast<char>('0' + (c & 7)), '\0'};
            out += digits;
        } else {
            out += ch;
        }
    }
    return out + "\"";
}

// ---- the generator

class generator {
public:
    generator(const description& d, const std::string& where, const std::atomic<bool>* cancel)
        : m_d(d), m_where(where), m_cancel(cancel), m_reader(where), m_n(static_cast<int>(d.state.size())),
          m_p(static_cast<int>(d.parameters.size())), m_nd(static_cast<int>(d.derived.size()))
    {
        for (int j = 0; j < m_n; ++j) {
            m_x.emplace_back("x[" + std::to_string(j) + "]");
            m_reader.add(d.state[static_cast<std::size_t>(j)].name, state_kind, m_x.back());
            m_out.emplace_back("out[" + std::to_string(j) + "]");
        }
        for (int k = 0; k < m_p + m_nd; ++k) m_ctx.emplace_back("p[" + std::to_string(k) + "]");
        for (int k = 0; k < m_p; ++k) m_reader.add(d.parameters[static_cast<std::size_t>(k)].name, parameter_kind, m_ctx[static_cast<std::size_t>(k)]);
        for (int k = 0; k < m_nd; ++k) m_reader.add(d.derived[static_cast<std::size_t>(k)].name, derived_kind, m_ctx[static_cast<std::size_t>(m_p + k)]);
        for (const auto& e : d.expressions) m_reader.add(e.name, expression_kind, 0, false);
        // A switch's side: S[k] in every function of the state, from the context or the state
        // (vimpact_sides).
        for (int j = 0; j < m_n; ++j) m_user_names["x[" + std::to_string(j) + "]"] = d.state[static_cast<std::size_t>(j)].name;
        for (int k = 0; k < m_p; ++k) m_user_names["p[" + std::to_string(k) + "]"] = d.parameters[static_cast<std::size_t>(k)].name;
        for (int k = 0; k < m_nd; ++k) m_user_names["p[" + std::to_string(m_p + k) + "]"] = d.derived[static_cast<std::size_t>(k)].name;
        for (std::size_t k = 0; k < d.switches.size(); ++k) m_user_names["S[" + std::to_string(k) + "]"] = "side(" + d.switches[k].name + ")";
        for (std::size_t k = 0; k < d.switches.size(); ++k) {
            m_side.emplace_back("S[" + std::to_string(k) + "]");
            m_reader.add(d.switches[k].name, switch_kind, m_side.back());
            m_switches.push_back({d.switches[k].name, d.switches[k].meaning, d.switches[k].direction, !d.switches[k].reset.empty()});
        }
    }

    std::string run()
    {
        read_derived();
        read_expressions();
        read_periods();
        build_field();
        std::string body = functions();
        std::string top = preamble();
        return top + body + table();
    }

private:
    static constexpr expression_rules derived_rules{parameter_kind | derived_kind,
                                                    "derived quantities depend on the parameters only"};
    static constexpr expression_rules state_rules{
        state_kind | parameter_kind | derived_kind | expression_kind | switch_kind, ""};
    static constexpr expression_rules constant_rules{0, "a period must be a constant, such as 2*pi"};

    void read_derived()
    {
        std::vector<std::vector<std::string>> uses;
        for (const auto& n : m_d.derived) uses.push_back(m_reader.names_used(n.expr, derived_rules));
        m_derived_order = dependency_order(m_d.derived, uses, m_where);
        m_derived.resize(m_d.derived.size());
        for (const std::size_t i : m_derived_order) m_derived[i] = m_reader.read(m_d.derived[i].expr, derived_rules);
    }

    void read_expressions()
    {
        std::vector<std::vector<std::string>> uses;
        for (const auto& n : m_d.expressions) uses.push_back(m_reader.names_used(n.expr, state_rules));
        for (const std::size_t i : dependency_order(m_d.expressions, uses, m_where)) {
            poll_cancel();
            const auto& e = m_d.expressions[i].expr;
            m_reader.set_value(m_d.expressions[i].name, m_reader.read(e, state_rules), m_reader.nesting(e));
        }
    }

    void read_periods()
    {
        for (const auto& s : m_d.state) {
            double period = 0.0;
            if (s.period) {
                period = evaluate_constant(m_reader.read(*s.period, constant_rules));
                if (!std::isfinite(period) || period <= 0.0)
                    fail(m_where, s.period->key, "the period must be a positive number, got " + format_double(period));
            }
            m_periods.push_back(period);
        }
    }

    ex read(const expression_text& e)
    {
        poll_cancel();
        return m_reader.read(e, state_rules);
    }

    // Between GiNaC's steps, each bounded in size: a Ctrl-C stops the work at once.
    void poll_cancel() const
    {
        if (m_cancel && m_cancel->load(std::memory_order_relaxed)) throw cancelled();
    }

    // The derivative of e by x, once its size, bounded before it is taken, fits in what is
    // left of the code's budget (everything differentiated is printed at least once).
    ex derivative(const ex& e, int j, const std::string& key)
    {
        poll_cancel();
        // Nothing here depends on x_j: zero, which the code never writes out (bilinear skips
        // it), so it takes nothing of the budget. A reset that leaves most of a large state as
        // it is has N^2 such second derivatives per component it leaves.
        if (!e.has(sym(j))) return 0;
        expression_sizes& sizes = m_reader.sizes();
        if (m_terms + sizes.derivative_size(e, sym(j)) > max_code_terms)
            code_too_large(m_where, key, "the derivative by " + m_d.state[static_cast<std::size_t>(j)].name);
        ex d = e.diff(sym(j));
        m_terms += sizes.size(d);
        return d;
    }

    // The values of an assignment list, defaulting to `otherwise` for unnamed variables.
    std::vector<ex> assigned(const std::vector<assignment>& list, const std::vector<ex>& otherwise)
    {
        std::vector<ex> v = otherwise;
        for (const auto& a : list) v[static_cast<std::size_t>(a.index)] = read(a.expr);
        return v;
    }

    struct vector_function {  // a map of the state and its first and second derivatives
        std::string key;
        std::vector<ex> value;
        std::vector<std::vector<ex>> jacobian;                  // [i][j]
        std::vector<std::vector<std::vector<ex>>> hessian;      // [i][j][k], j <= k used
    };
    struct scalar_function {
        std::string key;
        ex value;
        std::vector<ex> gradient;
        std::vector<std::vector<ex>> hessian;
    };

    vector_function differentiate(const std::string& key, std::vector<ex> value, bool second)
    {
        vector_function f{key, std::move(value), {}, {}};
        try {
            for (const ex& fi : f.value) {
                m_terms += m_reader.sizes().size(fi);
                std::vector<ex> row;
                for (int j = 0; j < m_n; ++j) row.push_back(derivative(fi, j, key));
                if (second) {
                    std::vector<std::vector<ex>> h(static_cast<std::size_t>(m_n), std::vector<ex>(static_cast<std::size_t>(m_n)));
                    for (int j = 0; j < m_n; ++j)
                        for (int k = j; k < m_n; ++k)
                            h[static_cast<std::size_t>(j)][static_cast<std::size_t>(k)] =
                                derivative(row[static_cast<std::size_t>(j)], k, key);
                    f.hessian.push_back(std::move(h));
                }
                f.jacobian.push_back(std::move(row));
            }
        } catch (const input_error&) {
            throw;
        } catch (const cancelled&) {
            throw;
        } catch (const std::exception& x) {
            fail(m_where, key, std::string("cannot differentiate: ") + x.what());
        }
        return f;
    }

    scalar_function differentiate(const std::string& key, const ex& value, bool second)
    {
        vector_function v = differentiate(key, std::vector<ex>{value}, second);
        scalar_function s{key, value, v.jacobian[0], {}};
        if (second) {
            s.hessian = v.hessian[0];
            for (int j = 0; j < m_n; ++j)
                for (int k = 0; k < j; ++k) s.hessian[static_cast<std::size_t>(j)][static_cast<std::size_t>(k)] = s.hessian[static_cast<std::size_t>(k)][static_cast<std::size_t>(j)];
        }
        return s;
    }

    const GiNaC::realsymbol& sym(int j) const { return m_x[static_cast<std::size_t>(j)]; }

    // ---- kinks of the state in a vector field become switches

    // A field with abs, sgn, heaviside, min or max of the state has a kink or a jump where the
    // argument (b - a for min and max) changes sign. Inside a step it would cost the
    // integrator its order and hide an event (a soft stop written with abs() had 20 times the
    // error of the located switch); so each such argument becomes a switch of its own, its
    // side held between located crossings like a declared one's: abs(u) = S u, sgn(u) = S,
    // heaviside(u) = (1 + S)/2, min and max the branch of their side. One switch per distinct
    // argument. Gaps, resets, sections and switching functions keep the functions: they are
    // evaluated at points, never integrated.
    //
    // Two passes over the laws, read once: the first finds the arguments, which are then
    // numbered in the order of their text (GiNaC's order of terms follows its symbols' serial
    // numbers, which vary from one process to the next; a switch's name must not), the second
    // writes the sides in. A law without any of the five functions is left as it is.
    struct law {
        ex value;
        std::string key;
    };
    law read_law(const expression_text& e) { return {read(e), e.key}; }
    ex with_sides(const law& l) { return has_kink(l.value) ? switchify(l.value, l.key) : l.value; }

    static bool has_kink(const ex& e)
    {
        const ex a = GiNaC::wild(0), b = GiNaC::wild(1);
        const std::array<ex, 5> patterns{vimpact_abs(a), vimpact_csgn(a), vimpact_heaviside(a), vimpact_min(a, b),
                                         vimpact_max(a, b)};
        for (const ex& pattern : patterns)
            if (e.has(pattern)) return true;
        return false;
    }

    void find_kinks(const std::vector<law>& laws)
    {
        m_finding_kinks = true;
        for (const auto& l : laws) (void)with_sides(l);
        m_finding_kinks = false;
        std::vector<std::size_t> order(m_kinks.size());
        for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
        std::vector<std::string> text;
        for (const auto& k : m_kinks) text.push_back(canonical(k.when));
        std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return text[a] < text[b]; });
        std::vector<kink> sorted;
        for (const std::size_t k : order) sorted.push_back(std::move(m_kinks[k]));
        m_kinks = std::move(sorted);
        if (m_side.size() + m_kinks.size() > static_cast<std::size_t>(switch_sides::max_switches))
            fail(m_where, "derivatives",
                 "the model has " + std::to_string(m_side.size() + m_kinks.size()) +
                     " switches, those that abs, sgn, heaviside, min and max of the state make included; at most " +
                     std::to_string(switch_sides::max_switches));
        constexpr std::array<std::string_view, 5> naming{"abs", "sgn", "heaviside", "min", "max"};
        for (std::size_t k = 0; k < m_kinks.size(); ++k) {
            const auto& q = m_kinks[k];
            const auto first = std::find_if(naming.begin(), naming.end(), [&](std::string_view f) { return q.functions.count(std::string(f)); });
            std::string from, keys;
            for (const auto& f : naming)
                if (q.functions.count(std::string(f))) from += (from.empty() ? "" : ", ") + std::string(f) + "()";
            for (const auto& key : q.keys) keys += (keys.empty() ? "" : ", ") + key;
            m_side.emplace_back("S[" + std::to_string(m_side.size()) + "]");
            m_switches.push_back({std::string(*first) + "#" + std::to_string(k + 1),
                                  "the sign of " + canonical(q.when) + ", from " + from + " in " + keys, crossing::both, false});
        }
    }

    bool depends_on_state(const ex& e) const
    {
        return std::any_of(m_x.begin(), m_x.end(), [&](const GiNaC::realsymbol& x) { return e.has(x); });
    }

    ex switchify(const ex& e, const std::string& key)
    {
        if (e.nops() == 0) return e;
        if (!is_a<GiNaC::function>(e)) return map_operands(e, [&](const ex& q) { return switchify(q, key); });
        const unsigned serial = ex_to<GiNaC::function>(e).get_serial();
        const bool kinked = serial == vimpact_abs_SERIAL::serial || serial == vimpact_csgn_SERIAL::serial ||
                          serial == vimpact_heaviside_SERIAL::serial || serial == vimpact_min_SERIAL::serial ||
                          serial == vimpact_max_SERIAL::serial;
        if (kinked && !depends_on_state(e)) return e;  // of the parameters only: no kink in time
        const ex a = e.op(0);
        const auto side = [&](const ex& when, const char* function) { return automatic_switch(when, function, key); };
        if (serial == vimpact_abs_SERIAL::serial) return side(a, "abs") * switchify(a, key);
        if (serial == vimpact_csgn_SERIAL::serial) return side(a, "sgn");
        if (serial == vimpact_heaviside_SERIAL::serial) return (1 + side(a, "heaviside")) / 2;
        if (serial == vimpact_min_SERIAL::serial || serial == vimpact_max_SERIAL::serial) {
            const bool min = serial == vimpact_min_SERIAL::serial;
            const ex b = e.op(1);
            const ex S = side(min ? b - a : a - b, min ? "min" : "max");
            return ((1 + S) * switchify(a, key) + (1 - S) * switchify(b, key)) / 2;
        }
        return map_operands(e, [&](const ex& q) { return switchify(q, key); });
    }

    // The side of the automatic switch whose switching function is `when` (while finding
    // them: a placeholder).
    ex automatic_switch(const ex& when, const char* function, const std::string& key)
    {
        if (std::any_of(m_side.begin(), m_side.end(), [&](const GiNaC::realsymbol& S) { return when.has(S); }))
            fail(m_where, key,
                 std::string(function) + "() of an expression with side() or on() cannot become a switch: declare one in [[switches]]");
        for (std::size_t k = 0; k < m_kinks.size(); ++k)
            if (m_kinks[k].when.is_equal(when)) {
                if (!m_finding_kinks) return m_side[m_d.switches.size() + k];
                m_kinks[k].functions.insert(function);
                m_kinks[k].keys.insert(key);
                return 1;
            }
        if (!m_finding_kinks) fail(m_where, key, std::string("internal: a kink of ") + function + "() missed by the first pass");
        m_kinks.push_back({when, {function}, {key}});
        return 1;
    }

    // An expression as text in the file's own names, its sums and products in the order of
    // their terms' texts.
    std::string canonical(const ex& e) const
    {
        if (is_a<GiNaC::numeric>(e)) return format_double(ex_to<GiNaC::numeric>(e).to_double());
        if (is_a<GiNaC::constant>(e)) return "pi";
        if (is_a<GiNaC::symbol>(e)) {
            const std::string name = ex_to<GiNaC::symbol>(e).get_name();
            const auto it = m_user_names.find(name);
            return it == m_user_names.end() ? name : it->second;
        }
        const auto parenthesized = [&](const ex& q) {
            const std::string t = canonical(q);
            const bool plain = is_a<GiNaC::symbol>(q) || is_a<GiNaC::function>(q) || is_a<GiNaC::constant>(q) ||
                               (is_a<GiNaC::numeric>(q) && t[0] != '-');
            return plain ? t : "(" + t + ")";
        };
        std::vector<std::string> parts;
        if (is_a<GiNaC::add>(e)) {
            for (std::size_t i = 0; i < e.nops(); ++i) parts.push_back(canonical(e.op(i)));
            std::sort(parts.begin(), parts.end(), [](const std::string& a, const std::string& b) {
                return std::pair{a[0] == '-', a} < std::pair{b[0] == '-', b};
            });
            std::string t;
            for (const auto& q : parts) t += t.empty() ? q : (q[0] == '-' ? " - " + q.substr(1) : " + " + q);
            return t;
        }
        if (is_a<GiNaC::mul>(e)) {
            GiNaC::numeric coefficient(1);
            for (std::size_t i = 0; i < e.nops(); ++i) {
                if (is_a<GiNaC::numeric>(e.op(i))) coefficient = coefficient.mul(ex_to<GiNaC::numeric>(e.op(i)));
                else parts.push_back(is_a<GiNaC::add>(e.op(i)) ? "(" + canonical(e.op(i)) + ")" : canonical(e.op(i)));
            }
            std::sort(parts.begin(), parts.end());
            std::string t;
            for (const auto& q : parts) t += (t.empty() ? "" : "*") + q;
            if (coefficient.is_equal(GiNaC::numeric(1))) return t;
            if (coefficient.is_equal(GiNaC::numeric(-1))) return "-" + t;
            return format_double(coefficient.to_double()) + "*" + t;
        }
        if (is_a<GiNaC::power>(e)) return parenthesized(e.op(0)) + "^" + parenthesized(e.op(1));
        if (is_a<GiNaC::function>(e)) {
            std::string name = ex_to<GiNaC::function>(e).get_name();
            if (name == "vimpact_csgn") name = "sgn";
            else if (name.starts_with("vimpact_")) name = name.substr(8);
            for (std::size_t i = 0; i < e.nops(); ++i) parts.push_back(canonical(e.op(i)));
            std::string t;
            for (const auto& q : parts) t += (t.empty() ? "" : ", ") + q;
            return name + "(" + t + ")";
        }
        std::ostringstream s;
        s << e;
        return s.str();
    }

    void build_field()
    {
        // The laws: the derivatives, then each contact phase's.
        std::vector<law> laws;
        for (const auto& e : m_d.derivatives) laws.push_back(read_law(e));
        for (const auto& s : m_d.surfaces)
            if (s.sticking)
                for (const auto& a : s.sticking->derivatives) laws.push_back(read_law(a.expr));
        find_kinks(laws);
        auto next_law = laws.begin();
        std::vector<ex> f;
        for (std::size_t i = 0; i < m_d.derivatives.size(); ++i) f.push_back(with_sides(*next_law++));
        m_field = differentiate("derivatives", f, true);
        m_identity.assign(m_x.begin(), m_x.end());
        for (const auto& s : m_d.surfaces) {
            m_gaps.push_back(differentiate(s.gap.key, read(s.gap), true));
            const std::string reset_key = s.reset.empty() ? s.gap.key : s.reset.front().expr.key;
            m_resets.push_back(differentiate(reset_key, assigned(s.reset, m_identity), true));
            if (s.sticking) {
                const auto& k = *s.sticking;
                std::vector<ex> field = m_field.value;
                for (const auto& a : k.derivatives) field[static_cast<std::size_t>(a.index)] = with_sides(*next_law++);
                m_sticking_field.push_back(std::move(field));
                m_release.push_back(differentiate(k.release.key, read(k.release), false));
                m_rest.push_back(assigned(k.rest, m_identity));
            } else {
                m_sticking_field.push_back(std::vector<ex>(static_cast<std::size_t>(m_n), ex(0)));
                m_release.push_back(scalar_function{s.gap.key, ex(1), std::vector<ex>(static_cast<std::size_t>(m_n), ex(0)), {}});
                m_rest.push_back(m_identity);
            }
        }
        for (const auto& s : m_d.sections) m_sections.push_back(differentiate(s.when.key, read(s.when), false));
        for (const auto& w : m_d.switches) {
            const ex h = read(w.when);
            for (const auto& side : m_side)
                if (h.has(side)) fail(m_where, w.when.key, "a switching function cannot use side() or on(): its sign is the side");
            m_switching.push_back(differentiate(w.when.key, h, false));
            const std::string key = w.reset.empty() ? w.when.key : w.reset.front().expr.key;
            m_switch_resets.push_back(differentiate(key, assigned(w.reset, m_identity), false));
        }
        for (std::size_t k = 0; k < m_kinks.size(); ++k) {
            const std::string key = *m_kinks[k].keys.begin();
            m_switching.push_back(differentiate(key, m_kinks[k].when, false));
            m_switch_resets.push_back(differentiate(key, m_identity, false));
        }
    }

    // ---- printing

    // An expression of the state as C, its parts that depend on the parameters only read from
    // their slots (hoisted); `hoist` false for what is computed once already (the derived
    // quantities).
    std::string c(const ex& e, const std::string& key, bool hoist = true)
    {
        poll_cancel();
        m_printed += m_reader.sizes().size(e);
        if (m_printed > max_code_terms) code_too_large(m_where, key, "the expression with its derivatives");
        expression_reader::check_translatable(e, key, m_where);
        std::ostringstream s;
        (hoist ? hoisted(e) : e).print(c_printer(s, m_powers));
        return s.str();
    }

    // ---- components of the field computed once

    // The vector field's components as printed: a later component that holds an earlier one
    // (a sum of two or more terms with the state in it, up to a numeric factor: an acceleration
    // written again inside another equation, as a coupled model's equations read) reads it
    // from out[i], computed just before, instead of computing it again. GiNaC keeps such a sum
    // as a factor but may scale its terms (by 16 in the paper's wake equation), and the
    // compiler would then not see the two as one. The derivatives are not concerned: they
    // are taken from the field itself.
    std::vector<ex> shared_field_values() const
    {
        constexpr std::size_t max_terms = 32;  // normal() of larger sums costs more than it saves
        std::vector<ex> v = m_field.value;
        for (std::size_t j = 1; j < v.size(); ++j)
            for (std::size_t i = 0; i < j; ++i) {
                poll_cancel();
                const ex& e = m_field.value[i];
                if (!is_a<GiNaC::add>(e) || e.nops() > max_terms || parameter_only(e)) continue;
                GiNaC::exmap found;
                for (auto it = v[j].preorder_begin(); it != v[j].preorder_end(); ++it) {
                    const ex& a = *it;
                    if (!is_a<GiNaC::add>(a) || a.nops() != e.nops() || found.count(a)) continue;
                    // A sum that is zero unsimplified makes normal() divide by zero: no match.
                    try {
                        const ex q = GiNaC::normal(a / e);
                        if (is_a<GiNaC::numeric>(q) && !q.is_zero()) found[a] = q * m_out[i];
                    } catch (const std::exception&) {
                    }
                }
                if (!found.empty()) v[j] = v[j].subs(found, GiNaC::subs_options::no_pattern);
            }
        return v;
    }

    // ---- parts that depend on the parameters only
    //
    // A model written as its equations read, (1/(St*Ur))^2*y or CL0/(16*pi^2*St^2*mu)*x, would
    // divide at every call of the vector field, its derivatives, gaps and sections. Every
    // largest part of a printed expression that depends on the parameters only (a subtree, or
    // the factors of a product or the terms of a sum that do, unless that is one parameter or
    // number) is computed once per parameter set instead, in a slot after the derived
    // quantities (vimpact_create). A part is named by its canonical text (or its negative's,
    // whichever is smaller, so that GiNaC's choice of sign does not matter), slots are
    // numbered in the order of those texts within each expression: the same model gives the
    // same source in every process, as the cache needs. A part's derivatives by the state are
    // zero, so the Jacobians and Hessians, taken before, are unchanged in value.
    // Only parameters, derived quantities and numbers (not the state, nor the symbols of other
    // inputs of a function, such as the field's values in a section's rate).
    bool parameter_only(const ex& e) const
    {
        if (is_a<GiNaC::symbol>(e))
            return std::any_of(m_ctx.begin(), m_ctx.end(), [&](const GiNaC::realsymbol& q) { return e.is_equal(q); });
        if (is_a<GiNaC::numeric>(e) || is_a<GiNaC::constant>(e)) return true;
        for (std::size_t i = 0; i < e.nops(); ++i)
            if (!parameter_only(e.op(i))) return false;
        return true;
    }
    static bool leaf(const ex& e)
    {
        return is_a<GiNaC::symbol>(e) || is_a<GiNaC::numeric>(e) || is_a<GiNaC::constant>(e);
    }
    // Not worth a slot: a leaf, or a number times one. Also what keeps the source the same in
    // every process: GiNaC may store A*(x + a) as -A*(-x - a), and a rule that hoisted -a or -A
    // but not a or A would print the two differently.
    static bool trivial(const ex& e)
    {
        if (leaf(e)) return true;
        return is_a<GiNaC::mul>(e) && e.nops() == 2 &&
               ((is_a<GiNaC::numeric>(e.op(0)) && leaf(e.op(1))) || (is_a<GiNaC::numeric>(e.op(1)) && leaf(e.op(0))));
    }

    // e with part(q) in place of each part q to hoist, visited in a fixed order.
    template <class Part>
    ex with_parts(const ex& e, Part& part) const
    {
        if (leaf(e)) return e;
        if (parameter_only(e)) return trivial(e) ? e : part(e);
        const bool sum = is_a<GiNaC::add>(e);
        if (sum || is_a<GiNaC::mul>(e)) {
            ex fixed = sum ? ex(0) : ex(1), rest = sum ? ex(0) : ex(1);
            int count = 0;
            for (std::size_t i = 0; i < e.nops(); ++i) {
                const ex& o = e.op(i);
                if (parameter_only(o)) {
                    fixed = sum ? fixed + o : fixed * o;
                    ++count;
                } else {
                    const ex h = with_parts(o, part);
                    rest = sum ? rest + h : rest * h;
                }
            }
            if (count > 0 && !trivial(fixed)) fixed = part(fixed);
            return sum ? fixed + rest : fixed * rest;
        }
        struct mapped : GiNaC::map_function {
            const generator& g;
            Part& part;
            mapped(const generator& g_, Part& p_) : g(g_), part(p_) {}
            ex operator()(const ex& o) override { return g.with_parts(o, part); }
        } m(*this, part);
        return e.map(m);
    }

    // The text a part is named by and whether that text is the part's negative's.
    std::pair<std::string, bool> part_name(const ex& q)
    {
        std::ostringstream a, b;
        q.print(c_printer(a, m_powers));
        (-q).print(c_printer(b, m_powers));
        return b.str() < a.str() ? std::pair{b.str(), true} : std::pair{a.str(), false};
    }

    ex hoisted(const ex& e)
    {
        std::vector<std::string> fresh;
        auto collect = [&](const ex& q) {
            const auto name = part_name(q).first;
            if (!m_part_slot.count(name)) fresh.push_back(name);
            return q;
        };
        (void)with_parts(e, collect);
        std::sort(fresh.begin(), fresh.end());
        fresh.erase(std::unique(fresh.begin(), fresh.end()), fresh.end());
        for (const auto& name : fresh) {
            m_part_slot.emplace(name, static_cast<int>(m_parts.size()));
            m_parts.push_back(name);
            m_part_symbols.emplace_back("p[" + std::to_string(m_p + m_nd + static_cast<int>(m_parts.size()) - 1) + "]");
        }
        auto replace = [&](const ex& q) {
            const auto [name, negated] = part_name(q);
            const ex slot = m_part_symbols[static_cast<std::size_t>(m_part_slot.at(name))];
            return negated ? -slot : slot;
        };
        return with_parts(e, replace);
    }

    // sum over j <= k of h_jk (u_j w_k + u_k w_j), halved on the diagonal: D2f[u, w].
    std::string bilinear(const std::vector<std::vector<ex>>& h, const std::string& key)
    {
        std::string out;
        for (int j = 0; j < m_n; ++j)
            for (int k = j; k < m_n; ++k) {
                const ex& v = h[static_cast<std::size_t>(j)][static_cast<std::size_t>(k)];
                if (v.is_zero()) continue;
                const std::string J = std::to_string(j), K = std::to_string(k);
                if (!out.empty()) out += " + ";
                out += "(";
                out += c(v, key);
                out += ")*";
                out += j == k ? "u[" + J + "]*w[" + J + "]" : "(u[" + J + "]*w[" + K + "]+u[" + K + "]*w[" + J + "])";
            }
        return out.empty() ? "0.0" : out;
    }

    // `sides`: the function reads the sides of the switches, S[k] (all but the switching
    // functions themselves).
    std::string prologue(bool bilinear_args = false, bool sides = true) const
    {
        std::string s = std::string("    const double* p = (const double*)c;\n    (void)p;\n    (void)x;\n") +
                        (bilinear_args ? "    (void)u;\n    (void)w;\n" : "");
        if (sides && !m_side.empty())
            s += "    double S[" + std::to_string(m_side.size()) + "];\n    vimpact_sides(p, x, S);\n    (void)S;\n";
        return s;
    }

    // One case of a switch over surfaces or sections, or the body of a plain function.
    std::string assign_vector(const std::vector<ex>& v, const std::string& key, const std::string& indent)
    {
        std::string s;
        for (std::size_t i = 0; i < v.size(); ++i) s += indent + "out[" + std::to_string(i) + "] = " + c(v[i], key) + ";\n";
        return s;
    }
    std::string assign_matrix(const std::vector<std::vector<ex>>& m, const std::string& key, const std::string& indent)
    {
        // column-major: out[i + n j] = m[i][j]
        std::string s;
        for (int j = 0; j < m_n; ++j)
            for (int i = 0; i < m_n; ++i)
                s += indent + "out[" + std::to_string(i + m_n * j) + "] = " +
                     c(m[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)], key) + ";\n";
        return s;
    }
    std::string assign_bilinear(const std::vector<std::vector<std::vector<ex>>>& h, const std::string& key,
                                const std::string& indent)
    {
        std::string s;
        for (std::size_t i = 0; i < h.size(); ++i) s += indent + "out[" + std::to_string(i) + "] = " + bilinear(h[i], key) + ";\n";
        return s;
    }

    // A switch over items with a fill of zeros for an index out of range.
    template <class Body>
    std::string indexed_void(const std::string& signature, std::size_t count, std::size_t outputs, Body body,
                             bool bilinear_args = false, bool sides = true)
    {
        std::string s = "static void " + signature + "\n{\n" + prologue(bilinear_args, sides) + "    switch (i) {\n";
        for (std::size_t i = 0; i < count; ++i)
            s += "    case " + std::to_string(i) + ":\n" + body(i) + "        return;\n";
        s += "    default:\n        break;\n    }\n";
        s += "    for (int k = 0; k < " + std::to_string(outputs) + "; ++k) out[k] = 0.0;\n}\n\n";
        return s;
    }
    template <class Body>
    std::string indexed_scalar(const std::string& signature, std::size_t count, Body body, bool sides = true)
    {
        std::string s = "static double " + signature + "\n{\n" + prologue(false, sides) + "    switch (i) {\n";
        for (std::size_t i = 0; i < count; ++i) s += "    case " + std::to_string(i) + ":\n        return " + body(i) + ";\n";
        s += "    default:\n        return 0.0;\n    }\n}\n\n";
        return s;
    }

    std::string functions()
    {
        const std::string in = "        ";
        const auto n = static_cast<std::size_t>(m_n);
        const std::size_t S = m_d.surfaces.size(), K = m_d.sections.size();
        std::string s;

        const std::string rhs_body = assign_vector(shared_field_values(), "derivatives", "    ");
        s += "static void vimpact_rhs(const void* c, const double* x, double* out)\n{\n" + prologue() + rhs_body + "}\n\n";
        s += "static void vimpact_jacobian(const void* c, const double* x, double* out)\n{\n" + prologue() +
             assign_matrix(m_field.jacobian, "derivatives", "    ") + "}\n\n";
        s += "static void vimpact_second_derivative(const void* c, const double* x, const double* u, const double* w, "
             "double* out)\n{\n" +
             prologue(true) + assign_bilinear(m_field.hessian, "derivatives", "    ") + "}\n\n";
        ex divergence = 0;
        for (int j = 0; j < m_n; ++j) divergence += m_field.jacobian[static_cast<std::size_t>(j)][static_cast<std::size_t>(j)];
        s += "static double vimpact_divergence(const void* c, const double* x)\n{\n" + prologue() + "    return " +
             c(divergence, "derivatives") + ";\n}\n\n";

        // The gaps' and sections' texts, printed once: the same in the one-job functions and in
        // the lanes' (lanes_code).
        std::vector<std::string> gap_value, gap_gradient, section_value, section_gradient;
        for (const auto& g : m_gaps) {
            gap_value.push_back(c(g.value, g.key));
            gap_gradient.push_back(assign_vector(g.gradient, g.key, in));
        }
        for (const auto& k : m_sections) {
            section_value.push_back(c(k.value, k.key));
            section_gradient.push_back(assign_vector(k.gradient, k.key, in));
        }
        s += indexed_scalar("vimpact_gap(const void* c, int i, const double* x)", S,
                            [&](std::size_t i) { return gap_value[i]; });
        s += indexed_void("vimpact_gap_gradient(const void* c, int i, const double* x, double* out)", S, n,
                          [&](std::size_t i) { return gap_gradient[i]; });
        s += indexed_void("vimpact_gap_hessian(const void* c, int i, const double* x, double* out)", S, n * n,
                          [&](std::size_t i) { return assign_matrix(m_gaps[i].hessian, m_gaps[i].key, in); });
        s += indexed_void("vimpact_reset(const void* c, int i, const double* x, double* out)", S, n,
                          [&](std::size_t i) { return assign_vector(m_resets[i].value, m_resets[i].key, in); });
        s += indexed_void("vimpact_reset_jacobian(const void* c, int i, const double* x, double* out)", S, n * n,
                          [&](std::size_t i) { return assign_matrix(m_resets[i].jacobian, m_resets[i].key, in); });
        s += indexed_void(
            "vimpact_reset_second_derivative(const void* c, int i, const double* x, const double* u, const double* w, "
            "double* out)",
            S, n, [&](std::size_t i) { return assign_bilinear(m_resets[i].hessian, m_resets[i].key, in); }, true);

        s += indexed_scalar("vimpact_section(const void* c, int i, const double* x)", K,
                            [&](std::size_t k) { return section_value[k]; });
        s += indexed_void("vimpact_section_gradient(const void* c, int i, const double* x, double* out)", K, n,
                          [&](std::size_t k) { return section_gradient[k]; });
        // The switching functions and their gradients, printed once: h_k and grad h_k in the
        // one-job functions (switch_functions), side * h_k and side * grad h_k in the lanes'
        // (abi.h, lanes_points and lanes_switching), as the flow's switch values are.
        std::vector<std::string> switch_value, switch_gradient;
        for (std::size_t k = 0; k < m_switching.size(); ++k) {
            const std::string side = "S[" + std::to_string(k) + "]";
            const std::string h = c(m_switching[k].value, m_switching[k].key);
            m_switch_value.push_back(h);
            switch_value.push_back(side + "*(" + h + ")");
            std::string g, lanes_g;
            for (std::size_t i = 0; i < n; ++i) {
                const std::string gi = c(m_switching[k].gradient[i], m_switching[k].key), out = in + "out[" + std::to_string(i) + "] = ";
                g += out + gi + ";\n";
                lanes_g += out + side + "*(" + gi + ");\n";
            }
            m_switch_gradient.push_back(g);
            switch_gradient.push_back(lanes_g);
        }
        m_lanes_code = lanes_code(rhs_body, gap_value, gap_gradient, section_value, section_gradient, switch_value,
                                  switch_gradient);

        // Every gap and section with its rate grad . f in one call: the flow samples each step
        // end with it (abi.h, samples).
        {
            std::vector<GiNaC::realsymbol> f;
            for (int j = 0; j < m_n; ++j) f.emplace_back("f[" + std::to_string(j) + "]");
            auto rate = [&](const std::vector<ex>& gradient) {
                ex r = 0;
                for (std::size_t j = 0; j < n; ++j) r += gradient[j] * f[j];
                return r;
            };
            s += "static void vimpact_samples(const void* c, const double* x, const double* f, double* gaps, "
                 "double* sections)\n{\n" + prologue() + "    (void)f;\n    (void)gaps;\n    (void)sections;\n";
            // Each (value, rate) pair in one 16-byte store (vimpact_store_pair): the flow reads a
            // pair with one load right after the call, which two 8-byte stores could not
            // forward to (a stall that took 4 % of a model file's protocol run).
            for (std::size_t i = 0; i < S; ++i)
                s += "    vimpact_store_pair(gaps + " + std::to_string(2 * i) + ", " + c(m_gaps[i].value, m_gaps[i].key) +
                     ", " + c(rate(m_gaps[i].gradient), m_gaps[i].key) + ");\n";
            for (std::size_t k = 0; k < K; ++k)
                s += "    vimpact_store_pair(sections + " + std::to_string(2 * k) + ", " +
                     c(m_sections[k].value, m_sections[k].key) + ", " + c(rate(m_sections[k].gradient), m_sections[k].key) +
                     ");\n";
            s += "}\n\n";
        }

        s += indexed_void("vimpact_sticking_rhs(const void* c, int i, const double* x, double* out)", S, n,
                          [&](std::size_t i) { return assign_vector(m_sticking_field[i], sticking_key(i, "derivatives"), in); });
        s += indexed_scalar("vimpact_release(const void* c, int i, const double* x)", S,
                            [&](std::size_t i) { return c(m_release[i].value, m_release[i].key); });
        s += indexed_void("vimpact_release_gradient(const void* c, int i, const double* x, double* out)", S, n,
                          [&](std::size_t i) { return assign_vector(m_release[i].gradient, m_release[i].key, in); });
        s += indexed_void("vimpact_rest(const void* c, int i, const double* x, double* out)", S, n,
                          [&](std::size_t i) { return assign_vector(m_rest[i], sticking_key(i, "rest"), in); });
        if (!m_side.empty()) s += switch_functions();
        return create() + s;
    }

    // The switches' functions (abi.h, ABI version 6). The context holds, after the parameters,
    // derived quantities and hoisted parts, a flag (nonzero: pinned) and the pinned sides.
    std::string switch_functions()
    {
        const std::string in = "        ";
        const std::size_t W = m_side.size(), n = static_cast<std::size_t>(m_n);
        const std::string w = std::to_string(W), dim = std::to_string(m_n);
        std::string s;
        s += indexed_scalar(
            "vimpact_switching(const void* c, int i, const double* x)", W, [&](std::size_t k) { return m_switch_value[k]; },
            false);
        s += indexed_void(
            "vimpact_switching_gradient(const void* c, int i, const double* x, double* out)", W, n,
            [&](std::size_t k) { return m_switch_gradient[k]; }, false, false);
        s += indexed_void("vimpact_switch_reset(const void* c, int i, const double* x, double* out)", W, n,
                          [&](std::size_t k) { return assign_vector(m_switch_resets[k].value, m_switch_resets[k].key, in); });
        s += indexed_void("vimpact_switch_reset_jacobian(const void* c, int i, const double* x, double* out)", W, n * n,
                          [&](std::size_t k) { return assign_matrix(m_switch_resets[k].jacobian, m_switch_resets[k].key, in); });
        std::string directions, resets;
        for (std::size_t k = 0; k < W; ++k) {
            directions += (k ? ", " : "") + std::to_string(static_cast<int>(m_switches[k].direction));
            resets += (k ? ", " : "") + std::string(m_switches[k].reset ? "1" : "0");
        }
        s += "static void* vimpact_copy_context(const void* c)\n{\n"
             "    double* q = (double*)malloc(VIMPACT_CONTEXT_SIZE * sizeof(double));\n"
             "    if (q) memcpy(q, c, VIMPACT_CONTEXT_SIZE * sizeof(double));\n    return q;\n}\n\n"
             "static void vimpact_pin_sides(void* c, unsigned long long negative)\n{\n"
             "    double* p = (double*)c;\n    p[VIMPACT_PINNED] = 1.0;\n"
             "    for (int k = 0; k < " + w + "; ++k) p[VIMPACT_PINNED + 1 + k] = ((negative >> k) & 1ULL) ? -1.0 : 1.0;\n}\n\n"
             "static unsigned long long vimpact_sides_at(const void* c, const double* x)\n{\n"
             "    double S[" + w + "];\n    unsigned long long negative = 0;\n    vimpact_sides((const double*)c, x, S);\n"
             "    for (int k = 0; k < " + w + "; ++k)\n        if (S[k] < 0.0) negative |= 1ULL << k;\n"
             "    return negative;\n}\n\n"
             "static int vimpact_cross(void* c, int i, const double* x, double* out)\n{\n"
             "    static const int direction[] = {" + directions + "};\n"
             "    static const int has_reset[] = {" + resets + "};\n"
             "    double* p = (double*)c;\n"
             "    if (p[VIMPACT_PINNED] == 0.0) vimpact_pin_sides(c, vimpact_sides_at(c, x));\n"
             "    const int down = p[VIMPACT_PINNED + 1 + i] > 0.0;\n"
             "    p[VIMPACT_PINNED + 1 + i] = -p[VIMPACT_PINNED + 1 + i];\n"
             "    if (has_reset[i] && (direction[i] == 2 || (direction[i] == 0) == down)) {\n"
             "        vimpact_switch_reset(c, i, x, out);\n        return 1;\n    }\n"
             "    for (int j = 0; j < " + dim + "; ++j) out[j] = x[j];\n    return 0;\n}\n\n";
        return s;
    }

    // The SIMD lanes' functions (abi.h, lanes_step and the lanes' gaps and sections): the same
    // texts as the one-job functions, on core/lanes.hpp's type, whose operations are those of
    // one double lane by lane (the lanes' csgn and integer powers are overloads of the same
    // operations). The contexts and states are the library's lanes values.
    std::string lanes_code(const std::string& rhs_body, const std::vector<std::string>& gap_value,
                           const std::vector<std::string>& gap_gradient, const std::vector<std::string>& section_value,
                           const std::vector<std::string>& section_gradient, const std::vector<std::string>& switch_value,
                           const std::vector<std::string>& switch_gradient) const
    {
        const std::string n = std::to_string(m_n), L = "vimpact::lanes";
        // Each lane's sides are those its context holds: the library gives the lanes of a model
        // with switches the pinned contexts of the lanes' flows (abi.h, lanes_switching).
        const std::string sides = m_side.empty() ? "" : "    const " + L + "* S = p + VIMPACT_PINNED + 1;\n    (void)S;\n";
        const std::string prologue = "    const " + L + "* p = (const " + L + "*)c;\n    const " + L + "* x = (const " + L +
                                     "*)xd;\n    " + L + "* out = (" + L + "*)od;\n    (void)p;\n    (void)x;\n" + sides;
        std::string s = "static inline " + L + " vimpact_csgn(" + L + " v)\n{\n    return vimpact::select(v > " + L +
                        "(0.0), " + L + "(1.0), vimpact::select(v < " + L + "(0.0), " + L + "(-1.0), " + L + "(0.0)));\n}\n";
        s += "static inline " + L + " vimpact_heaviside(" + L + " v)\n{\n    return vimpact::select(v >= " + L + "(0.0), " +
             L + "(1.0), " + L + "(0.0));\n}\n";
        s += "static inline " + L + " vimpact_min(" + L + " a, " + L + " b)\n{\n    return vimpact::select(b - a >= " + L +
             "(0.0), a, b);\n}\n";
        s += "static inline " + L + " vimpact_max(" + L + " a, " + L + " b)\n{\n    return vimpact::select(a - b >= " + L +
             "(0.0), a, b);\n}\n";
        for (const int k : m_powers)
            s += "static inline " + L + " vimpact_pow" + std::to_string(k) + "(" + L + " b) { return " +
                 multiplication_chain("b", k) + "; }\n";
        s += "\nstatic void vimpact_lanes_rhs(const double* c, const double* xd, double* od)\n{\n" + prologue + rhs_body +
             "}\n\n";
        const auto indexed = [&](const std::string& name, const std::vector<std::string>& bodies, bool scalar,
                                 std::size_t outputs) {
            std::string f = "static void " + name + "(const double* c, int i, const double* xd, double* od)\n{\n" +
                            prologue + "    switch (i) {\n";
            for (std::size_t i = 0; i < bodies.size(); ++i)
                f += "    case " + std::to_string(i) + ":\n" + (scalar ? "        out[0] = " + bodies[i] + ";\n" : bodies[i]) +
                     "        return;\n";
            f += "    default:\n        break;\n    }\n    for (int k = 0; k < " + std::to_string(outputs) +
                 "; ++k) out[k] = " + L + "(0.0);\n}\n\n";
            return f;
        };
        // Every gap and section with its gradient at one state (abi.h, lanes_points).
        s += "static void vimpact_lanes_points(const double* c, const double* xd, double* vd, double* gd)\n{\n"
             "    const " + L + "* p = (const " + L + "*)c;\n    const " + L + "* x = (const " + L + "*)xd;\n    " + L +
             "* v = (" + L + "*)vd;\n    (void)p;\n    (void)x;\n    (void)v;\n    (void)gd;\n" + sides;
        const auto point = [&](std::size_t slot, const std::string& value, const std::string& gradient) {
            s += "    v[" + std::to_string(slot) + "] = " + value + ";\n    {\n        " + L + "* out = (" + L + "*)gd + " +
                 std::to_string(slot * static_cast<std::size_t>(m_n)) + ";\n" + gradient + "    }\n";
        };
        for (std::size_t i = 0; i < gap_value.size(); ++i) point(i, gap_value[i], gap_gradient[i]);
        for (std::size_t k = 0; k < section_value.size(); ++k)
            point(gap_value.size() + k, section_value[k], section_gradient[k]);
        for (std::size_t k = 0; k < switch_value.size(); ++k)
            point(gap_value.size() + section_value.size() + k, switch_value[k], switch_gradient[k]);
        s += "}\n\n";
        s += indexed("vimpact_lanes_gap", gap_value, true, 1);
        s += indexed("vimpact_lanes_gap_gradient", gap_gradient, false, static_cast<std::size_t>(m_n));
        s += indexed("vimpact_lanes_section", section_value, true, 1);
        s += indexed("vimpact_lanes_section_gradient", section_gradient, false, static_cast<std::size_t>(m_n));
        s += indexed("vimpact_lanes_switching", switch_value, true, 1);
        s += "namespace {\nstruct vimpact_lanes_field {\n    const double* c;\n"
             "    vimpact::vec_t<" + L + ", " + n + "> operator()(const vimpact::vec_t<" + L + ", " + n + ">& x) const\n"
             "    {\n        vimpact::vec_t<" + L + ", " + n + "> f;\n"
             "        vimpact_lanes_rhs(c, (const double*)x.data(), (double*)f.data());\n        return f;\n    }\n};\n}  // namespace\n";
        return s;
    }

    std::string sticking_key(std::size_t i, const char* what) const
    {
        return "surfaces[" + std::to_string(i) + "].sticking." + what;
    }

    // The doubles of a context: parameters, derived quantities and hoisted parts, then, with
    // switches, the pinned flag and the pinned sides.
    [[nodiscard]] int pinned_slot() const { return m_p + m_nd + static_cast<int>(m_parts.size()); }
    [[nodiscard]] int context_count() const
    {
        const int W = static_cast<int>(m_side.size());
        return pinned_slot() + (W > 0 ? 1 + W : 0);
    }

    std::string create()
    {
        const int W = static_cast<int>(m_side.size());
        const int pinned = pinned_slot();
        const int count = context_count();
        std::string s;
        if (W > 0)
            s += "#define VIMPACT_PINNED " + std::to_string(pinned) + "\n#define VIMPACT_CONTEXT_SIZE " +
                 std::to_string(count) +
                 "\nstatic double vimpact_switching(const void* c, int i, const double* x);\n\n"
                 "/* The sides of the switches: those the context holds once pinned, the state's before. */\n"
                 "static void vimpact_sides(const double* p, const double* x, double* S)\n{\n"
                 "    if (p[VIMPACT_PINNED] != 0.0) {\n        for (int k = 0; k < " + std::to_string(W) +
                 "; ++k) S[k] = p[VIMPACT_PINNED + 1 + k];\n        return;\n    }\n"
                 "    for (int k = 0; k < " + std::to_string(W) +
                 "; ++k) S[k] = vimpact_switching(p, k, x) >= 0.0 ? 1.0 : -1.0;\n}\n\n";
        s +=
            "static void vimpact_refuse(char* error, size_t size, const char* name, double value)\n{\n"
            "    if (error && size > 0) snprintf(error, size, \"derived quantity %s = %.17g is not finite\", name, value);\n"
            "}\n\n"
            "static void* vimpact_create(const double* parameters, char* error, size_t error_size)\n{\n"
            "    double* p = (double*)calloc(" +
            std::to_string(count > 0 ? count : 1) +
            ", sizeof(double));\n"
            "    (void)parameters;\n"
            "    if (!p) {\n"
            "        if (error && error_size > 0) snprintf(error, error_size, \"out of memory\");\n"
            "        return 0;\n"
            "    }\n";
        if (m_p > 0) s += "    for (int k = 0; k < " + std::to_string(m_p) + "; ++k) p[k] = parameters[k];\n";
        for (const std::size_t i : m_derived_order) {
            const std::string slot = "p[" + std::to_string(m_p + static_cast<int>(i)) + "]";
            s += "    " + slot + " = " + c(m_derived[i], m_d.derived[i].expr.key, false) + ";\n";
            s += "    if (!isfinite(" + slot + ")) {\n        vimpact_refuse(error, error_size, " +
                 c_string(m_d.derived[i].name) + ", " + slot + ");\n        free(p);\n        return 0;\n    }\n";
        }
        // Then the parts of the expressions that depend on the parameters only (hoisted()).
        for (std::size_t k = 0; k < m_parts.size(); ++k)
            s += "    p[" + std::to_string(m_p + m_nd + static_cast<int>(k)) + "] = " + m_parts[k] + ";\n";
        s += "    return p;\n}\n\nstatic void vimpact_destroy(void* c) { free(c); }\n\n";
        return s;
    }

    std::string preamble() const
    {
        std::string s = "/* The function table of the model '" + m_d.name +
                        "', generated by vimpact from a model file. Compiled once per machine and cached. */\n";
        s += vimpact::detail::model_abi_text;
        s += "\n#include <math.h>\n#include <stdio.h>\n#include <stdlib.h>\n#include <string.h>\n\n";
        s += "static inline double vimpact_csgn(double v) { return v > 0.0 ? 1.0 : (v < 0.0 ? -1.0 : 0.0); }\n";
        s += "static inline double vimpact_heaviside(double v) { return v >= 0.0 ? 1.0 : 0.0; }\n"
             "static inline double vimpact_min(double a, double b) { return b - a >= 0.0 ? a : b; }\n"
             "static inline double vimpact_max(double a, double b) { return a - b >= 0.0 ? a : b; }\n";
        s += "static inline void vimpact_store_pair(double* out, double a, double b)\n{\n"
             "    typedef double vimpact_pair __attribute__((vector_size(16)));\n"
             "    const vimpact_pair v = {a, b};\n    __builtin_memcpy(out, &v, sizeof v);\n}\n";
        for (const int k : m_powers)
            s += "static inline double vimpact_pow" + std::to_string(k) + "(double b) { return " +
                 multiplication_chain("b", k) + "; }\n";
        return s + "\n";
    }

    template <class T, class F>
    std::string array(const std::string& type, const std::string& name, const std::vector<T>& items, F text,
                      std::string& out) const
    {
        if (items.empty()) return "0";
        out += "static " + type + " " + name + "[] = {";
        for (std::size_t i = 0; i < items.size(); ++i) out += (i ? ", " : "") + text(items[i]);
        out += "};\n";
        return name;
    }

    std::string table() const
    {
        std::string s;
        const auto str = [](const std::string& v) { return c_string(v); };
        const auto num = [](double v) {
            if (std::isinf(v)) return std::string(v > 0 ? "HUGE_VAL" : "-HUGE_VAL");
            return c_number(v);
        };
        const auto integer = [](int v) { return std::to_string(v); };
        std::vector<std::string> state_names, state_meanings, state_units;
        for (const auto& v : m_d.state) {
            state_names.push_back(v.name);
            state_meanings.push_back(v.meaning);
            state_units.push_back(v.unit);
        }
        std::vector<std::string> pn, pm, pu;
        std::vector<double> pd, pl, ph;
        std::vector<int> pc;
        for (const auto& p : m_d.parameters) {
            pn.push_back(p.name);
            pm.push_back(p.meaning);
            pu.push_back(p.unit);
            pd.push_back(p.default_value);
            pl.push_back(p.range.lower);
            ph.push_back(p.range.upper);
            pc.push_back((p.range.lower_inclusive ? 1 : 0) | (p.range.upper_inclusive ? 2 : 0));
        }
        std::vector<std::string> sn, sm, kn, km, rn, rm;
        std::vector<int> sticks, dirs, sizes, rp;
        std::vector<double> rv;
        for (const auto& x : m_d.surfaces) {
            sn.push_back(x.name);
            sm.push_back(x.meaning);
            sticks.push_back(x.sticking ? 1 : 0);
        }
        for (const auto& x : m_d.sections) {
            kn.push_back(x.name);
            km.push_back(x.meaning);
            dirs.push_back(static_cast<int>(x.direction));
        }
        // A function whose gradient holds no state variable is affine in the state: the flow
        // trusts the integrator to resolve it (abi.h, surface_affine).
        const auto affine = [this](const scalar_function& f) {
            for (const ex& d : f.gradient)
                for (int j = 0; j < m_n; ++j)
                    if (d.has(sym(j))) return 0;
            return 1;
        };
        std::vector<int> surface_affine, section_affine;
        for (const auto& g : m_gaps) surface_affine.push_back(affine(g));
        for (const auto& k : m_sections) section_affine.push_back(affine(k));
        std::vector<std::string> wn, wm;
        std::vector<int> wd, switch_affine;
        for (std::size_t k = 0; k < m_switching.size(); ++k) {
            wn.push_back(m_switches[k].name);
            wm.push_back(m_switches[k].meaning);
            wd.push_back(static_cast<int>(m_switches[k].direction));
            switch_affine.push_back(affine(m_switching[k]));
        }
        for (const auto& x : m_d.presets) {
            rn.push_back(x.name);
            rm.push_back(x.meaning);
            sizes.push_back(static_cast<int>(x.values.size()));
            for (const auto& [i, v] : x.values) {
                rp.push_back(i);
                rv.push_back(v);
            }
        }
        const std::string cs = "const char* const";
        std::vector<std::string> fields = {
            "VIMPACT_MODEL_ABI_VERSION",
            std::to_string(m_n),
            std::to_string(m_p),
            std::to_string(m_d.surfaces.size()),
            std::to_string(m_d.sections.size()),
            std::to_string(m_d.presets.size()),
            c_string(m_d.name),
            c_string(m_d.description),
            array(cs, "vimpact_state_names", state_names, str, s),
            array(cs, "vimpact_state_meanings", state_meanings, str, s),
            array(cs, "vimpact_state_units", state_units, str, s),
            array("const double", "vimpact_state_periods", m_periods, num, s),
            array("const double", "vimpact_initial_state", m_d.initial_state, num, s),
            array(cs, "vimpact_parameter_names", pn, str, s),
            array(cs, "vimpact_parameter_meanings", pm, str, s),
            array(cs, "vimpact_parameter_units", pu, str, s),
            array("const double", "vimpact_parameter_defaults", pd, num, s),
            array("const double", "vimpact_parameter_lower", pl, num, s),
            array("const double", "vimpact_parameter_upper", ph, num, s),
            array("const int", "vimpact_parameter_bounds_closed", pc, integer, s),
            array(cs, "vimpact_surface_names", sn, str, s),
            array(cs, "vimpact_surface_meanings", sm, str, s),
            array("const int", "vimpact_surface_sticks", sticks, integer, s),
            array(cs, "vimpact_section_names", kn, str, s),
            array(cs, "vimpact_section_meanings", km, str, s),
            array("const int", "vimpact_section_directions", dirs, integer, s),
            array(cs, "vimpact_preset_names", rn, str, s),
            array(cs, "vimpact_preset_meanings", rm, str, s),
            array("const int", "vimpact_preset_sizes", sizes, integer, s),
            array("const int", "vimpact_preset_parameters", rp, integer, s),
            array("const double", "vimpact_preset_values", rv, num, s),
            "vimpact_create",
            "vimpact_destroy",
            "vimpact_rhs",
            "vimpact_jacobian",
            "vimpact_second_derivative",
            "vimpact_divergence",
            "vimpact_gap",
            "vimpact_gap_gradient",
            "vimpact_gap_hessian",
            "vimpact_reset",
            "vimpact_reset_jacobian",
            "vimpact_reset_second_derivative",
            "vimpact_section",
            "vimpact_section_gradient",
            "vimpact_sticking_rhs",
            "vimpact_release",
            "vimpact_release_gradient",
            "vimpact_rest",
            "VIMPACT_STEP",
            "VIMPACT_DENSE",
            "vimpact_samples",
            array("const int", "vimpact_surface_affine", surface_affine, integer, s),
            array("const int", "vimpact_section_affine", section_affine, integer, s),
            "VIMPACT_LANES_WIDTH",
            std::to_string(std::max(1, context_count())),
            "VIMPACT_LANES(step)",
            "VIMPACT_LANES(gap)",
            "VIMPACT_LANES(gap_gradient)",
            "VIMPACT_LANES(section)",
            "VIMPACT_LANES(section_gradient)",
            "VIMPACT_LANES(points)",
            std::to_string(m_side.size()),
            array(cs, "vimpact_switch_names", wn, str, s),
            array(cs, "vimpact_switch_meanings", wm, str, s),
            array("const int", "vimpact_switch_directions", wd, integer, s),
            array("const int", "vimpact_switch_affine", switch_affine, integer, s),
        };
        for (const char* f : {"vimpact_switching", "vimpact_switching_gradient", "vimpact_copy_context",
                              "vimpact_pin_sides", "vimpact_sides_at", "vimpact_cross", "vimpact_switch_reset_jacobian"})
            fields.emplace_back(m_side.empty() ? "0" : f);
        fields.emplace_back(m_side.empty() ? "0" : "VIMPACT_LANES(switching)");
        // Positional, in the order of the fields of vimpact_model_table (abi.h), so that the
        // table is a constant in read-only memory, valid C and C++.
        static const char* const field_names[] = {
            "abi_version", "dim", "parameter_count", "surface_count", "section_count", "preset_count", "name",
            "description", "state_names", "state_meanings", "state_units", "state_periods", "initial_state",
            "parameter_names", "parameter_meanings", "parameter_units", "parameter_defaults", "parameter_lower",
            "parameter_upper", "parameter_bounds_closed", "surface_names", "surface_meanings", "surface_sticks",
            "section_names", "section_meanings", "section_directions", "preset_names", "preset_meanings",
            "preset_sizes", "preset_parameters", "preset_values", "create", "destroy", "rhs", "jacobian",
            "second_derivative", "divergence", "gap", "gap_gradient", "gap_hessian", "reset", "reset_jacobian",
            "reset_second_derivative", "section", "section_gradient", "sticking_rhs", "release",
            "release_gradient", "rest", "step", "dense", "samples", "surface_affine", "section_affine",
            "lanes_width", "context_size", "lanes_step", "lanes_gap", "lanes_gap_gradient", "lanes_section",
            "lanes_section_gradient", "lanes_points", "switch_count", "switch_names", "switch_meanings",
            "switch_directions", "switch_affine", "switching", "switching_gradient", "copy_context", "pin_sides",
            "sides_at", "cross", "switch_reset_jacobian", "lanes_switching"};
        static_assert(std::size(field_names) == 75);
        if (fields.size() != std::size(field_names)) throw std::logic_error("model file: table fields out of step");
        // The fused Runge-Kutta step (integrate/fused_step.hpp): the library's own stage code
        // compiled here with the field inlined, when the compiler is given vimpact's headers
        // (VIMPACT_FUSED_STEPS); without them the library calls vimpact_rhs once per stage.
        s += "\n#ifdef VIMPACT_FUSED_STEPS\n#include \"vimpact/integrate/fused_step.hpp\"\nnamespace {\n"
             "struct vimpact_field {\n    const void* c;\n"
             "    vimpact::vec<" + std::to_string(m_n) + "> operator()(const vimpact::vec<" + std::to_string(m_n) +
             ">& x) const\n    {\n        vimpact::vec<" + std::to_string(m_n) +
             "> f;\n        vimpact_rhs(c, x.data(), f.data());\n        return f;\n    }\n};\n}  // namespace\n"
             "#define VIMPACT_STEP (&vimpact::fused_step_entry<" + std::to_string(m_n) + ", vimpact_field>)\n"
             "#define VIMPACT_DENSE (&vimpact::fused_dense_entry<" + std::to_string(m_n) + ", vimpact_field>)\n"
             "#else\n#define VIMPACT_STEP 0\n#define VIMPACT_DENSE 0\n#endif\n";
        // The SIMD lanes (abi.h, ABI version 5), where the compiler is given vimpact's headers.
        s += "\n#if defined(VIMPACT_FUSED_STEPS) && defined(VIMPACT_LANES_DIM_" + std::to_string(m_n) +
             ") && __has_include(<xsimd/xsimd.hpp>)\n"
             "#include \"vimpact/integrate/fused_lanes.hpp\"\n" + m_lanes_code +
             "#define VIMPACT_LANES_WIDTH vimpact::lane_width\n"
             "#define VIMPACT_LANES(f) (&vimpact_lanes_##f)\n"
             "static void vimpact_lanes_step(const double* c, int method, const double* x, const double* f, const double* h,\n"
             "                               double rtol, double atol, double* x_new, double* f_new, double* stages, double* err2)\n"
             "{\n    vimpact::fused_lanes_step_entry<" + std::to_string(m_n) +
             ", vimpact_lanes_field>(c, method, x, f, h, rtol, atol, x_new, f_new, stages, err2);\n}\n"
             "#else\n#define VIMPACT_LANES_WIDTH 0\n#define VIMPACT_LANES(f) 0\n#endif\n";
        s += "\nstatic const vimpact_model_table vimpact_table = {\n";
        for (std::size_t i = 0; i < fields.size(); ++i)
            s += "    /* " + std::string(field_names[i]) + " */ " + fields[i] + (i + 1 < fields.size() ? ",\n" : "\n");
        s += "};\n\n#ifdef __cplusplus\nextern \"C\"\n#endif\n"
             "__attribute__((visibility(\"default\"))) const vimpact_model_table* vimpact_model(void) { return &vimpact_table; }\n";
        return s;
    }

    const description& m_d;
    const std::string& m_where;
    const std::atomic<bool>* m_cancel;
    expression_reader m_reader;
    double m_terms = 0.0;    // written-out sizes of what has been differentiated and its derivatives
    double m_printed = 0.0;  // of what has been printed
    std::map<std::string, int> m_part_slot;       // a hoisted part's text -> its index
    std::vector<std::string> m_parts;             // the hoisted parts' texts, by index
    std::vector<GiNaC::realsymbol> m_part_symbols;  // p[m_p + m_nd + index]
    int m_n, m_p, m_nd;
    std::vector<GiNaC::realsymbol> m_x;    // x[j]
    std::vector<GiNaC::realsymbol> m_out;  // out[j]: a field component already computed (shared_field_values)
    std::vector<GiNaC::realsymbol> m_ctx;  // p[k]: parameters, then derived quantities
    std::vector<ex> m_derived;
    std::vector<std::size_t> m_derived_order;
    std::vector<double> m_periods;
    std::vector<ex> m_identity;
    vector_function m_field;
    std::vector<scalar_function> m_gaps, m_sections, m_release;
    std::vector<vector_function> m_resets;
    std::vector<std::vector<ex>> m_sticking_field, m_rest;
    std::vector<GiNaC::realsymbol> m_side;  // S[k]: the side of switch k
    struct switch_entry {
        std::string name, meaning;
        crossing direction;
        bool reset;
    };
    std::vector<switch_entry> m_switches;  // the declared switches, then the automatic ones
    struct kink {  // an automatic switch: its function, the functions and keys it comes from
        ex when;
        std::set<std::string> functions, keys;
    };
    std::vector<kink> m_kinks;
    bool m_finding_kinks = false;
    std::map<std::string, std::string> m_user_names;  // "x[0]" -> the state's name, and so on
    std::vector<scalar_function> m_switching;
    std::vector<vector_function> m_switch_resets;
    std::set<int> m_powers;
    std::string m_lanes_code;  // lanes_code(), emitted with the fused steps
    std::vector<std::string> m_switch_value, m_switch_gradient;  // h_k and its gradient's assignments, printed
};

}  // namespace

// Internal (the library's forwarders of the same names load this module): the module's own
// calls stay here.
namespace {

bool reserved_name(std::string_view name)
{
    return name == "pi" || name == "side" || name == "on" || find_function(name) != nullptr;
}

std::string source_of(const description& d, const std::string& where, const std::atomic<bool>* cancel)
{
    static std::mutex ginac_mutex;
    const std::lock_guard<std::mutex> lock(ginac_mutex);
    set_up_ginac();
    return generator(d, where, cancel).run();
}

}  // namespace

}  // namespace vimpact::model_file_detail

// The module's entry (core/load_module.hpp).
extern "C" const vimpact::model_file_detail::symbolic_module* vimpact_symbolic_v1()
{
    static constexpr vimpact::model_file_detail::symbolic_module module{
        vimpact::model_file_detail::source_of, vimpact::model_file_detail::reserved_name,
        vimpact::model_file_detail::functions_text};
    return &module;
}

// Model files, stage 3: generated source -> a loaded shared library, through a cache.
//
// The cache entry's name is a hash of everything that determines the binary: the ABI
// version, the generated source, the compiler command and flags, and the CPU (the code is
// compiled with -march=native, so it is not portable; a home directory shared by machines
// of different CPUs keeps one entry per CPU). An existing entry is loaded without running
// the compiler. A new one is compiled to a unique temporary name in the cache directory and
// renamed into place: rename is atomic, so processes compiling the same model at the same
// moment each produce a complete file and the last one wins with identical content, and a
// process that has already loaded the old file keeps its mapping.
#include <dlfcn.h>
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <optional>
#include <random>
#include <sstream>

#include "model_file_detail.hpp"
#include "vimpact/io/build_info.hpp"
#include "vimpact/core/input_error.hpp"

extern char** environ;

namespace vimpact::model_file_detail {

std::uint64_t fnv1a(std::string_view bytes, std::uint64_t h)
{
    for (const char c : bytes) {
        h ^= static_cast<unsigned char>(c);
        h *= 1099511628211ULL;
    }
    return h;
}

std::string hex64(std::uint64_t h)
{
    char buf[17];
    std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
    return buf;
}

namespace fs = std::filesystem;

namespace {

std::optional<std::string> read_file(const fs::path& path)
{
    std::ifstream in(path, std::ios::binary);
    if (!in) return std::nullopt;
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// The "vimpact/..." names of a header's #include "..." lines, a conditional one too (its
// header is hashed even where the compiler skips it: a key that changes too often costs a
// compilation, one that changes too rarely loads stale code).
std::vector<std::string> quoted_vimpact_includes(const std::string& text)
{
    std::vector<std::string> names;
    std::istringstream lines(text);
    for (std::string line; std::getline(lines, line);) {
        std::size_t i = line.find_first_not_of(" \t");
        if (i == std::string::npos || line[i] != '#') continue;
        i = line.find_first_not_of(" \t", i + 1);
        if (i == std::string::npos || line.compare(i, 7, "include") != 0) continue;
        const std::size_t open = line.find_first_not_of(" \t", i + 7);
        if (open == std::string::npos || line[open] != '"') continue;
        const std::size_t close = line.find('"', open + 1);
        if (close == std::string::npos) continue;
        std::string name = line.substr(open + 1, close - open - 1);
        if (name.rfind("vimpact/", 0) == 0) names.push_back(std::move(name));
    }
    return names;
}

}  // namespace

std::optional<std::vector<header_text>> vimpact_includes(const fs::path& include_dir, const std::string& root)
{
    std::vector<header_text> found;
    std::vector<std::string> pending{root};
    while (!pending.empty()) {
        std::string name = std::move(pending.back());
        pending.pop_back();
        if (std::any_of(found.begin(), found.end(), [&](const header_text& h) { return h.name == name; })) continue;
        auto text = read_file(include_dir / name);
        if (!text) return std::nullopt;
        auto next = quoted_vimpact_includes(*text);
        pending.insert(pending.end(), next.rbegin(), next.rend());  // the first include is taken next
        found.push_back({std::move(name), std::move(*text)});
    }
    return found;
}

namespace {

// The headers the generated code includes for its fused Runge-Kutta steps (the library's own
// stage code): the installed copy of vimpact's headers, else the source tree's; none found
// complete (a header one of them names is missing), the model is compiled without fused steps
// (correct, about twice as slow per step).
struct fused_headers {
    std::string vimpact, eigen;
    std::string text;  // their names and content, part of the cache key: changed stage code, new entry
};

const std::optional<fused_headers>& find_fused_headers()
{
    static const std::optional<fused_headers> found = []() -> std::optional<fused_headers> {
        const std::string eigen(vimpact::eigen_include_dir());
        if (eigen.empty() || !fs::exists(fs::path(eigen) / "Eigen" / "Core")) return std::nullopt;
        for (const std::string_view dir : {vimpact::installed_include_dir(), vimpact::source_include_dir()}) {
            const auto files = vimpact_includes(fs::path(dir), "vimpact/integrate/fused_step.hpp");
            if (!files) continue;
            fused_headers h{std::string(dir), eigen, {}};
            for (const auto& f : *files) h.text += f.name + "\n" + f.text + "\n";
            return h;
        }
        return std::nullopt;
    }();
    return found;
}

// No -ffast-math: the results must be IEEE arithmetic, as in the library's own code. The
// Eigen alignment is the library's (its stage code runs here).
const std::vector<std::string>& compile_flags()
{
    static const std::vector<std::string> flags = [] {
        std::vector<std::string> f{"-std=c++20", "-O3",     "-march=native",       "-fPIC",
                                   "-shared",    "-fno-math-errno", "-fvisibility=hidden"};
        if (const auto& h = find_fused_headers()) {
            f.insert(f.end(), {"-DVIMPACT_FUSED_STEPS", "-DEIGEN_MAX_ALIGN_BYTES=64", "-DEIGEN_MAX_STATIC_ALIGN_BYTES=64",
                               "-I" + h->vimpact, "-isystem", h->eigen});
        }
        return f;
    }();
    return flags;
}

fs::path cache_directory(const std::string& where)
{
    fs::path dir;
    if (const char* v = std::getenv("VIMPACT_CACHE_DIR"); v && *v) dir = v;
    else if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x) dir = fs::path(x) / "vimpact";
    else if (const char* h = std::getenv("HOME"); h && *h) dir = fs::path(h) / ".cache" / "vimpact";
    else throw input_error(where + ": no directory for the compiled model (set VIMPACT_CACHE_DIR; HOME is not set)");
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec || !fs::is_directory(dir))
        throw input_error(where + ": cannot create the model cache directory " + dir.string() + ": " +
                          (ec ? ec.message() : std::string("not a directory")) + " (set VIMPACT_CACHE_DIR)");
    return dir;
}

std::string cpu_identity()
{
    std::ifstream f("/proc/cpuinfo");
    std::string line, model, flags;
    while (std::getline(f, line) && (model.empty() || flags.empty())) {
        if (model.empty() && line.rfind("model name", 0) == 0) model = line;
        else if (flags.empty() && (line.rfind("flags", 0) == 0 || line.rfind("Features", 0) == 0)) flags = line;
    }
    return model + "\n" + flags;
}

std::vector<std::string> compiler_command()
{
    std::vector<std::string> words;
    const char* cxx = std::getenv("CXX");
    std::istringstream in(cxx && *cxx ? cxx : "c++");
    for (std::string w; in >> w;) words.push_back(w);
    if (words.empty()) words.push_back("c++");
    return words;
}

bool is_executable_file(const fs::path& p)
{
    std::error_code ec;
    return fs::is_regular_file(p, ec) && ::access(p.c_str(), X_OK) == 0;
}

// The program as execvp would find it, or empty.
std::string find_program(const std::string& name)
{
    if (name.find('/') != std::string::npos) return is_executable_file(name) ? name : std::string();
    const char* path = std::getenv("PATH");
    std::string dirs = path && *path ? path : "/usr/local/bin:/usr/bin:/bin";
    std::size_t start = 0;
    while (start <= dirs.size()) {
        const std::size_t end = std::min(dirs.find(':', start), dirs.size());
        const std::string dir = dirs.substr(start, end - start);
        const fs::path candidate = fs::path(dir.empty() ? "." : dir) / name;
        if (is_executable_file(candidate)) return candidate.string();
        start = end + 1;
    }
    return {};
}

[[noreturn]] void no_compiler(const std::string& where, const std::string& detail)
{
    throw input_error(where + " needs a C++ compiler to be compiled to native code: none found (" + detail +
                      "; set CXX or install g++)");
}

// A name no other process or thread uses.
std::string unique_suffix()
{
    static std::atomic<unsigned> counter{0};
    static const unsigned salt = std::random_device{}();
    return ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++) + "-" + std::to_string(salt);
}

void write_atomically(const fs::path& path, const std::string& text, const std::string& where)
{
    const fs::path tmp = path.string() + unique_suffix();
    {
        std::ofstream out(tmp, std::ios::binary);
        out << text;
        out.close();
        if (!out) {
            std::error_code ec;
            fs::remove(tmp, ec);
            throw input_error(where + ": cannot write " + tmp.string() + ": " + std::strerror(errno));
        }
    }
    std::error_code ec;
    fs::rename(tmp, path, ec);
    if (ec) {
        fs::remove(tmp, ec);
        throw input_error(where + ": cannot write " + path.string() + ": " + ec.message());
    }
}

std::string read_text(const fs::path& path)
{
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

// The line of the compiler's output that says what went wrong.
std::string first_error_line(const std::string& log)
{
    std::istringstream in(log);
    std::string line, first;
    while (std::getline(in, line)) {
        if (first.empty() && line.find_first_not_of(" \t\r") != std::string::npos) first = line;
        if (line.find("error") != std::string::npos || line.find("Error") != std::string::npos) {
            first = line;
            break;
        }
    }
    if (first.empty()) return "no message";
    if (first.size() > 400) first = first.substr(0, 400) + "...";
    return first;
}

// Runs argv (argv[0] resolved to `program`) with its output in `log`; returns the wait status.
int run(const std::string& program, const std::vector<std::string>& args, const fs::path& log,
        const std::string& where)
{
    std::vector<char*> argv;
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);

    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&actions, 1, 2);
    pid_t pid = 0;
    const int rc = ::posix_spawn(&pid, program.c_str(), &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (rc != 0) no_compiler(where, "cannot run " + program + ": " + std::strerror(rc));
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0)
        if (errno != EINTR) throw input_error(where + ": lost the compiler process: " + std::strerror(errno));
    return status;
}

void compile(const std::vector<std::string>& command, const fs::path& cpp, const fs::path& so,
             const std::string& source, const std::string& where)
{
    const std::string program = find_program(command[0]);
    if (program.empty()) {
        const char* cxx = std::getenv("CXX");
        no_compiler(where, cxx && *cxx ? "CXX=" + std::string(cxx) + " is not an executable program"
                                       : std::string("no c++ on PATH"));
    }
    write_atomically(cpp, source, where);
    const fs::path tmp = so.string() + unique_suffix();
    const fs::path log = tmp.string() + ".log";
    std::vector<std::string> args = command;
    args.insert(args.end(), compile_flags().begin(), compile_flags().end());
    args.insert(args.end(), {"-o", tmp.string(), cpp.string()});
    const int status = run(program, args, log, where);
    const std::string output = read_text(log);
    std::error_code ec;
    fs::remove(log, ec);
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || !fs::exists(tmp, ec)) {
        fs::remove(tmp, ec);
        const std::string how = WIFEXITED(status) ? "exit code " + std::to_string(WEXITSTATUS(status))
                                : WIFSIGNALED(status) ? "signal " + std::to_string(WTERMSIG(status))
                                                      : std::string("no output file");
        throw input_error(where + ": the C++ compiler " + program + " failed (" + how + "): " + first_error_line(output) +
                          " (the generated source is kept in " + cpp.string() + ")");
    }
    fs::rename(tmp, so, ec);
    if (ec) {
        fs::remove(tmp, ec);
        throw input_error(where + ": cannot store the compiled model in " + so.string() + ": " + ec.message());
    }
}

}  // namespace

loaded_library open_library(const fs::path& path, const std::string& what)
{
    // An absolute path: dlopen would search the library path for a bare file name.
    const std::string file = fs::absolute(path).string();
    ::dlerror();
    void* h = ::dlopen(file.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!h) {
        const char* e = ::dlerror();
        throw input_error(what + ": cannot load it: " + (e ? e : "unknown error"));
    }
    std::shared_ptr<void> handle(h, [](void* x) { ::dlclose(x); });
    void* symbol = ::dlsym(h, VIMPACT_MODEL_ENTRY);
    if (!symbol)
        throw input_error(what + " does not export " VIMPACT_MODEL_ENTRY
                                 "() (a C++ model library is built with VIMPACT_EXPORT_MODEL from "
                                 "vimpact/model/export.hpp)");
    vimpact_model_entry entry = nullptr;
    static_assert(sizeof entry == sizeof symbol);
    std::memcpy(&entry, &symbol, sizeof entry);
    const vimpact_model_table* table = entry();
    if (!table) throw input_error(what + ": " VIMPACT_MODEL_ENTRY "() returned no model");
    if (table->abi_version != VIMPACT_MODEL_ABI_VERSION)
        throw input_error(what + " was built for model ABI version " + std::to_string(table->abi_version) +
                          "; this vimpact loads version " + std::to_string(VIMPACT_MODEL_ABI_VERSION) + " (rebuild it)");
    return {std::move(handle), table};
}

loaded_library compile_cached(const std::string& source, const std::string& model_name, const std::string& where)
{
    const fs::path dir = cache_directory(where);
    const std::vector<std::string> command = compiler_command();
    std::uint64_t h = fnv1a("vimpact model cache\nABI " + std::to_string(VIMPACT_MODEL_ABI_VERSION) + "\n");
    for (const auto& w : command) h = fnv1a(w + "\n", h);
    for (const auto& f : compile_flags()) h = fnv1a(f + "\n", h);
    h = fnv1a(cpu_identity() + "\n", h);
    if (const auto& fh = find_fused_headers()) h = fnv1a(fh->text, h);
    h = fnv1a(source, h);
    // The name only helps a reader of the directory; kept short for the file-name limit.
    const std::string stem = model_name.substr(0, 64) + "-" + hex64(h);
    const fs::path so = dir / (stem + ".so");
    const fs::path cpp = dir / (stem + ".cpp");
    std::error_code ec;
    if (fs::exists(so, ec)) {
        try {
            return open_library(so, where);
        } catch (const input_error&) {
            // A damaged entry (a disk that filled up, a file copied from elsewhere): compile again.
        }
    }
    compile(command, cpp, so, source, where);
    return open_library(so, where);
}

}  // namespace vimpact::model_file_detail

// Model files, stage 3: generated source -> a loaded shared library, through a cache.
//
// The cache holds native code that this process will run, so it is trusted only as far as
// it is checked:
// - The directory is private: created 0700, and refused (one line naming it) when it is not
//   owned by the effective user or is writable by its group or others, where anyone could
//   plant a library. Everything in it is reached through the opened directory (openat,
//   renameat), so a path swapped after the check leads nowhere else.
// - An entry is NAME-KEY.so with NAME-KEY.sha256 beside it. KEY is the SHA-256 of
//   everything that determines the binary: the ABI version, the generated source, the
//   compiler (its command, the program it resolves to, and that program's size and
//   modification time, which an upgrade changes), the flags, the headers the fused steps
//   include, and the CPU (-march=native code is not portable; machines sharing a home keep
//   one entry each). The .sha256 record, written when the library is compiled, holds KEY and
//   the SHA-256 of the library's bytes.
// - An entry is loaded only if the file opened without following links (O_NOFOLLOW) is a
//   regular file of the user's, not writable by others, and the bytes read from that very
//   descriptor hash to the record's value under this KEY; the library is then loaded from the
//   same descriptor (/proc/self/fd/N), so nothing can be swapped between check and load. A
//   damaged entry (truncated, or another model's library copied over it, with or without its
//   record) fails the check and is compiled again; an entry of another user, a link or a
//   writable file is refused. No constructor of an unchecked file ever runs.
// - A new entry is compiled under unique temporary names (the source written 0600 with
//   O_EXCL | O_NOFOLLOW), checked and loaded from its descriptor, then renamed into place:
//   rename is atomic, so processes compiling the same model at the same moment all succeed
//   and each has loaded what it checked. Temporaries of a process that was killed are
//   removed by the next compilation on the same host.
// The compiler runs in the cache directory and is given names relative to it ("./..."): no
// path it sees can start with '-'.
#include <dirent.h>
#include <dlfcn.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <openssl/evp.h>

#include <algorithm>
#include <array>
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
#include "vimpact/core/input_error.hpp"
#include "vimpact/io/build_info.hpp"

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
            const auto files = vimpact_includes(fs::path(dir), "vimpact/integrate/fused_lanes.hpp");
            if (!files) continue;
            fused_headers h{std::string(dir), eigen, {}};
            for (const auto& f : *files) h.text += f.name + "\n" + f.text + "\n";
            return h;
        }
        return std::nullopt;
    }();
    return found;
}


// No -ffast-math: the results must be IEEE arithmetic, as in the library's own code, and no
// multiply-add fused by the compiler (-ffp-contract=off, as the library's analyses): a job in
// SIMD lanes then gets the bits it gets alone, whichever side runs its stages. The Eigen
// alignment and the lanes' width are the library's (its stage code runs here).
const std::vector<std::string>& compile_flags()
{
    static const std::vector<std::string> flags = [] {
        std::vector<std::string> f{"-std=c++20",      "-O3",    "-march=native",       "-fPIC",
                                   "-shared",         "-fno-math-errno", "-fvisibility=hidden", "-ffp-contract=off"};
        if (const auto& h = find_fused_headers()) {
            f.insert(f.end(), {"-DVIMPACT_FUSED_STEPS", "-DEIGEN_MAX_ALIGN_BYTES=64", "-DEIGEN_MAX_STATIC_ALIGN_BYTES=64",
                               "-I" + h->vimpact, "-isystem", h->eigen});
            // The lanes as the library's (core/lanes.hpp): 512 bits only where the library has
            // them, whatever the machine has; and compiled only for the dimensions the library
            // runs in lanes, those with fixed-size states (src/engine_instances.hpp).
#if defined(VIMPACT_LANES_512) && defined(__AVX512F__)
            f.emplace_back("-DVIMPACT_LANES_512");
#endif
            for (const int n : {VIMPACT_MODEL_DIMS}) f.push_back("-DVIMPACT_LANES_DIM_" + std::to_string(n));
        }
        return f;
    }();
    return flags;
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

// The program as execvp would find it, as an absolute path (the compiler runs in the cache
// directory), or empty.
std::string find_program(const std::string& name)
{
    if (name.find('/') != std::string::npos) return is_executable_file(name) ? fs::absolute(name).string() : std::string();
    const char* path = std::getenv("PATH");
    std::string dirs = path && *path ? path : "/usr/local/bin:/usr/bin:/bin";
    std::size_t start = 0;
    while (start <= dirs.size()) {
        const std::size_t end = std::min(dirs.find(':', start), dirs.size());
        const std::string dir = dirs.substr(start, end - start);
        const fs::path candidate = fs::path(dir.empty() ? "." : dir) / name;
        if (is_executable_file(candidate)) return fs::absolute(candidate).string();
        start = end + 1;
    }
    return {};
}

// What identifies the compiler beyond its command: each program the command names (a
// wrapper such as ccache and the compiler it is given), resolved through links, with its
// size and modification time, which a package upgrade changes.
std::string compiler_identity(const std::vector<std::string>& command)
{
    std::string id;
    for (const auto& word : command) {
        id += "word " + word + "\n";
        if (word.starts_with('-')) continue;
        const std::string program = find_program(word);
        if (program.empty()) continue;
        std::error_code ec;
        const fs::path real = fs::canonical(program, ec);
        struct stat st {};
        if (ec || ::stat(real.c_str(), &st) != 0) continue;
        id += "program " + real.string() + " " + std::to_string(st.st_size) + " " + std::to_string(st.st_mtim.tv_sec) +
              "." + std::to_string(st.st_mtim.tv_nsec) + "\n";
    }
    return id;
}

[[noreturn]] void no_compiler(const std::string& where, const std::string& detail)
{
    throw input_error(where + " needs a C++ compiler to be compiled to native code: none found (" + detail +
                      "; set CXX or install g++)");
}

// ---- SHA-256 (OpenSSL's libcrypto)

class sha256 {
public:
    sha256() : m_ctx(EVP_MD_CTX_new())
    {
        if (!m_ctx || EVP_DigestInit_ex(m_ctx, EVP_sha256(), nullptr) != 1) throw std::runtime_error("SHA-256 is not available");
    }
    ~sha256() { EVP_MD_CTX_free(m_ctx); }
    sha256(const sha256&) = delete;
    sha256& operator=(const sha256&) = delete;

    sha256& add(std::string_view bytes)
    {
        if (EVP_DigestUpdate(m_ctx, bytes.data(), bytes.size()) != 1) throw std::runtime_error("SHA-256 failed");
        return *this;
    }
    // A piece with its length, so that no two sequences of pieces hash alike.
    sha256& field(std::string_view bytes) { return add(std::to_string(bytes.size()) + ":").add(bytes); }

    std::string hex()
    {
        std::array<unsigned char, EVP_MAX_MD_SIZE> digest{};
        unsigned int n = 0;
        if (EVP_DigestFinal_ex(m_ctx, digest.data(), &n) != 1) throw std::runtime_error("SHA-256 failed");
        static const char digits[] = "0123456789abcdef";
        std::string s;
        for (unsigned int i = 0; i < n; ++i) {
            s += digits[digest[i] >> 4];
            s += digits[digest[i] & 15];
        }
        return s;
    }

private:
    EVP_MD_CTX* m_ctx;
};

// The SHA-256 of the bytes of an open file, read from its start; nullopt when a read fails
// or the file does not hold `size` bytes.
std::optional<std::string> file_sha256(int fd, off_t size)
{
    sha256 h;
    std::vector<char> buf(1 << 16);
    off_t at = 0;
    for (;;) {
        const ssize_t n = ::pread(fd, buf.data(), buf.size(), at);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) return std::nullopt;
        if (n == 0) break;
        h.add(std::string_view(buf.data(), static_cast<std::size_t>(n)));
        at += n;
    }
    if (at != size) return std::nullopt;
    return h.hex();
}

// ---- the directory

struct cache_directory {
    fs::path path;  // absolute
    unique_fd fd;
};

fs::path cache_path(const std::string& where)
{
    fs::path dir;
    if (const char* v = std::getenv("VIMPACT_CACHE_DIR"); v && *v) dir = v;
    else if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x) dir = fs::path(x) / "vimpact";
    else if (const char* h = std::getenv("HOME"); h && *h) dir = fs::path(h) / ".cache" / "vimpact";
    else throw input_error(where + ": no directory for the compiled model (set VIMPACT_CACHE_DIR; HOME is not set)");
    // Absolute: a relative name (even "-odd") means the same directory wherever it is used.
    dir = fs::absolute(dir).lexically_normal();
    return dir.has_filename() ? dir : dir.parent_path();
}

std::string octal_mode(mode_t m)
{
    char buf[8];
    std::snprintf(buf, sizeof buf, "%04o", static_cast<unsigned>(m & 07777));
    return buf;
}

// Creates the directory and any missing parent, each 0700 (as a fresh ~/.cache should be),
// opens it and checks that it is private.
cache_directory open_cache_directory(const std::string& where)
{
    const fs::path dir = cache_path(where);
    const auto cannot = [&](const std::string& why) {
        throw input_error(where + ": cannot create the model cache directory " + dir.string() + ": " + why +
                          " (set VIMPACT_CACHE_DIR)");
    };
    fs::path partial;
    for (const auto& part : dir) {
        partial /= part;
        if (partial == partial.root_path()) continue;
        if (::mkdir(partial.c_str(), 0700) != 0 && errno != EEXIST) cannot(std::strerror(errno));
    }
    unique_fd fd(::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC));
    if (!fd.valid()) cannot(errno == ENOTDIR ? "not a directory" : std::strerror(errno));
    struct stat st {};
    if (::fstat(fd.get(), &st) != 0) cannot(std::strerror(errno));
    if (st.st_uid != ::geteuid())
        throw input_error(where + ": the model cache directory " + dir.string() + " belongs to another user (uid " +
                          std::to_string(st.st_uid) +
                          "), who could plant code in it: use a directory of your own (set VIMPACT_CACHE_DIR)");
    if ((st.st_mode & (S_IWGRP | S_IWOTH)) != 0)
        throw input_error(where + ": the model cache directory " + dir.string() + " is writable by other users (mode " +
                          octal_mode(st.st_mode) + "), who could plant code in it: make it private (chmod 700 " +
                          dir.string() + ") or set VIMPACT_CACHE_DIR");
    return {dir, std::move(fd)};
}

// ---- entries

// Opens a file of an entry for reading and checks it; nullopt when it does not exist. The
// checks are of the opened file: no link is followed, and a FIFO does not block the open.
std::optional<unique_fd> open_entry_file(const cache_directory& dir, const std::string& name, const std::string& where)
{
    const std::string path = (dir.path / name).string();
    unique_fd fd(::openat(dir.fd.get(), name.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC));
    const auto refuse = [&](const std::string& why) {
        throw input_error(where + ": the model cache entry " + path + " " + why +
                          ", so it is not loaded: remove it (the cache holds only your own files)");
    };
    if (!fd.valid()) {
        if (errno == ENOENT) return std::nullopt;
        if (errno == ELOOP) refuse("is a symbolic link");
        throw input_error(where + ": cannot open the model cache entry " + path + ": " + std::strerror(errno));
    }
    struct stat st {};
    if (::fstat(fd.get(), &st) != 0) throw input_error(where + ": cannot read " + path + ": " + std::strerror(errno));
    if (!S_ISREG(st.st_mode)) refuse("is not a regular file");
    if (st.st_uid != ::geteuid()) refuse("belongs to another user (uid " + std::to_string(st.st_uid) + ")");
    if ((st.st_mode & (S_IWGRP | S_IWOTH)) != 0) refuse("is writable by other users (mode " + octal_mode(st.st_mode) + ")");
    return fd;
}

off_t file_size(int fd)
{
    struct stat st {};
    return ::fstat(fd, &st) == 0 ? st.st_size : -1;
}

std::string record_text(const std::string& key, const std::string& library_sha256)
{
    return "vimpact model cache entry\nkey " + key + "\nlibrary sha256 " + library_sha256 + "\n";
}

// The entry `stem`, loaded if it passes every check; nullopt when it is missing or damaged
// (to be compiled again).
std::optional<loaded_library> load_entry(const cache_directory& dir, const std::string& stem, const std::string& key,
                                         const std::string& where)
{
    const auto so = open_entry_file(dir, stem + ".so", where);
    if (!so) return std::nullopt;
    const auto record = open_entry_file(dir, stem + ".sha256", where);
    if (!record) return std::nullopt;
    std::string text(512, '\0');
    const ssize_t n = ::pread(record->get(), text.data(), text.size(), 0);
    if (n <= 0) return std::nullopt;
    text.resize(static_cast<std::size_t>(n));
    const auto hash = file_sha256(so->get(), file_size(so->get()));
    if (!hash || text != record_text(key, *hash)) return std::nullopt;
    try {
        return open_library_fd(so->get(), where + ": the compiled model " + (dir.path / (stem + ".so")).string());
    } catch (const input_error&) {
        return std::nullopt;  // checked, yet not loadable (a changed system library): compile again
    }
}

// A name no other process (on any host sharing the directory) or thread uses:
// ".tmp-HOST-PID-N-SALT", where HOST is a hash of the host name.
std::string host_tag()
{
    char name[256] = {};
    ::gethostname(name, sizeof name - 1);
    return hex64(fnv1a(name)).substr(0, 8);
}

std::string unique_suffix()
{
    static std::atomic<unsigned> counter{0};
    static const unsigned salt = std::random_device{}();
    return ".tmp-" + host_tag() + "-" + std::to_string(::getpid()) + "-" + std::to_string(counter++) + "-" +
           std::to_string(salt);
}

// Removes the temporaries that processes of this host, since ended (killed while compiling),
// left in the directory. A live process's, another host's and other users' are left alone.
void remove_stale_temporaries(const cache_directory& dir)
{
    const int fd = ::openat(dir.fd.get(), ".", O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) return;
    DIR* d = ::fdopendir(fd);
    if (!d) {
        ::close(fd);
        return;
    }
    const std::string mark = ".tmp-" + host_tag() + "-";
    std::vector<std::string> stale;
    while (const dirent* e = ::readdir(d)) {
        const std::string name = e->d_name;
        const std::size_t at = name.find(mark);
        if (at == std::string::npos) continue;
        const std::size_t digits = at + mark.size();
        const std::size_t end = name.find('-', digits);
        if (end == std::string::npos || end == digits) continue;
        const std::string pid_text = name.substr(digits, end - digits);
        if (pid_text.find_first_not_of("0123456789") != std::string::npos || pid_text.size() > 9) continue;
        const auto pid = static_cast<pid_t>(std::stol(pid_text));
        if (::kill(pid, 0) == 0 || errno != ESRCH) continue;
        struct stat st {};
        if (::fstatat(dir.fd.get(), name.c_str(), &st, AT_SYMLINK_NOFOLLOW) == 0 && st.st_uid == ::geteuid())
            stale.push_back(name);
    }
    ::closedir(d);
    for (const auto& name : stale) ::unlinkat(dir.fd.get(), name.c_str(), 0);
}

// Temporary files of one compilation, removed unless kept.
class temporaries {
public:
    explicit temporaries(int dir_fd) : m_dir(dir_fd) {}
    temporaries(const temporaries&) = delete;
    temporaries& operator=(const temporaries&) = delete;
    ~temporaries()
    {
        for (const auto& n : m_names) ::unlinkat(m_dir, n.c_str(), 0);
    }
    std::string add(std::string name)
    {
        m_names.push_back(name);
        return name;
    }
    // Renames a temporary into place (it is then no longer removed).
    bool install(const std::string& name, const std::string& final_name)
    {
        if (::renameat(m_dir, name.c_str(), m_dir, final_name.c_str()) != 0) return false;
        m_names.erase(std::find(m_names.begin(), m_names.end(), name));
        return true;
    }

private:
    int m_dir;
    std::vector<std::string> m_names;
};

// Writes a new private file (0600; never through a link or over an existing file).
void write_private(int dir_fd, const std::string& name, std::string_view text, const std::string& what)
{
    unique_fd fd(::openat(dir_fd, name.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0600));
    if (!fd.valid()) throw input_error(what + ": " + std::strerror(errno));
    while (!text.empty()) {
        const ssize_t n = ::write(fd.get(), text.data(), text.size());
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) throw input_error(what + ": " + std::strerror(n < 0 ? errno : EIO));
        text.remove_prefix(static_cast<std::size_t>(n));
    }
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

std::string replace_all(std::string s, const std::string& from, const std::string& to)
{
    for (std::size_t at = s.find(from); at != std::string::npos; at = s.find(from, at + to.size()))
        s.replace(at, from.size(), to);
    return s;
}

// Whether an open file starts like a shared library (an ELF file of type ET_DYN).
bool is_shared_library(int fd)
{
    unsigned char h[18] = {};
    if (::pread(fd, h, sizeof h, 0) != static_cast<ssize_t>(sizeof h)) return false;
    if (h[0] != 0x7f || h[1] != 'E' || h[2] != 'L' || h[3] != 'F') return false;
    const int type = h[5] == 2 ? (h[16] << 8 | h[17]) : (h[17] << 8 | h[16]);  // e_type, in the file's byte order
    return type == 3;                                                           // ET_DYN
}

loaded_library compile_entry(const cache_directory& dir, const std::vector<std::string>& command,
                             const std::string& program, const std::string& stem, const std::string& key,
                             const std::string& source, const std::string& where, const std::atomic<bool>* cancel)
{
    remove_stale_temporaries(dir);
    temporaries temp(dir.fd.get());
    const std::string tmp = stem + unique_suffix();
    const std::string cpp = temp.add(tmp + ".cpp"), so = temp.add(tmp + ".so"), record = temp.add(tmp + ".sha256");
    write_private(dir.fd.get(), cpp, source, where + ": cannot write " + (dir.path / cpp).string());

    std::vector<std::string> args = command;
    args.insert(args.end(), compile_flags().begin(), compile_flags().end());
    args.insert(args.end(), {"-o", "./" + so, "./" + cpp});
    const compiler_run run = run_compiler(program, args, dir.fd.get(), cancel);
    if (!WIFEXITED(run.status) || WEXITSTATUS(run.status) != 0) {
        const std::string kept = stem + ".cpp";
        temp.install(cpp, kept);
        const std::string how = WIFEXITED(run.status)     ? "exit code " + std::to_string(WEXITSTATUS(run.status))
                                : WIFSIGNALED(run.status) ? "signal " + std::to_string(WTERMSIG(run.status))
                                                          : std::string("no status");
        throw input_error(where + ": the C++ compiler " + program + " failed (" + how +
                          "): " + replace_all(first_error_line(run.output), "./" + cpp, kept) +
                          " (the generated source is kept in " + (dir.path / kept).string() + ")");
    }
    const std::string not_a_library = where + ": the C++ compiler " + program + " did not produce a loadable shared library";
    unique_fd lib(::openat(dir.fd.get(), so.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC));
    struct stat st {};
    if (!lib.valid() || ::fstat(lib.get(), &st) != 0 || !S_ISREG(st.st_mode) || st.st_uid != ::geteuid())
        throw input_error(not_a_library + " (it exited with code 0 but wrote no output file; CXX selects the compiler)");
    if (!is_shared_library(lib.get()))
        throw input_error(not_a_library + " (it wrote a file that is not an ELF shared object; CXX selects the compiler)");
    ::fchmod(lib.get(), 0600);  // whatever the umask: a group-writable entry would be refused
    const auto hash = file_sha256(lib.get(), st.st_size);
    if (!hash) throw input_error(where + ": cannot read the compiled model " + (dir.path / so).string());
    loaded_library loaded;
    try {
        loaded = open_library_fd(lib.get(), where + ": the compiled model");
    } catch (const input_error& e) {
        throw input_error(not_a_library + " (" + e.what() + ")");
    }
    write_private(dir.fd.get(), record, record_text(key, *hash), where + ": cannot write " + (dir.path / record).string());
    if (!temp.install(so, stem + ".so") || !temp.install(record, stem + ".sha256"))
        throw input_error(where + ": cannot store the compiled model in " + (dir.path / (stem + ".so")).string() + ": " +
                          std::strerror(errno));
    temp.install(cpp, stem + ".cpp");
    return loaded;
}

// A name under which dlopen reaches descriptor fd and that no earlier load of this process
// used. The dynamic loader looks a name up among the names of what it has loaded before it
// opens anything, and those names include every alias under which an object was asked for
// again (glibc adds "/proc/self/fd/M" to a library already loaded from another descriptor of
// the same file): a /proc/self/fd/N of a descriptor closed since, now naming another model's
// library, would give back the first library. Each load therefore spells the path anew: the
// load count n in binary as "/." (1) and "//" (0) components after /proc/self/fd, which the
// kernel reads as the same directory. The count is the loader's process-wide state mirrored.
std::string fresh_descriptor_name(int fd)
{
    static std::atomic<std::uint64_t> loads{0};
    std::uint64_t n = loads.fetch_add(1);
    std::string name = "/proc/self/fd";
    for (; n != 0; n >>= 1) name += (n & 1U) ? "/." : "//";
    return name + "/" + std::to_string(fd);
}

loaded_library library_table(void* h, const std::string& what)
{
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
    return library_table(h, what);
}

loaded_library open_library_fd(int fd, const std::string& what)
{
    const std::string name = fresh_descriptor_name(fd);
    ::dlerror();
    void* h = ::dlopen(name.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!h) {
        const char* e = ::dlerror();
        std::string message = e ? e : "unknown error";
        if (message.starts_with(name + ": ")) message.erase(0, name.size() + 2);
        throw input_error(what + ": cannot load it: " + message);
    }
    return library_table(h, what);
}

loaded_library compile_cached(const std::string& source, const std::string& model_name, const std::string& where,
                              const std::atomic<bool>* cancel)
{
    const cache_directory dir = open_cache_directory(where);
    const std::vector<std::string> command = compiler_command();
    const std::string program = find_program(command[0]);
    if (program.empty()) {
        const char* cxx = std::getenv("CXX");
        no_compiler(where, cxx && *cxx ? "CXX=" + std::string(cxx) + " is not an executable program"
                                       : std::string("no c++ on PATH"));
    }
    sha256 h;
    h.field("vimpact model cache entry").field("ABI " + std::to_string(VIMPACT_MODEL_ABI_VERSION));
    h.field(compiler_identity(command));
    for (const auto& f : compile_flags()) h.field(f);
    h.field(cpu_identity());
    h.field(find_fused_headers() ? find_fused_headers()->text : std::string());
    h.field(source);
    const std::string key = h.hex();
    // The name only helps a reader of the directory; kept short for the file-name limit.
    const std::string stem = model_name.substr(0, 64) + "-" + key;
    if (auto lib = load_entry(dir, stem, key, where)) return std::move(*lib);
    return compile_entry(dir, command, program, stem, key, source, where, cancel);
}

}  // namespace vimpact::model_file_detail

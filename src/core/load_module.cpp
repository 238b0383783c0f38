#include "core/load_module.hpp"

#include <dlfcn.h>

#include <filesystem>
#include <map>
#include <mutex>
#include <stdexcept>
#include <string>

namespace vimpact::detail {

namespace {

std::filesystem::path library_directory()
{
    Dl_info info{};
    if (dladdr(reinterpret_cast<void*>(&module_symbol), &info) == 0 || info.dli_fname == nullptr)
        throw std::runtime_error("cannot find the directory of libvimpact.so");
    return std::filesystem::path(info.dli_fname).parent_path();
}

}  // namespace

void* module_symbol(const char* file, const char* symbol)
{
    // dlopen counts its own references, but the lock keeps the message of one failure whole
    // (dlerror is per thread, the handles' map is not).
    static std::mutex mutex;
    static std::map<std::string, void*> handles;
    const std::lock_guard lock(mutex);
    void*& handle = handles[file];
    if (handle == nullptr) {
        const std::string path = (library_directory() / file).string();
        handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
        if (handle == nullptr) {
            const char* why = dlerror();
            throw std::runtime_error("cannot load " + path + " (" + (why ? why : "unknown reason") +
                                     "): this vimpact is not completely built (build all its targets) or installed");
        }
    }
    void* address = dlsym(handle, symbol);
    if (address == nullptr) throw std::runtime_error(std::string("no ") + symbol + " in " + file);
    return address;
}

}  // namespace vimpact::detail

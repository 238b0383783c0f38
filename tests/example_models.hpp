#pragma once
// The example model files (examples/models/*.toml) loaded once per test program, compiled
// into a cache that is never the user's: the one the test run shares (VIMPACT_TEST_CACHE_DIR,
// set by CTest, which runs every test in a process of its own: each model is then compiled
// once per build, not once per test), else a fresh temporary directory removed at exit.
#include <sys/types.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <optional>
#include <string>

#include "vimpact/model/model.hpp"

namespace vimpact::test {

namespace detail {

class example_cache {
public:
    example_cache()
    {
        if (const char* shared = std::getenv("VIMPACT_TEST_CACHE_DIR"); shared && *shared) {
            m_dir = shared;
            m_shared = true;
            return;
        }
        std::string pattern = (std::filesystem::temp_directory_path() / "vimpact-engine-tests-XXXXXX").string();
        if (::mkdtemp(pattern.data())) m_dir = pattern;
    }
    ~example_cache()
    {
        std::error_code ec;
        if (!m_dir.empty() && !m_shared) std::filesystem::remove_all(m_dir, ec);
    }
    example_cache(const example_cache&) = delete;
    example_cache& operator=(const example_cache&) = delete;

    // The model of examples/models/<name>.toml with its default parameters.
    model load(const std::string& name)
    {
        if (const auto it = m_models.find(name); it != m_models.end()) return it->second;
        const model m = compile([&] {
            return model::from_file(std::filesystem::path(VIMPACT_SOURCE_DIR) / "examples" / "models" / (name + ".toml"));
        });
        return m_models.emplace(name, m).first->second;
    }

    // A model compiled into this cache.
    template <class Load>
    model compile(Load load) const
    {
        // VIMPACT_CACHE_DIR for this load only (another test may have set its own).
        std::optional<std::string> old;
        if (const char* v = std::getenv("VIMPACT_CACHE_DIR")) old = v;
        ::setenv("VIMPACT_CACHE_DIR", m_dir.c_str(), 1);
        struct restore {
            const std::optional<std::string>& value;
            ~restore()
            {
                if (value) ::setenv("VIMPACT_CACHE_DIR", value->c_str(), 1);
                else ::unsetenv("VIMPACT_CACHE_DIR");
            }
        } guard{old};
        return load();
    }
    [[nodiscard]] const std::filesystem::path& dir() const { return m_dir; }

private:
    std::filesystem::path m_dir;
    bool m_shared = false;
    std::map<std::string, model> m_models;
};

inline example_cache& examples()
{
    static example_cache cache;
    return cache;
}

}  // namespace detail

// examples/models/<name>.toml, compiled once per test program.
inline model example_model(const std::string& name) { return detail::examples().load(name); }

// The text of examples/models/<name>.toml.
inline std::string example_text(const std::string& name)
{
    std::ifstream in(std::filesystem::path(VIMPACT_SOURCE_DIR) / "examples" / "models" / (name + ".toml"));
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// A model file's text compiled into the examples' cache.
inline model model_from_text(const std::string& text, const std::string& source)
{
    return detail::examples().compile([&] { return model::from_toml(text, source); });
}

}  // namespace vimpact::test

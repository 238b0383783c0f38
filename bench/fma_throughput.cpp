// How much multiply-add arithmetic the machine gives per instruction width: the time of one
// fused multiply-add with twelve independent chains (enough to fill every multiply-add unit),
// for 512-bit (8 doubles), 256-bit (4) and scalar operands. The SIMD lanes' width
// (include/vimpact/core/lanes.hpp) follows from it: a processor that issues one 512-bit
// multiply-add per cycle against two of 256 bits, or slows its clock for 512-bit arithmetic,
// gives no more arithmetic per double with the wider registers.
// Prints one JSON line: ns per instruction and per double, medians of 5 rounds.
// Usage: build/fma_throughput
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <immintrin.h>
#include <vector>

namespace {

template <class V, class Fma>
double ns_per_fma(Fma fma, V start, V factor)
{
    constexpr long iterations = 20'000'000;
    constexpr int chains = 12;
    V acc[chains];
    for (auto& a : acc) a = start;
    const auto t0 = std::chrono::steady_clock::now();
    for (long k = 0; k < iterations; ++k) {
#pragma GCC unroll 12
        for (int i = 0; i < chains; ++i) acc[i] = fma(acc[i], factor, factor);
        // Keeps the chains in registers and the loop from being folded.
        asm volatile("" : "+v"(acc[0]), "+v"(acc[1]), "+v"(acc[2]), "+v"(acc[3]), "+v"(acc[4]), "+v"(acc[5]));
        asm volatile("" : "+v"(acc[6]), "+v"(acc[7]), "+v"(acc[8]), "+v"(acc[9]), "+v"(acc[10]), "+v"(acc[11]));
    }
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return s / (static_cast<double>(iterations) * chains) * 1e9;
}

template <class F>
double median_of_5(F f)
{
    std::vector<double> v;
    for (int r = 0; r < 5; ++r) v.push_back(f());
    std::sort(v.begin(), v.end());
    return v[2];
}

}  // namespace

int main()
{
    std::printf("{");
#if defined(__AVX512F__)
    const double z = median_of_5([] {
        return ns_per_fma([](__m512d a, __m512d b, __m512d c) { return _mm512_fmadd_pd(a, b, c); },
                          _mm512_set1_pd(1.0), _mm512_set1_pd(0.999999));
    });
    std::printf("\"ns_512\": %.3f, \"ns_per_double_512\": %.4f, ", z, z / 8);
#endif
#if defined(__FMA__)
    const double y = median_of_5([] {
        return ns_per_fma([](__m256d a, __m256d b, __m256d c) { return _mm256_fmadd_pd(a, b, c); },
                          _mm256_set1_pd(1.0), _mm256_set1_pd(0.999999));
    });
    const double s = median_of_5([] {
        return ns_per_fma([](__m128d a, __m128d b, __m128d c) { return _mm_fmadd_sd(a, b, c); },
                          _mm_set1_pd(1.0), _mm_set1_pd(0.999999));
    });
    std::printf("\"ns_256\": %.3f, \"ns_per_double_256\": %.4f, \"ns_scalar\": %.3f", y, y / 4, s);
#else
    std::printf("\"fma\": false");
#endif
    std::printf("}\n");
    return 0;
}

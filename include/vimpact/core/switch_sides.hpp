#pragma once
// The side of each switching surface of a model (model/spec.hpp, switching_surface): +1 where
// its switching function h_k is positive, -1 where negative. The hybrid flow holds the sides
// between located crossings, so that the vector field does not change inside a step (a kink
// inside a step would cost the integrator its order and hide the crossing); away from a flow,
// a model takes them from the state.
#include <cstdint>

namespace vimpact {

class switch_sides {
public:
    static constexpr int max_switches = 64;

    // side(k): +1 or -1; on(k): 1 on the positive side, 0 on the negative, (1 + side) / 2.
    [[nodiscard]] double side(int k) const { return negative(k) ? -1.0 : 1.0; }
    [[nodiscard]] double on(int k) const { return negative(k) ? 0.0 : 1.0; }
    [[nodiscard]] bool negative(int k) const { return ((m_negative >> k) & 1U) != 0; }
    void set(int k, bool positive)
    {
        const std::uint64_t bit = std::uint64_t{1} << k;
        m_negative = positive ? (m_negative & ~bit) : (m_negative | bit);
    }
    void flip(int k) { m_negative ^= std::uint64_t{1} << k; }
    // Bit k set: side -1 (a function table's form, model/abi.h).
    [[nodiscard]] std::uint64_t negative_bits() const { return m_negative; }
    static switch_sides from_bits(std::uint64_t negative)
    {
        switch_sides s;
        s.m_negative = negative;
        return s;
    }
    friend bool operator==(const switch_sides&, const switch_sides&) = default;

private:
    std::uint64_t m_negative = 0;
};

}  // namespace vimpact

// rng.h: the project's random numbers. xoshiro256** (Blackman & Vigna 2018) seeded through
// splitmix64 from (seed, stream): the same stream on every platform and compiler (unlike
// std::uniform_real_distribution), and independent streams for independent chunks of work, so
// results depend on the seed alone, never on the thread count.
#pragma once

#include <cstddef>
#include <cstdint>

namespace retroprism {

// splitmix64 (Steele, Lea & Flood 2014): advances x and returns the next output.
inline std::uint64_t splitmix64(std::uint64_t& x) {
    std::uint64_t z = (x += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

class Rng {
  public:
    explicit Rng(std::uint64_t seed, std::uint64_t stream = 0) {
        std::uint64_t x = seed ^ (0xD1B54A32D192ED03ull * (stream + 1));
        for (std::uint64_t& s : s_)
            s = splitmix64(x);
    }
    // The generator whose state is s (four words, not all zero), and its state: for code that
    // keeps many generators' states in arrays of its own (sim/wavefront.cpp).
    static Rng from_state(const std::uint64_t s[4]) {
        Rng r(0);
        for (int i = 0; i < 4; ++i)
            r.s_[i] = s[i];
        return r;
    }
    void state(std::uint64_t s[4]) const {
        for (int i = 0; i < 4; ++i)
            s[i] = s_[i];
    }
    std::uint64_t next() { return xoshiro256ss(s_[0], s_[1], s_[2], s_[3]); }
    // One step of xoshiro256** on a state held in four words anywhere.
    static std::uint64_t xoshiro256ss(std::uint64_t& s0, std::uint64_t& s1, std::uint64_t& s2,
                                      std::uint64_t& s3) {
        const std::uint64_t result = rotl(s1 * 5, 7) * 9;
        const std::uint64_t t = s1 << 17;
        s2 ^= s0;
        s3 ^= s1;
        s1 ^= s2;
        s0 ^= s3;
        s2 ^= t;
        s3 = rotl(s3, 45);
        return result;
    }
    double uniform() { return uniform_of(next()); }           // [0, 1)
    double uniform_open() { return uniform_open_of(next()); } // (0, 1)
    // The same variates of a draw's bits (for code that draws in bulk).
    static double uniform_of(std::uint64_t bits) { return double(bits >> 11) * 0x1.0p-53; }
    static double uniform_open_of(std::uint64_t bits) {
        return (double(bits >> 11) + 0.5) * 0x1.0p-53;
    }
    std::size_t index(std::size_t n) { return std::size_t(next() % n); } // [0, n)

  private:
    static std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
    std::uint64_t s_[4];
};

} // namespace retroprism

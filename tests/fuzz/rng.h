#pragma once
/// The fuzzer's random numbers: splitmix64, the same sequence on every platform and standard
/// library (std::uniform_int_distribution is not), so a seed and a case number name one input.

#include <cstddef>
#include <cstdint>
#include <vector>

namespace atelier::fuzz {

class Rng {
  public:
    /// The generator of case `index` of a run with seed `seed`: each case is reproducible alone.
    Rng(std::uint64_t seed, std::uint64_t index) : m_state(seed) {
        m_state = next() ^ (index * 0xD1B54A32D192ED03ULL);
        next();
    }

    std::uint64_t next() {
        std::uint64_t z = (m_state += 0x9E3779B97F4A7C15ULL);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
        return z ^ (z >> 31);
    }
    /// Uniform in [0, n) (n > 0; the modulo bias is irrelevant here).
    std::size_t below(std::size_t n) { return static_cast<std::size_t>(next() % n); }
    /// True with probability `percent`/100.
    bool chance(int percent) { return below(100) < static_cast<std::size_t>(percent); }
    template <class T> const T& pick(const std::vector<T>& items) {
        return items[below(items.size())];
    }

  private:
    std::uint64_t m_state;
};

} // namespace atelier::fuzz

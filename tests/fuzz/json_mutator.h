#pragma once
/// Structural and value mutations of JSON text: keys deleted, duplicated, renamed or added,
/// types swapped, values swapped, arrays emptied or repeated, deep nesting, and numbers and
/// strings replaced by the values readers get wrong (0, −1, 1e300, 2^63, "NaN", "", control
/// characters, invalid UTF-8, "../", /dev/zero, a FIFO). What a JSON document cannot hold
/// (duplicate keys, invalid UTF-8, numbers beyond double, 100 000 levels) is written as raw text
/// spliced into the serialized document.

#include "rng.h"

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace atelier::fuzz {

class JsonMutator {
  public:
    /// `corpus`: the seed texts; their keys, strings and values become the dictionary that
    /// mutations draw from (an unknown key that is a known key elsewhere, a panel where a seam
    /// was).
    explicit JsonMutator(const std::vector<std::string>& corpus);

    /// `text` with `count` mutations; each appends a line to `notes` (`/cloths/0/mesh/cells/0:
    /// number -> 1e18`). Nothing when `text` is not JSON.
    std::optional<std::string> mutate(std::string_view text, Rng& rng, int count,
                                      std::vector<std::string>& notes) const;

  private:
    std::vector<std::string> m_keys;
    std::vector<std::string> m_strings;
    std::vector<nlohmann::ordered_json> m_values;
};

} // namespace atelier::fuzz

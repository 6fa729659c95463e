#include "patterns/garment.h"

namespace atelier::patterns {

int Garment::panelIndex(const std::string& panelName) const {
    for (std::size_t i = 0; i < panels.size(); ++i) {
        if (panels[i].name == panelName) {
            return static_cast<int>(i);
        }
    }
    return -1;
}

} // namespace atelier::patterns

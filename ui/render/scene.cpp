#include "ui/render/scene.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>

namespace atelier::render {

Eigen::AlignedBox3d sceneBounds(const Scene& scene) {
    Eigen::AlignedBox3d box;
    for (const DrawMesh& mesh : scene.meshes) {
        for (Eigen::Index i = 0; i < mesh.positions.rows(); ++i) {
            box.extend(mesh.positions.row(i).transpose());
        }
    }
    return box;
}

Colour panelColour(int index) {
    // Muted fabric tones that stay apart from each other and from the body's grey.
    static constexpr std::array<Colour, 8> PALETTE = {{
        {0.80f, 0.36f, 0.31f, 1.0f}, // brick
        {0.29f, 0.50f, 0.70f, 1.0f}, // denim blue
        {0.91f, 0.70f, 0.32f, 1.0f}, // mustard
        {0.42f, 0.64f, 0.45f, 1.0f}, // sage
        {0.58f, 0.44f, 0.69f, 1.0f}, // lavender
        {0.30f, 0.67f, 0.71f, 1.0f}, // teal
        {0.88f, 0.56f, 0.62f, 1.0f}, // rose
        {0.60f, 0.58f, 0.36f, 1.0f}, // olive
    }};
    const auto n = static_cast<int>(PALETTE.size());
    return PALETTE[static_cast<std::size_t>(((index % n) + n) % n)];
}

Colour seamColour(int index) {
    static constexpr std::array<Colour, 8> PALETTE = {{
        {0.85f, 0.10f, 0.45f, 1.0f}, // magenta
        {0.10f, 0.45f, 0.90f, 1.0f}, // blue
        {0.95f, 0.55f, 0.00f, 1.0f}, // orange
        {0.05f, 0.60f, 0.25f, 1.0f}, // green
        {0.55f, 0.15f, 0.80f, 1.0f}, // violet
        {0.00f, 0.65f, 0.70f, 1.0f}, // cyan
        {0.80f, 0.15f, 0.10f, 1.0f}, // red
        {0.45f, 0.35f, 0.05f, 1.0f}, // brown
    }};
    const auto n = static_cast<int>(PALETTE.size());
    return PALETTE[static_cast<std::size_t>(((index % n) + n) % n)];
}

Colour bodyColour() {
    return {0.74f, 0.72f, 0.69f, 1.0f};
}

std::vector<Colour> scalarColours(const sim::VecX& values, double low, double high) {
    std::vector<Colour> out(static_cast<std::size_t>(values.size()));
    const double span = high > low ? high - low : 1.0;
    for (Eigen::Index i = 0; i < values.size(); ++i) {
        Colour& c = out[static_cast<std::size_t>(i)];
        if (!std::isfinite(values[i])) {
            c = {0.5f, 0.5f, 0.5f, 1.0f};
            continue;
        }
        const auto t = static_cast<float>(std::clamp((values[i] - low) / span, 0.0, 1.0));
        const Colour blue{0.23f, 0.30f, 0.75f, 1.0f};
        const Colour red{0.71f, 0.02f, 0.15f, 1.0f};
        const Colour& end = t < 0.5f ? blue : red;
        const float w = std::abs(2 * t - 1); // 0 at the midpoint (white), 1 at either end
        c = {1 + w * (end.r - 1), 1 + w * (end.g - 1), 1 + w * (end.b - 1), 1.0f};
    }
    return out;
}

bool parseColour(const std::string& text, Colour& out) {
    std::string s;
    for (const char ch : text) {
        s += static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    }
    if (s == "white") {
        out = {1, 1, 1, 1};
    } else if (s == "black") {
        out = {0, 0, 0, 1};
    } else if (s == "grey" || s == "gray") {
        out = {0.5f, 0.5f, 0.5f, 1};
    } else if (s == "transparent") {
        out = {0, 0, 0, 0};
    } else {
        if (!s.empty() && s.front() == '#') {
            s.erase(0, 1);
        }
        if ((s.size() != 6 && s.size() != 8) ||
            !std::all_of(s.begin(), s.end(), [](char ch) { return std::isxdigit(ch) != 0; })) {
            return false;
        }
        std::array<float, 4> c{0, 0, 0, 1};
        for (std::size_t k = 0; k < s.size() / 2; ++k) {
            c[k] = static_cast<float>(std::stoi(s.substr(2 * k, 2), nullptr, 16)) / 255.0f;
        }
        out = {c[0], c[1], c[2], c[3]};
    }
    return true;
}

} // namespace atelier::render

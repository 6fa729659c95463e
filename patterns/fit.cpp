#include "patterns/fit.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace atelier::patterns {

std::vector<PanelStrain> panelStrains(const AssembledGarment& assembled, const sim::MatX3& x) {
    std::vector<PanelStrain> out;
    const sim::SceneSpec& scene = assembled.scene;
    for (std::size_t c = 0; c < scene.cloths.size(); ++c) {
        const sim::ClothMesh& mesh = scene.cloths[c].mesh;
        const int offset = assembled.panelOffsets[c];
        PanelStrain p;
        p.panel = scene.cloths[c].name;
        double area = 0, over5 = 0, over10 = 0;
        p.maxStrain = -1;
        for (int t = 0; t < mesh.triangleCount(); ++t) {
            const int i0 = mesh.triangles(t, 0);
            const int i1 = mesh.triangles(t, 1);
            const int i2 = mesh.triangles(t, 2);
            sim::Mat2 rest;
            rest.col(0) = (mesh.rest.row(i1) - mesh.rest.row(i0)).transpose();
            rest.col(1) = (mesh.rest.row(i2) - mesh.rest.row(i0)).transpose();
            const double det = rest.determinant();
            if (!(std::abs(det) > 0)) {
                continue;
            }
            Eigen::Matrix<double, 3, 2> edges;
            edges.col(0) = (x.row(offset + i1) - x.row(offset + i0)).transpose();
            edges.col(1) = (x.row(offset + i2) - x.row(offset + i0)).transpose();
            const Eigen::Matrix<double, 3, 2> f = edges * rest.inverse();
            const sim::Mat2 cauchyGreen = f.transpose() * f;
            // Largest eigenvalue of the symmetric 2×2, in closed form.
            const double mean = 0.5 * cauchyGreen.trace();
            const double half = 0.5 * (cauchyGreen(0, 0) - cauchyGreen(1, 1));
            const double radius = std::sqrt(half * half + cauchyGreen(0, 1) * cauchyGreen(0, 1));
            const double strain = std::sqrt(std::max(mean + radius, 0.0)) - 1.0;
            const double a = 0.5 * std::abs(det);
            area += a;
            over5 += strain > 0.05 ? a : 0.0;
            over10 += strain > 0.10 ? a : 0.0;
            if (strain > p.maxStrain) {
                p.maxStrain = strain;
                p.maxHeight = (x(offset + i0, 1) + x(offset + i1, 1) + x(offset + i2, 1)) / 3.0;
            }
        }
        p.maxStrain = std::max(p.maxStrain, 0.0);
        p.over5 = area > 0 ? over5 / area : 0.0;
        p.over10 = area > 0 ? over10 / area : 0.0;
        out.push_back(std::move(p));
    }
    return out;
}

std::string_view fitName(FitLevel fit) {
    switch (fit) {
    case FitLevel::Fits:
        return "fits";
    case FitLevel::Tight:
        return "tight";
    case FitLevel::DoesNotFit:
        return "does not fit";
    }
    return "fits";
}

FitVerdict fitVerdict(const std::vector<PanelStrain>& strains,
                      const std::vector<ForcedWeld>& openSeams, int intersectingPairs,
                      int withBody) {
    FitVerdict v;
    std::vector<const PanelStrain*> order;
    for (const PanelStrain& p : strains) {
        order.push_back(&p);
    }
    std::stable_sort(order.begin(), order.end(), [](const PanelStrain* a, const PanelStrain* b) {
        return a->over10 != b->over10 ? a->over10 > b->over10 : a->over5 > b->over5;
    });
    const auto append = [&](const std::string& part) {
        v.message += (v.message.empty() ? "" : "; ") + part;
    };
    char text[256];
    for (const PanelStrain* p : order) {
        const bool over10 = p->over10 >= FIT_AREA_SHARE;
        if (!over10 && p->over5 < FIT_AREA_SHARE) {
            continue;
        }
        v.fit = over10 ? FitLevel::DoesNotFit : std::max(v.fit, FitLevel::Tight);
        std::snprintf(text, sizeof text,
                      "%s: %.1f%% of its area stretched beyond %s (up to %.0f%% at %.2f m "
                      "height)",
                      p->panel.c_str(), 100 * (over10 ? p->over10 : p->over5),
                      over10 ? "10%" : "5%", 100 * p->maxStrain, p->maxHeight);
        append(text);
    }
    for (const ForcedWeld& w : openSeams) {
        v.fit = FitLevel::DoesNotFit;
        std::snprintf(text, sizeof text, "seam %s left open (%d pairs, widest %.1f mm)",
                      w.seam.c_str(), w.pairs, 1000 * w.widest);
        append(text);
    }
    const int clothPairs = intersectingPairs - withBody;
    if (clothPairs > 0) {
        v.fit = FitLevel::DoesNotFit;
        std::snprintf(text, sizeof text, "%d intersecting triangle pairs (cloth through cloth)",
                      clothPairs);
        append(text);
    }
    if (withBody > 0) {
        v.fit = FitLevel::DoesNotFit;
        std::snprintf(text, sizeof text,
                      "%d cloth triangles intersecting the body's (cloth through the body)",
                      withBody);
        append(text);
    }
    return v;
}

double GarmentFit::largestStrain() const {
    double largest = 0;
    for (const PanelStrain& p : panels) {
        largest = std::max(largest, p.maxStrain);
    }
    return largest;
}

double GarmentFit::largestShareBeyond10() const {
    double largest = 0;
    for (const PanelStrain& p : panels) {
        largest = std::max(largest, p.over10);
    }
    return largest;
}

} // namespace atelier::patterns

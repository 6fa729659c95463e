#include "app/cli/bench_cusick.h"

#include "app/cli/commands.h"

#include "io/atomic_file.h"
#include "io/materials.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <numeric>
#include <sstream>
#include <vector>

namespace atelier::app {

namespace {

/// The draped specimen from above: its triangles in grey, the shadow's outline, the specimen's
/// and the support's circles (1 px per mm).
std::string topView(const patterns::CusickResult& r, const patterns::CusickOptions& o) {
    const double R = o.specimenDiameter / 2;
    const double scale = 1000; // px per m
    const double half = R * scale + 20;
    std::ostringstream s;
    s << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << 2 * half << "\" height=\""
      << 2 * half << "\" viewBox=\"" << -half << " " << -half << " " << 2 * half << " " << 2 * half
      << "\" font-family=\"sans-serif\" font-size=\"12\">\n";
    s << "<rect x=\"" << -half << "\" y=\"" << -half << "\" width=\"100%\" height=\"100%\" "
      << "fill=\"white\"/>\n";
    s << "<g fill=\"#c8c8d2\" stroke=\"#9a9aa8\" stroke-width=\"0.3\">\n";
    for (Eigen::Index t = 0; t < r.triangles.rows(); ++t) {
        s << "<polygon points=\"";
        for (int c = 0; c < 3; ++c) {
            const auto v = r.triangles(t, c);
            s << r.positions(v, 0) * scale << "," << r.positions(v, 2) * scale << " ";
        }
        s << "\"/>\n";
    }
    s << "</g>\n<polygon fill=\"none\" stroke=\"#1f4fa0\" stroke-width=\"1.5\" points=\"";
    for (std::size_t k = 0; k < r.radius.size(); ++k) {
        const double a = (static_cast<double>(k) + 0.5) * M_PI / 180;
        s << r.radius[k] * std::cos(a) * scale << "," << r.radius[k] * std::sin(a) * scale << " ";
    }
    s << "\"/>\n";
    for (const double d : {o.specimenDiameter, o.supportDiameter}) {
        s << "<circle r=\"" << d / 2 * scale << "\" fill=\"none\" stroke=\"#666\" "
          << "stroke-dasharray=\"4 3\"/>\n";
    }
    s << "<text x=\"" << -half + 8 << "\" y=\"" << -half + 16 << "\">drape coefficient "
      << std::fixed << std::setprecision(3) << r.drapeCoefficient << ", " << r.nodes
      << " nodes</text>\n</svg>\n";
    return s.str();
}

} // namespace

int runCusickBench(const CusickBenchOptions& options) {
    const auto& presets = io::builtinMaterialPresets();
    const auto preset = presets.find(options.fabric);
    if (preset == presets.end()) {
        std::cerr << "bench cusick: no fabric \"" << options.fabric
                  << "\" (presets: " << io::presetNames(presets) << ")\n";
        return EXIT_BAD_INPUT;
    }
    if (options.starts < 1) {
        std::cerr << "bench cusick: --starts must be at least 1\n";
        return EXIT_BAD_INPUT;
    }
    std::vector<patterns::CusickResult> results;
    std::vector<double> seconds;
    std::printf("Cusick drape of %s at %.0f mm: specimen %.0f mm on a %.0f mm disc\n",
                options.fabric.c_str(), options.test.particleDistance * 1000,
                options.test.specimenDiameter * 1000, options.test.supportDiameter * 1000);
    std::printf("%6s %10s %6s %10s %8s %8s\n", "start", "DC", "nodes", "at rest", "sim s",
                "wall s");
    for (int k = 1; k <= options.starts; ++k) {
        patterns::CusickOptions o = options.test;
        o.material = preset->second;
        o.seed = static_cast<unsigned>(k);
        const auto start = std::chrono::steady_clock::now();
        patterns::CusickResult r = patterns::runCusick(o);
        seconds.push_back(
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
        if (!r.error.empty()) {
            std::cerr << "bench cusick: start " << k << ": " << r.error << "\n";
            return EXIT_RUN_FAILED;
        }
        std::printf("%6d %10.4f %6d %10s %8.2f %8.2f\n", k, r.drapeCoefficient, r.nodes,
                    r.atRest ? "yes" : "no", r.settledTime, seconds.back());
        results.push_back(std::move(r));
    }
    std::vector<double> dc;
    for (const auto& r : results) {
        dc.push_back(r.drapeCoefficient);
    }
    const double mean = std::accumulate(dc.begin(), dc.end(), 0.0) / static_cast<double>(dc.size());
    const auto [lo, hi] = std::minmax_element(dc.begin(), dc.end());
    std::printf("drape coefficient %.4f (from %.4f to %.4f over %d starts)\n", mean, *lo, *hi,
                options.starts);
    if (options.out.empty()) {
        return EXIT_OK;
    }
    std::error_code ec;
    std::filesystem::create_directories(options.out, ec);
    const std::filesystem::path dir(options.out);
    std::ostringstream csv;
    csv << "start,drape_coefficient,nodes,at_rest,settled_time_s,wall_time_s\n";
    std::ostringstream json;
    json.precision(17);
    json << "{\n  \"fabric\": \"" << options.fabric
         << "\",\n  \"particle_distance_m\": " << options.test.particleDistance
         << ",\n  \"specimen_diameter_m\": " << options.test.specimenDiameter
         << ",\n  \"support_diameter_m\": " << options.test.supportDiameter
         << ",\n  \"drape_coefficient_mean\": " << mean << ",\n  \"drape_coefficient_min\": " << *lo
         << ",\n  \"drape_coefficient_max\": " << *hi << ",\n  \"starts\": [";
    for (std::size_t k = 0; k < results.size(); ++k) {
        const auto& r = results[k];
        csv << k + 1 << "," << r.drapeCoefficient << "," << r.nodes << "," << r.atRest << ","
            << r.settledTime << "," << seconds[k] << "\n";
        json << (k == 0 ? "\n" : ",\n") << "    {\"seed\": " << k + 1
             << ", \"drape_coefficient\": " << r.drapeCoefficient << ", \"nodes\": " << r.nodes
             << ", \"at_rest\": " << (r.atRest ? "true" : "false")
             << ", \"settled_time_s\": " << r.settledTime << "}";
    }
    json << "\n  ]\n}\n";
    for (const auto& [name, text] : {std::pair<std::string, std::string>{"cusick.csv", csv.str()},
                                     {"cusick.json", json.str()},
                                     {"cusick.svg", topView(results.front(), options.test)}}) {
        if (auto written = io::writeFileAtomically(dir / name, text); !written.ok()) {
            std::cerr << "bench cusick: " << written.error().toString() << "\n";
            return EXIT_RUN_FAILED;
        }
    }
    std::printf("wrote %s/cusick.csv, cusick.json, cusick.svg\n", options.out.c_str());
    return EXIT_OK;
}

} // namespace atelier::app

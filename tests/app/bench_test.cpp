/// `atelier-cli bench tensile` (`bench material`) and `bench work-precision`, run as a user would.

#include "io/temp_dir.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace atelier::test {

namespace {

/// Runs atelier-cli with `args` (stdout and stderr to `log`); returns its exit status.
int runCli(const std::string& args, const std::filesystem::path& log) {
    const std::string command =
        std::string("\"") + ATELIER_CLI + "\" " + args + " > \"" + log.string() + "\" 2>&1";
    const int status = std::system(command.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

struct MaterialFigures {
    double stretch = NAN;
    double poisson = NAN;
    double requestedStretch = NAN;
    double requestedPoisson = NAN;
};

MaterialFigures runMaterial(const TempDir& dir, const std::string& model, const std::string& mesh,
                            const std::string& extra = "") {
    const auto out = dir / (model + "-" + mesh + ".json");
    const auto log = dir / (model + "-" + mesh + ".log");
    const int code = runCli("bench tensile --model " + model + " --mesh " + mesh + " --out \"" +
                                out.string() + "\" " + extra,
                            log);
    EXPECT_EQ(code, 0) << readText(log);
    MaterialFigures f;
    if (code != 0) {
        return f;
    }
    const auto j = nlohmann::json::parse(readText(out));
    EXPECT_EQ(j.at("model"), model);
    EXPECT_EQ(j.at("mesh"), mesh);
    EXPECT_TRUE(j.at("converged").get<bool>());
    EXPECT_LT(j.at("residual").get<double>(), 1e-9);
    f.stretch = j.at("measured").at("stretch_n_per_m").get<double>();
    f.poisson = j.at("measured").at("poisson").get<double>();
    f.requestedStretch = j.at("requested").at("stretch_n_per_m").get<double>();
    f.requestedPoisson = j.at("requested").at("poisson").get<double>();
    return f;
}

} // namespace

class BenchMaterial : public ::testing::TestWithParam<std::string> {};

TEST_P(BenchMaterial, FemReproducesYoungsModulusAndPoissonRatio) {
    const TempDir dir;
    const std::string mesh = GetParam();
    const MaterialFigures f =
        runMaterial(dir, "fem", mesh, "--weft 3000 --warp 1500 --shear 400 --poisson 0.35");
    EXPECT_DOUBLE_EQ(f.requestedStretch, 3000);
    EXPECT_DOUBLE_EQ(f.requestedPoisson, 0.35);
    EXPECT_LT(std::abs(f.stretch / f.requestedStretch - 1.0), 0.05) << f.stretch;
    EXPECT_LT(std::abs(f.poisson - f.requestedPoisson), 0.03) << f.poisson;
}

TEST_P(BenchMaterial, FemAlongWarp) {
    const TempDir dir;
    const std::string mesh = GetParam();
    const MaterialFigures f = runMaterial(
        dir, "fem", mesh, "--direction warp --weft 3000 --warp 1500 --shear 400 --poisson 0.3");
    EXPECT_DOUBLE_EQ(f.requestedStretch, 1500);
    EXPECT_DOUBLE_EQ(f.requestedPoisson, 0.15); // nu21 = nu12 E2 / E1
    EXPECT_LT(std::abs(f.stretch / f.requestedStretch - 1.0), 0.05) << f.stretch;
    EXPECT_LT(std::abs(f.poisson - f.requestedPoisson), 0.03) << f.poisson;
}

// Past the knee the strip gives what the stiffening law says, exactly (a homogeneous strain),
// along the weft and the warp; a built-in preset's law is taken with --fabric.
TEST_P(BenchMaterial, FemStiffensAsItsLawSaysAndTakesAPresetsLaw) {
    const TempDir dir;
    const std::string mesh = GetParam();
    for (const char* direction : {"weft", "warp"}) {
        SCOPED_TRACE(direction);
        const auto out = dir / (std::string(direction) + "-law.json");
        const auto log = dir / (std::string(direction) + "-law.log");
        ASSERT_EQ(runCli("bench tensile --model fem --mesh " + mesh + " --direction " + direction +
                             " --weft 3000 --warp 1500 --shear 400 --poisson 0.3 --knee 0.03 "
                             "--weft-beyond 12000 --warp-beyond 9000 --strain 0.1 --out \"" +
                             out.string() + "\"",
                         log),
                  0)
            << readText(log);
        const auto j = nlohmann::json::parse(readText(out));
        const double strain = 0.1, green = strain + 0.5 * strain * strain;
        const bool weft = std::string(direction) == "weft";
        const double law = (1 + strain) *
                           ((weft ? 3000 : 1500) * green + (weft ? 9000 : 7500) * (green - 0.03)) /
                           strain;
        EXPECT_NEAR(j.at("law").at("stretch_n_per_m").get<double>(), law, 1e-9 * law);
        EXPECT_NEAR(j.at("measured").at("stretch_n_per_m").get<double>(), law, 1e-6 * law);
        EXPECT_EQ(j.at("material").at("knee_strain"), 0.03);
    }
    const auto out = dir / "preset.json";
    ASSERT_EQ(runCli("bench tensile --model fem --mesh " + mesh +
                         " --fabric wang-gray-interlock --direction warp --strain 0.2 --out \"" +
                         out.string() + "\"",
                     dir / "preset.log"),
              0)
        << readText(dir / "preset.log");
    const auto j = nlohmann::json::parse(readText(out));
    EXPECT_EQ(j.at("material").at("fabric"), "wang-gray-interlock");
    EXPECT_GT(j.at("material").at("knee_strain").get<double>(), 0.0);
    const double law = j.at("law").at("stretch_n_per_m").get<double>();
    EXPECT_NEAR(j.at("measured").at("stretch_n_per_m").get<double>(), law, 1e-6 * law);
    EXPECT_GT(law, 2 * j.at("requested").at("stretch_n_per_m").get<double>())
        << "the knit locks up beyond its knee";
    EXPECT_NE(runCli("bench tensile --model fem --fabric no-such-fabric", dir / "bad.log"), 0);
    EXPECT_NE(readText(dir / "bad.log").find("no built-in preset 'no-such-fabric'"),
              std::string::npos);
    EXPECT_NE(runCli("bench tensile --model fem --fabric cotton --weft 10", dir / "both.log"), 0);
}

TEST_P(BenchMaterial, FemOnTheBiasIsTheOrthotropicPlateTurnedBy45Degrees) {
    const TempDir dir;
    const std::string mesh = GetParam();
    const MaterialFigures f = runMaterial(
        dir, "fem", mesh, "--direction bias --weft 3000 --warp 1500 --shear 400 --poisson 0.3");
    // 1/E45 = (1/E1 + 1/E2 + 1/G - 2 nu12/E1)/4; nu45 = E45 (nu12/(2 E1) - (1/E1 + 1/E2 - 1/G)/4).
    const double s1 = 1.0 / 3000, s2 = 1.0 / 1500, s6 = 1.0 / 400;
    const double e45 = 4.0 / (s1 + s2 + s6 - 2 * 0.3 * s1);
    EXPECT_NEAR(f.requestedStretch, e45, 1e-9);
    EXPECT_NEAR(f.requestedPoisson, e45 * (0.15 * s1 - 0.25 * (s1 + s2 - s6)), 1e-12);
    EXPECT_LT(std::abs(f.stretch / f.requestedStretch - 1.0), 0.05) << f.stretch;
    EXPECT_LT(std::abs(f.poisson - f.requestedPoisson), 0.03) << f.poisson;
    // Much softer on the bias than along either thread: the shear carries the load.
    EXPECT_LT(f.stretch, 0.9 * 1500);
}

TEST_P(BenchMaterial, AnIsotropicPlateIsTheSameOnTheBias) {
    const TempDir dir;
    const std::string mesh = GetParam();
    // G = E / (2 (1 + nu)): isotropic, so E45 = E and nu45 = nu.
    const MaterialFigures f = runMaterial(
        dir, "fem", mesh, "--direction bias --weft 2000 --warp 2000 --shear 800 --poisson 0.25");
    EXPECT_NEAR(f.requestedStretch, 2000, 1e-9);
    EXPECT_NEAR(f.requestedPoisson, 0.25, 1e-12);
    EXPECT_LT(std::abs(f.stretch / 2000 - 1.0), 0.05) << f.stretch;
    EXPECT_LT(std::abs(f.poisson - 0.25), 0.03) << f.poisson;
}

TEST_P(BenchMaterial, SpringsAndVolinoReportFinitePositiveFigures) {
    const TempDir dir;
    const std::string mesh = GetParam();
    for (const std::string model : {"springs", "volino"}) {
        const MaterialFigures f = runMaterial(dir, model, mesh);
        EXPECT_TRUE(std::isfinite(f.stretch) && f.stretch > 0) << model << ": " << f.stretch;
        EXPECT_TRUE(std::isfinite(f.poisson) && f.poisson > 0) << model << ": " << f.poisson;
    }
}

INSTANTIATE_TEST_SUITE_P(Meshes, BenchMaterial, ::testing::Values("regular", "irregular"));

TEST(BenchMaterialCli, RejectsAnUnknownModel) {
    const TempDir dir;
    EXPECT_EQ(runCli("bench tensile --model cotton --out x.json", dir / "log"), 2);
    EXPECT_EQ(runCli("bench tensile --model fem --direction diagonal --out x.json", dir / "log"),
              2);
}

TEST(BenchMaterialCli, BenchMaterialIsTheTensileTestsFormerName) {
    const TempDir dir;
    const auto out = dir / "m.json";
    ASSERT_EQ(
        runCli("bench material --model fem --cells 4 --out \"" + out.string() + "\"", dir / "log"),
        0)
        << readText(dir / "log");
    const auto j = nlohmann::json::parse(readText(out));
    EXPECT_EQ(j.at("format"), "atelier-bench-material");
    EXPECT_EQ(j.at("direction"), "weft");
}

TEST(BenchCantileverCli, WritesTheTableAndThePlot) {
    // One coarse scene (20 mm, 5 × 3 cells): the accuracy is the slow tier's business.
    const TempDir dir;
    const auto out = dir / "cantilever";
    ASSERT_EQ(runCli("bench cantilever --ratios 8 --particle-distance 20 --mesh regular --out \"" +
                         out.string() + "\"",
                     dir / "log"),
              0)
        << readText(dir / "log");
    std::istringstream csv(readText(out / "cantilever.csv"));
    std::string header;
    std::string row;
    std::getline(csv, header);
    std::getline(csv, row);
    EXPECT_EQ(header.rfind("mesh,particle_distance_mm,ratio,", 0), 0u) << header;
    EXPECT_EQ(row.rfind("regular,20,8,", 0), 0u) << row;
    EXPECT_NE(readText(out / "cantilever.svg").find("</svg>"), std::string::npos);
}

TEST(BenchCantileverCli, RejectsBadInput) {
    const TempDir dir;
    EXPECT_EQ(runCli("bench cantilever --mesh hexagonal --out x", dir / "log"), 2);
    EXPECT_EQ(runCli("bench cantilever --ratios -1 --out x", dir / "log"), 2);
    EXPECT_EQ(runCli("bench cantilever --particle-distance 0 --out x", dir / "log"), 2);
}

namespace {

/// A small hanging sheet: 4×4 cells, two pins, gravity; a soft, lightly damped fabric so that
/// the explicit methods are stable at steps of about 1e-3 s.
constexpr const char* TINY_SCENE = R"({
  "format": "atelier-scene",
  "version": 1,
  "cloths": [
    {
      "name": "sheet",
      "mesh": {"type": "rectangle", "width": 0.4, "height": 0.4, "cells": [4, 4], "triangulation": "regular"},
      "placement": {"origin": [-0.2, 1.0, 0.0], "u_axis": [1, 0, 0], "v_axis": [0, 0, -1]},
      "material": {"preset": "cotton", "stretch_weft_n_per_m": 500, "stretch_warp_n_per_m": 500,
                   "damping_s": 0.0001},
      "model": "fem",
      "bending": true
    }
  ],
  "pins": [
    {"cloth": "sheet", "corner": "top-left"},
    {"cloth": "sheet", "corner": "top-right"}
  ],
  "gravity": true,
  "integrator": {"type": "rk45", "dt": 1e-4, "tolerance": 1e-4, "max_dt": 0.01},
  "duration": 1.0,
  "frame_rate": 30
}
)";

struct CsvRow {
    std::string integrator;
    double setting = 0;
    double wall = 0;
    long evaluations = 0;
    double rms = 0;
    double max = 0;
    bool stable = false;
};

double parseNumber(const std::string& s) {
    if (s == "nan") {
        return NAN;
    }
    std::size_t used = 0;
    const double v = std::stod(s, &used);
    EXPECT_EQ(used, s.size()) << s;
    return v;
}

std::vector<CsvRow> parseCsv(const std::string& text) {
    std::vector<CsvRow> rows;
    std::istringstream in(text);
    std::string line;
    bool header = false;
    while (std::getline(in, line)) {
        if (line.empty() || line[0] == '#') {
            continue;
        }
        if (!header) {
            EXPECT_EQ(line, "integrator,setting,wall_s,force_evaluations,rms_error_m,max_error_m,"
                            "stable");
            header = true;
            continue;
        }
        std::vector<std::string> cells;
        std::istringstream fields(line);
        for (std::string cell; std::getline(fields, cell, ',');) {
            cells.push_back(cell);
        }
        EXPECT_EQ(cells.size(), 7u) << line;
        if (cells.size() != 7) {
            continue;
        }
        CsvRow r;
        r.integrator = cells[0];
        r.setting = parseNumber(cells[1]);
        r.wall = parseNumber(cells[2]);
        r.evaluations = std::stol(cells[3]);
        r.rms = parseNumber(cells[4]);
        r.max = parseNumber(cells[5]);
        EXPECT_TRUE(cells[6] == "true" || cells[6] == "false") << line;
        r.stable = cells[6] == "true";
        rows.push_back(r);
    }
    EXPECT_TRUE(header);
    return rows;
}

} // namespace

TEST(BenchWorkPrecision, SweepsEveryIntegratorAndPlots) {
    const TempDir dir;
    const auto scene = dir.write("tiny.json", TINY_SCENE);
    const auto csv = dir / "wp.csv";
    const auto svg = dir / "wp.svg";
    const int code = runCli("bench work-precision \"" + scene.string() + "\" --out \"" +
                                csv.string() + "\" --plot \"" + svg.string() +
                                "\" --duration 0.1 --min-dt 2e-4 --min-tolerance 1e-6 --threads 1",
                            dir / "log");
    ASSERT_EQ(code, 0) << readText(dir / "log");

    const std::vector<CsvRow> rows = parseCsv(readText(csv));
    std::map<std::string, std::vector<CsvRow>> by;
    for (const CsvRow& r : rows) {
        by[r.integrator].push_back(r);
        EXPECT_GT(r.setting, 0);
        EXPECT_GE(r.wall, 0);
        EXPECT_GT(r.evaluations, 0);
        if (r.stable) {
            EXPECT_TRUE(std::isfinite(r.rms) && std::isfinite(r.max)) << r.integrator;
            EXPECT_LE(r.rms, r.max + 1e-15);
        }
    }
    for (const char* name : {"euler", "midpoint", "rk4", "rk45", "implicit-euler"}) {
        EXPECT_FALSE(by[name].empty()) << name;
    }
    // rk4: the error falls as the step falls (over its stable steps, above the reference's
    // own error).
    std::vector<CsvRow> rk4;
    for (const CsvRow& r : by["rk4"]) {
        if (r.stable) {
            rk4.push_back(r);
        }
    }
    ASSERT_GE(rk4.size(), 2u) << readText(csv);
    for (std::size_t k = 1; k < rk4.size(); ++k) {
        EXPECT_LT(rk4[k].setting, rk4[k - 1].setting);
        EXPECT_LT(rk4[k].rms, rk4[k - 1].rms + 1e-8) << "dt " << rk4[k].setting;
    }
    EXPECT_LT(rk4.back().rms, 0.1 * rk4.front().rms + 1e-8);

    const std::string plot = readText(svg);
    EXPECT_EQ(plot.rfind("<svg", 0), 0u);
    EXPECT_NE(plot.find("</svg>"), std::string::npos);
    for (const char* name : {"euler", "midpoint", "rk4", "rk45", "implicit-euler"}) {
        EXPECT_NE(plot.find(std::string(">") + name + "</text>"), std::string::npos) << name;
    }
}

TEST(BenchWorkPrecision, APlotTitleIsValidXmlWhateverTheSceneName) {
    // The title names the scene: markup escaped, a control character (invalid in XML even
    // escaped) and a byte that is not UTF-8 replaced.
    const TempDir dir;
    const auto scene = dir.write("a<b&\x01\xff.json", TINY_SCENE);
    const auto svg = dir / "wp.svg";
    const int code = runCli("bench work-precision \"" + scene.string() + "\" --out \"" +
                                (dir / "wp.csv").string() + "\" --plot \"" + svg.string() +
                                "\" --duration 0.02 --integrators rk45 --min-tolerance 1e-3",
                            dir / "log");
    ASSERT_EQ(code, 0) << readText(dir / "log");
    const std::string plot = readText(svg);
    EXPECT_NE(plot.find("a&lt;b&amp; \xEF\xBF\xBD.json"), std::string::npos) << plot.substr(0, 600);
    EXPECT_EQ(plot.find('\x01'), std::string::npos);
    EXPECT_EQ(plot.find('\xff'), std::string::npos);
}

} // namespace atelier::test

// The Cusick drape test on the engine (patterns/cusick.h), at 20 mm to stay quick: a specimen
// comes to rest hanging round its support, a limp one in folds, and a stiffer fabric (longer
// bending length (B/ρg)^⅓) drapes less than a limp one, as on a real drape tester.

#include "io/materials.h"

#include "patterns/cusick.h"

#include <gtest/gtest.h>

namespace atelier::patterns {
namespace {

CusickResult drape(const std::string& fabric, unsigned seed) {
    CusickOptions o;
    o.material = io::builtinMaterialPresets().at(fabric);
    o.particleDistance = 0.02;
    o.maxTime = 4;
    o.seed = seed;
    return runCusick(o);
}

TEST(CusickDrape, AStifferFabricDrapesLessAndALimpOneFolds) {
    const CusickResult silk = drape("silk", 1);
    const CusickResult denim = drape("denim", 1);
    for (const CusickResult* r : {&silk, &denim}) {
        ASSERT_TRUE(r->error.empty()) << r->error;
        EXPECT_TRUE(r->atRest) << "settled at " << r->settledTime << " s";
        EXPECT_TRUE(r->positions.allFinite());
        EXPECT_GT(r->drapeCoefficient, 0.0);
        EXPECT_LT(r->drapeCoefficient, 1.0);
        EXPECT_LE(r->nodes, 12);
        // Nothing hangs below the support's edge by more than the free ring's width.
        EXPECT_GT(r->positions.col(1).minCoeff(), -0.061);
    }
    EXPECT_GE(silk.nodes, 4) << "a limp fabric hangs in folds"; // 6 when measured
    EXPECT_LT(silk.drapeCoefficient + 0.05, denim.drapeCoefficient)
        << "silk " << silk.drapeCoefficient << ", denim " << denim.drapeCoefficient;
    // Another start of the same fabric gives a nearby coefficient, not the same bits.
    const CusickResult again = drape("denim", 2);
    ASSERT_TRUE(again.error.empty()) << again.error;
    EXPECT_NEAR(again.drapeCoefficient, denim.drapeCoefficient, 0.1);
}

} // namespace
} // namespace atelier::patterns

// The mannequin over a range of measurements: closed, manifold, girths within 1 cm.
#include "patterns/body_measure.h"
#include "patterns/mannequin.h"

#include <gtest/gtest.h>

namespace atelier::patterns {
namespace {

struct Case {
    const char* name;
    const char* base;
    BodyMeasurements m;
};

class MannequinRange : public ::testing::TestWithParam<Case> {};

TEST_P(MannequinRange, ClosedManifoldAndMeasured) {
    const Case& c = GetParam();
    ASSERT_TRUE(checkMeasurements(c.m).empty());
    const Mannequin m = makeMannequin(c.base, c.m);
    const MeshTopology topo = meshTopology(m.body.vertices, m.body.triangles);
    EXPECT_TRUE(topo.watertight());
    EXPECT_EQ(topo.eulerCharacteristic, 2);
    EXPECT_EQ(topo.components, 1);
    EXPECT_GT(m.body.triangles.rows(), 12000);
    EXPECT_LT(m.body.triangles.rows(), 32000);
    const auto fields = measurementFields();
    for (const auto& [name, member] : fields) {
        EXPECT_NEAR(m.measured.*member, c.m.*member, 0.01) << name;
    }
}

BodyMeasurements male() {
    BodyMeasurements m;
    baseMeasurements("male", m);
    return m;
}

BodyMeasurements with(BodyMeasurements m, double BodyMeasurements::*field, double v) {
    m.*field = v;
    return m;
}

INSTANTIATE_TEST_SUITE_P(
    Bodies, MannequinRange,
    ::testing::Values(
        Case{"female_default", "female", BodyMeasurements{}}, Case{"male_default", "male", male()},
        Case{"female_petite", "female",
             BodyMeasurements{1.52, 0.82, 0.70, 0.62, 0.86, 0.31, 0.35, 0.51, 0.25, 0.69, 0.49}},
        Case{"female_plus", "female",
             BodyMeasurements{1.70, 1.16, 0.98, 0.98, 1.20, 0.38, 0.41, 0.58, 0.36, 0.76, 0.64}},
        Case{"male_tall", "male",
             BodyMeasurements{1.95, 1.08, 0.98, 0.90, 1.04, 0.41, 0.50, 0.69, 0.33, 0.92, 0.60}},
        Case{"male_slim_long_arms", "male", with(male(), &BodyMeasurements::armLength, 0.68)}),
    [](const ::testing::TestParamInfo<Case>& info) { return std::string(info.param.name); });

} // namespace
} // namespace atelier::patterns

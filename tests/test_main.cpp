// Test entry point. In Debug builds floating-point traps are on, so a NaN produced by the
// engine fails the test where it happens (libigl's tests/main.cpp does the same).
#include <gtest/gtest.h>

#if !defined(NDEBUG) && defined(__GLIBC__)
#include <cfenv>
#endif

int main(int argc, char** argv) {
#if !defined(NDEBUG) && defined(__GLIBC__)
    feenableexcept(FE_INVALID | FE_DIVBYZERO | FE_OVERFLOW);
#endif
    ::testing::InitGoogleTest(&argc, argv);
    return RUN_ALL_TESTS();
}

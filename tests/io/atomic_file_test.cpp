#include "io/atomic_file.h"
#include "io/temp_dir.h"

#include <gtest/gtest.h>

namespace atelier::io {
namespace {

std::size_t fileCount(const std::filesystem::path& dir) {
    std::size_t n = 0;
    for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(dir)) {
        ++n;
    }
    return n;
}

TEST(AtomicFile, WritesNewFileAndLeavesNoTemporary) {
    test::TempDir dir;
    const auto path = dir / "out.txt";
    const auto written = writeFileAtomically(path, "hello\n");
    ASSERT_TRUE(written.ok()) << written.error().toString();
    EXPECT_EQ(test::readText(path), "hello\n");
    EXPECT_EQ(fileCount(dir.path()), 1U);
}

TEST(AtomicFile, ReplacesOldContent) {
    test::TempDir dir;
    const auto path = dir.write("out.txt", "an old and much longer content\n");
    ASSERT_TRUE(writeFileAtomically(path, "new").ok());
    EXPECT_EQ(test::readText(path), "new");
    ASSERT_TRUE(writeFileAtomically(path, "").ok());
    EXPECT_EQ(test::readText(path), "");
    EXPECT_EQ(fileCount(dir.path()), 1U);
}

TEST(AtomicFile, FailureNamesTheFileAndKeepsNothing) {
    test::TempDir dir;
    const auto path = dir / "missing-dir" / "out.txt";
    const auto written = writeFileAtomically(path, "x");
    ASSERT_FALSE(written.ok());
    EXPECT_EQ(written.error().file, path.string());
    EXPECT_FALSE(written.error().message.empty());
    EXPECT_EQ(fileCount(dir.path()), 0U);
}

TEST(AtomicFile, ReadFileRoundTrip) {
    test::TempDir dir;
    const std::string binary("a\0b\nc", 5);
    ASSERT_TRUE(writeFileAtomically(dir / "bin", binary).ok());
    const auto read = readFile(dir / "bin");
    ASSERT_TRUE(read.ok());
    EXPECT_EQ(read.value(), binary);
    EXPECT_FALSE(readFile(dir / "nope").ok());
}

TEST(ErrorMessage, JoinsNonEmptyParts) {
    EXPECT_EQ((Error{"shirt.json", "/panels/3", "bad"}).toString(), "shirt.json: /panels/3: bad");
    EXPECT_EQ((Error{"shirt.json", "", "bad"}).toString(), "shirt.json: bad");
}

} // namespace
} // namespace atelier::io

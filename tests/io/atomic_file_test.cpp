#include "io/atomic_file.h"
#include "io/temp_dir.h"

#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

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

TEST(AtomicFile, AFailedRenameLeavesNoTemporary) {
    test::TempDir dir;
    std::filesystem::create_directory(dir / "taken");
    ASSERT_FALSE(writeFileAtomically(dir / "taken", "x").ok()); // a folder is in the way
    EXPECT_EQ(fileCount(dir.path()), 1U);
}

TEST(AtomicFile, RemovesTemporariesOfKilledWritersOnly) {
    test::TempDir dir;
    const pid_t gone = ::fork(); // a process that has ended: its pid names no process
    if (gone == 0) {
        ::_exit(0);
    }
    ASSERT_GT(gone, 0);
    ::waitpid(gone, nullptr, 0);
    const std::string dead = ".out.obj.tmp-" + std::to_string(gone) + "-abcdef";
    const std::string alive = ".out.obj.tmp-" + std::to_string(::getppid()) + "-abcdef";
    const std::string other = ".other.obj.tmp-" + std::to_string(gone) + "-abcdef";
    for (const std::string& name : {dead, alive, other}) {
        dir.write(name, "half a mesh");
    }
    ASSERT_TRUE(writeFileAtomically(dir / "out.obj", "mesh").ok());
    EXPECT_FALSE(std::filesystem::exists(dir / dead));
    EXPECT_TRUE(std::filesystem::exists(dir / alive)); // its writer may still be at work
    EXPECT_TRUE(std::filesystem::exists(dir / other)); // another file's
    EXPECT_EQ(fileCount(dir.path()), 3U);
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

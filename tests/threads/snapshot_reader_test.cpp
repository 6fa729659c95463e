// A window's view of a drape: a reader thread copies snapshots while the session drapes the
// 20 mm tshirt on the pool's threads. Under ThreadSanitizer (the tsan preset) this is the race
// check; everywhere it checks that no snapshot is torn: each one's normals are those of its
// own positions, and versions only grow.

#include "io/body_file.h"
#include "io/project_file.h"

#include "patterns/drape_session.h"

#include "sim/core/parallel.h"
#include "sim/mesh/vertex_normals.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <thread>

namespace atelier {
namespace {

const std::filesystem::path TSHIRT =
    std::filesystem::path(ATELIER_SOURCE_DIR) / "assets/garments/tshirt.atelier";

TEST(SnapshotReader, ReaderThreadSeesWholeSnapshotsWhileTheTshirtDrapes) {
    auto loaded = io::loadProject(TSHIRT);
    ASSERT_TRUE(loaded.ok()) << loaded.error().toString();
    patterns::Project project = std::move(loaded).value();
    project.drape.particleDistance = 0.02;
    project.drape.timeLimit = 0.25; // sewing and the first fall: hundreds of published steps
    const std::filesystem::path dir = TSHIRT.parent_path();
    patterns::DrapeSession session(
        [&](const patterns::BodySource& source) { return io::loadBody(source, dir, TSHIRT); });
    session.setProject(project);
    ASSERT_TRUE(session.prepare().ok());
    session.setPublishing(true);
    const sim::MatX3i triangles = session.simulation()->clothTriangles();
    const int threads = sim::threadCount();
    sim::setThreadCount(2);

    std::atomic<bool> done{false};
    long reads = 0, torn = 0, backwards = 0;
    std::uint64_t lastVersion = 0;
    sim::Snapshot last;
    std::thread reader([&] {
        sim::Snapshot snap;
        sim::MatX3 normals;
        while (!done.load()) {
            if (session.snapshots().read(snap)) {
                ++reads;
                backwards += snap.version < lastVersion ? 1 : 0;
                lastVersion = snap.version;
                sim::vertexNormals(snap.clothPositions, triangles, normals);
                torn += (normals.rows() != snap.clothNormals.rows() ||
                         std::memcmp(normals.data(), snap.clothNormals.data(),
                                     sizeof(double) * normals.size()) != 0)
                            ? 1
                            : 0;
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
        }
        ASSERT_TRUE(session.snapshots().read(last));
    });
    const patterns::DrapeStatus status = session.runUntil();
    done = true;
    reader.join();
    sim::setThreadCount(threads);

    EXPECT_EQ(status, patterns::DrapeStatus::TimeLimit);
    EXPECT_GT(reads, 10);
    EXPECT_EQ(torn, 0);
    EXPECT_EQ(backwards, 0);
    // The last snapshot is the final state.
    EXPECT_EQ(last.steps, session.simulation()->stats().steps);
    EXPECT_EQ(std::memcmp(last.clothPositions.data(), session.positions().data(),
                          sizeof(double) * session.positions().size()),
              0);
    ASSERT_EQ(last.obstaclePositions.size(), 1u);
    EXPECT_EQ(last.obstaclePositions[0].rows(), session.body().vertices.rows());
}

} // namespace
} // namespace atelier

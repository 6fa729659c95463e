/// Touching a simulation between steps (grabs, pins, obstacle poses) and publishing snapshots
/// for other threads.

#include "sim/collision/obstacle.h"
#include "sim/constraints/kinematic.h"
#include "sim/mesh/vertex_normals.h"
#include "sim/simulation.h"
#include "sim/simulation_impl.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <atomic>

namespace atelier::sim {

namespace {
/// Versions of obstacle positions, unique across simulations (a snapshot buffer outlives the
/// simulations that publish into it).
std::atomic<std::uint64_t> g_obstacleVersions{0};
std::atomic<int> g_grabIds{0};
} // namespace

void Simulation::Impl::settlePosedObstacles() {
    for (auto it = posedObstacles.begin(); it != posedObstacles.end();) {
        ObstacleSpec& o = scene.obstacles[static_cast<std::size_t>(*it)];
        if (t < o.frameTimes.back() - 1e-12) {
            ++it;
            continue;
        }
        // Arrived: static again where it is (one frame), so its hierarchy and hull are fitted
        // once more and snapshots stop re-sending it.
        o.frames.erase(o.frames.begin(), o.frames.end() - 1);
        o.frameTimes.erase(o.frameTimes.begin(), o.frameTimes.end() - 1);
        collision->obstacleMotionChanged(static_cast<std::size_t>(*it));
        obstacleVersion.resize(std::max(obstacleVersion.size(), scene.obstacles.size()), 0);
        obstacleVersion[static_cast<std::size_t>(*it)] = ++g_obstacleVersions;
        it = posedObstacles.erase(it);
    }
}

const MatX3i& Simulation::Impl::globalTriangles() {
    if (clothTriangles.rows() == 0) {
        Eigen::Index count = 0;
        for (const ClothSpec& c : scene.cloths) {
            count += c.mesh.triangles.rows();
        }
        clothTriangles.resize(count, 3);
        Eigen::Index row = 0;
        for (std::size_t c = 0; c < scene.cloths.size(); ++c) {
            const MatX3i& f = scene.cloths[c].mesh.triangles;
            clothTriangles.middleRows(row, f.rows()) = f.array() + offsets[c];
            row += f.rows();
        }
    }
    return clothTriangles;
}

void Simulation::Impl::publishSnapshot() {
    Snapshot& s = snapshots->back();
    s.time = t;
    s.steps = stats.steps;
    s.wallTime = stats.wallTime;
    s.kineticEnergy = 0.5 * (mass.array() * v.rowwise().squaredNorm().array()).sum();
    s.contacts = stats.contacts;
    s.clothPositions = x;
    vertexNormals(x, globalTriangles(), s.clothNormals);
    const std::size_t obstacles = collision ? scene.obstacles.size() : 0;
    while (obstacleVersion.size() < obstacles) {
        obstacleVersion.push_back(++g_obstacleVersions);
    }
    normalVersion.resize(obstacles, 0);
    obstacleNormals.resize(obstacles);
    s.obstaclePositions.resize(obstacles);
    s.obstacleNormals.resize(obstacles);
    s.obstacleVersions.resize(obstacles, 0);
    for (std::size_t k = 0; k < obstacles; ++k) {
        if (collision->obstacleMoving(k) && publishedStep != stats.steps) {
            obstacleVersion[k] = ++g_obstacleVersions; // it may have moved in the step
        }
        if (s.obstacleVersions[k] == obstacleVersion[k]) {
            continue; // this slot holds them already
        }
        const MatX3& ox = collision->obstaclePositions(static_cast<int>(k));
        if (normalVersion[k] != obstacleVersion[k]) {
            vertexNormals(ox, scene.obstacles[k].triangles, obstacleNormals[k]);
            normalVersion[k] = obstacleVersion[k];
        }
        s.obstaclePositions[k] = ox;
        s.obstacleNormals[k] = obstacleNormals[k];
        s.obstacleVersions[k] = obstacleVersion[k];
    }
    publishedStep = stats.steps;
    snapshots->publish();
}

const MatX3i& Simulation::clothTriangles() const {
    return m_impl->globalTriangles();
}

void Simulation::publishTo(SnapshotBuffer* buffer) {
    m_impl->snapshots = buffer;
    if (buffer != nullptr && !m_impl->failed) {
        m_impl->publishSnapshot();
    }
}

int Simulation::grab(const ClothPoint& point, const Vec3& target, double timeConstant) {
    Impl& s = *m_impl;
    if (s.failed) {
        return 0;
    }
    const MatX3i& triangles = s.globalTriangles();
    if (point.triangle < 0 || point.triangle >= triangles.rows() || !(timeConstant > 0) ||
        !std::isfinite(timeConstant) || !target.allFinite() || !point.barycentric.allFinite()) {
        return 0;
    }
    Vec3 p = Vec3::Zero();
    for (int k = 0; k < 3; ++k) {
        p += point.barycentric[k] * s.x.row(triangles(point.triangle, k)).transpose();
    }
    detail::Grab g;
    bool any = false;
    for (int k = 0; k < 3; ++k) {
        const int vertex = triangles(point.triangle, k);
        const int d = s.driveOf[static_cast<std::size_t>(vertex)];
        const bool driven = d >= 0 && driveActive(s.scene.drives[static_cast<std::size_t>(d)], s.t);
        if (s.pinned[static_cast<std::size_t>(vertex)] || driven) {
            continue; // held already: the grab leaves it to its pin or drive
        }
        g.vertices[static_cast<std::size_t>(k)] = vertex;
        g.offsets[static_cast<std::size_t>(k)] = s.x.row(vertex).transpose() - p;
        Drive drive;
        drive.vertex = vertex;
        drive.times = {s.t};
        drive.positions = {target + g.offsets[static_cast<std::size_t>(k)]};
        drive.followTimeConstant = timeConstant;
        s.driveOf[static_cast<std::size_t>(vertex)] = static_cast<int>(s.scene.drives.size());
        s.scene.drives.push_back(std::move(drive));
        any = true;
    }
    if (!any) {
        return 0;
    }
    g.id = ++g_grabIds; // unique across simulations: a stale handle never finds another grab
    s.grabs.push_back(g);
    s.updateHeld();
    return g.id;
}

bool Simulation::moveGrab(int handle, const Vec3& target) {
    Impl& s = *m_impl;
    const auto it = std::find_if(s.grabs.begin(), s.grabs.end(),
                                 [&](const detail::Grab& g) { return g.id == handle; });
    if (it == s.grabs.end() || !target.allFinite()) {
        return false;
    }
    for (std::size_t k = 0; k < 3; ++k) {
        if (it->vertices[k] >= 0) {
            const int d = s.driveOf[static_cast<std::size_t>(it->vertices[k])];
            s.scene.drives[static_cast<std::size_t>(d)].positions.front() = target + it->offsets[k];
        }
    }
    return true;
}

bool Simulation::release(int handle) {
    Impl& s = *m_impl;
    const auto it = std::find_if(s.grabs.begin(), s.grabs.end(),
                                 [&](const detail::Grab& g) { return g.id == handle; });
    if (it == s.grabs.end()) {
        return false;
    }
    std::vector<int> drives;
    for (int vertex : it->vertices) {
        if (vertex >= 0) {
            drives.push_back(s.driveOf[static_cast<std::size_t>(vertex)]);
        }
    }
    std::sort(drives.rbegin(), drives.rend());
    for (int d : drives) {
        s.scene.drives.erase(s.scene.drives.begin() + d);
    }
    s.grabs.erase(it);
    // Drive indices after the erased ones moved down: map every vertex to its drive again.
    std::fill(s.driveOf.begin(), s.driveOf.end(), -1);
    for (std::size_t d = 0; d < s.scene.drives.size(); ++d) {
        s.driveOf[static_cast<std::size_t>(s.scene.drives[d].vertex)] = static_cast<int>(d);
    }
    s.updateHeld();
    return true;
}

bool Simulation::pin(int vertex) {
    Impl& s = *m_impl;
    if (vertex < 0 || vertex >= s.n || s.pinned[static_cast<std::size_t>(vertex)]) {
        return false;
    }
    s.pinned[static_cast<std::size_t>(vertex)] = 1;
    s.scene.pins.push_back(vertex);
    s.pinPosition.row(vertex) = s.x.row(vertex);
    s.updateHeld();
    return true;
}

bool Simulation::unpin(int vertex) {
    Impl& s = *m_impl;
    if (!pinned(vertex)) {
        return false;
    }
    s.pinned[static_cast<std::size_t>(vertex)] = 0;
    std::erase(s.scene.pins, vertex); // a scene may list a vertex twice
    s.updateHeld();
    return true;
}

int Simulation::grabCount() const {
    return static_cast<int>(m_impl->grabs.size());
}

bool Simulation::pinned(int vertex) const {
    const Impl& s = *m_impl;
    return vertex >= 0 && vertex < s.n && s.pinned[static_cast<std::size_t>(vertex)] != 0;
}

bool Simulation::setObstacleFrame(int k, const MatX3& world, double duration) {
    Impl& s = *m_impl;
    if (!s.collision || k < 0 || k >= static_cast<int>(s.scene.obstacles.size())) {
        return false;
    }
    ObstacleSpec& o = s.scene.obstacles[static_cast<std::size_t>(k)];
    if (world.rows() != o.vertices.rows() || !world.allFinite() || !std::isfinite(duration)) {
        return false;
    }
    // From where it is now to the new positions over the next step(s): a frame is a path
    // event, so a step ends on it, and the swept detection sees the whole motion.
    const double reach = duration > 0 ? duration : s.dtNext;
    o.frameTimes = {s.t, s.t + reach};
    o.frames = {s.collision->obstaclePositions(k), world};
    o.keys.clear();
    s.collision->obstacleMotionChanged(static_cast<std::size_t>(k));
    s.posedObstacles.push_back(k);
    return true;
}

bool Simulation::setObstaclePose(int k, const Vec3& translation, const Vec3& rotation,
                                 double duration) {
    Impl& s = *m_impl;
    if (k < 0 || k >= static_cast<int>(s.scene.obstacles.size()) || !translation.allFinite() ||
        !rotation.allFinite()) {
        return false;
    }
    const MatX3& local = s.scene.obstacles[static_cast<std::size_t>(k)].vertices;
    const double angle = rotation.norm();
    const Mat3 r = angle > 0 ? Mat3(Eigen::AngleAxisd(angle, rotation / angle).toRotationMatrix())
                             : Mat3(Mat3::Identity());
    MatX3 world(local.rows(), 3);
    for (Eigen::Index i = 0; i < local.rows(); ++i) {
        world.row(i) = (r * local.row(i).transpose() + translation).transpose();
    }
    return setObstacleFrame(k, world, duration);
}

} // namespace atelier::sim

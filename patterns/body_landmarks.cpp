#include "patterns/body_landmarks.h"

#include "patterns/body_measure.h"
#include "patterns/curve.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>

namespace atelier::patterns {

using sim::Vec2;
using sim::Vec3;

namespace {

/// One loop of a horizontal section in the body's frame: (x, z) points, its area and centroid.
struct SectionLoop {
    std::vector<Vec2> points;
    double area = 0;
    Vec2 centroid = Vec2::Zero();
    double minX = 0, maxX = 0;

    bool contains(const Vec2& q) const { return insidePolygon(points, q); }
};

/// Horizontal sections of the body in its own frame (x left, z facing, torso axis at 0).
class Sections {
  public:
    Sections(const sim::MatX3& local, const sim::MatX3i& triangles) : m_x(local), m_f(triangles) {}

    std::vector<SectionLoop> at(double y) const {
        std::vector<SectionLoop> loops;
        for (const auto& raw : planeSection(m_x, m_f, Vec3(0, y, 0), Vec3::UnitY())) {
            if (raw.size() < 3) {
                continue;
            }
            SectionLoop loop;
            loop.minX = std::numeric_limits<double>::infinity();
            loop.maxX = -loop.minX;
            for (const Vec3& p : raw) {
                loop.points.emplace_back(p.x(), p.z());
                loop.minX = std::min(loop.minX, p.x());
                loop.maxX = std::max(loop.maxX, p.x());
            }
            double a2 = 0;
            Vec2 c = Vec2::Zero();
            const auto& q = loop.points;
            for (std::size_t i = 0, j = q.size() - 1; i < q.size(); j = i++) {
                const double w = q[j].x() * q[i].y() - q[i].x() * q[j].y();
                a2 += w;
                c += w * (q[j] + q[i]);
            }
            loop.area = std::abs(a2) / 2;
            loop.centroid = std::abs(a2) > 1e-18 ? Vec2(c / (3 * a2)) : q.front();
            loops.push_back(std::move(loop));
        }
        return loops;
    }

    /// The smallest loop at y enclosing the torso's axis (x = z = 0), if any.
    std::optional<SectionLoop> torso(double y) const {
        std::optional<SectionLoop> best;
        for (SectionLoop& loop : at(y)) {
            if (loop.contains(Vec2::Zero()) && (!best || loop.area < best->area)) {
                best = std::move(loop);
            }
        }
        return best;
    }

    /// Tape girth round the torso's axis at y (0 where no loop encloses it) [m].
    double girth(double y) const {
        return tapeGirth(m_x, m_f, Vec3(0, y, 0), Vec3::UnitY()).value_or(0.0);
    }

  private:
    const sim::MatX3& m_x;
    const sim::MatX3i& m_f;
};

/// The y in [lo, hi] (steps of `step`) where `value` is largest (sign +1) or smallest (−1),
/// skipping levels where it is 0 (no section).
double extremum(const std::function<double(double)>& value, double lo, double hi, double step,
                double sign, double& best) {
    double where = 0.5 * (lo + hi);
    best = 0;
    bool found = false;
    for (double y = lo; y <= hi + 1e-12; y += step) {
        const double v = value(y);
        if (v > 0 && (!found || sign * v > sign * best)) {
            best = v;
            where = y;
            found = true;
        }
    }
    return where;
}

} // namespace

std::variant<FoundLandmarks, std::string> findLandmarks(const sim::MatX3& vertices,
                                                        const sim::MatX3i& triangles) {
    const sim::MatX3& x = vertices;
    if (x.rows() < 100 || triangles.rows() < 100) {
        return std::string("a body mesh needs at least 100 vertices and triangles");
    }
    BodyLandmarks L;
    L.floorY = x.col(1).minCoeff();
    const double H = x.col(1).maxCoeff() - L.floorY;
    L.height = H;
    if (!(H > 0.5 && H < 3.0)) {
        return "a body mesh must be 0.5–3 m tall, Y up, in metres (found " + std::to_string(H) +
               " m)";
    }
    const double y0 = L.floorY;
    // Left–right is the widest horizontal direction of the legs and hips (principal
    // components of their vertices); the feet point forward from the shins.
    Vec2 mean = Vec2::Zero();
    int n = 0;
    for (Eigen::Index v = 0; v < x.rows(); ++v) {
        if (x(v, 1) > y0 + 0.3 * H && x(v, 1) < y0 + 0.55 * H) {
            mean += Vec2(x(v, 0), x(v, 2));
            ++n;
        }
    }
    if (n < 10) {
        return std::string("no vertices between the knees and the hips");
    }
    mean /= n;
    sim::Mat2 cov = sim::Mat2::Zero();
    Vec3 feet = Vec3::Zero();
    Vec3 shins = Vec3::Zero();
    int nFeet = 0;
    int nShins = 0;
    for (Eigen::Index v = 0; v < x.rows(); ++v) {
        const double y = x(v, 1) - y0;
        if (y > 0.3 * H && y < 0.55 * H) {
            const Vec2 d = Vec2(x(v, 0), x(v, 2)) - mean;
            cov += d * d.transpose();
        } else if (y < 0.03 * H) {
            feet += Vec3(x.row(v));
            ++nFeet;
        } else if (y > 0.06 * H && y < 0.1 * H) {
            shins += Vec3(x.row(v));
            ++nShins;
        }
    }
    if (nFeet == 0 || nShins == 0) {
        return std::string("cannot find the feet and shins (expected a standing figure)");
    }
    const Eigen::SelfAdjointEigenSolver<sim::Mat2> eig(cov);
    const Vec2 across = eig.eigenvectors().col(1);
    const Vec3 facing(-across.y(), 0, across.x());
    // Where the feet point neither way (a dress form's stand), the body files' convention
    // decides: facing +z.
    const double toes = (feet / nFeet - shins / nShins).dot(facing);
    const double sign = std::abs(toes) >= 0.005 * H ? toes : facing.z();
    L.facing = sign >= 0 ? facing : Vec3(-facing);
    L.left = Vec3::UnitY().cross(L.facing);

    // The torso's axis: the centroid of the largest section loop at 0.6 H (the pelvis, above
    // the crotch, beside the hands).
    L.centre = Vec3(mean.x(), 0, mean.y());
    sim::MatX3 local(x.rows(), 3);
    auto toLocal = [&]() {
        for (Eigen::Index v = 0; v < x.rows(); ++v) {
            local.row(v) = L.toLocal(x.row(v)).transpose();
        }
    };
    toLocal();
    {
        const Sections sections(local, triangles);
        const std::vector<SectionLoop> loops = sections.at(y0 + 0.6 * H);
        const SectionLoop* pelvis = nullptr;
        for (const SectionLoop& loop : loops) {
            if (pelvis == nullptr || loop.area > pelvis->area) {
                pelvis = &loop;
            }
        }
        if (pelvis == nullptr) {
            return std::string("nothing at 0.6 of the height to take for the pelvis (expected "
                               "a standing figure)");
        }
        L.centre = L.toWorld(Vec3(pelvis->centroid.x(), 0, pelvis->centroid.y()));
        L.centre.y() = y0 + 0.6 * H;
    }
    toLocal();
    const Sections sections(local, triangles);

    // Crotch: going down from the pelvis, the last level whose section encloses the axis.
    const double fine = 0.0005 * H;
    {
        double y = y0 + 0.6 * H;
        if (!sections.torso(y)) {
            return std::string("the section at 0.6 of the height does not enclose its centroid "
                               "(expected a standing figure)");
        }
        const double coarse = 0.005 * H;
        while (y > y0 + 0.2 * H && sections.torso(y - coarse)) {
            y -= coarse;
        }
        while (sections.torso(y - fine)) {
            y -= fine;
        }
        if (y <= y0 + 0.2 * H) {
            return std::string("cannot find the crotch (the legs' sections never part)");
        }
        L.crotchY = y;
    }

    // Armpits: going up from 3% of the height above the crotch, where the torso's section suddenly
    // widens on a side (an arm's loop joining it); below it, the torso's half-width on that side.
    const double step = 0.005 * H;
    std::vector<double> levels;
    std::array<std::vector<double>, 2> halfWidth;
    std::array<bool, 2> joined{false, false};
    for (double y = L.crotchY + 0.03 * H; y < y0 + 0.95 * H && !(joined[0] && joined[1]);
         y += step) {
        const std::optional<SectionLoop> loop = sections.torso(y);
        if (!loop) {
            return "the torso's section is lost at " + std::to_string(y - y0) + " m";
        }
        const std::array<double, 2> ext{loop->maxX, -loop->minX};
        for (std::size_t s = 0; s < 2; ++s) {
            if (joined[s]) {
                continue;
            }
            if (!halfWidth[s].empty() && ext[s] - halfWidth[s].back() > 0.02 * H) {
                joined[s] = true;
                L.armpitY[s] = y;
            } else {
                halfWidth[s].push_back(ext[s]);
            }
        }
        if (!(joined[0] && joined[1])) {
            levels.push_back(y);
        }
    }
    if (!(joined[0] && joined[1])) {
        return std::string("cannot find where the arms join the torso (expected arms away from "
                           "the torso, A-pose to T-pose)");
    }
    auto torsoHalfWidth = [&](std::size_t s, double y) {
        const auto& w = halfWidth[s];
        const double u = (y - levels.front()) / step;
        if (u <= 0) {
            return w.front();
        }
        const auto k = static_cast<std::size_t>(u);
        if (k + 1 >= w.size()) {
            return w.back();
        }
        const double f = u - static_cast<double>(k);
        return (1 - f) * w[k] + f * w[k + 1];
    };
    L.shoulderHalfWidth = std::max(halfWidth[0].back(), halfWidth[1].back());

    // Parts: below the crotch the legs; beyond the torso's half-width (on a side, from the
    // armpit up its width there) the arms, and what hangs from them below the crotch (hands in
    // A-pose: reached from an arm's vertices through the mesh's edges without crossing the
    // torso); the rest the torso with neck and head.
    std::vector<int> part(static_cast<std::size_t>(x.rows()), 0);
    const double armFloor = L.crotchY + 0.03 * H;
    for (Eigen::Index v = 0; v < x.rows(); ++v) {
        const Vec3 p = local.row(v);
        const int s = p.x() >= 0 ? 0 : 1;
        int label = 0;
        if (p.y() < L.crotchY) {
            label = 3 + s;
        } else if (p.y() > armFloor &&
                   std::abs(p.x()) >
                       torsoHalfWidth(static_cast<std::size_t>(s), p.y()) + 0.01 * H) {
            label = 1 + s;
        }
        part[static_cast<std::size_t>(v)] = label;
    }
    {
        std::vector<std::vector<int>> next(static_cast<std::size_t>(x.rows()));
        for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
            for (int k = 0; k < 3; ++k) {
                const int a = triangles(t, k);
                const int b = triangles(t, (k + 1) % 3);
                next[static_cast<std::size_t>(a)].push_back(b);
                next[static_cast<std::size_t>(b)].push_back(a);
            }
        }
        std::vector<int> queue;
        for (Eigen::Index v = 0; v < x.rows(); ++v) {
            if (part[static_cast<std::size_t>(v)] == 1 || part[static_cast<std::size_t>(v)] == 2) {
                queue.push_back(static_cast<int>(v));
            }
        }
        while (!queue.empty()) {
            const int v = queue.back();
            queue.pop_back();
            for (const int w : next[static_cast<std::size_t>(v)]) {
                int& label = part[static_cast<std::size_t>(w)];
                if (local(w, 1) <= armFloor && label != 1 && label != 2) {
                    label = part[static_cast<std::size_t>(v)];
                    queue.push_back(w);
                }
            }
        }
    }
    std::array<std::vector<Vec3>, 4> limbs; // arm l, arm r, leg l, leg r
    for (Eigen::Index v = 0; v < x.rows(); ++v) {
        if (const int label = part[static_cast<std::size_t>(v)]; label > 0) {
            limbs[static_cast<std::size_t>(label - 1)].push_back(local.row(v));
        }
    }

    // Arm axes: principal components of each arm's vertices, pointing toward the torso.
    std::array<Vec3, 2> jointLocal;
    std::array<double, 2> armLength{};
    for (std::size_t s = 0; s < 2; ++s) {
        const auto& arm = limbs[s];
        if (arm.size() < 10 || limbs[2 + s].size() < 10) {
            return std::string("cannot find the ") + (s == 0 ? "left" : "right") +
                   " arm and leg (expected a standing figure, arms away from the torso)";
        }
        Vec3 m = Vec3::Zero();
        for (const Vec3& p : arm) {
            m += p;
        }
        m /= static_cast<double>(arm.size());
        sim::Mat3 c = sim::Mat3::Zero();
        for (const Vec3& p : arm) {
            c += (p - m) * (p - m).transpose();
        }
        const Eigen::SelfAdjointEigenSolver<sim::Mat3> e(c);
        Vec3 axis = e.eigenvectors().col(2);
        if (axis.dot(Vec3(0, L.armpitY[s], 0) - m) < 0) {
            axis = -axis;
        }
        double top = -std::numeric_limits<double>::infinity();
        double bottom = std::numeric_limits<double>::infinity();
        for (const Vec3& p : arm) {
            top = std::max(top, (p - m).dot(axis));
            bottom = std::min(bottom, (p - m).dot(axis));
        }
        // The upper arm's own axis (an elbow bent forward, as the MakeHuman body's is by 25°,
        // tilts the whole arm's): a line through the centroids of the arm's 5% slices across
        // that axis from 10% to 40% of its length below the shoulder (below the shoulder's
        // cap, above the elbow).
        const double length = top - bottom;
        std::array<Vec3, 20> sum;
        sum.fill(Vec3::Zero());
        std::array<int, 20> count{};
        for (const Vec3& p : arm) {
            const double t = (top - (p - m).dot(axis)) / length;
            const auto k = static_cast<std::size_t>(std::clamp(t * 20, 0.0, 19.0));
            sum[k] += p;
            ++count[k];
        }
        std::vector<Vec3> centres;
        for (std::size_t k = 2; k < 8; ++k) {
            if (count[k] > 0) {
                centres.push_back(sum[k] / count[k]);
            }
        }
        if (centres.size() >= 3) {
            Vec3 um = Vec3::Zero();
            for (const Vec3& c : centres) {
                um += c;
            }
            um /= static_cast<double>(centres.size());
            sim::Mat3 cu = sim::Mat3::Zero();
            for (const Vec3& c : centres) {
                cu += (c - um) * (c - um).transpose();
            }
            const Eigen::SelfAdjointEigenSolver<sim::Mat3> eu(cu);
            Vec3 upperAxis = eu.eigenvectors().col(2);
            if (upperAxis.dot(axis) < 0) {
                upperAxis = -upperAxis;
            }
            top = -std::numeric_limits<double>::infinity();
            for (const Vec3& p : arm) {
                top = std::max(top, (p - um).dot(upperAxis));
            }
            m = um;
            axis = upperAxis;
            bottom = top - length;
        }
        jointLocal[s] = m + top * axis;
        armLength[s] = top - bottom;
        L.shoulderJoint[s] = L.toWorld(jointLocal[s]);
        L.wrist[s] = L.toWorld(m + bottom * axis);
        L.armAxis[s] = L.directionToWorld(axis);
        // Upper arm: a quarter of the way from the shoulder, across the axis.
        const Vec3 upper = L.toWorld(jointLocal[s] - 0.265 * armLength[s] * axis);
        L.upperArm[s] = tapeGirth(x, triangles, upper, L.armAxis[s]).value_or(0.0);
    }

    // Shoulders: the top of the surface right above the armpits.
    double shoulder = 0;
    for (std::size_t s = 0; s < 2; ++s) {
        const double w = halfWidth[s].back();
        double top = L.armpitY[s];
        for (Eigen::Index v = 0; v < x.rows(); ++v) {
            if (std::abs(std::abs(local(v, 0)) - w) < 0.01 * H && (local(v, 0) >= 0) == (s == 0) &&
                local(v, 1) > L.armpitY[s]) {
                top = std::max(top, local(v, 1));
            }
        }
        shoulder += 0.5 * top;
    }
    L.shoulderY = shoulder;

    // Girths round the torso's axis.
    const auto girth = [&](double y) { return sections.girth(y); };
    const double armpit = std::min(L.armpitY[0], L.armpitY[1]);
    const double span = armpit - L.crotchY;
    const double gstep = 0.0025 * H;
    L.hipY = extremum(girth, L.crotchY + 0.01 * H, L.crotchY + 0.35 * span, gstep, 1, L.hip);
    L.waistY = extremum(girth, L.crotchY + 0.3 * span, L.crotchY + 0.85 * span, gstep, -1, L.waist);
    L.bustY = extremum(girth, L.waistY, armpit - 0.01 * H, gstep, 1, L.bust);
    const double top = y0 + H;
    L.neckY =
        extremum(girth, L.shoulderY, L.shoulderY + 0.5 * (top - L.shoulderY), gstep, -1, L.neck);
    L.neckBaseY = L.neckY;
    while (L.neckBaseY > L.shoulderY && girth(L.neckBaseY) < 1.2 * L.neck) {
        L.neckBaseY -= gstep;
    }

    // Legs: each one's vertices' centroid; its section's centre below the crotch and near the
    // floor.
    for (std::size_t s = 0; s < 2; ++s) {
        const double sx = s == 0 ? 1.0 : -1.0;
        auto legCentre = [&](double y) -> std::optional<Vec3> {
            const SectionLoop* best = nullptr;
            const std::vector<SectionLoop> loops = sections.at(y);
            for (const SectionLoop& loop : loops) {
                if (sx * loop.centroid.x() > 0 && (best == nullptr || loop.area > best->area)) {
                    best = &loop;
                }
            }
            if (best == nullptr) {
                return std::nullopt;
            }
            return L.toWorld(Vec3(best->centroid.x(), y, best->centroid.y()));
        };
        const auto thigh = legCentre(L.crotchY - 0.035 * H);
        const auto ankle = legCentre(y0 + 0.06 * H);
        if (!thigh || !ankle) {
            return std::string("cannot find the ") + (s == 0 ? "left" : "right") +
                   " leg's sections";
        }
        L.thighPoint[s] = *thigh;
        // The hip joint: above the thigh's centre, at the crotch (a leg's vertices are mostly
        // its foot's on a scan, so their centroid is not the leg's).
        L.hipJoint[s] = Vec3(thigh->x(), L.crotchY, thigh->z());
        L.ankle[s] = *ankle;
        L.thigh[s] = tapeGirth(x, triangles, *thigh, Vec3::UnitY()).value_or(0.0);
    }
    L.centre.y() = L.waistY;
    return FoundLandmarks{L, std::move(part)};
}

} // namespace atelier::patterns

#include "patterns/assemble.h"

#include "patterns/placement.h"

#include "sim/constraints/kinematic.h"
#include "sim/forces/seam_bending.h"
#include "sim/mesh/joined_vertices.h"
#include "sim/simulation.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <utility>

namespace atelier::patterns {

namespace {

/// Per hinge of a built cloth mesh, the fold angle of the internal line its edge lies on.
sim::VecX hingeRestAngles(const sim::ClothMesh& cloth, const PanelMesh& mesh) {
    if (mesh.lineEdges.empty()) {
        return {};
    }
    std::map<std::pair<int, int>, double> fold;
    for (std::size_t k = 0; k < mesh.lineEdges.size(); ++k) {
        const auto [a, b] = mesh.lineEdges[k];
        fold[{std::min(a, b), std::max(a, b)}] =
            k < mesh.lineFoldAngles.size() ? mesh.lineFoldAngles[k] : 0.0;
    }
    sim::VecX angles = sim::VecX::Zero(cloth.hinges.rows());
    bool any = false;
    for (int h = 0; h < cloth.hinges.rows(); ++h) {
        const int a = cloth.hinges(h, 0), b = cloth.hinges(h, 1);
        const auto it = fold.find({std::min(a, b), std::max(a, b)});
        if (it != fold.end() && it->second != 0) {
            angles[h] = it->second;
            any = true;
        }
    }
    return any ? angles : sim::VecX();
}

/// Per vertex of a cloth mesh, half the rest length of the border edges it ends (0 inside): the
/// length of outline the vertex stands for [m].
std::vector<double> boundaryLengths(const sim::ClothMesh& mesh) {
    std::vector<double> length(static_cast<std::size_t>(mesh.vertexCount()), 0.0);
    for (int e = 0; e < mesh.edges.rows(); ++e) {
        if (mesh.edgeTriangles(e, 1) < 0) {
            const int a = mesh.edges(e, 0), b = mesh.edges(e, 1);
            const double half = 0.5 * (mesh.rest.row(a) - mesh.rest.row(b)).norm();
            length[static_cast<std::size_t>(a)] += half;
            length[static_cast<std::size_t>(b)] += half;
        }
    }
    return length;
}

/// The panel wrapped on its slot as placed, moved by `shift`.
sim::MatX3 shiftedOnSlot(const Panel& panel, const PanelMesh& mesh, const ArrangementSlot& slot,
                         const SlotShift& shift) {
    sim::MatX2 coordinates = placementCoordinates(panel, mesh);
    coordinates.col(0).array() += shift.around;
    return wrapOnSlot(coordinates, slot, panel.placement.clearance + shift.lift);
}

} // namespace

std::optional<std::string> assembleGarment(const Garment& garment, const GarmentMesh& mesh,
                                           const Body& body, const DrapeSettings& settings,
                                           AssembledGarment& out,
                                           const std::vector<SlotShift>& shifts) {
    out = {};
    if (mesh.panels.size() != garment.panels.size()) {
        return std::string("the mesh does not match the garment's panels");
    }
    sim::SceneSpec& scene = out.scene;
    out.panelOffsets.push_back(0);
    for (std::size_t p = 0; p < garment.panels.size(); ++p) {
        const Panel& panel = garment.panels[p];
        const PanelMesh& pm = mesh.panels[p];
        const std::string who = "panel \"" + panel.name + "\"";
        const ArrangementSlot* slot = body.slot(panel.placement.slot);
        if (slot == nullptr) {
            std::string names;
            for (const ArrangementSlot& s : body.slots) {
                names += (names.empty() ? "" : ", ") + s.name;
            }
            return who + ": the body has no slot \"" + panel.placement.slot +
                   "\" (it has: " + names + ")";
        }
        const auto material =
            std::find_if(garment.materials.begin(), garment.materials.end(),
                         [&](const GarmentMaterial& m) { return m.name == panel.material; });
        if (material == garment.materials.end()) {
            return who + ": no material \"" + panel.material + "\"";
        }
        sim::ClothSpec cloth;
        cloth.name = panel.name;
        if (auto err = sim::buildClothMesh(pm.rest, pm.triangles, cloth.mesh)) {
            return who + ": " + *err;
        }
        cloth.position =
            shiftedOnSlot(panel, pm, *slot, p < shifts.size() ? shifts[p] : SlotShift{});
        cloth.material = material->material;
        cloth.model = settings.model;
        cloth.bendingModel = settings.bendingModel;
        cloth.restAngles = hingeRestAngles(cloth.mesh, pm);
        cloth.thickness = settings.clothThickness;
        cloth.selfCollision = settings.selfCollision;
        scene.cloths.push_back(std::move(cloth));
        out.panelOffsets.push_back(out.panelOffsets.back() + pm.pattern.rows());
    }
    std::vector<std::vector<double>> outline;
    for (const sim::ClothSpec& cloth : scene.cloths) {
        outline.push_back(boundaryLengths(cloth.mesh));
    }
    for (std::size_t k = 0; k < mesh.seamPairs.size(); ++k) {
        const auto& pair = mesh.seamPairs[k];
        const int a = out.panelOffsets[static_cast<std::size_t>(pair[0].panel)] + pair[0].vertex;
        const int b = out.panelOffsets[static_cast<std::size_t>(pair[1].panel)] + pair[1].vertex;
        if (a != b) {
            // A pair stands for the outline around its two vertices (a corner vertex, the end
            // of two seams, counts for both).
            const double length = 0.5 * (outline[static_cast<std::size_t>(pair[0].panel)]
                                                [static_cast<std::size_t>(pair[0].vertex)] +
                                         outline[static_cast<std::size_t>(pair[1].panel)]
                                                [static_cast<std::size_t>(pair[1].vertex)]);
            sim::SeamPair seamPair{a, b, length};
            const int seam = k < mesh.seamOfPair.size() ? mesh.seamOfPair[k] : -1;
            if (seam >= 0 && seam < static_cast<int>(garment.seams.size())) {
                const Seam& s = garment.seams[static_cast<std::size_t>(seam)];
                seamPair.foldAngle = s.foldAngle;
                seamPair.bendingScale = s.bendingScale;
            } // a dart's legs: sewn flat, as stiff as the cloth
            scene.seams.push_back(seamPair);
            out.pairSeam.push_back(seam);
        }
    }
    // Implicit Euler: seams as elastics inside the solve (their Jacobian keeps it stable at
    // any gap); an imposed velocity after the solve would drag the seam vertices away from
    // cloth that does not know about it. Explicit integrators impose the law (B).
    scene.seamMode = settings.integrator == sim::IntegratorKind::ImplicitEuler
                         ? sim::SeamMode::Elastic
                         : sim::SeamMode::Imposed;
    scene.integrator.cgTolerance = settings.cgTolerance;
    scene.integrator.linearSolver = settings.linearSolver;
    scene.seamTimeConstant = settings.seamTimeConstant;
    scene.seamReach = settings.seamReach;
    scene.seamStiffnessPerLength = settings.seamStiffness;
    scene.seamWeldDistance = settings.seamWeldDistance;
    scene.seamBending = settings.seamBending;
    // Seams whose chord crosses the body (a shirt's shoulders, a skirt's hips) are led around
    // it rather than pressed into it.
    scene.seamRouteClearance = settings.seamRouteClearance;

    sim::ObstacleSpec obstacle;
    obstacle.name = "body";
    obstacle.vertices = body.vertices;
    obstacle.triangles = body.triangles;
    obstacle.closed = true;
    obstacle.thickness = settings.bodyThickness;
    obstacle.staticFriction = settings.bodyStaticFriction;
    obstacle.kineticFriction = settings.bodyKineticFriction;
    scene.obstacles.push_back(std::move(obstacle));

    // Gravity is held while the garment is sewn (patterns/sewing.h).
    scene.gravity = true;
    // Cloth–cloth contacts stay out of the implicit solve for garments: measured twice on the
    // eight sample drapes (README, "Collisions"), they fix the 20 mm tshirt but cost 10 mm
    // drapes (once the tshirt's sewing; on the corrected samples the dress's and trousers' rest).
    scene.collision.solve.selfContacts = false;
    scene.integrator.kind = settings.integrator;
    scene.integrator.dt = settings.dt;
    scene.duration = settings.timeLimit;
    pinGarment(garment, mesh, settings, 0.0, out);
    return std::nullopt;
}

std::vector<PanelCrossing> startCrossings(const AssembledGarment& assembled, const sim::MatX3& x,
                                          bool withinPanels) {
    const sim::SceneSpec& scene = assembled.scene;
    // Seam partners within the weld distance weld at the first step: one vertex, whose
    // triangles touch there (panels sewn edge to edge, as GarmentCode places them).
    std::vector<int> one(static_cast<std::size_t>(x.rows()));
    for (std::size_t v = 0; v < one.size(); ++v) {
        one[v] = static_cast<int>(v);
    }
    auto find = [&](int v) {
        while (one[static_cast<std::size_t>(v)] != v) {
            v = one[static_cast<std::size_t>(v)] =
                one[static_cast<std::size_t>(one[static_cast<std::size_t>(v)])];
        }
        return v;
    };
    for (const sim::SeamPair& pair : scene.seams) {
        if ((x.row(pair.a) - x.row(pair.b)).norm() <= scene.seamWeldDistance) {
            one[static_cast<std::size_t>(find(pair.a))] = find(pair.b);
        }
    }
    std::vector<sim::MatX3> positions;
    std::vector<sim::MatX3i> triangles;
    std::vector<std::vector<int>> joined;
    for (std::size_t p = 0; p < scene.cloths.size(); ++p) {
        const sim::ClothSpec& cloth = scene.cloths[p];
        const int offset = assembled.panelOffsets[p];
        positions.emplace_back(x.middleRows(offset, cloth.position.rows()));
        triangles.push_back(cloth.mesh.triangles);
        std::vector<int>& names =
            joined.emplace_back(static_cast<std::size_t>(cloth.position.rows()));
        for (std::size_t v = 0; v < names.size(); ++v) {
            names[v] = find(offset + static_cast<int>(v));
        }
    }
    return panelCrossings(positions, triangles, &joined, withinPanels);
}

std::string liftText(const PlacementLift& lift) {
    std::string crossed;
    for (const std::string& name : lift.crossed) {
        crossed += (crossed.empty() ? "" : ", ") + name;
    }
    char text[64];
    if (lift.around == 0) {
        std::snprintf(text, sizeof text, " %.0f mm out", lift.lift * 1000);
    } else if (lift.lift == 0) {
        std::snprintf(text, sizeof text, " %.0f mm around", lift.around * 1000);
    } else {
        std::snprintf(text, sizeof text, " %.0f mm out, %.0f mm around", lift.lift * 1000,
                      lift.around * 1000);
    }
    return lift.panel + text + " (crossed " + crossed + ")";
}

std::vector<SlotShift> liftCrossedPanels(const Garment& garment, const GarmentMesh& mesh,
                                         const Body& body, const AssembledGarment& assembled,
                                         const std::vector<PanelCrossing>& crossings,
                                         std::vector<PlacementLift>& lifted,
                                         const std::vector<char>& movable) {
    constexpr double STEP = 0.005;
    constexpr int MAX_STEPS = 6;
    const std::size_t panels = assembled.scene.cloths.size();
    lifted.clear();
    // A panel's moves in steps: out from its slot (≥ 0), round it (either way, then on the same
    // way only).
    struct Steps {
        int out = 0;
        int around = 0;
        int count() const { return out + std::abs(around); }
        SlotShift shift() const { return {out * STEP, around * STEP}; }
    };
    auto canMove = [&](int p) {
        return movable.empty() || movable[static_cast<std::size_t>(p)] != 0;
    };
    // The crossings a move can undo: those of a movable panel.
    auto ofMovable = [&](std::vector<PanelCrossing> c) {
        std::erase_if(c, [&](const PanelCrossing& k) { return !canMove(k.a) && !canMove(k.b); });
        return c;
    };
    AssembledGarment trial = assembled; // its scene, with the tried panels' positions
    auto crossingsWith = [&](std::size_t p, const Steps& steps) {
        const Panel& panel = garment.panels[p];
        trial.scene.cloths[p].position =
            shiftedOnSlot(panel, mesh.panels[p], *body.slot(panel.placement.slot), steps.shift());
        const sim::Simulation simulation(trial.scene);
        return ofMovable(startCrossings(trial, simulation.positions()));
    };
    auto total = [](const std::vector<PanelCrossing>& c) {
        long n = 0;
        for (const PanelCrossing& k : c) {
            n += k.pairs;
        }
        return n;
    };
    std::vector<Steps> steps(panels), bestSteps = steps;
    std::vector<PanelCrossing> now = ofMovable(crossings);
    long best = total(now);
    while (!now.empty()) {
        const PanelCrossing worst = *std::max_element(
            now.begin(), now.end(),
            [](const PanelCrossing& l, const PanelCrossing& r) { return l.pairs < r.pairs; });
        std::size_t chosen = panels;
        Steps chosenSteps;
        std::vector<PanelCrossing> after;
        sim::MatX3 chosenPosition;
        for (const int p : {worst.b, worst.a}) {
            if (!canMove(p)) {
                continue;
            }
            const auto q = static_cast<std::size_t>(p);
            const Steps& s = steps[q];
            std::vector<Steps> moves;
            if (s.out < MAX_STEPS) {
                moves.push_back({s.out + 1, s.around});
            }
            for (const int way : {1, -1}) {
                if (s.around * way >= 0 && std::abs(s.around) < MAX_STEPS) {
                    moves.push_back({s.out, s.around + way});
                }
            }
            for (const Steps& m : moves) {
                sim::MatX3 before = trial.scene.cloths[q].position;
                std::vector<PanelCrossing> c = crossingsWith(q, m);
                std::swap(before, trial.scene.cloths[q].position); // before: the moved position
                // On a tie, the panel moved more goes on: moving two crossed panels in turn
                // keeps them as they were to each other.
                if (chosen == panels || total(c) < total(after) ||
                    (total(c) == total(after) && s.count() > steps[chosen].count())) {
                    chosen = q;
                    chosenSteps = m;
                    after = std::move(c);
                    chosenPosition = std::move(before);
                }
            }
        }
        if (chosen == panels) {
            break; // both panels as far as they go
        }
        steps[chosen] = chosenSteps;
        trial.scene.cloths[chosen].position = std::move(chosenPosition);
        now = std::move(after);
        if (total(now) < best) {
            best = total(now);
            bestSteps = steps;
        }
    }
    std::vector<SlotShift> shifts(panels);
    for (std::size_t p = 0; p < panels; ++p) {
        if (bestSteps[p].count() == 0) {
            continue;
        }
        shifts[p] = bestSteps[p].shift();
        PlacementLift lift;
        lift.panel = garment.panels[p].name;
        lift.lift = shifts[p].lift;
        lift.around = shifts[p].around;
        for (const PanelCrossing& c : crossings) {
            if (c.a == static_cast<int>(p) || c.b == static_cast<int>(p)) {
                const int other = c.a == static_cast<int>(p) ? c.b : c.a;
                lift.crossed.push_back(garment.panels[static_cast<std::size_t>(other)].name);
            }
        }
        lifted.push_back(std::move(lift));
    }
    return shifts;
}

void pinGarment(const Garment& garment, const GarmentMesh& mesh, const DrapeSettings& settings,
                double drapeTime, AssembledGarment& out) {
    sim::SceneSpec& scene = out.scene;
    scene.pins.clear();
    scene.drives.clear();
    out.pins.clear();
    std::vector<char> held(out.panelOffsets.empty() ? 0 : out.panelOffsets.back(), 0);
    for (std::size_t p = 0; p < garment.panels.size() && p < mesh.panels.size(); ++p) {
        const Panel& panel = garment.panels[p];
        const PanelMesh& pm = mesh.panels[p];
        const sim::ClothSpec& cloth = scene.cloths[p];
        for (std::size_t k = 0; k < panel.pins.size(); ++k) {
            const Pin& pin = panel.pins[k];
            const double release = pin.releaseTime - drapeTime;
            if (!(release > 0) || pm.pattern.rows() == 0) {
                continue;
            }
            int vertex = -1;
            if (pin.notch >= 0 && pin.notch < static_cast<int>(pm.notchVertices.size())) {
                vertex = pm.notchVertices[static_cast<std::size_t>(pin.notch)];
            } else {
                (pm.pattern.rowwise() - pin.point.transpose())
                    .rowwise()
                    .squaredNorm()
                    .minCoeff(&vertex);
            }
            const int global = out.panelOffsets[p] + vertex;
            if (held[static_cast<std::size_t>(global)] != 0) {
                continue;
            }
            held[static_cast<std::size_t>(global)] = 1;
            HeldPin h;
            h.panel = static_cast<int>(p);
            h.pin = static_cast<int>(k);
            h.hold.vertex = global;
            h.hold.releaseTime = std::isfinite(release) ? release : 1e300;
            const sim::Vec3 start = cloth.position.row(vertex).transpose();
            h.hold.times = {0.0};
            h.hold.positions = {start};
            const double arrival = settings.sewingTime - drapeTime;
            if (pin.position) {
                if (arrival > 0) {
                    h.hold.times.push_back(arrival);
                    h.hold.positions.push_back(*pin.position);
                } else {
                    h.hold.positions = {*pin.position};
                }
            }
            if (!pin.position && !std::isfinite(release)) {
                scene.pins.push_back(global);
            } else {
                scene.drives.push_back(h.hold);
            }
            out.pins.push_back(std::move(h));
        }
    }
}

PinFigures pinFigures(const AssembledGarment& assembled, const sim::MatX3& x, double time) {
    PinFigures f;
    for (const HeldPin& h : assembled.pins) {
        if (!sim::driveActive(h.hold, time) || h.hold.vertex >= x.rows()) {
            continue;
        }
        ++f.holding;
        const sim::Vec3 at = sim::samplePath(h.hold, time).position;
        f.largestDisplacement =
            std::max(f.largestDisplacement, (x.row(h.hold.vertex).transpose() - at).norm());
    }
    return f;
}

std::vector<ForcedWeld> forcedWelds(const Garment& garment, const AssembledGarment& assembled,
                                    const std::vector<double>& gaps) {
    std::map<int, ForcedWeld> bySeam;
    const std::size_t n = std::min(gaps.size(), assembled.pairSeam.size());
    for (std::size_t k = 0; k < n; ++k) {
        if (!(gaps[k] > 0)) {
            continue;
        }
        const int seam = assembled.pairSeam[k];
        ForcedWeld& w = bySeam[seam];
        if (w.pairs == 0) {
            if (seam >= 0 && static_cast<std::size_t>(seam) < garment.seams.size()) {
                w.seam = garment.seams[static_cast<std::size_t>(seam)].name;
            } else {
                const std::size_t panel = static_cast<std::size_t>(-1 - seam);
                w.seam = "dart of " + (panel < garment.panels.size() ? garment.panels[panel].name
                                                                     : std::string("?"));
            }
        }
        w.widest = std::max(w.widest, gaps[k]);
        ++w.pairs;
    }
    std::vector<ForcedWeld> out;
    out.reserve(bySeam.size());
    for (auto& [seam, w] : bySeam) {
        out.push_back(std::move(w));
    }
    std::stable_sort(out.begin(), out.end(),
                     [](const ForcedWeld& a, const ForcedWeld& b) { return a.widest > b.widest; });
    return out;
}

double seamGapMax(const AssembledGarment& assembled, const sim::MatX3& x) {
    double gap = 0;
    for (const sim::SeamPair& p : assembled.scene.seams) {
        gap = std::max(gap, (x.row(p.a) - x.row(p.b)).norm());
    }
    return gap;
}

namespace {

/// The median of `values` (reordered); 0 when empty.
double medianOf(std::vector<double>& values) {
    if (values.empty()) {
        return 0.0;
    }
    const auto mid = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
    std::nth_element(values.begin(), mid, values.end());
    if (values.size() % 2 == 1) {
        return *mid;
    }
    return 0.5 * (*mid + *std::max_element(values.begin(), mid));
}

/// |θ| of the hinge (x₀, x₁ | x₂, x₃) at positions x [rad].
double foldAt(const sim::MatX3& x, int a, int b, int c, int d) {
    return std::abs(sim::dihedralAngle(x.row(a).transpose(), x.row(b).transpose(),
                                       x.row(c).transpose(), x.row(d).transpose()));
}

/// Positions as a single-surface export writes them (io::weldedSurface): each group of sewn
/// vertices at its mean position, whether welded yet or not.
sim::MatX3 surfacePositions(const AssembledGarment& assembled, const sim::MatX3& positions) {
    std::vector<std::pair<int, int>> pairs;
    for (const sim::SeamPair& p : assembled.scene.seams) {
        pairs.emplace_back(p.a, p.b);
    }
    const std::vector<int> group = sim::joinedGroups(static_cast<int>(positions.rows()), pairs);
    sim::MatX3 sum = sim::MatX3::Zero(positions.rows(), 3);
    sim::VecX members = sim::VecX::Zero(positions.rows());
    for (int v = 0; v < positions.rows(); ++v) {
        sum.row(group[static_cast<std::size_t>(v)]) += positions.row(v);
        members[group[static_cast<std::size_t>(v)]] += 1;
    }
    sim::MatX3 x(positions.rows(), 3);
    for (int v = 0; v < positions.rows(); ++v) {
        const int g = group[static_cast<std::size_t>(v)];
        x.row(v) = sum.row(g) / members[g];
    }
    return x;
}

} // namespace

FoldFigures foldFigures(const AssembledGarment& assembled, const sim::MatX3& positions) {
    const sim::SceneSpec& scene = assembled.scene;
    const std::vector<int>& offsets = assembled.panelOffsets;
    const sim::MatX3 x = surfacePositions(assembled, positions);
    const auto panelOf = [&](int v) {
        return static_cast<int>(std::upper_bound(offsets.begin(), offsets.end(), v) -
                                offsets.begin()) -
               1;
    };
    std::vector<double> seam, cloth;
    for (const sim::SeamHinge& h : sim::seamHinges(scene, offsets)) {
        // A seam inside one panel (a dart, a sleeve's underarm) is the panel's own cloth once
        // sewn, as the exported surface has it.
        const bool between = panelOf(h.corners[2]) != panelOf(h.corners[3]);
        (between ? seam : cloth)
            .push_back(foldAt(x, h.corners[0], h.corners[1], h.corners[2], h.corners[3]));
    }
    for (std::size_t c = 0; c < scene.cloths.size(); ++c) {
        const auto& hinges = scene.cloths[c].mesh.hinges;
        const int off = offsets[c];
        for (int h = 0; h < hinges.rows(); ++h) {
            cloth.push_back(foldAt(x, off + hinges(h, 0), off + hinges(h, 1), off + hinges(h, 2),
                                   off + hinges(h, 3)));
        }
    }
    FoldFigures f;
    f.seamEdges = static_cast<int>(seam.size());
    f.seamMax = seam.empty() ? 0.0 : *std::max_element(seam.begin(), seam.end());
    f.seamMedian = medianOf(seam);
    f.clothMedian = medianOf(cloth);
    return f;
}

double areaRatio(const sim::SceneSpec& scene, const sim::MatX3& x) {
    double area = 0, rest = 0;
    int offset = 0;
    for (const sim::ClothSpec& c : scene.cloths) {
        for (int t = 0; t < c.mesh.triangleCount(); ++t) {
            const sim::Vec3 a = x.row(offset + c.mesh.triangles(t, 0));
            const sim::Vec3 b = x.row(offset + c.mesh.triangles(t, 1));
            const sim::Vec3 d = x.row(offset + c.mesh.triangles(t, 2));
            area += 0.5 * (b - a).cross(d - a).norm();
        }
        rest += c.mesh.restArea.sum();
        offset += c.mesh.vertexCount();
    }
    return rest > 0 ? area / rest : 0.0;
}

} // namespace atelier::patterns

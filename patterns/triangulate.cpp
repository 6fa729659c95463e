#include "patterns/triangulate.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_mesh_face_base_2.h>
#include <CGAL/Delaunay_mesh_size_criteria_2.h>
#include <CGAL/Delaunay_mesh_vertex_base_2.h>
#include <CGAL/Delaunay_mesher_no_edge_refinement_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/lloyd_optimize_mesh_2.h>

#include <cmath>
#include <map>

namespace atelier::patterns {

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Vb = CGAL::Delaunay_mesh_vertex_base_2<K>;
using Fb = CGAL::Delaunay_mesh_face_base_2<K>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<K, Tds, CGAL::Exact_predicates_tag>;
using Criteria = CGAL::Delaunay_mesh_size_criteria_2<Cdt>;
using Mesher = CGAL::Delaunay_mesher_no_edge_refinement_2<Cdt, Criteria>;

} // namespace

std::optional<std::string> triangulate(const TriangulationInput& input, TriangulationOutput& out) {
    Cdt cdt;
    std::vector<Cdt::Vertex_handle> handles;
    handles.reserve(input.points.size());
    for (const sim::Vec2& p : input.points) {
        handles.push_back(cdt.insert(K::Point_2(p.x(), p.y())));
    }
    std::map<Cdt::Vertex_handle, int> index;
    for (std::size_t i = 0; i < handles.size(); ++i) {
        if (!index.emplace(handles[i], static_cast<int>(i)).second) {
            return "points " + std::to_string(index[handles[i]]) + " and " + std::to_string(i) +
                   " coincide";
        }
    }
    for (const auto& [a, b] : input.constraints) {
        cdt.insert_constraint(handles[static_cast<std::size_t>(a)],
                              handles[static_cast<std::size_t>(b)]);
    }
    if (cdt.number_of_vertices() != input.points.size()) {
        return std::string("constraints cross each other (the outline, holes or internal lines "
                           "intersect)");
    }
    const double angle = input.minAngleDeg * M_PI / 180.0;
    const double shape = std::sin(angle) * std::sin(angle);
    std::list<K::Point_2> seeds;
    for (const sim::Vec2& s : input.holeSeeds) {
        seeds.emplace_back(s.x(), s.y());
    }
    Mesher mesher(cdt, Criteria(shape, input.maxEdge));
    mesher.set_seeds(seeds.begin(), seeds.end(), false);
    mesher.refine_mesh();
    if (input.lloydIterations > 0) {
        CGAL::lloyd_optimize_mesh_2(cdt,
                                    CGAL::parameters::max_iteration_number = input.lloydIterations);
        // Smoothing may leave a few triangles under the angle bound: refine those again.
        Mesher again(cdt, Criteria(shape, input.maxEdge));
        again.set_seeds(seeds.begin(), seeds.end(), false);
        again.refine_mesh();
    }
    if (cdt.number_of_vertices() < input.points.size()) {
        return std::string("meshing lost input points");
    }
    out.points = input.points;
    std::map<Cdt::Vertex_handle, int> all = index;
    for (auto v = cdt.finite_vertices_begin(); v != cdt.finite_vertices_end(); ++v) {
        if (all.find(v) == all.end()) {
            all.emplace(v, static_cast<int>(out.points.size()));
            out.points.emplace_back(v->point().x(), v->point().y());
        }
    }
    std::vector<std::array<int, 3>> tris;
    for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
        if (!f->is_in_domain()) {
            continue;
        }
        tris.push_back({all[f->vertex(0)], all[f->vertex(1)], all[f->vertex(2)]});
    }
    // Points that ended up outside the domain (none expected) are left unused.
    out.triangles.resize(static_cast<Eigen::Index>(tris.size()), 3);
    for (std::size_t t = 0; t < tris.size(); ++t) {
        out.triangles.row(static_cast<Eigen::Index>(t)) << tris[t][0], tris[t][1], tris[t][2];
    }
    return std::nullopt;
}

} // namespace atelier::patterns

#include "contact/body_overlap.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include "common/error.hpp"
#include "contact/spatial_hash.hpp"
#include "kernels/primitive_distance.hpp"

namespace descent {

namespace {

using Point = const double*;

// det[b - a, c - a, d - a]: six times the signed volume of (a, b, c, d).
double orient(Point a, Point b, Point c, Point d) {
  const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  const double w[3] = {d[0] - a[0], d[1] - a[1], d[2] - a[2]};
  return u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
         u[2] * (v[0] * w[1] - v[1] * w[0]);
}

// Volumes below this times L^3 (L the primitives' size) count as zero, so
// faces that touch in a plane, whose volumes are rounding noise once the
// bodies are rotated, are not taken for crossings.
constexpr double kTouching = 1e-10;
// A vertex this close to a surface triangle, relative to L, is on it.
constexpr double kOnSurface = 1e-9;

struct Primitives {
  std::vector<std::array<index_t, 3>> triangles;  // surface, outward
  std::vector<std::array<index_t, 2>> edges;      // of the surface triangles, each once
  std::vector<index_t> surface_vertices;
  std::vector<index_t> tets;  // ids into mesh.tets
  Aabb bounds;
  double size = 0;  // mean surface edge length
};

// Each body's surface (faces of one tet only), edges, vertices and tets.
std::vector<Primitives> body_primitives(const Mesh& mesh, int num_bodies) {
  const auto& offsets = mesh.body_vertex_offsets;
  auto body_of = [&](index_t v) {
    return static_cast<int>(std::upper_bound(offsets.begin(), offsets.end(), v) - offsets.begin()) -
           1;
  };
  std::vector<Primitives> bodies(num_bodies);
  // (sorted corners, tet, face) per face; a face listed once is surface.
  struct Face {
    std::array<index_t, 3> key;
    index_t tet;
    int face;
  };
  std::vector<Face> faces;
  faces.reserve(4 * static_cast<std::size_t>(mesh.num_tets()));
  for (index_t t = 0; t < mesh.num_tets(); ++t) {
    bodies[body_of(mesh.tets[4 * t])].tets.push_back(t);
    for (int f = 0; f < 4; ++f) {
      std::array<index_t, 3> key;
      for (int k = 0; k < 3; ++k) key[k] = mesh.tets[4 * t + kTetFaces[f][k]];
      std::sort(key.begin(), key.end());
      faces.push_back({key, t, f});
    }
  }
  std::sort(faces.begin(), faces.end(), [](const Face& a, const Face& b) { return a.key < b.key; });
  for (std::size_t i = 0; i < faces.size();) {
    std::size_t j = i + 1;
    while (j < faces.size() && faces[j].key == faces[i].key) ++j;
    if (j == i + 1) {
      const Face& f = faces[i];
      std::array<index_t, 3> corners;
      for (int k = 0; k < 3; ++k) corners[k] = mesh.tets[4 * f.tet + kTetFaces[f.face][k]];
      bodies[body_of(corners[0])].triangles.push_back(corners);
    }
    i = j;
  }
  for (Primitives& body : bodies) {
    for (const auto& tri : body.triangles)
      for (int k = 0; k < 3; ++k) {
        const index_t a = tri[k], b = tri[(k + 1) % 3];
        body.edges.push_back({std::min(a, b), std::max(a, b)});
        body.surface_vertices.push_back(a);
      }
    std::sort(body.edges.begin(), body.edges.end());
    body.edges.erase(std::unique(body.edges.begin(), body.edges.end()), body.edges.end());
    std::sort(body.surface_vertices.begin(), body.surface_vertices.end());
    body.surface_vertices.erase(
        std::unique(body.surface_vertices.begin(), body.surface_vertices.end()),
        body.surface_vertices.end());
    double length = 0;
    for (const auto& e : body.edges) {
      const double* a = &mesh.positions[3 * static_cast<std::size_t>(e[0])];
      const double* b = &mesh.positions[3 * static_cast<std::size_t>(e[1])];
      length += std::hypot(b[0] - a[0], b[1] - a[1], b[2] - a[2]);
    }
    body.size = body.edges.empty() ? 0 : length / static_cast<double>(body.edges.size());
    for (index_t v : body.surface_vertices)
      body.bounds.add(&mesh.positions[3 * static_cast<std::size_t>(v)]);
  }
  return bodies;
}

std::string point_text(const double* p) {
  char text[96];
  std::snprintf(text, sizeof text, "(%.6g, %.6g, %.6g)", p[0], p[1], p[2]);
  return text;
}

[[noreturn]] void throw_overlap(const std::string& a, const std::string& b, const double* at,
                                const std::string& how) {
  throw InputError(detail::concat(a, " and ", b, " overlap near ", point_text(at), ": ", how,
                                  "; bodies may start closer than contact.distance, never "
                                  "inside each other: move them apart"));
}

// Whether segment (p, q) crosses triangle (a, b, c) through both open
// sides; `at` gets the crossing point.
bool crosses(Point p, Point q, Point a, Point b, Point c, double zero, double* at) {
  const double sp = orient(a, b, c, p), sq = orient(a, b, c, q);
  if (!((sp > zero && sq < -zero) || (sp < -zero && sq > zero))) return false;
  const double u = orient(p, q, a, b), v = orient(p, q, b, c), w = orient(p, q, c, a);
  const bool inside = (u > zero && v > zero && w > zero) || (u < -zero && v < -zero && w < -zero);
  if (!inside) return false;
  const double s = sp / (sp - sq);
  for (int i = 0; i < 3; ++i) at[i] = p[i] + s * (q[i] - p[i]);
  return true;
}

// Where p lies against tet x: outside (0), on its boundary (1: a face,
// edge or corner of it, to `zero`) or strictly inside (2).
int in_tet(Point p, const std::array<Point, 4>& x, double zero) {
  bool boundary = false;
  for (int f = 0; f < 4; ++f) {
    std::array<Point, 4> y = x;
    y[f] = p;
    const double volume = orient(y[0], y[1], y[2], y[3]);
    if (volume < -zero) return 0;
    boundary = boundary || volume <= zero;
  }
  return boundary ? 1 : 2;
}

Aabb bounds_of(const Mesh& mesh, const index_t* ids, int count) {
  Aabb box;
  for (int k = 0; k < count; ++k) box.add(&mesh.positions[3 * static_cast<std::size_t>(ids[k])]);
  return box;
}

}  // namespace

void check_bodies_apart(const Mesh& mesh, const std::vector<std::string>& names) {
  const int num_bodies = static_cast<int>(mesh.body_vertex_offsets.size()) - 1;
  if (num_bodies < 2) return;
  const std::vector<Primitives> bodies = body_primitives(mesh, num_bodies);
  auto at = [&](index_t v) { return &mesh.positions[3 * static_cast<std::size_t>(v)]; };
  std::vector<index_t> found;
  for (int b = 0; b < num_bodies; ++b) {
    bool near_another = false;
    for (int a = 0; a < num_bodies; ++a)
      near_another = near_another || (a != b && bodies[a].bounds.overlaps(bodies[b].bounds));
    if (!near_another) continue;
    // b's surface triangles and tets, against every other body's edges and
    // vertices inside b's bounds.
    const Primitives& target = bodies[b];
    std::vector<Aabb> triangle_boxes, tet_boxes;
    for (const auto& tri : target.triangles)
      triangle_boxes.push_back(bounds_of(mesh, tri.data(), 3));
    for (index_t t : target.tets) tet_boxes.push_back(bounds_of(mesh, &mesh.tets[4 * t], 4));
    const SpatialHash triangles(triangle_boxes, SpatialHash::cell_size_for(triangle_boxes));
    const SpatialHash tets(tet_boxes, SpatialHash::cell_size_for(tet_boxes));
    for (int a = 0; a < num_bodies; ++a) {
      if (a == b || !bodies[a].bounds.overlaps(target.bounds)) continue;
      const double length = std::max(bodies[a].size, target.size);
      const double zero = kTouching * length * length * length;
      for (const auto& e : bodies[a].edges) {
        const Aabb box = bounds_of(mesh, e.data(), 2);
        if (!box.overlaps(target.bounds)) continue;
        triangles.candidates(box, found);
        for (index_t k : found) {
          const auto& tri = target.triangles[k];
          double point[3];
          if (crosses(at(e[0]), at(e[1]), at(tri[0]), at(tri[1]), at(tri[2]), zero, point))
            throw_overlap(names[a], names[b], point,
                          "a surface edge of the first crosses the surface of the second");
        }
      }
      for (index_t v : bodies[a].surface_vertices) {
        Aabb box;
        box.add(at(v));
        if (!box.overlaps(target.bounds)) continue;
        // Grown by the distance that still counts as on the surface: a
        // vertex on a face may lie a rounding outside the face's box.
        for (int i = 0; i < 3; ++i) {
          box.lo[i] -= kOnSurface * length;
          box.hi[i] += kOnSurface * length;
        }
        // Inside: strictly inside a tet, or on a tet's boundary (an inner
        // face, edge or corner) and on no surface triangle of the body.
        tets.candidates(box, found);
        int where = 0;
        for (index_t k : found) {
          const index_t* corners = &mesh.tets[4 * target.tets[k]];
          where = std::max(
              where, in_tet(at(v), {at(corners[0]), at(corners[1]), at(corners[2]), at(corners[3])},
                            zero));
          if (where == 2) break;
        }
        if (where == 1) {
          triangles.candidates(box, found);
          for (index_t k : found) {
            const auto& tri = target.triangles[k];
            const double x[12] = {at(v)[0],      at(v)[1],      at(v)[2],      at(tri[0])[0],
                                  at(tri[0])[1], at(tri[0])[2], at(tri[1])[0], at(tri[1])[1],
                                  at(tri[1])[2], at(tri[2])[0], at(tri[2])[1], at(tri[2])[2]};
            if (point_triangle_distance(x, false).d2 <= kOnSurface * kOnSurface * length * length)
              where = 0;  // on the surface: touching
          }
        }
        if (where > 0)
          throw_overlap(names[a], names[b], at(v), "a vertex of the first lies inside the second");
      }
    }
  }
}

}  // namespace descent

#include "contact/contact_halo.hpp"

#include <algorithm>
#include <cmath>

#include "comm/exchange.hpp"
#include "comm/mpi_check.hpp"
#include "comm/mpi_type.hpp"
#include "contact/spatial_hash.hpp"
#include "contact/surface_vertices.hpp"

namespace descent {

namespace {

constexpr int kGhostTag = 7301;

// A surface triangle as it travels: its vertices' global ids.
struct GhostTriangle {
  global_index_t v[3];
};

// A vertex as it travels: global id and position.
struct GhostVertex {
  global_index_t id;
  double x[3];
  double value;  // the vertex's carried value (ContactHalo::rebuild)
};

// What each rank tells the others at a rebuild: the box of its surface
// vertices and its longest surface edge.
struct SurfaceBox {
  double lo[3], hi[3];
  double longest_edge;
};

bool meets(const SurfaceBox& a, const Aabb& b, double grow) {
  for (int i = 0; i < 3; ++i)
    if (b.hi[i] < a.lo[i] - grow || a.hi[i] + grow < b.lo[i]) return false;
  return true;
}

}  // namespace

template <class Real>
ContactHalo<Real>::ContactHalo(const LocalMesh& mesh, Halo<Real>& halo)
    : mesh_(mesh), comm_(halo.comm()) {
  for (index_t t = 0; t < mesh.num_tets(); ++t)
    for (int f = 0; f < 4; ++f) {
      if (!(mesh.surface_faces[t] & (1u << f))) continue;
      std::array<index_t, 3> tri;
      for (int k = 0; k < 3; ++k)
        tri[k] = mesh.tets[4 * static_cast<std::size_t>(t) + kTetFaces[f][k]];
      own_triangles_.push_back(tri);
    }
  surface_ = surface_vertices(mesh, halo);
  num_local_ = static_cast<index_t>(surface_.size());
}

template <class Real>
void ContactHalo<Real>::rebuild(const Real* q, double reach, const std::vector<Real>& carried,
                                const Real* to) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm_, &rank);
  MPI_Comm_size(comm_, &size);
  auto point = [](const Real* x, index_t v) {
    return std::array<double, 3>{static_cast<double>(x[3 * v]), static_cast<double>(x[3 * v + 1]),
                                 static_cast<double>(x[3 * v + 2])};
  };
  // The positions the boxes cover: q, and with `to` also the ends of the
  // moves (a primitive moved along a straight path, scaled or not, stays
  // in the box of its two ends).
  std::vector<const Real*> ends{q};
  if (to) ends.push_back(to);
  SurfaceBox mine{{1e300, 1e300, 1e300}, {-1e300, -1e300, -1e300}, 0.0};
  for (const Real* x : ends)
    for (index_t v : surface_) {
      const std::array<double, 3> p = point(x, v);
      for (int i = 0; i < 3; ++i) {
        mine.lo[i] = std::min(mine.lo[i], p[i]);
        mine.hi[i] = std::max(mine.hi[i], p[i]);
      }
    }
  std::vector<Aabb> boxes(own_triangles_.size());
  for (const Real* x : ends)
    for (std::size_t k = 0; k < own_triangles_.size(); ++k)
      for (int a = 0; a < 3; ++a) {
        const std::array<double, 3> p = point(x, own_triangles_[k][a]),
                                    r = point(x, own_triangles_[k][(a + 1) % 3]);
        boxes[k].add(p.data());
        mine.longest_edge =
            std::max(mine.longest_edge, std::hypot(p[0] - r[0], p[1] - r[1], p[2] - r[2]));
      }
  std::vector<SurfaceBox> all(size);
  DESCENT_MPI_CHECK(MPI_Allgather(&mine, sizeof(SurfaceBox), MPI_BYTE, all.data(),
                                  sizeof(SurfaceBox), MPI_BYTE, comm_));
  double longest = 0;
  for (const SurfaceBox& box : all) longest = std::max(longest, box.longest_edge);
  const double grow = reach + longest;
  Aabb surface;  // this rank's surface vertices (empty without any)
  surface.lo = {mine.lo[0], mine.lo[1], mine.lo[2]};
  surface.hi = {mine.hi[0], mine.hi[1], mine.hi[2]};

  // Each triangle goes to every other rank whose grown box it meets, with
  // its vertices (each once per rank).
  Outbox<GhostTriangle> triangle_out(size);
  Outbox<GhostVertex> vertex_out(size);
  std::vector<std::vector<index_t>> sent(size);
  for (int pass = 0; pass < 2; ++pass) {
    for (int s = 0; s < size; ++s) {
      if (pass == 0) sent[s].clear();
      // No triangle of this rank can meet a box its whole surface misses.
      if (s == rank || !meets(all[s], surface, grow)) continue;
      for (std::size_t k = 0; k < own_triangles_.size(); ++k) {
        if (!meets(all[s], boxes[k], grow)) continue;
        const auto& tri = own_triangles_[k];
        if (pass == 0) {
          triangle_out.count(s);
          sent[s].insert(sent[s].end(), tri.begin(), tri.end());
        } else {
          triangle_out.place(s, {{mesh_.global_vertex[tri[0]], mesh_.global_vertex[tri[1]],
                                  mesh_.global_vertex[tri[2]]}});
        }
      }
      if (pass == 0) {
        // Sorted by global id (local ids of one group are), each once.
        std::sort(sent[s].begin(), sent[s].end(), [&](index_t a, index_t b) {
          return mesh_.global_vertex[a] < mesh_.global_vertex[b];
        });
        sent[s].erase(std::unique(sent[s].begin(), sent[s].end()), sent[s].end());
        for (std::size_t i = 0; i < sent[s].size(); ++i) vertex_out.count(s);
      } else {
        for (index_t v : sent[s]) {
          const std::array<double, 3> x = point(q, v);
          vertex_out.place(s, {mesh_.global_vertex[v],
                               {x[0], x[1], x[2]},
                               carried.empty() ? 0.0 : static_cast<double>(carried[v])});
        }
      }
    }
    if (pass == 0) {
      triangle_out.allocate();
      vertex_out.allocate();
    }
  }
  const Inbox<GhostTriangle> triangles_in = exchange(comm_, triangle_out);
  const Inbox<GhostVertex> vertices_in = exchange(comm_, vertex_out);

  // Contact vertices: the local surface, then the ghosts by global id.
  std::unordered_map<global_index_t, index_t> index_of;
  local_vertex_.assign(surface_.begin(), surface_.end());
  global_id_.clear();
  for (index_t v : surface_) {
    index_of.emplace(mesh_.global_vertex[v], static_cast<index_t>(global_id_.size()));
    global_id_.push_back(mesh_.global_vertex[v]);
  }
  std::vector<global_index_t> ghosts;
  for (const GhostVertex& g : vertices_in.records)
    if (!index_of.count(g.id)) ghosts.push_back(g.id);
  std::sort(ghosts.begin(), ghosts.end());
  ghosts.erase(std::unique(ghosts.begin(), ghosts.end()), ghosts.end());
  for (global_index_t id : ghosts) {
    index_of.emplace(id, static_cast<index_t>(global_id_.size()));
    global_id_.push_back(id);
    local_vertex_.push_back(-1);
  }
  body_.resize(global_id_.size());
  for (std::size_t c = 0; c < global_id_.size(); ++c)
    body_[c] = body_of_vertex(mesh_.body_vertex_offsets, global_id_[c]);

  triangles_.clear();
  std::vector<index_t> contact_of_local(mesh_.num_vertices(), -1);
  for (index_t c = 0; c < num_local_; ++c) contact_of_local[surface_[c]] = c;
  for (const auto& tri : own_triangles_)
    triangles_.push_back(
        {contact_of_local[tri[0]], contact_of_local[tri[1]], contact_of_local[tri[2]]});
  for (const GhostTriangle& t : triangles_in.records)
    triangles_.push_back({index_of.at(t.v[0]), index_of.at(t.v[1]), index_of.at(t.v[2])});
  if (triangles_ != derived_triangles_ || global_id_ != derived_ids_) derive_primitives();

  positions_.assign(3 * global_id_.size(), Real(0));
  carried_.assign(global_id_.size(), Real(0));
  for (index_t c = 0; c < num_local_; ++c) {
    for (int i = 0; i < 3; ++i) positions_[3 * c + i] = q[3 * surface_[c] + i];
    if (!carried.empty()) carried_[c] = carried[surface_[c]];
  }
  for (const GhostVertex& g : vertices_in.records) {
    const index_t c = index_of.at(g.id);
    if (c < num_local_) continue;
    for (int i = 0; i < 3; ++i) positions_[3 * c + i] = static_cast<Real>(g.x[i]);
    carried_[c] = static_cast<Real>(g.value);
  }

  // The neighbours of update_ghosts: who sent vertices, who was sent them.
  destinations_.clear();
  send_vertices_.clear();
  for (int s = 0; s < size; ++s)
    if (!sent[s].empty()) {
      destinations_.push_back(s);
      send_vertices_.push_back(sent[s]);
    }
  sources_.clear();
  receive_slots_.clear();
  for (int s = 0; s < size; ++s) {
    const std::size_t begin = vertices_in.from_offsets[s], end = vertices_in.from_offsets[s + 1];
    if (begin == end) continue;
    sources_.push_back(s);
    std::vector<index_t>& slots = receive_slots_.emplace_back();
    for (std::size_t k = begin; k < end; ++k) {
      const index_t c = index_of.at(vertices_in.records[k].id);
      slots.push_back(c >= num_local_ ? c : -1);
    }
  }
}

template <class Real>
void ContactHalo<Real>::gather(const Real* values, std::vector<Real>& out) const {
  out.resize(3 * global_id_.size());
  for (index_t c = 0; c < num_local_; ++c)
    for (int i = 0; i < 3; ++i) out[3 * c + i] = values[3 * surface_[c] + i];
  // Buffers kept between calls: this runs every iteration.
  std::vector<std::vector<Real>>& sending = sending_;
  std::vector<std::vector<Real>>& in = receiving_;
  std::vector<MPI_Request>& requests = requests_;
  sending.resize(destinations_.size());
  in.resize(sources_.size());
  requests.clear();
  requests.reserve(sources_.size() + destinations_.size());
  for (std::size_t s = 0; s < sources_.size(); ++s) {
    in[s].resize(3 * receive_slots_[s].size());
    DESCENT_MPI_CHECK(MPI_Irecv(in[s].data(), static_cast<int>(in[s].size()), mpi_type<Real>(),
                                sources_[s], kGhostTag, comm_, &requests.emplace_back()));
  }
  for (std::size_t d = 0; d < destinations_.size(); ++d) {
    sending[d].clear();
    for (index_t v : send_vertices_[d])
      for (int i = 0; i < 3; ++i) sending[d].push_back(values[3 * v + i]);
    DESCENT_MPI_CHECK(MPI_Isend(sending[d].data(), static_cast<int>(sending[d].size()),
                                mpi_type<Real>(), destinations_[d], kGhostTag, comm_,
                                &requests.emplace_back()));
  }
  DESCENT_MPI_CHECK(
      MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE));
  for (std::size_t s = 0; s < sources_.size(); ++s)
    for (std::size_t k = 0; k < receive_slots_[s].size(); ++k) {
      const index_t c = receive_slots_[s][k];
      if (c >= 0)
        for (int i = 0; i < 3; ++i) out[3 * c + i] = in[s][3 * k + i];
    }
}

template <class Real>
void ContactHalo<Real>::derive_primitives() {
  // Edges sorted with their global ids beside them: the comparisons then
  // read no other array.
  std::vector<char> on_triangle(global_id_.size(), 0);
  std::vector<std::pair<std::array<global_index_t, 2>, std::array<index_t, 2>>> keyed;
  keyed.reserve(3 * triangles_.size());
  for (const auto& t : triangles_)
    for (int k = 0; k < 3; ++k) {
      on_triangle[t[k]] = 1;
      std::array<index_t, 2> e{t[k], t[(k + 1) % 3]};
      if (global_id_[e[1]] < global_id_[e[0]]) std::swap(e[0], e[1]);
      keyed.push_back({{global_id_[e[0]], global_id_[e[1]]}, e});
    }
  triangle_vertices_.clear();
  for (std::size_t c = 0; c < on_triangle.size(); ++c)
    if (on_triangle[c]) triangle_vertices_.push_back(static_cast<index_t>(c));
  std::sort(keyed.begin(), keyed.end());
  edges_.clear();
  for (std::size_t i = 0; i < keyed.size(); ++i)
    if (i == 0 || keyed[i].first != keyed[i - 1].first) edges_.push_back(keyed[i].second);
  derived_triangles_ = triangles_;
  derived_ids_ = global_id_;
}

template class ContactHalo<double>;
template class ContactHalo<float>;

}  // namespace descent

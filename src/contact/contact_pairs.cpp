#include "contact/contact_pairs.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include "common/error.hpp"
#include "contact/spatial_hash.hpp"
#include "kernels/primitive_distance.hpp"

namespace descent {

namespace {

// The box of the primitive's vertices at the halo's positions and, with
// `to` (per contact vertex), at the ends of their paths.
template <class Real>
Aabb bounds(const ContactHalo<Real>& halo, const std::vector<Real>* to, const index_t* v, int count,
            double grow) {
  Aabb box;
  for (const std::vector<Real>* x : {&halo.positions(), to}) {
    if (!x) continue;
    for (int k = 0; k < count; ++k) {
      const Real* y = &(*x)[3 * static_cast<std::size_t>(v[k])];
      const double p[3] = {y[0], y[1], y[2]};
      box.add(p);
    }
  }
  for (int i = 0; i < 3; ++i) {
    box.lo[i] -= grow;
    box.hi[i] += grow;
  }
  return box;
}

// Boxes hashed body by body: a query asks only the bodies it may pair with
// (without contact.self, not its own, whose surface is most of what lies
// near its vertices) and whose box it meets. A body's hash is built at the
// first query that reaches it: bodies far from every other (most of a
// scene's, most of the time) cost only their box.
class HashByBody {
 public:
  HashByBody(const std::vector<Aabb>& boxes, const std::vector<int>& body, double cell_size)
      : cell_size_(cell_size) {
    const int num_bodies = body.empty() ? 0 : *std::max_element(body.begin(), body.end()) + 1;
    ids_.resize(num_bodies);
    bounds_.resize(num_bodies);
    boxes_of_.resize(num_bodies);
    hashes_.resize(num_bodies);
    for (std::size_t i = 0; i < boxes.size(); ++i) {
      ids_[body[i]].push_back(static_cast<index_t>(i));
      boxes_of_[body[i]].push_back(boxes[i]);
      bounds_[body[i]].add(boxes[i].lo.data());
      bounds_[body[i]].add(boxes[i].hi.data());
    }
  }

  // Ids of the boxes overlapping `query` among the bodies admit(b) accepts,
  // in no particular order.
  template <class Admit>
  void candidates(const Aabb& query, Admit&& admit, std::vector<index_t>& out) const {
    out.clear();
    for (std::size_t b = 0; b < hashes_.size(); ++b) {
      if (ids_[b].empty() || !admit(static_cast<int>(b)) || !bounds_[b].overlaps(query)) continue;
      if (!hashes_[b]) hashes_[b].emplace(boxes_of_[b], cell_size_);
      hashes_[b]->candidates(query, found_);
      for (index_t k : found_) out.push_back(ids_[b][k]);
    }
  }

 private:
  double cell_size_;
  std::vector<std::vector<index_t>> ids_;  // per body: its boxes' ids
  std::vector<Aabb> bounds_;               // per body: the box of its boxes
  std::vector<std::vector<Aabb>> boxes_of_;
  mutable std::vector<std::optional<SpatialHash>> hashes_;  // built when first asked
  mutable std::vector<index_t> found_;
};

template <class Real>
void gather(const ContactHalo<Real>& halo, const std::array<index_t, 4>& v, Real* x) {
  for (int k = 0; k < 4; ++k)
    for (int i = 0; i < 3; ++i)
      x[3 * k + i] = halo.positions()[3 * static_cast<std::size_t>(v[k]) + i];
}

}  // namespace

template <class Real>
ContactPairs find_contact_pairs(const ContactHalo<Real>& halo, double reach, bool self,
                                const std::vector<Real>* to, const std::vector<double>* caps) {
  const auto& gid = halo.global_id();
  const auto& body = halo.body();
  const auto& triangles = halo.triangles();
  const index_t local = halo.num_local();
  auto touches_local = [&](const std::array<index_t, 4>& v) {
    return std::any_of(v.begin(), v.end(), [&](index_t c) { return c < local; });
  };
  // Along the paths a pair's gap closes by at most the longest move of one
  // side plus the longest of the other whatever the fractions (a point of a
  // primitive moves by a convex combination of its vertices' moves, all
  // scaled alike as they lie on one body), and within one body (its moves
  // scaled alike) by at most the largest difference between a move of one
  // side and one of the other (kernels/pair_path.hpp).
  auto move = [&](index_t c, int i) {
    return static_cast<double>((*to)[3 * c + i] - halo.positions()[3 * c + i]);
  };
  auto distance_of_moves = [&](index_t a, index_t b) {  // b < 0: from no move
    double d2 = 0;
    for (int i = 0; i < 3; ++i) {
      const double d = move(a, i) - (b < 0 ? 0.0 : move(b, i));
      d2 += d * d;
    }
    return std::sqrt(d2);
  };
  // The largest cap of the vertices v[0, count) (0 without caps).
  auto cap_of = [&](const index_t* v, int count) {
    double cap = 0;
    if (caps)
      for (int k = 0; k < count; ++k) cap = std::max(cap, (*caps)[v[k]]);
    return cap;
  };
  auto within = [&](const std::array<index_t, 4>& v, Real d2, int second_side) {
    if (!to) {
      const double r =
          reach + cap_of(v.data(), second_side) + cap_of(v.data() + second_side, 4 - second_side);
      return static_cast<double>(d2) < r * r;
    }
    double closing = 0;
    if (std::all_of(v.begin(), v.end(), [&](index_t c) { return body[c] == body[v[0]]; })) {
      for (int a = 0; a < second_side; ++a)
        for (int b = second_side; b < 4; ++b)
          closing = std::max(closing, distance_of_moves(v[a], v[b]));
    } else {
      double longest[2] = {0, 0};
      for (int a = 0; a < 4; ++a) {
        double& side = longest[a < second_side ? 0 : 1];
        side = std::max(side, distance_of_moves(v[a], -1));
      }
      closing = longest[0] + longest[1];
    }
    return std::sqrt(static_cast<double>(d2)) - closing < reach;
  };

  const std::vector<index_t>& vertices = halo.triangle_vertices();
  const std::vector<std::array<index_t, 2>>& edges = halo.edges();

  ContactPairs pairs;
  std::vector<index_t> found;
  Real x[12];

  // Each primitive's box grown by its cap, a query's also by the reach; the
  // cells sized for the mean cap.
  double mean_cap = 0;
  if (caps && !caps->empty()) {
    for (double c : *caps) mean_cap += c;
    mean_cap /= static_cast<double>(caps->size());
  }
  const double growth = 2 * (reach + 2 * mean_cap);
  std::vector<Aabb> triangle_boxes;
  std::vector<int> triangle_body;
  for (const auto& t : triangles) {
    triangle_boxes.push_back(bounds(halo, to, t.data(), 3, cap_of(t.data(), 3)));
    triangle_body.push_back(body[t[0]]);
  }
  const HashByBody triangle_hash(triangle_boxes, triangle_body,
                                 SpatialHash::cell_size_for(triangle_boxes, growth));
  for (index_t p : vertices) {
    triangle_hash.candidates(
        bounds(halo, to, &p, 1, reach + cap_of(&p, 1)), [&](int b) { return self || b != body[p]; },
        found);
    for (index_t k : found) {
      const auto& t = triangles[k];
      if (p == t[0] || p == t[1] || p == t[2]) continue;
      const std::array<index_t, 4> v{p, t[0], t[1], t[2]};
      if (!touches_local(v)) continue;
      gather(halo, v, x);
      if (within(v, point_triangle_distance(x, false).d2, 1)) pairs.vertex_triangle.push_back(v);
    }
  }

  std::vector<Aabb> edge_boxes;
  std::vector<int> edge_body;
  for (const auto& e : edges) {
    edge_boxes.push_back(bounds(halo, to, e.data(), 2, cap_of(e.data(), 2)));
    edge_body.push_back(body[e[0]]);
  }
  const HashByBody edge_hash(edge_boxes, edge_body, SpatialHash::cell_size_for(edge_boxes, growth));
  for (std::size_t i = 0; i < edges.size(); ++i) {
    const int own = body[edges[i][0]];
    edge_hash.candidates(
        bounds(halo, to, edges[i].data(), 2, reach + cap_of(edges[i].data(), 2)),
        [&](int b) { return self || b != own; }, found);
    for (index_t k : found) {
      if (static_cast<std::size_t>(k) <= i) continue;  // each pair once: the later edge
      const auto& a = edges[i];
      const auto& b = edges[k];
      if (a[0] == b[0] || a[0] == b[1] || a[1] == b[0] || a[1] == b[1]) continue;
      const std::array<index_t, 4> v{a[0], a[1], b[0], b[1]};
      if (!touches_local(v)) continue;
      gather(halo, v, x);
      if (within(v, edge_edge_distance(x, false).d2, 2)) pairs.edge_edge.push_back(v);
    }
  }

  const auto key = [&](const std::array<index_t, 4>& v) {
    return std::array<global_index_t, 4>{gid[v[0]], gid[v[1]], gid[v[2]], gid[v[3]]};
  };
  for (auto* list : {&pairs.vertex_triangle, &pairs.edge_edge})
    std::sort(list->begin(), list->end(),
              [&](const auto& a, const auto& b) { return key(a) < key(b); });
  return pairs;
}

void require_bodies_apart(double least_distance, double dh) {
  if (least_distance > 0) return;
  throw InputError(
      "bodies touch at the start (a vertex on another body's surface, or two edges meeting), "
      "where the contact barrier is infinite and no contact plane is defined: leave a gap, "
      "below contact.distance = " +
      std::to_string(dh) + " m if they should rest on each other");
}

template ContactPairs find_contact_pairs(const ContactHalo<double>&, double, bool,
                                         const std::vector<double>*, const std::vector<double>*);
template ContactPairs find_contact_pairs(const ContactHalo<float>&, double, bool,
                                         const std::vector<float>*, const std::vector<double>*);

}  // namespace descent

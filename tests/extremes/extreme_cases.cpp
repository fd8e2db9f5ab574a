#include "extreme_cases.hpp"

#include <cmath>
#include <random>

#include "app/scene_mesh.hpp"
#include "common/error.hpp"
#include "meshes/generators.hpp"

namespace descent::extremes {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Edge length over height of the glued sliver and needle tets.
constexpr double kBadAspect = 1e4;

void set_model(Scene& scene, const std::string& model) {
  scene.material.model = model;
  // Stiffening terms scaled with E, as in the recovery tests (E / 20).
  if (model == "mooney_rivlin" || model == "fung") scene.material.c2 = scene.material.young / 20;
  if (model == "fung") scene.material.c3 = 2.0;
}

// The hanging helix of the foundation tests, coarser (1,704 tets) so the
// sweep stays fast: top cap held, gravity along -y, E = 100 kPa, 96
// iterations per step at h = 1/30 s.
Case helix_case() {
  Case c;
  Scene& s = c.scene;
  s.mesh.generator = "double_helix";
  s.mesh.helix.resolution = 0.8;
  const double height = double_helix_height(s.mesh.helix);
  FixedRegion top;
  top.box_min = {-1.0, height - 0.04, -1.0};
  top.box_max = {1.0, height + 1.0, 1.0};
  s.fixed.push_back(top);
  s.material.young = 1e5;
  s.material.poisson = 0.3;
  s.material.density = 1000;
  s.time.dt = 1.0 / 30.0;
  s.solver.iterations = 96;
  c.frames = 10;
  return c;
}

Scene unit_box_scene(int cells) {
  Scene s;
  s.mesh.generator = "box";
  s.mesh.box.cells = {cells, cells, cells};
  s.material.young = 1e5;
  s.material.poisson = 0.3;
  return s;
}

// jobs/box/deform.toml: the bottom face held, the top face moved over 1 s of
// 20 quasi-static frames, conversion on.
Case deform_case(const Motion& motion) {
  Case c;
  Scene& s = c.scene;
  s = unit_box_scene(3);
  s.gravity = {0.0, 0.0, 0.0};
  s.material.conversion.enabled = true;
  FixedRegion bottom, top;
  bottom.box_min = {-0.01, -0.01, -0.01};
  bottom.box_max = {1.01, 0.01, 1.01};
  top.box_min = {-0.01, 0.99, -0.01};
  top.box_max = {1.01, 1.01, 1.01};
  top.motion = motion;
  top.motion.until = 1.0;
  s.fixed = {bottom, top};
  s.time.quasistatic = true;
  s.time.dt = 0.05;
  s.solver.iterations = 400;
  s.solver.init = "velocity";
  c.frames = 20;
  return c;
}

// The recovery tests' set-up on a 3x3x3-cell box: no gravity, nothing held,
// quasi-static, conversion on, 100 frames of 200 iterations.
Case recovery_case(Start start) {
  Case c;
  Scene& s = c.scene;
  s = unit_box_scene(3);
  s.gravity = {0.0, 0.0, 0.0};
  s.material.conversion.enabled = true;
  s.time.quasistatic = true;
  s.solver.iterations = 200;
  s.solver.init = "position";
  c.frames = 100;
  c.start = start;
  c.recovers = true;
  return c;
}

void orient_positively(const Mesh& mesh, index_t* tet) {
  const double* p[4];
  for (int a = 0; a < 4; ++a) p[a] = &mesh.positions[3 * std::size_t(tet[a])];
  double e[3][3];
  for (int k = 0; k < 3; ++k)
    for (int i = 0; i < 3; ++i) e[k][i] = p[k + 1][i] - p[0][i];
  const double d = e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) -
                   e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
                   e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0]);
  if (d < 0) std::swap(tet[2], tet[3]);
}

// A face of the box's top (y = size) with its three corners, the first found.
std::array<index_t, 3> top_face(const Mesh& box, double top) {
  for (index_t t = 0; t < box.num_tets(); ++t)
    for (const auto& face : kTetFaces) {
      std::array<index_t, 3> f;
      bool on_top = true;
      for (int k = 0; k < 3; ++k) {
        f[k] = box.tets[4 * t + face[k]];
        on_top = on_top && box.positions[3 * std::size_t(f[k]) + 1] == top;
      }
      if (on_top) return f;
    }
  throw LogicError("the box has no face on its top");
}

index_t add_vertex(Mesh& mesh, const std::array<double, 3>& x) {
  mesh.positions.insert(mesh.positions.end(), x.begin(), x.end());
  return mesh.num_vertices() - 1;
}

std::array<double, 3> at(const Mesh& mesh, index_t v) {
  const double* p = &mesh.positions[3 * std::size_t(v)];
  return {p[0], p[1], p[2]};
}

// The 3x3x3-cell unit box standing on its held bottom face under gravity,
// dynamic, with one bad tet glued on its top: a sliver
// (four nearly coplanar corners, all edges ~1/3 m, height 1e-4 of that) or a
// needle (one edge 1/3 m, the two other corners within 1e-4 of its middle).
Case glued_case(bool sliver) {
  Case c;
  Scene& s = c.scene;
  s = unit_box_scene(3);
  FixedRegion bottom;
  bottom.box_min = {-0.01, -0.01, -0.01};
  bottom.box_max = {1.01, 0.01, 1.01};
  s.fixed = {bottom};
  s.time.dt = 1.0 / 30.0;
  s.solver.iterations = 96;
  c.frames = 10;
  Mesh mesh = make_box(s.mesh.box);
  const std::array<index_t, 3> f = top_face(mesh, 1.0);
  const auto a = at(mesh, f[0]), b = at(mesh, f[1]), cc = at(mesh, f[2]);
  index_t tet[4];
  if (sliver) {
    // Above the parallelogram a, b, c, a + c - b: a flat tet on the face.
    double edge = 0;
    for (int i = 0; i < 3; ++i) edge = std::max(edge, std::abs(a[i] - b[i]));
    const std::array<double, 3> d = {a[0] + cc[0] - b[0], 1.0 + edge / kBadAspect,
                                     a[2] + cc[2] - b[2]};
    tet[0] = f[0];
    tet[1] = f[1];
    tet[2] = f[2];
    tet[3] = add_vertex(mesh, d);
    mesh.source += " + a sliver tet (aspect ratio 1e4) on its top";
  } else {
    // Along the edge a-b, two corners within eps of its middle, above it.
    double length = 0;
    for (int i = 0; i < 3; ++i) length += (a[i] - b[i]) * (a[i] - b[i]);
    length = std::sqrt(length);
    const double eps = length / kBadAspect;
    const std::array<double, 3> m = {(a[0] + b[0]) / 2, 1.0, (a[2] + b[2]) / 2};
    // A horizontal direction across the edge.
    std::array<double, 3> across = {-(b[2] - a[2]) / length, 0.0, (b[0] - a[0]) / length};
    tet[0] = f[0];
    tet[1] = f[1];
    tet[2] = add_vertex(mesh, {m[0], 1.0 + eps, m[2]});
    tet[3] = add_vertex(mesh, {m[0] + eps * across[0], 1.0 + eps / 2, m[2] + eps * across[2]});
    mesh.source += " + a needle tet (aspect ratio 1e4) on a top edge";
  }
  orient_positively(mesh, tet);
  mesh.tets.insert(mesh.tets.end(), tet, tet + 4);
  c.mesh = std::move(mesh);
  return c;
}

// A rod (1.5 x 0.5 x 0.5 m) whose far end face is held; everything else
// flies at 100 m/s toward it: the free part slams into the held vertices.
Case throw_case() {
  Case c;
  Scene& s = c.scene;
  s.mesh.generator = "box";
  s.mesh.box.cells = {6, 2, 2};
  s.mesh.box.size = {1.5, 0.5, 0.5};
  s.gravity = {0.0, 0.0, 0.0};
  s.material.young = 1e5;
  s.material.poisson = 0.3;
  s.material.conversion.enabled = true;
  FixedRegion end;
  end.box_min = {1.49, -0.01, -0.01};
  end.box_max = {1.51, 0.51, 0.51};
  s.fixed = {end};
  s.time.dt = 1.0 / 30.0;
  s.solver.iterations = 96;
  c.frames = 10;
  c.velocity = {100.0, 0.0, 0.0};
  return c;
}

// A box (0.3 m, 162 tets) thrown at 20 m/s straight down at a floor 0.1 m
// below it, h = 1/30 s: in its first step it would pass 0.67 m, through the
// floor, without contact (docs/contact.md: the barrier, the guarded guess
// and iterations).
Case floor_case() {
  Case c;
  Scene& s = c.scene;
  s = unit_box_scene(3);
  s.mesh.box.size = {0.3, 0.3, 0.3};
  s.mesh.box.origin = {0.0, 0.1, 0.0};
  s.gravity = {0.0, -9.81, 0.0};
  s.material.conversion.enabled = true;
  Obstacle floor;
  floor.kind = "plane";
  floor.normal = {0.0, 1.0, 0.0};
  floor.friction = 0.5;
  s.obstacles = {floor};
  s.time.dt = 1.0 / 30.0;
  s.solver.iterations = 96;
  c.frames = 10;
  c.velocity = {0.0, -20.0, 0.0};
  return c;
}

// Two boxes thrown at each other at 10 m/s each (20 m/s relative), 0.1 m
// apart: contact between bodies (docs/contact.md) at the crossing-prone
// extreme, with conversion on.
Case bodies_case() {
  Case c;
  Scene& s = c.scene;
  s = unit_box_scene(3);
  Body left, right;
  for (Body* b : {&left, &right}) {
    b->mesh = s.mesh;
    b->mesh.box.size = {0.2, 0.2, 0.2};
  }
  left.velocity = {10.0, 0.0, 0.0};
  right.translate = {0.3, 0.03, 0.02};
  right.velocity = {-10.0, 0.0, 0.0};
  s.mesh = MeshSpec{};
  s.bodies = {left, right};
  s.gravity = {0.0, -9.81, 0.0};
  s.material.conversion.enabled = true;
  s.time.dt = 1.0 / 30.0;
  s.solver.iterations = 96;
  c.frames = 10;
  return c;
}

}  // namespace

std::vector<std::string> case_names() {
  return {"dt_0.001",
          "dt_0.01",
          "dt_0.033",
          "dt_0.1",
          "dt_1",
          "quasistatic",
          "E_1e3",
          "E_1e7",
          "E_1e9",
          "E_1e11",
          "nu_0.45",
          "nu_0.499",
          "stretch_5x",
          "compress_0.05",
          "twist_2pi",
          "random",
          "collapse",
          "sliver",
          "needle",
          "throw_100",
          "floor_20",
          "bodies_20",
          "bodies_20_projection"};
}

const std::vector<std::string>& model_names() {
  static const std::vector<std::string> names = {"stvk", "neo_hookean", "mooney_rivlin",
                                                 "fung", "corotated",   "arap"};
  return names;
}

Case make_case(const std::string& name, const std::string& model) {
  bool known_model = false;
  for (const std::string& m : model_names()) known_model = known_model || m == model;
  if (!known_model) throw InputError(detail::concat("unknown model '", model, "'"));
  Case c;
  if (name.rfind("dt_", 0) == 0 || name == "quasistatic" || name.rfind("E_", 0) == 0 ||
      name.rfind("nu_", 0) == 0) {
    c = helix_case();
    c.group = name.rfind("E_", 0) == 0    ? "stiffness"
              : name.rfind("nu_", 0) == 0 ? "Poisson ratio"
                                          : "time step";
    if (name == "dt_0.001")
      c.scene.time.dt = 1e-3;
    else if (name == "dt_0.01")
      c.scene.time.dt = 1e-2;
    else if (name == "dt_0.033")
      c.scene.time.dt = 1.0 / 30.0;
    else if (name == "dt_0.1")
      c.scene.time.dt = 0.1;
    else if (name == "dt_1")
      c.scene.time.dt = 1.0;
    else if (name == "quasistatic")
      c.scene.time.quasistatic = true;
    else if (name == "E_1e3")
      c.scene.material.young = 1e3;
    else if (name == "E_1e7")
      c.scene.material.young = 1e7;
    else if (name == "E_1e9")
      c.scene.material.young = 1e9;
    else if (name == "E_1e11")
      c.scene.material.young = 1e11;
    else if (name == "nu_0.45")
      c.scene.material.poisson = 0.45;
    else if (name == "nu_0.499")
      c.scene.material.poisson = 0.499;
    else
      throw InputError(detail::concat("unknown case '", name, "'"));
    c.what =
        detail::concat("hanging helix (1,704 tets), h = ", c.scene.time.dt, " s",
                       c.scene.time.quasistatic ? " (quasi-static)" : "",
                       ", E = ", c.scene.material.young, " Pa, nu = ", c.scene.material.poisson,
                       ", ", c.frames, " steps of ", c.scene.solver.iterations, " iterations");
  } else if (name == "stretch_5x" || name == "compress_0.05" || name == "twist_2pi") {
    Motion motion;
    if (name == "twist_2pi") {
      motion.kind = "rotate";
      motion.axis = {0.0, 1.0, 0.0};
      motion.centre = {0.5, 0.0, 0.5};
      motion.angular_velocity = 2 * kPi;
    } else {
      motion.kind = "translate";
      motion.velocity = {0.0, name == "stretch_5x" ? 4.0 : -0.95, 0.0};
    }
    c = deform_case(motion);
    c.group = "deformation";
    c.what = name == "stretch_5x"      ? "unit box (162 tets), top face pulled to 5x height"
             : name == "compress_0.05" ? "unit box (162 tets), top face pushed to 5% height"
                                       : "unit box (162 tets), top face twisted by 2 pi";
    c.what += ", 20 quasi-static frames of 400 iterations, conversion on";
  } else if (name == "random" || name == "collapse") {
    c = recovery_case(name == "random" ? Start::random : Start::collapsed);
    c.group = "recovery";
    c.what = name == "random"
                 ? "unit box (162 tets), every vertex uniform in the box; recover the rest shape"
                 : "unit box (162 tets), every vertex at the centre; recover the rest shape";
    c.what += " (quasi-static, 100 frames of 200 iterations, conversion on)";
  } else if (name == "sliver" || name == "needle") {
    c = glued_case(name == "sliver");
    c.group = "bad elements";
    c.what = detail::concat("unit box (162 tets) standing under gravity with a ", name,
                            " tet of aspect ratio 1e4 glued on top, h = 1/30 s");
  } else if (name == "throw_100") {
    c = throw_case();
    c.group = "velocity";
    c.what = "rod (144 tets) flying at 100 m/s into its held far end, h = 1/30 s, conversion on";
  } else if (name == "floor_20") {
    c = floor_case();
    c.group = "contact";
    c.what = "box (162 tets) thrown at 20 m/s onto a floor 0.1 m below, h = 1/30 s, conversion on";
  } else if (name == "bodies_20" || name == "bodies_20_projection") {
    c = bodies_case();
    c.group = "contact";
    c.what =
        "two boxes (2 x 162 tets) thrown at each other at 20 m/s relative, h = 1/30 s, "
        "conversion on";
    if (name == "bodies_20_projection") {
      // Each solve takes them through each other; the pass brings them back.
      c.scene.contact.method = "projection";
      c.what += ", contact.method = \"projection\"";
    }
  } else {
    throw InputError(detail::concat("unknown case '", name, "'"));
  }
  c.name = name;
  set_model(c.scene, model);
  if (c.mesh.tets.empty()) c.mesh = build_scene_mesh(c.scene);
  return c;
}

std::vector<double> start_positions(const Case& c) {
  std::vector<double> x = c.mesh.positions;
  if (c.start == Start::rest) return x;
  double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
  for (std::size_t k = 0; k < x.size(); ++k) {
    lo[k % 3] = std::min(lo[k % 3], x[k]);
    hi[k % 3] = std::max(hi[k % 3], x[k]);
  }
  std::mt19937_64 rng(2024);  // the same draw on every rank
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (std::size_t k = 0; k < x.size(); ++k) {
    const int i = static_cast<int>(k % 3);
    x[k] = c.start == Start::random ? lo[i] + (hi[i] - lo[i]) * u(rng) : (lo[i] + hi[i]) / 2;
  }
  return x;
}

}  // namespace descent::extremes

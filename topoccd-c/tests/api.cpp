// Tests of the C++ wrapper, run under AddressSanitizer by scripts/test-c.sh, with Eigen (and
// once without, -DTOPOCCD_NO_EIGEN): RAII and moves, exceptions carrying the library's
// message, views that point into the library's arrays, every input layout, the Eigen
// overloads and their refusals. The last line says how many checks passed and failed.
#include <topoccd.hpp>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

static int passed, failed;

#define CHECK(cond, what)                                                               \
  do {                                                                                  \
    if (cond) {                                                                         \
      passed++;                                                                         \
    } else {                                                                            \
      failed++;                                                                         \
      std::fprintf(stderr, "FAILED %s:%d: %s: %s\n", __FILE__, __LINE__, #cond,         \
                   std::string(what).c_str());                                          \
    }                                                                                   \
  } while (0)

// Runs `body`, which must throw topoccd::Error with `status` and a message containing `part`.
template <class F>
static void expect_error(F body, topoccd_status status, const std::string& part,
                         const std::string& what) {
  try {
    body();
    CHECK(false, what + ": no exception");
  } catch (const topoccd::Error& e) {
    CHECK(e.status() == status, what + ": " + e.status_name());
    CHECK(std::string(e.what()).find(part) != std::string::npos,
          what + ": '" + e.what() + "' lacks '" + part + "'");
  }
}

// A triangle (3 4 5) falls through a fixed one (0 1 2): vertex 3 at t=0.5, 4 and 5 at 0.75.
static const std::vector<std::array<double, 3>> X0 = {
    {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.2, 0.2, 1}, {0.3, 0.2, 1.5}, {0.2, 0.3, 1.5}};
static const std::vector<std::array<double, 3>> X1 = {
    {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.2, 0.2, -1}, {0.3, 0.2, -0.5}, {0.2, 0.3, -0.5}};
static const std::vector<std::array<std::uint32_t, 3>> TRIS = {{0, 1, 2}, {3, 4, 5}};

static bool is_fall(const topoccd::Report& r) {
  if (r.vf().size() != 3 || !r.ee().empty()) return false;
  const std::uint32_t vertex[3] = {3, 4, 5};
  const double toi[3] = {0.5, 0.75, 0.75};
  for (std::size_t i = 0; i < 3; i++) {
    const topoccd_vf_contact& c = r.vf()[i];
    if (c.vertex != vertex[i] || c.face != 0 || !(c.toi <= toi[i] && c.toi > toi[i] - 1e-6))
      return false;
  }
  return r.earliest_vf() == &r.vf()[0] && r.earliest_ee() == nullptr && r.unresolved() == 0;
}

static void test_layouts() {
  topoccd::Ccd ccd;
  topoccd::Report r = ccd.query(X0, X1, TRIS);
  CHECK(is_fall(r), "vectors of arrays");
  CHECK(r.vf().data() == r.c().vf, "the view points into the library's array, no copy");
  CHECK(r.method() == topoccd::Method::Bvh, "auto ran bvh");
  CHECK(r.earliest_toi() && *r.earliest_toi() == r.vf()[0].toi, "earliest toi");

  const double c0[6][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.2, 0.2, 1}, {0.3, 0.2, 1.5}, {0.2, 0.3, 1.5}};
  const double c1[6][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.2, 0.2, -1}, {0.3, 0.2, -0.5}, {0.2, 0.3, -0.5}};
  const std::uint32_t ct[2][3] = {{0, 1, 2}, {3, 4, 5}};
  CHECK(is_fall(ccd.query(c0, c1, ct)), "C arrays");

  std::vector<double> f0(&X0[0][0], &X0[0][0] + 18), f1(&X1[0][0], &X1[0][0] + 18);
  std::vector<std::uint32_t> ft = {0, 1, 2, 3, 4, 5};
  CHECK(is_fall(ccd.query(f0, f1, ft)), "flat vectors");
  CHECK(is_fall(ccd.query(topoccd::Points(f0.data(), 6), topoccd::Points(f1.data(), 6),
                          topoccd::Indices(ft.data(), 2))),
        "pointers and row counts");
  f0.pop_back();
  expect_error([&] { ccd.query(f0, f1, ft); }, TOPOCCD_STATUS_INVALID_ARGUMENT,
               "a flat array of 17 values is not rows of 3", "flat size");
  expect_error([&] { r.vf().at(3); }, TOPOCCD_STATUS_OUT_OF_RANGE, "index 3 is out of range",
               "at() past the end");

  auto groups = std::vector<std::uint32_t>{0, 0, 0, 0, 0, 0};
  CHECK(ccd.query(topoccd::Step(X0, X1, TRIS).groups(groups)).contact_count() == 0, "one group");
}

static void test_options_and_errors() {
  topoccd::Ccd ccd;
  auto earliest = topoccd::QueryOptions().mode(topoccd::Mode::Earliest).geometry(true);
  CHECK(earliest.mode() == topoccd::Mode::Earliest && earliest.geometry() && earliest.k() == 18,
        "setters and getters");
  topoccd::Report r = ccd.query(topoccd::Step(X0, X1, TRIS), earliest);
  CHECK(r.vf().size() == 1 && r.vf()[0].vertex == 3 && r.vf()[0].has_geometry, "earliest");
  CHECK(r.vf()[0].geometry.normal[2] == 1.0, "the face's normal, towards the vertex");
  CHECK(r.earliest_complete(), "one pair at the earliest time, listed");

  // A triangle falls flat through another, its three corners over the other's interior: three
  // vertex-face pairs at t = 1/2. Under a cap of one, Earliest keeps one and says so.
  const std::vector<std::array<double, 3>> flat0 = {
      {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.2, 0.2, 1}, {0.3, 0.2, 1}, {0.2, 0.3, 1}};
  std::vector<std::array<double, 3>> flat1 = flat0;
  for (int v = 3; v < 6; ++v) flat1[v][2] = -1;
  auto first = topoccd::QueryOptions().mode(topoccd::Mode::Earliest);
  topoccd::Report all3 = ccd.query(flat0, flat1, TRIS, first);
  CHECK(all3.vf().size() == 3 && all3.earliest_complete(), "three pairs, complete");
  topoccd::Report capped = ccd.query(flat0, flat1, TRIS, first.max_contacts(1));
  CHECK(capped.vf().size() == 1 && !capped.earliest_complete(), "one pair kept, incomplete");
  CHECK(capped.earliest_toi() && *capped.earliest_toi() <= 0.5 &&
            *capped.earliest_toi() > 0.5 - 1e-6,
        "the earliest time is exact under the cap");

  expect_error([&] { ccd.query(X0, X1, TRIS, topoccd::QueryOptions().tolerance(0)); },
               TOPOCCD_STATUS_INVALID_OPTIONS, "tolerance must be in (0, 1), got 0", "tolerance");
  expect_error([&] { ccd.query(X0, X1, TRIS, topoccd::QueryOptions().k(7)); },
               TOPOCCD_STATUS_INVALID_OPTIONS, "k must be 6, 14, 18 or 26, got 7", "k");
  CHECK(ccd.report().contact_count() == 0, "the report is empty after a failure");

  auto bad = TRIS;
  bad[1][2] = 99;
  expect_error([&] { ccd.query(X0, X1, bad); }, TOPOCCD_STATUS_INVALID_STEP,
               "triangle 1 names vertex 99, but there are only 6 vertices", "index out of range");
  auto nan = X1;
  nan[4][1] = std::nan("");
  expect_error([&] { ccd.query(X0, nan, TRIS); }, TOPOCCD_STATUS_INVALID_STEP,
               "vertex 4 has a non-finite coordinate at t=1", "NaN");
  auto shorter = X1;
  shorter.pop_back();
  expect_error([&] { ccd.query(X0, shorter, TRIS); }, TOPOCCD_STATUS_INVALID_STEP,
               "the step has 6 vertices at t=0 but 5 at t=1", "mismatched lengths");

  // A moved-from Ccd holds nothing: its queries are refused, not run on freed memory.
  topoccd::Ccd moved = std::move(ccd);
  CHECK(ccd.get() == nullptr && moved.get() != nullptr, "move");
  expect_error([&] { ccd.query(X0, X1, TRIS); }, TOPOCCD_STATUS_NULL_POINTER, "ccd is NULL",
               "moved-from Ccd");
  CHECK(is_fall(moved.query(X0, X1, TRIS)), "the moved-to Ccd works");
  ccd = std::move(moved);
  CHECK(is_fall(ccd.query(X0, X1, TRIS)), "move assignment");
}

static void test_cut() {
  // The README's step across a cut (see the guide's C++ quick start).
  std::vector<std::array<double, 3>> x0 = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.8, 0.8, 1}};
  std::vector<std::array<double, 3>> x1 = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0},
                                           {0, 0, -1}, {1, 0, 0}, {0, 1, 0}};
  std::vector<std::array<std::uint32_t, 3>> triangles = {{0, 1, 2}, {4, 3, 5}};
  std::vector<std::array<std::uint32_t, 2>> parents = {{4, 1}, {5, 2}};
  topoccd::Ccd ccd;
  auto r = ccd.query(topoccd::Step(x0, x1, triangles).parents(parents));
  CHECK(r.contact_count() == 1 && r.vf()[0].vertex == 3 && std::fabs(r.vf()[0].toi - 0.5) < 1e-6,
        "the tip falls through at 0.5");
  expect_error([&] { ccd.query(x0, x1, triangles); }, TOPOCCD_STATUS_INVALID_STEP,
               "4 vertices at t=0 but 6 at t=1", "a cut without parents");
  std::vector<std::array<std::uint32_t, 2>> none;
  CHECK(ccd.query(topoccd::Step(x0, x1, triangles).parents(none)).contact_count() > 1,
        "empty parents: the new vertices do not move, and sit on the old ones");
}

static void test_pairs_and_files() {
  topoccd_vertex_face q{};
  q.v_t0[0] = q.v_t0[1] = q.v_t1[0] = q.v_t1[1] = 0.2;
  q.v_t0[2] = 1;
  q.v_t1[2] = -1;
  q.f1_t0[0] = q.f1_t1[0] = 1;
  q.f2_t0[1] = q.f2_t1[1] = 1;
  topoccd::Outcome o = topoccd::vertex_face(q);
  CHECK(o && o.toi <= 0.5 && o.toi > 0.5 - 1e-6 && o.certainty == TOPOCCD_CERTAINTY_RESOLVED,
        "vertex_face");
  expect_error([&] { topoccd::vertex_face(q, topoccd::QueryOptions().max_iterations(0)); },
               TOPOCCD_STATUS_INVALID_OPTIONS, "max_iterations must be at least 1", "pair options");
  topoccd_edge_edge e{};
  e.ea1_t0[0] = e.ea1_t1[0] = 1;  // edge a from the origin along x, edge b far away
  e.eb0_t0[2] = e.eb1_t0[2] = e.eb0_t1[2] = e.eb1_t1[2] = 5;
  e.eb1_t0[1] = e.eb1_t1[1] = 1;
  CHECK(!topoccd::edge_edge(e) && std::isnan(topoccd::edge_edge(e).toi), "edge_edge apart");

  expect_error([] { topoccd::Mesh::read("/nonexistent/x.ply"); }, TOPOCCD_STATUS_IO,
               "/nonexistent/x.ply: cannot open", "missing mesh");
  expect_error([] { topoccd::Frames::read("/nonexistent/a.obj", "/nonexistent/b.obj"); },
               TOPOCCD_STATUS_IO, "/nonexistent/a.obj", "missing frames");
  expect_error([] { topoccd::Sequence::open("/nonexistent"); }, TOPOCCD_STATUS_IO,
               "cannot list the folder", "missing sequence");
}

#if defined(TOPOCCD_HAS_EIGEN)
using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
using RowIndices = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;

static void test_eigen() {
  RowMatrix x0(6, 3), x1(6, 3);
  for (int i = 0; i < 6; i++) {
    for (int j = 0; j < 3; j++) {
      x0(i, j) = X0[i][j];
      x1(i, j) = X1[i][j];
    }
  }
  RowIndices f(2, 3);
  f << 0, 1, 2, 3, 4, 5;
  topoccd::Ccd ccd;
  CHECK(is_fall(ccd.query(x0, x1, f)), "Eigen row-major matrices");
  topoccd::Points view(x0);
  CHECK(view.data() == x0.data() && view.rows() == 6, "read in place, not copied");

  Eigen::Map<const RowMatrix> m0(&X0[0][0], 6, 3), m1(&X1[0][0], 6, 3);
  CHECK(is_fall(ccd.query(m0, m1, f)), "Eigen maps of the caller's memory");
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> dyn = x0;
  CHECK(is_fall(ccd.query(dyn, x1, f)), "a dynamic row-major matrix of 3 columns");
  RowMatrix both(12, 3);
  both << x0, x1;
  CHECK(is_fall(ccd.query(both.topRows(6), both.bottomRows(6), f)), "row blocks are contiguous");

  Eigen::Matrix<double, Eigen::Dynamic, 4, Eigen::RowMajor> wide(6, 4);
  wide.leftCols(3) = x0;
  expect_error([&] { ccd.query(wide.leftCols(3), x1, f); }, TOPOCCD_STATUS_INVALID_ARGUMENT,
               "rows are not contiguous", "a column block");
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> four(6, 4);
  expect_error([&] { ccd.query(four, x1, f); }, TOPOCCD_STATUS_INVALID_ARGUMENT,
               "an Eigen matrix of 4 columns, not 3", "4 columns");
  f(1, 2) = -1;  // a negative index reads as 4294967295: out of range, refused
  expect_error([&] { ccd.query(x0, x1, f); }, TOPOCCD_STATUS_INVALID_STEP,
               "triangle 1 names vertex 4294967295", "a negative index");
}
#endif

// The accessors that return a reference into their object compile on an lvalue only: on a
// temporary (`frames.step().c()`) the reference would dangle, so those overloads are deleted.
// (scripts/test-c.sh also checks that the dangling form itself fails to compile.)
template <class T, class = void>
struct c_on_rvalue : std::false_type {};
template <class T>
struct c_on_rvalue<T, std::void_t<decltype(std::declval<T>().c())>> : std::true_type {};
static_assert(!c_on_rvalue<topoccd::Step>::value, "Step::c() on a temporary must not compile");
static_assert(!c_on_rvalue<const topoccd::Step>::value, "nor on a const temporary");
static_assert(c_on_rvalue<topoccd::Step&>::value, "Step::c() on an lvalue compiles");
static_assert(c_on_rvalue<const topoccd::Step&>::value, "and on a const lvalue");
static_assert(!c_on_rvalue<topoccd::QueryOptions>::value, "QueryOptions::c() on a temporary");
static_assert(c_on_rvalue<topoccd::QueryOptions&>::value, "QueryOptions::c() on an lvalue");
static_assert(!c_on_rvalue<topoccd::LineSearchOptions>::value, "LineSearchOptions::c() too");
static_assert(c_on_rvalue<const topoccd::LineSearchOptions&>::value, "on an lvalue");
// A chain of setters on a temporary stays a temporary (so `.c()` at its end is refused too).
static_assert(std::is_same<decltype(topoccd::QueryOptions().tmax(0.5)), topoccd::QueryOptions&&>::value,
              "a setter on a temporary returns an rvalue");
static_assert(std::is_same<decltype(std::declval<topoccd::QueryOptions&>().tmax(0.5)),
                           topoccd::QueryOptions&>::value,
              "a setter on an lvalue returns an lvalue");
static_assert(std::is_same<decltype(topoccd::LineSearchOptions().check_start(true)),
                           topoccd::LineSearchOptions&&>::value,
              "LineSearchOptions too");

// The line-search helpers on the falling triangle (analytic: vertex 3 on face 0 at t=0.5), a
// piercing start with check_start, and a timeout.
static void test_line_search() {
  topoccd::Ccd ccd;
  topoccd::Step step(X0, X1, TRIS);
  topoccd::StepSize size = ccd.collision_free_stepsize(step);
  CHECK(size.alpha <= 0.4 && size.alpha >= 0.8 * (0.5 - 1e-6), std::to_string(size.alpha));
  const topoccd_vf_contact* c = size.report.earliest_vf();
  CHECK(c != nullptr && c->vertex == 3 && c->face == 0, "the earliest contact is vertex 3's");
  CHECK(size.report.earliest_toi() && size.alpha == 0.8 * *size.report.earliest_toi(), "0.8 toi");
  CHECK(!ccd.is_step_collision_free(step), "the step collides");
  auto before = topoccd::LineSearchOptions().query(topoccd::QueryOptions().tmax(0.4));
  CHECK(ccd.is_step_collision_free(step, before), "free before the contact");
  CHECK(ccd.collision_free_stepsize(step, before).alpha == 0.4, "tmax without contact");
  auto half = topoccd::LineSearchOptions().conservative_rescaling(0.5);
  size = ccd.collision_free_stepsize(step, half);
  CHECK(size.alpha == 0.5 * *size.report.earliest_toi(), "conservative_rescaling 0.5");

  // Triangle 1 pierces triangle 0 and stays: taken whole unless check_start looks.
  std::vector<std::array<double, 3>> pierce = {
      {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.2, 0.2, -1}, {0.3, 0.2, 1}, {0.2, 0.3, 1}};
  topoccd::Step pierced(pierce, pierce, TRIS);
  CHECK(ccd.collision_free_stepsize(pierced).alpha == 1.0, "unchecked");
  auto checked = topoccd::LineSearchOptions().check_start(true);
  expect_error([&] { ccd.collision_free_stepsize(pierced, checked); },
               TOPOCCD_STATUS_START_INTERSECTS, "triangles 0 and 1 intersect at t=0", "check_start");
  expect_error([&] { ccd.is_step_collision_free(pierced, checked); },
               TOPOCCD_STATUS_START_INTERSECTS, "intersect at t=0", "check_start");
  expect_error([&] { ccd.collision_free_stepsize(step, topoccd::LineSearchOptions().conservative_rescaling(0)); },
               TOPOCCD_STATUS_INVALID_OPTIONS, "conservative_rescaling must be in (0, 1]", "0");
  topoccd::LineSearchOptions timed;
  timed.query().timeout(60).max_contacts(1);
  CHECK(timed.query().timeout() == 60 && timed.query().max_contacts() == 1, "query options kept");
  CHECK(ccd.collision_free_stepsize(step, timed).alpha == 0.8 * *ccd.report().earliest_toi(),
        "a timeout that does not pass and a cap");
}

// Proximity through the wrapper: the pairs of a vertex above a triangle and a rod over it.
static void test_proximity() {
  const std::vector<std::array<double, 3>> x = {
      {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.2, 0.2, 0.5e-3}, {0.5, -0.5, 0.2e-3}, {0.6, 0.5, 0.2e-3}};
  const std::vector<std::array<std::uint32_t, 3>> tris = {{0, 1, 2}};
  const std::vector<std::array<std::uint32_t, 2>> rods = {{4, 5}};
  topoccd::Ccd ccd;
  auto p = ccd.proximity(x, tris, rods, topoccd::ProximityOptions().dhat(1e-3));
  CHECK(p.vf().size() == 1 && p.vf()[0].vertex == 3 && p.vf()[0].type == 6, "vf");
  CHECK(p.ee().size() == 2 && p.ee()[0].type == 8, "ee");
  CHECK(p.size() == 3 && !p.refitted(), "count, built");
  CHECK(ccd.proximity(x, tris, rods).refitted(), "refitted");
  expect_error([&] { ccd.proximity(x, tris, topoccd::ProximityOptions().dhat(0)); },
               TOPOCCD_STATUS_INVALID_OPTIONS, "dhat", "dhat 0");
}

// Codimensional geometry: a free edge (0 1), a point (2) falling across it at t=0.5, a point
// (3) falling onto a fixed point (4) at t=0.25; no triangles.
static void test_codim() {
  const std::vector<std::array<double, 3>> x0 = {
      {0, 0, 0}, {1, 0, 0}, {0.5, 0, 1}, {3, 0, 0.5}, {3, 0, 0}};
  const std::vector<std::array<double, 3>> x1 = {
      {0, 0, 0}, {1, 0, 0}, {0.5, 0, -1}, {3, 0, -1.5}, {3, 0, 0}};
  const std::vector<std::array<std::uint32_t, 3>> none;
  const std::vector<std::array<std::uint32_t, 2>> edges = {{0, 1}};
  topoccd::Ccd ccd;
  auto r = ccd.query(topoccd::Step(x0, x1, none).edges(edges));
  CHECK(r.contact_count() == 2 && r.ve().size() == 1 && r.vv().size() == 1, "one ve, one vv");
  if (r.ve().size() == 1) {
    const topoccd_ve_contact& c = r.ve()[0];
    CHECK(c.vertex == 2 && c.edge[0] == 0 && c.edge[1] == 1, "the ve pair");
    CHECK(c.toi <= 0.5 && c.toi > 0.5 - 1e-6, "ve toi " + std::to_string(c.toi));
  }
  if (r.vv().size() == 1) {
    const topoccd_vv_contact& c = r.vv()[0];
    CHECK(c.a == 3 && c.b == 4, "the vv pair");
    CHECK(c.toi <= 0.25 && c.toi > 0.25 - 1e-6, "vv toi " + std::to_string(c.toi));
    CHECK(r.earliest_vv() == &r.vv()[0] && r.earliest_ve() == nullptr && r.earliest_vf() == nullptr,
          "the earliest is the vv contact");
  }
  // The edge alone with the falling point: the earliest is the ve contact.
  const std::vector<std::array<double, 3>> y0(x0.begin(), x0.begin() + 3);
  const std::vector<std::array<double, 3>> y1(x1.begin(), x1.begin() + 3);
  r = ccd.query(topoccd::Step(y0, y1, none).edges(edges));
  CHECK(r.ve().size() == 1 && r.earliest_ve() == &r.ve()[0] && r.earliest_vv() == nullptr,
        "the earliest is the ve contact");
  // Without edges, vertices in no triangle are ignored.
  CHECK(ccd.query(topoccd::Step(x0, x1, none)).contact_count() == 0, "no edges, no contacts");
  const std::vector<std::array<std::uint32_t, 2>> far = {{0, 9}};
  expect_error([&] { ccd.query(topoccd::Step(x0, x1, none).edges(far)); },
               TOPOCCD_STATUS_INVALID_STEP, "edge 0 names vertex 9", "an edge out of range");
}

// The contact potential's wrapper: a point over a triangle (the analytic energy), Eigen's
// sparse matrix when there, and the errors as exceptions.
static void test_ipc() {
  namespace ti = topoccd::ipc;
  const std::vector<std::array<double, 3>> x = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.2, 0.2, 0.5e-3}};
  const std::vector<std::array<std::uint32_t, 3>> f = {{0, 1, 2}};
  const ti::CollisionMesh mesh(x, f);
  ti::NormalCollisions c;
  const ti::BarrierPotential B(1e-3, 1.0);
  expect_error([&] { B(c, mesh, x); }, TOPOCCD_STATUS_NULL_POINTER, "never built", "unbuilt set");
  CHECK(c.size() == 0 && c.empty(), "empty before build");
  c.build(mesh, x, 1e-3);
  CHECK(c.size() == 1 && c.fv_collisions().size() == 1 && c.fv_collisions()[0].vertex == 3, "one fv");
  const double s = 0.25e-6, t = 1e-6;
  CHECK(std::abs(B(c, mesh, x) + (s - t) * (s - t) * std::log(s / t)) <= 1e-12 * B(c, x), "energy");
  const ti::Csr h = B.hessian(c, x, ti::PSDProjectionMethod::CLAMP);
  CHECK(h.size == 12 && h.nnz() == 144 && h.indptr.size() == 13, "a 12x12 Hessian block");
  // Rebuilt after the point moved above dhat: no collision, zero gradient.
  std::vector<std::array<double, 3>> far = x;
  far[3][2] = 2e-3;
  c.build(mesh, far, 1e-3);
  CHECK(c.empty() && B(c, far) == 0.0 && B.hessian(c, far).nnz() == 0, "nothing beyond dhat");
#if defined(TOPOCCD_HAS_EIGEN_SPARSE)
  c.build(mesh, x, 1e-3);
  const Eigen::SparseMatrix<double, Eigen::RowMajor> e = B.hessian(c, x).eigen();
  CHECK(e.rows() == 12 && e.nonZeros() == 144 && e.coeff(11, 11) > 0, "Eigen's sparse Hessian");
#endif
  const std::vector<std::array<std::uint32_t, 3>> bad = {{0, 1, 9}};
  expect_error([&] { c.build(ti::CollisionMesh(x, bad), x, 1e-3); }, TOPOCCD_STATUS_INVALID_STEP, "vertex 9",
               "bad index");
  expect_error([&] { c.build(mesh, x, -1.0); }, TOPOCCD_STATUS_INVALID_OPTIONS, "dhat", "negative dhat");
  std::vector<std::array<double, 3>> nan = x;
  nan[1][0] = std::nan("");
  expect_error([&] { c.build(mesh, nan, 1e-3); }, TOPOCCD_STATUS_INVALID_STEP, "", "NaN position");
  c.build(mesh, x, 1e-3);
  expect_error([&] { B.gradient(c, nan); }, TOPOCCD_STATUS_INVALID_STEP, "vertex 1 is not finite", "NaN x");
  const std::vector<std::array<double, 3>> three(x.begin(), x.begin() + 3);
  expect_error([&] { B(c, three); }, TOPOCCD_STATUS_INVALID_ARGUMENT, "x has 3 rows", "short x");
  expect_error([&] { ti::BarrierPotential(1e-3, -1.0)(c, x); }, TOPOCCD_STATUS_INVALID_OPTIONS, "stiffness",
               "negative stiffness");
  double kmax = 0;
  expect_error(
      [&] { ti::initial_barrier_stiffness(1, ti::Barrier::ClampedLog, 1e-3, 1, {0, 1}, {0}, kmax); },
      TOPOCCD_STATUS_INVALID_ARGUMENT, "different lengths", "gradients of different lengths");
  CHECK(ti::update_barrier_stiffness(1e-20, 1e-21, 100, 1, 1) == 2.0, "the stiffness doubles");
  ti::TangentialCollisions tc;
  const ti::FrictionPotential D(1e-3);
  expect_error([&] { D(tc, x); }, TOPOCCD_STATUS_NULL_POINTER, "never built", "unbuilt tangential set");
  expect_error([&] { tc.build(mesh, x, c, B, -1.0); }, TOPOCCD_STATUS_INVALID_OPTIONS, "friction coefficient",
               "negative mu");
  tc.build(mesh, x, c, B, 0.5);
  std::vector<std::array<double, 3>> v(4, {0, 0, 0});
  v[3] = {1, 0, 0};
  // mu N |v|, with N the barrier's push on the point (its gradient's z).
  const double push = -B.gradient(c, x)[11];
  CHECK(tc.size() == 1 && std::abs(D(tc, mesh, v) - 0.5 * push) <= 1e-12 * push, "friction energy");
  expect_error([&] { ti::FrictionPotential(-1.0)(tc, v); }, TOPOCCD_STATUS_INVALID_OPTIONS, "eps_v", "bad eps_v");
}

int main() {
  test_layouts();
  test_options_and_errors();
  test_cut();
  test_codim();
  test_pairs_and_files();
  test_line_search();
  test_proximity();
  test_ipc();
#if defined(TOPOCCD_HAS_EIGEN)
  test_eigen();
  std::printf("(with Eigen %d.%d.%d) ", EIGEN_WORLD_VERSION, EIGEN_MAJOR_VERSION, EIGEN_MINOR_VERSION);
#else
  std::printf("(without Eigen) ");
#endif
  std::printf("\n%d passed, %d failed\n", passed, failed);
  return failed != 0;
}

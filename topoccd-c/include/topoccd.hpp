// topoccd: continuous collision detection for deforming, topology-changing triangle meshes.
// The header-only C++17 wrapper of the C API (topoccd.h, libtopoccd_c): RAII objects,
// exceptions carrying the library's message, views of the results without copies, and, when
// Eigen is found, overloads taking its row-major n x 3 matrices.
// SPDX-License-Identifier: MIT OR Apache-2.0
//
//     topoccd::Ccd ccd;                                   // keep it across steps
//     auto report = ccd.query(topoccd::Step(x0, x1, triangles).parents(parents));
//     for (const auto& c : report.vf()) use(c.vertex, c.face, c.toi);
//
// Every failure throws topoccd::Error (a std::runtime_error) whose what() is the library's
// message and whose status() is the C status code. Views (Report, Span, Rows) borrow: a
// Report is valid until the next query on its Ccd, the arrays of a Mesh or Frames until it is
// destroyed, and the arrays given to a Step must outlive the query.
//
// topoccd.hpp includes topoccd.h, <array>, <cstdint>, <optional>, <string> and <vector>.
//
// topoccd::ipc holds the contact potential in the IPC toolkit's names: NormalCollisions,
// BarrierPotential, TangentialCollisions, FrictionPotential, PSDProjectionMethod and the
// stiffness helpers; Hessians come back as a topoccd::ipc::Csr (and as an Eigen::SparseMatrix
// through Csr::eigen() when <Eigen/Sparse> is found too).
//
// Eigen: with <Eigen/Dense> on the include path (and TOPOCCD_NO_EIGEN not defined), Rows (so
// Step and Ccd::query) also take Eigen matrices, maps and blocks with 3 columns in row-major
// order, read in place: Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> for
// positions, Eigen::Matrix<int or uint32_t, Eigen::Dynamic, 3, Eigen::RowMajor> for
// triangles. A column-major matrix (Eigen's default, libigl's V and F) is refused at compile
// time rather than copied: convert it once with
// `Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> V_rows = V;`.

#ifndef TOPOCCD_HPP
#define TOPOCCD_HPP

#if !defined(__cplusplus) || (__cplusplus < 201703L && (!defined(_MSVC_LANG) || _MSVC_LANG < 201703L))
#error "topoccd.hpp needs C++17 or later (use topoccd.h from C)"
#endif

#include "topoccd.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#if !defined(TOPOCCD_NO_EIGEN) && defined(__has_include)
#if __has_include(<Eigen/Dense>)
#include <Eigen/Dense>
#define TOPOCCD_HAS_EIGEN 1
#if __has_include(<Eigen/Sparse>)
#include <Eigen/Sparse>
#define TOPOCCD_HAS_EIGEN_SPARSE 1
#endif
#endif
#endif

#if defined(__has_include)
#if __has_include(<span>) && __cplusplus >= 202002L
#include <span>
#endif
#endif

namespace topoccd {

/// A failed call: the library's message (what()) and status code.
class Error : public std::runtime_error {
 public:
  Error(topoccd_status status, const std::string& message)
      : std::runtime_error(message), status_(status) {}

  /// The C status code (TOPOCCD_STATUS_...).
  topoccd_status status() const noexcept { return status_; }

  /// The status code's name, e.g. "TOPOCCD_STATUS_INVALID_STEP".
  const char* status_name() const noexcept { return topoccd_status_name(status_); }

 private:
  topoccd_status status_;
};

/// A view of `size()` contiguous elements owned by someone else (std::span's subset that
/// C++17 lacks); converts to std::span in C++20.
template <class T>
class Span {
 public:
  using element_type = T;
  using value_type = std::remove_cv_t<T>;
  using iterator = T*;

  constexpr Span() noexcept = default;
  constexpr Span(T* data, std::size_t size) noexcept : data_(data), size_(size) {}

  constexpr T* data() const noexcept { return data_; }
  constexpr std::size_t size() const noexcept { return size_; }
  constexpr bool empty() const noexcept { return size_ == 0; }
  constexpr T& operator[](std::size_t i) const noexcept { return data_[i]; }
  constexpr T* begin() const noexcept { return data_; }
  constexpr T* end() const noexcept { return data_ + size_; }
  constexpr T& front() const noexcept { return data_[0]; }
  constexpr T& back() const noexcept { return data_[size_ - 1]; }

  /// Element `i`, checked: throws topoccd::Error (TOPOCCD_STATUS_OUT_OF_RANGE) past the end.
  T& at(std::size_t i) const {
    if (i >= size_) {
      throw Error(TOPOCCD_STATUS_OUT_OF_RANGE, "index " + std::to_string(i) +
                                                   " is out of range: the view has " +
                                                   std::to_string(size_) + " elements");
    }
    return data_[i];
  }

#if defined(__cpp_lib_span)
  constexpr operator std::span<T>() const noexcept { return {data_, size_}; }
#endif

 private:
  T* data_ = nullptr;
  std::size_t size_ = 0;
};

/// The broad phase of a query (every method reports the same pairs).
enum class Method : std::uint32_t {
  Auto = TOPOCCD_METHOD_AUTO,
  Bvh = TOPOCCD_METHOD_BVH,
  Cluster = TOPOCCD_METHOD_CLUSTER,
  Brute = TOPOCCD_METHOD_BRUTE,
};

/// What a query reports: every contact, or the earliest ones (for a line search).
enum class Mode : std::uint32_t {
  All = TOPOCCD_MODE_ALL,
  Earliest = TOPOCCD_MODE_EARLIEST,
};

/// How the cluster method grows its leaf clusters.
enum class Growth : std::uint32_t {
  Certificate = TOPOCCD_GROWTH_CERTIFICATE,
  Paper = TOPOCCD_GROWTH_PAPER,
};

namespace detail {

/// Throws the message of a failed call that handed back a topoccd_error, and frees it. The
/// error is taken by reference: it is read after the call that sets it has run.
inline void check(topoccd_status status, topoccd_error*& error) {
  if (status == TOPOCCD_STATUS_OK) {
    topoccd_error_free(&error);
    return;
  }
  std::string message = error != nullptr ? topoccd_error_message(error) : "";
  topoccd_error_free(&error);
  if (message.empty()) {
    message = topoccd_status_name(status);
  }
  throw Error(status, message);
}

/// An object of the C API, freed by `Free` when this goes out of scope; movable, not copyable.
template <class T, void (*Free)(T**)>
class Owned {
 public:
  Owned() noexcept = default;
  explicit Owned(T* p) noexcept : p_(p) {}
  ~Owned() { Free(&p_); }
  Owned(Owned&& other) noexcept : p_(std::exchange(other.p_, nullptr)) {}
  Owned& operator=(Owned&& other) noexcept {
    if (this != &other) {
      Free(&p_);
      p_ = std::exchange(other.p_, nullptr);
    }
    return *this;
  }
  Owned(const Owned&) = delete;
  Owned& operator=(const Owned&) = delete;

  T* get() const noexcept { return p_; }

 private:
  T* p_ = nullptr;
};

}  // namespace detail

/// The options of a query and of the per-pair tests, with the library's defaults; set what
/// you need with the chained setters:
/// `topoccd::QueryOptions().mode(topoccd::Mode::Earliest).geometry(true)`. On a temporary the
/// setters return a temporary, so `c()` at the end of such a chain does not compile (its
/// reference would dangle).
/// Ranges are checked by the library at the query (topoccd::Error naming the option).
class QueryOptions {
 public:
  QueryOptions() {
    topoccd_status status = topoccd_query_options_default(&c_);
    if (status != TOPOCCD_STATUS_OK) {
      throw Error(status, "topoccd_query_options_default failed: the library is older than "
                          "topoccd.hpp");
    }
  }

  QueryOptions& method(Method m) & noexcept { return set(c_.method, static_cast<std::uint32_t>(m)); }
  QueryOptions&& method(Method m) && noexcept { return std::move(this->method(m)); }
  QueryOptions& mode(Mode m) & noexcept { return set(c_.mode, static_cast<std::uint32_t>(m)); }
  QueryOptions&& mode(Mode m) && noexcept { return std::move(this->mode(m)); }
  /// Resolution of the elementary tests, in time units, in (0, 1). Default 1e-6.
  QueryOptions& tolerance(double t) & noexcept { return set(c_.tolerance, t); }
  QueryOptions&& tolerance(double t) && noexcept { return std::move(this->tolerance(t)); }
  /// At least 1. Default 1,000,000.
  QueryOptions& max_iterations(std::uint32_t n) & noexcept { return set(c_.max_iterations, n); }
  QueryOptions&& max_iterations(std::uint32_t n) && noexcept { return std::move(this->max_iterations(n)); }
  /// 6, 14, 18 or 26. Default 18.
  QueryOptions& k(std::uint32_t k) & noexcept { return set(c_.k, k); }
  QueryOptions&& k(std::uint32_t k) && noexcept { return std::move(this->k(k)); }
  /// Distance (coordinate units, >= 0) at or below which features count as touching.
  QueryOptions& min_distance(double d) & noexcept { return set(c_.min_distance, d); }
  QueryOptions&& min_distance(double d) && noexcept { return std::move(this->min_distance(d)); }
  /// End of the time interval searched, in (0, 1]. Default 1.
  QueryOptions& tmax(double t) & noexcept { return set(c_.tmax, t); }
  QueryOptions&& tmax(double t) && noexcept { return std::move(this->tmax(t)); }
  QueryOptions& growth(Growth g) & noexcept { return set(c_.growth, static_cast<std::uint32_t>(g)); }
  QueryOptions&& growth(Growth g) && noexcept { return std::move(this->growth(g)); }
  /// 0 for one thread per core (the default), else a pool of n kept by the Ccd.
  QueryOptions& threads(std::uint32_t n) & noexcept { return set(c_.threads, n); }
  QueryOptions&& threads(std::uint32_t n) && noexcept { return std::move(this->threads(n)); }
  /// Contacts with their geometry (barycentric coordinates, point, normal, distance).
  QueryOptions& geometry(bool on) & noexcept { return set(c_.geometry, on); }
  QueryOptions&& geometry(bool on) && noexcept { return std::move(this->geometry(on)); }
  /// Keep the two sides of a fresh crack apart (default true).
  QueryOptions& crack_filter(bool on) & noexcept { return set(c_.crack_filter, on); }
  QueryOptions&& crack_filter(bool on) && noexcept { return std::move(this->crack_filter(on)); }
  /// Most contacts the report keeps, 0 for no cap (the default): see `Report::truncated`.
  QueryOptions& max_contacts(std::uint64_t n) & noexcept { return set(c_.max_contacts, n); }
  QueryOptions&& max_contacts(std::uint64_t n) && noexcept { return std::move(this->max_contacts(n)); }
  /// Seconds a query may run, 0 for no limit (the default): see `Report::truncated`.
  QueryOptions& timeout(double s) & noexcept { return set(c_.timeout, s); }
  QueryOptions&& timeout(double s) && noexcept { return std::move(this->timeout(s)); }

  Method method() const noexcept { return static_cast<Method>(c_.method); }
  Mode mode() const noexcept { return static_cast<Mode>(c_.mode); }
  double tolerance() const noexcept { return c_.tolerance; }
  std::uint32_t max_iterations() const noexcept { return c_.max_iterations; }
  std::uint32_t k() const noexcept { return c_.k; }
  double min_distance() const noexcept { return c_.min_distance; }
  double tmax() const noexcept { return c_.tmax; }
  Growth growth() const noexcept { return static_cast<Growth>(c_.growth); }
  std::uint32_t threads() const noexcept { return c_.threads; }
  bool geometry() const noexcept { return c_.geometry; }
  bool crack_filter() const noexcept { return c_.crack_filter; }
  std::uint64_t max_contacts() const noexcept { return c_.max_contacts; }
  double timeout() const noexcept { return c_.timeout; }

  /// The C struct, for the C API or for a field this wrapper does not name. Only on an
  /// object that outlives the reference: on a temporary it does not compile.
  const topoccd_query_options& c() const& noexcept { return c_; }
  topoccd_query_options& c() & noexcept { return c_; }
  const topoccd_query_options& c() const&& = delete;

 private:
  template <class F, class V>
  QueryOptions& set(F& field, V value) noexcept {
    field = static_cast<F>(value);
    return *this;
  }

  topoccd_query_options c_{};
};

/// `rows()` rows of `N` values of `T`, borrowed in place (never copied): from a pointer and a
/// row count, a std::vector<std::array<T, N>>, a C array T[M][N], a flat std::vector<T>, or
/// (with Eigen) a row-major matrix with N columns.
template <class T, std::size_t N>
class Rows {
  static_assert(sizeof(std::array<T, N>) == N * sizeof(T), "std::array<T, N> is padded");

 public:
  /// No rows.
  Rows() noexcept = default;
  /// `rows` rows at `data` (`rows * N` values).
  Rows(const T* data, std::size_t rows) noexcept : data_(data), rows_(rows) {}
  Rows(const std::vector<std::array<T, N>>& v) noexcept  // NOLINT: implicit on purpose
      : data_(v.empty() ? nullptr : v.front().data()), rows_(v.size()) {}
  template <std::size_t M>
  Rows(const std::array<std::array<T, N>, M>& a) noexcept  // NOLINT
      : data_(M == 0 ? nullptr : a[0].data()), rows_(M) {}
  template <std::size_t M>
  Rows(const T (&a)[M][N]) noexcept : data_(&a[0][0]), rows_(M) {}  // NOLINT
  /// A flat array `x0 y0 z0 x1 ...`; its size must be a multiple of N.
  Rows(const std::vector<T>& flat)  // NOLINT
      : data_(flat.empty() ? nullptr : flat.data()), rows_(flat.size() / N) {
    if (flat.size() % N != 0) {
      throw Error(TOPOCCD_STATUS_INVALID_ARGUMENT,
                  "a flat array of " + std::to_string(flat.size()) +
                      " values is not rows of " + std::to_string(N));
    }
  }

#if defined(TOPOCCD_HAS_EIGEN)
  /// An Eigen matrix, map or block of N columns in row-major order, read in place.
  template <class Derived>
  Rows(const Eigen::DenseBase<Derived>& m) {  // NOLINT
    using Scalar = typename Derived::Scalar;
    static_assert(std::is_same<Scalar, T>::value ||
                      (std::is_integral<T>::value && std::is_integral<Scalar>::value &&
                       sizeof(Scalar) == sizeof(T)),
                  "topoccd: positions are double, indices 32-bit integers (int or uint32_t)");
    static_assert(Derived::ColsAtCompileTime == static_cast<int>(N) ||
                      Derived::ColsAtCompileTime == Eigen::Dynamic,
                  "topoccd: the matrix must have 3 columns (2 for parents)");
    static_assert(bool(Derived::IsRowMajor),
                  "topoccd reads matrices in row-major order, in place: use "
                  "Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> (convert a "
                  "column-major matrix once: RowMatrix V_rows = V;)");
    static_assert(bool(Derived::Flags & Eigen::DirectAccessBit),
                  "topoccd: evaluate the expression into a matrix first");
    const Derived& d = m.derived();
    if (d.cols() != static_cast<Eigen::Index>(N)) {
      throw Error(TOPOCCD_STATUS_INVALID_ARGUMENT,
                  "an Eigen matrix of " + std::to_string(d.cols()) + " columns, not " +
                      std::to_string(N));
    }
    if (d.rows() > 1 && (d.outerStride() != static_cast<Eigen::Index>(N) || d.innerStride() != 1)) {
      throw Error(TOPOCCD_STATUS_INVALID_ARGUMENT,
                  "an Eigen block whose rows are not contiguous: copy it into a matrix first");
    }
    data_ = d.rows() == 0 ? nullptr : reinterpret_cast<const T*>(d.data());
    rows_ = static_cast<std::size_t>(d.rows());
  }
#endif

  const T* data() const noexcept { return data_; }
  std::size_t rows() const noexcept { return rows_; }
  bool empty() const noexcept { return rows_ == 0; }
  /// Row `i`: its N values.
  const T* operator[](std::size_t i) const noexcept { return data_ + i * N; }

 private:
  const T* data_ = nullptr;
  std::size_t rows_ = 0;
};

/// Positions: rows of x y z.
using Points = Rows<double, 3>;
/// Triangles: rows of three vertex indices.
using Indices = Rows<std::uint32_t, 3>;
/// Parents of a topology change: rows [child, parent].
using ParentRows = Rows<std::uint32_t, 2>;
/// One group id per vertex.
using GroupIds = Rows<std::uint32_t, 1>;
/// Edges (codimensional geometry): rows of two vertex indices.
using EdgeRows = Rows<std::uint32_t, 2>;

/// The input of one step, borrowed (see topoccd_step): positions at t=0 and t=1, triangles,
/// and optionally the parents of a topology change and group ids.
class Step {
 public:
  Step(Points x0, Points x1, Indices triangles) noexcept {
    c_.x0 = x0.data();
    c_.x0_count = x0.rows();
    c_.x1 = x1.data();
    c_.x1_count = x1.rows();
    c_.triangles = triangles.data();
    c_.triangle_count = triangles.rows();
  }

  /// A step as the C API describes it (e.g. from topoccd_frames_step).
  explicit Step(const topoccd_step& step) noexcept : c_(step) {}

  /// A topology change: x0 may have fewer vertices than x1 (the new ones start at their
  /// parent); each row [child, parent] says child was split from parent. Given even when empty.
  Step& parents(ParentRows rows) & noexcept {
    c_.parents = rows.empty() ? kNoRows : rows.data();
    c_.parent_count = rows.rows();
    return *this;
  }
  /// On a temporary Step, a temporary (to give to Ccd::query in the same expression).
  Step&& parents(ParentRows rows) && noexcept { return std::move(this->parents(rows)); }

  /// One group id per vertex: features whose vertices all share one group with the other
  /// feature's are not tested (one id per object turns off its self-collision).
  Step& groups(GroupIds ids) & noexcept {
    c_.groups = ids.empty() ? kNoRows : ids.data();
    c_.group_count = ids.rows();
    return *this;
  }
  Step&& groups(GroupIds ids) && noexcept { return std::move(this->groups(ids)); }

  /// The group ids as a std::vector<std::uint32_t>.
  Step& groups(const std::vector<std::uint32_t>& ids) & noexcept {
    return groups(GroupIds(ids.empty() ? nullptr : ids.data(), ids.size()));
  }
  Step&& groups(const std::vector<std::uint32_t>& ids) && noexcept {
    return std::move(groups(ids));
  }

  /// Edges (codimensional geometry): those in no triangle are free edges (rods, hair), and
  /// vertices in no triangle and no edge are free points (particles). Their contacts are the
  /// report's ve() and vv().
  Step& edges(EdgeRows rows) & noexcept {
    c_.edges = rows.data();
    c_.edge_count = rows.rows();
    return *this;
  }
  Step&& edges(EdgeRows rows) && noexcept { return std::move(this->edges(rows)); }

  /// The C struct. Only on a Step that outlives the reference: `frames.step().c()` would
  /// point into a temporary, so it does not compile (keep the Step in a variable).
  const topoccd_step& c() const& noexcept { return c_; }
  const topoccd_step& c() const&& = delete;

 private:
  // A non-NULL pointer for an empty array that is given (a topology change without rows).
  static constexpr std::uint32_t kNoRows[2] = {0, 0};
  topoccd_step c_{};
};

/// The report of a query, read in place from its Ccd: valid until the Ccd's next query or
/// destruction. Contacts are the C structs topoccd_vf_contact (vertex, face, toi, certainty,
/// geometry), topoccd_ee_contact (a[2], b[2], toi, ...), topoccd_ve_contact (vertex, edge[2],
/// ...) and topoccd_vv_contact (a, b, ...).
class Report {
 public:
  explicit Report(const topoccd_report* r) noexcept : r_(r) {}

  /// Vertex-face contacts, sorted by (vertex, face).
  Span<const topoccd_vf_contact> vf() const noexcept { return {r_->vf, r_->vf_count}; }
  /// Edge-edge contacts, sorted by (a, b).
  Span<const topoccd_ee_contact> ee() const noexcept { return {r_->ee, r_->ee_count}; }
  /// Contacts of a free point with a free edge, sorted by (vertex, edge).
  Span<const topoccd_ve_contact> ve() const noexcept { return {r_->ve, r_->ve_count}; }
  /// Contacts of two free points, sorted by (a, b).
  Span<const topoccd_vv_contact> vv() const noexcept { return {r_->vv, r_->vv_count}; }
  /// Contacts of every kind.
  std::size_t contact_count() const noexcept {
    return r_->vf_count + r_->ee_count + r_->ve_count + r_->vv_count;
  }
  /// The earliest time of impact, or none when nothing collides.
  std::optional<double> earliest_toi() const noexcept {
    if (r_->earliest_kind == TOPOCCD_CONTACT_KIND_NONE) {
      return std::nullopt;
    }
    return r_->earliest_toi;
  }
  /// Whether the report lists every pair within the tolerance of the earliest time (every
  /// contact in Mode::All): false when the query stopped early, or when Mode::Earliest found
  /// more such pairs than max_contacts and kept the earliest of them (the earliest time is
  /// exact either way).
  bool earliest_complete() const noexcept { return r_->earliest_complete; }
  /// The earliest contact if it is a vertex-face one, else nullptr.
  const topoccd_vf_contact* earliest_vf() const noexcept {
    return r_->earliest_kind == TOPOCCD_CONTACT_KIND_VF ? r_->vf + r_->earliest_index : nullptr;
  }
  /// The earliest contact if it is an edge-edge one, else nullptr.
  const topoccd_ee_contact* earliest_ee() const noexcept {
    return r_->earliest_kind == TOPOCCD_CONTACT_KIND_EE ? r_->ee + r_->earliest_index : nullptr;
  }
  /// The earliest contact if it is a vertex-edge one, else nullptr.
  const topoccd_ve_contact* earliest_ve() const noexcept {
    return r_->earliest_kind == TOPOCCD_CONTACT_KIND_VE ? r_->ve + r_->earliest_index : nullptr;
  }
  /// The earliest contact if it is a vertex-vertex one, else nullptr.
  const topoccd_vv_contact* earliest_vv() const noexcept {
    return r_->earliest_kind == TOPOCCD_CONTACT_KIND_VV ? r_->vv + r_->earliest_index : nullptr;
  }
  /// Contacts where the search gave up (their times are only lower bounds).
  std::size_t unresolved() const noexcept { return r_->unresolved; }
  /// Why the query stopped early (`max_contacts`, `timeout`), or
  /// `TOPOCCD_STOP_REASON_NONE` for a complete report.
  topoccd_stop_reason truncated() const noexcept { return r_->truncated; }
  /// Work counters and seconds per phase.
  const topoccd_stats& stats() const noexcept { return r_->stats; }
  /// The method that ran (what Method::Auto chose).
  Method method() const noexcept { return static_cast<Method>(r_->stats.method); }
  const topoccd_report& c() const noexcept { return *r_; }

 private:
  const topoccd_report* r_;
};

/// The options of a line search (Ccd::collision_free_stepsize, Ccd::is_step_collision_free):
/// the query's options (their mode is ignored: the helpers run Mode::Earliest), the
/// conservative rescaling and the check of the start.
/// `topoccd::LineSearchOptions().check_start(true).query(topoccd::QueryOptions().timeout(1))`.
class LineSearchOptions {
 public:
  LineSearchOptions() {
    topoccd_status status = topoccd_line_search_options_default(&c_);
    if (status != TOPOCCD_STATUS_OK) {
      throw Error(status, "topoccd_line_search_options_default failed: the library is older "
                          "than topoccd.hpp");
    }
  }

  /// The query's options (min_distance, tmax, timeout, max_contacts, threads, ...).
  LineSearchOptions& query(const QueryOptions& q) & {
    query_ = q;
    return *this;
  }
  LineSearchOptions&& query(const QueryOptions& q) && { return std::move(query(q)); }
  /// The fraction of the earliest time of impact returned, in (0, 1]. Default 0.8.
  LineSearchOptions& conservative_rescaling(double r) & noexcept {
    c_.conservative_rescaling = r;
    return *this;
  }
  LineSearchOptions&& conservative_rescaling(double r) && noexcept {
    return std::move(conservative_rescaling(r));
  }
  /// Refuse a start where triangles intersect (Error with TOPOCCD_STATUS_START_INTERSECTS).
  /// Default false.
  LineSearchOptions& check_start(bool on) & noexcept {
    c_.check_start = on;
    return *this;
  }
  LineSearchOptions&& check_start(bool on) && noexcept { return std::move(this->check_start(on)); }

  const QueryOptions& query() const& noexcept { return query_; }
  QueryOptions& query() & noexcept { return query_; }
  const QueryOptions& query() const&& = delete;
  double conservative_rescaling() const noexcept { return c_.conservative_rescaling; }
  bool check_start() const noexcept { return c_.check_start; }

  /// The C struct; its `query` points into this object, so only on an lvalue.
  topoccd_line_search_options c() const& noexcept {
    topoccd_line_search_options out = c_;
    out.query = &query_.c();
    return out;
  }
  topoccd_line_search_options c() const&& = delete;

 private:
  topoccd_line_search_options c_{};
  QueryOptions query_;
};

/// What Ccd::collision_free_stepsize returns: the fraction of the step, and the report of its
/// Earliest query (its earliest_vf(), earliest_ee() and earliest_toi() name the contact that
/// cut the step short), valid until the Ccd's next query.
struct StepSize {
  /// conservative_rescaling times the earliest time of impact, or tmax without contact.
  double alpha;
  /// The Earliest query's report.
  Report report;
};

/// The options of a proximity query, with the library's defaults; chained setters:
/// `topoccd::ProximityOptions().dhat(1e-3).dmin(1e-4)`.
class ProximityOptions {
 public:
  ProximityOptions() noexcept : c_(topoccd_proximity_options_default()) {}
  /// The distance threshold, > 0. Default 1e-3.
  ProximityOptions& dhat(double d) & noexcept { c_.dhat = d; return *this; }
  ProximityOptions&& dhat(double d) && noexcept { return std::move(this->dhat(d)); }
  /// The minimum distance offset, >= 0: pairs closer than dhat + dmin. Default 0.
  ProximityOptions& dmin(double d) & noexcept { c_.dmin = d; return *this; }
  ProximityOptions&& dmin(double d) && noexcept { return std::move(this->dmin(d)); }
  /// Most pairs kept, 0 for no cap (the default): see `Proximity::truncated`.
  ProximityOptions& max_contacts(std::uint64_t n) & noexcept { c_.max_contacts = n; return *this; }
  ProximityOptions&& max_contacts(std::uint64_t n) && noexcept {
    return std::move(this->max_contacts(n));
  }
  /// Seconds the query may run, 0 for no limit (the default).
  ProximityOptions& timeout(double s) & noexcept { c_.timeout = s; return *this; }
  ProximityOptions&& timeout(double s) && noexcept { return std::move(this->timeout(s)); }
  /// 0 for one thread per core (the default), else a pool of n kept by the Ccd.
  ProximityOptions& threads(std::uint32_t n) & noexcept { c_.threads = n; return *this; }
  ProximityOptions&& threads(std::uint32_t n) && noexcept { return std::move(this->threads(n)); }
  /// The C struct, only on an lvalue (a reference into a temporary would dangle).
  const topoccd_proximity_options& c() const& noexcept { return c_; }
  const topoccd_proximity_options& c() const&& = delete;

 private:
  topoccd_proximity_options c_;
};

/// The pairs of a proximity query, read in place from its Ccd: valid until the Ccd's next
/// proximity query or destruction. Each kind is sorted by its indices.
class Proximity {
 public:
  explicit Proximity(const topoccd_proximity_report* r) noexcept : r_(r) {}
  /// Vertex-face pairs (vertex, face, distance, type: ipctk's PointTriangleDistanceType).
  Span<const topoccd_vf_proximity> vf() const noexcept { return {r_->vf, r_->vf_count}; }
  /// Edge-edge pairs (a[2], b[2], distance, type: ipctk's EdgeEdgeDistanceType).
  Span<const topoccd_ee_proximity> ee() const noexcept { return {r_->ee, r_->ee_count}; }
  /// Free point-edge pairs.
  Span<const topoccd_ve_proximity> ve() const noexcept { return {r_->ve, r_->ve_count}; }
  /// Free point-free point pairs.
  Span<const topoccd_vv_proximity> vv() const noexcept { return {r_->vv, r_->vv_count}; }
  std::size_t size() const noexcept {
    return r_->vf_count + r_->ee_count + r_->ve_count + r_->vv_count;
  }
  /// Whether max_contacts cut the report.
  bool truncated() const noexcept { return r_->truncated; }
  /// Whether the Ccd's hierarchy was refitted rather than built.
  bool refitted() const noexcept { return r_->refitted; }
  const topoccd_proximity_report& c() const noexcept { return *r_; }

 private:
  const topoccd_proximity_report* r_;
};

/// A reusable query: keep one per simulation (its buffers are reused) and per thread.
class Ccd {
 public:
  Ccd() : p_(topoccd_ccd_new()) {
    if (p_.get() == nullptr) {
      throw Error(TOPOCCD_STATUS_INTERNAL, "topoccd_ccd_new failed");
    }
  }

  /// Every contact of one step (or the earliest, with Mode::Earliest).
  Report query(const Step& step, const QueryOptions& options = QueryOptions()) {
    check(topoccd_ccd_query(p_.get(), &step.c(), &options.c()));
    return report();
  }

  /// A step without topology change.
  Report query(Points x0, Points x1, Indices triangles,
               const QueryOptions& options = QueryOptions()) {
    return query(Step(x0, x1, triangles), options);
  }

  /// The fraction of the step the mesh may take without contact (see
  /// topoccd_collision_free_stepsize), with the earliest contact in the report. Throws
  /// topoccd::Error: TOPOCCD_STATUS_START_INTERSECTS (check_start), TOPOCCD_STATUS_TIMEOUT,
  /// or as query().
  StepSize collision_free_stepsize(const Step& step,
                                   const LineSearchOptions& options = LineSearchOptions()) {
    double alpha = 0.0;
    topoccd_line_search_options c = options.c();
    check(topoccd_collision_free_stepsize(p_.get(), &step.c(), &c, &alpha));
    return StepSize{alpha, report()};
  }

  /// Whether no two features come within min_distance during [0, tmax] of the step; if not,
  /// report() gives the earliest contact. Throws as collision_free_stepsize().
  bool is_step_collision_free(const Step& step,
                              const LineSearchOptions& options = LineSearchOptions()) {
    bool collision_free = false;
    topoccd_line_search_options c = options.c();
    check(topoccd_is_step_collision_free(p_.get(), &step.c(), &c, &collision_free));
    return collision_free;
  }

  /// Every primitive pair closer than dhat + dmin at positions `x`: vertex-face, edge-edge
  /// (the triangles' edges and the free `edges`), free point-edge, free point-free point.
  /// The hierarchy is kept in this Ccd and refitted while the primitives stay the same.
  Proximity proximity(Points x, Indices triangles, Rows<std::uint32_t, 2> edges,
                      const ProximityOptions& options = ProximityOptions()) {
    topoccd_configuration config{};
    config.x = x.data();
    config.vertex_count = x.rows();
    config.triangles = triangles.data();
    config.triangle_count = triangles.rows();
    config.edges = edges.data();
    config.edge_count = edges.rows();
    const topoccd_proximity_report* r = nullptr;
    check(topoccd_proximity(p_.get(), &config, &options.c(), &r));
    return Proximity(r);
  }

  /// Triangles only (their vertices; vertices in no triangle are free points).
  Proximity proximity(Points x, Indices triangles,
                      const ProximityOptions& options = ProximityOptions()) {
    return proximity(x, triangles, Rows<std::uint32_t, 2>(), options);
  }

  /// The report of the last query (empty before the first and after a failed one).
  Report report() const {
    const topoccd_report* r = nullptr;
    check(topoccd_ccd_report(p_.get(), &r));
    return Report(r);
  }

  /// The C object (NULL after a move).
  topoccd_ccd* get() const noexcept { return p_.get(); }

 private:
  void check(topoccd_status status) const {
    if (status != TOPOCCD_STATUS_OK) {
      throw Error(status, topoccd_ccd_last_error(p_.get()));
    }
  }

  detail::Owned<topoccd_ccd, topoccd_ccd_free> p_;
};

/// The answer of a per-pair test.
struct Outcome {
  /// Whether the features (may) touch during [0, tmax].
  bool contact = false;
  /// With a contact, its time of impact (never later than the first contact); NaN without.
  double toi = 0.0;
  topoccd_certainty certainty = TOPOCCD_CERTAINTY_RESOLVED;

  explicit operator bool() const noexcept { return contact; }
};

/// The per-pair test of a vertex against a triangle (see topoccd_pair_vertex_face).
inline Outcome vertex_face(const topoccd_vertex_face& query,
                           const QueryOptions& options = QueryOptions()) {
  topoccd_outcome o{};
  topoccd_error* error = nullptr;
  detail::check(topoccd_pair_vertex_face(&query, &options.c(), &o, &error), error);
  return Outcome{o.contact, o.toi, o.certainty};
}

/// The per-pair test of two edges (see topoccd_pair_edge_edge).
inline Outcome edge_edge(const topoccd_edge_edge& query,
                         const QueryOptions& options = QueryOptions()) {
  topoccd_outcome o{};
  topoccd_error* error = nullptr;
  detail::check(topoccd_pair_edge_edge(&query, &options.c(), &o, &error), error);
  return Outcome{o.contact, o.toi, o.certainty};
}

/// A triangle mesh read from a PLY, OBJ or STL file; its arrays live as long as it does.
class Mesh {
 public:
  /// Reads a mesh (the format by the extension); throws topoccd::Error naming the file and
  /// the line or element.
  static Mesh read(const std::string& path) {
    topoccd_mesh* m = nullptr;
    topoccd_error* error = nullptr;
    detail::check(topoccd_mesh_read(path.c_str(), &m, &error), error);
    return Mesh(m);
  }

  Points positions() const noexcept { return {view().positions, view().vertex_count}; }
  Indices triangles() const noexcept { return {view().triangles, view().triangle_count}; }
  /// nullptr when triangle t is face t of the file; else rows [face, sub] per triangle.
  const std::uint32_t* face_origin() const noexcept { return view().face_origin; }

  /// What the reader did beyond reading (polygons split, an STL welded), one sentence each.
  std::vector<std::string> notes() const {
    std::size_t n = 0;
    topoccd_mesh_note_count(p_.get(), &n);
    std::vector<std::string> out;
    for (std::size_t i = 0; i < n; i++) {
      const char* note = nullptr;
      if (topoccd_mesh_note(p_.get(), i, &note) == TOPOCCD_STATUS_OK) {
        out.emplace_back(note);
      }
    }
    return out;
  }

  topoccd_mesh* get() const noexcept { return p_.get(); }

 private:
  explicit Mesh(topoccd_mesh* m) noexcept : p_(m) { topoccd_mesh_data(m, &view_); }
  const topoccd_mesh_view& view() const noexcept { return view_; }

  detail::Owned<topoccd_mesh, topoccd_mesh_free> p_;
  topoccd_mesh_view view_{};
};

/// One step read from two frame files (and a parents file across a topology change); its
/// step() borrows its arrays, valid as long as it lives.
class Frames {
 public:
  /// Reads positions at t=0 from t0, positions at t=1 and the triangles from t1.
  static Frames read(const std::string& t0, const std::string& t1) {
    return read_paths(t0.c_str(), t1.c_str(), nullptr);
  }

  /// The same, with the parents file of a topology change (t1 may have more vertices).
  static Frames read(const std::string& t0, const std::string& t1, const std::string& parents) {
    return read_paths(t0.c_str(), t1.c_str(), parents.c_str());
  }

  /// The step, ready for Ccd::query.
  Step step() const noexcept { return Step(step_); }
  /// nullptr when triangle t is face t of t1's file; else rows [face, sub] per triangle.
  const std::uint32_t* face_origin() const noexcept {
    const std::uint32_t* rows = nullptr;
    topoccd_frames_face_origin(p_.get(), &rows);
    return rows;
  }

  /// What the readers did to either file, one sentence each, starting with the file.
  std::vector<std::string> notes() const {
    std::size_t n = 0;
    topoccd_frames_note_count(p_.get(), &n);
    std::vector<std::string> out;
    for (std::size_t i = 0; i < n; i++) {
      const char* note = nullptr;
      if (topoccd_frames_note(p_.get(), i, &note) == TOPOCCD_STATUS_OK) {
        out.emplace_back(note);
      }
    }
    return out;
  }

  topoccd_frames* get() const noexcept { return p_.get(); }

 private:
  friend class Sequence;

  explicit Frames(topoccd_frames* f) noexcept : p_(f) { topoccd_frames_step(f, &step_); }

  static Frames read_paths(const char* t0, const char* t1, const char* parents) {
    topoccd_frames* f = nullptr;
    topoccd_error* error = nullptr;
    detail::check(topoccd_frames_read(t0, t1, parents, &f, &error), error);
    return Frames(f);
  }

  detail::Owned<topoccd_frames, topoccd_frames_free> p_;
  topoccd_step step_{};
};

/// A frame sequence on disk (0000.ply, 0001.ply, ... with optional .parents files).
class Sequence {
 public:
  /// Lists the frames of a folder and checks their numbering.
  static Sequence open(const std::string& dir) {
    topoccd_sequence* s = nullptr;
    topoccd_error* error = nullptr;
    detail::check(topoccd_sequence_open(dir.c_str(), &s, &error), error);
    return Sequence(s);
  }

  /// The number of steps (frames less one).
  std::size_t steps() const noexcept {
    std::size_t n = 0;
    topoccd_sequence_step_count(p_.get(), &n);
    return n;
  }

  /// Reads step k (frames k and k + 1, and frame k + 1's parents file if any).
  Frames load(std::size_t k) const {
    topoccd_frames* f = nullptr;
    topoccd_error* error = nullptr;
    detail::check(topoccd_sequence_load(p_.get(), k, &f, &error), error);
    return Frames(f);
  }

  topoccd_sequence* get() const noexcept { return p_.get(); }

 private:
  explicit Sequence(topoccd_sequence* s) noexcept : p_(s) {}

  detail::Owned<topoccd_sequence, topoccd_sequence_free> p_;
};

/// The library's version, "MAJOR.MINOR.PATCH".
inline std::string version() { return topoccd_version(); }

/// The contact potential of incremental potential contact, in the IPC toolkit's names:
/// `NormalCollisions` (with `build(mesh, x, dhat)`), `BarrierPotential` (called as
/// `B(collisions, x)`, with `gradient` and `hessian`), `PSDProjectionMethod`, the stiffness
/// helpers. Gradients are std::vector<double> of 3 n entries `x0 y0 z0 x1 ...`; Hessians a
/// `Csr` (and, with Eigen, an Eigen::SparseMatrix through `Csr::eigen()`).
namespace ipc {

/// How the collision set is built (ipctk's `CollisionSetType`).
enum class CollisionSetType : std::uint32_t {
  IPC = TOPOCCD_COLLISION_SET_TYPE_IPC,
  IMPROVED_MAX_APPROX = TOPOCCD_COLLISION_SET_TYPE_IMPROVED_MAX_APPROX,
};

/// How each collision's Hessian is made positive semi-definite (ipctk's `PSDProjectionMethod`).
enum class PSDProjectionMethod : std::uint32_t {
  NONE = TOPOCCD_PSD_PROJECTION_NONE,
  CLAMP = TOPOCCD_PSD_PROJECTION_CLAMP,
  ABS = TOPOCCD_PSD_PROJECTION_ABS,
};

/// A barrier function (ipctk's barrier classes).
enum class Barrier : std::uint32_t {
  ClampedLog = TOPOCCD_BARRIER_CLAMPED_LOG,
  NormalizedClampedLog = TOPOCCD_BARRIER_NORMALIZED_CLAMPED_LOG,
  ClampedLogSq = TOPOCCD_BARRIER_CLAMPED_LOG_SQ,
  Cubic = TOPOCCD_BARRIER_CUBIC,
};

/// A square sparse matrix in compressed sparse rows, owned (copied out of the library's).
struct Csr {
  std::size_t size = 0;
  std::vector<std::size_t> indptr;
  std::vector<std::size_t> indices;
  std::vector<double> data;

  std::size_t nnz() const noexcept { return data.size(); }

  /// Entry (i, j), 0 where nothing is stored.
  double operator()(std::size_t i, std::size_t j) const noexcept {
    for (std::size_t k = indptr[i]; k < indptr[i + 1]; k++) {
      if (indices[k] == j) return data[k];
    }
    return 0.0;
  }

  /// y = A x (x of `size` entries).
  std::vector<double> operator*(const std::vector<double>& x) const {
    if (x.size() != size) {
      throw Error(TOPOCCD_STATUS_INVALID_ARGUMENT, "a vector of " + std::to_string(x.size()) +
                                                       " entries times a matrix of size " +
                                                       std::to_string(size));
    }
    std::vector<double> y(size, 0.0);
    for (std::size_t i = 0; i < size; i++) {
      for (std::size_t k = indptr[i]; k < indptr[i + 1]; k++) y[i] += data[k] * x[indices[k]];
    }
    return y;
  }

#if defined(TOPOCCD_HAS_EIGEN_SPARSE)
  /// The matrix as Eigen's (row-major, so the arrays are copied once, not re-sorted).
  Eigen::SparseMatrix<double, Eigen::RowMajor> eigen() const {
    Eigen::SparseMatrix<double, Eigen::RowMajor> m(static_cast<Eigen::Index>(size),
                                                   static_cast<Eigen::Index>(size));
    std::vector<Eigen::Triplet<double>> t;
    t.reserve(nnz());
    for (std::size_t i = 0; i < size; i++) {
      for (std::size_t k = indptr[i]; k < indptr[i + 1]; k++) {
        t.emplace_back(static_cast<int>(i), static_cast<int>(indices[k]), data[k]);
      }
    }
    m.setFromTriplets(t.begin(), t.end());
    return m;
  }
#endif

  /// Copies (and frees) a topoccd_sparse.
  static Csr take(topoccd_sparse* m) {
    detail::Owned<topoccd_sparse, topoccd_sparse_free> owned(m);
    topoccd_csr c{};
    topoccd_error* error = nullptr;
    detail::check(topoccd_sparse_csr(owned.get(), &c, &error), error);
    Csr out;
    out.size = c.size;
    out.indptr.assign(c.indptr, c.indptr + c.size + 1);
    out.indices.assign(c.indices, c.indices + c.nnz);
    out.data.assign(c.data, c.data + c.nnz);
    return out;
  }
};

/// The mesh a collision set is built on (ipctk's `CollisionMesh`), borrowed: rest positions
/// (one row per vertex), triangles and free edges. The arrays must outlive the builds.
struct CollisionMesh {
  Points rest_positions;
  Indices faces;
  Rows<std::uint32_t, 2> edges;

  CollisionMesh(Points rest, Indices f, Rows<std::uint32_t, 2> e = Rows<std::uint32_t, 2>())
      : rest_positions(rest), faces(f), edges(e) {}

  std::size_t num_vertices() const noexcept { return rest_positions.rows(); }
};

/// The normal collision set (ipctk's `NormalCollisions`). It keeps the proximity hierarchy of
/// its last build, refitted by the next one (a solver builds once per Newton iteration).
class NormalCollisions {
 public:
  NormalCollisions() = default;

  /// ipctk's `use_area_weighting` and `collision_set_type`, read at build().
  bool use_area_weighting = false;
  CollisionSetType collision_set_type = CollisionSetType::IPC;

  /// The collisions of `mesh` at positions `x` (one row per vertex) within dhat + dmin.
  void build(const CollisionMesh& mesh, Points x, double dhat, double dmin = 0.0) {
    topoccd_configuration config{};
    config.x = x.data();
    config.vertex_count = x.rows();
    config.triangles = mesh.faces.data();
    config.triangle_count = mesh.faces.rows();
    config.edges = mesh.edges.data();
    config.edge_count = mesh.edges.rows();
    topoccd_collision_options o = topoccd_collision_options_default();
    o.dhat = dhat;
    o.dmin = dmin;
    o.use_area_weighting = use_area_weighting;
    o.collision_set_type = static_cast<std::uint32_t>(collision_set_type);
    topoccd_collisions* c = nullptr;
    const topoccd_status s = topoccd_collisions_build(
        ccd_.get(), &config, mesh.rest_positions.data(), mesh.rest_positions.rows(), &o, &c);
    if (s != TOPOCCD_STATUS_OK) {
      throw Error(s, topoccd_ccd_last_error(ccd_.get()));
    }
    set_ = detail::Owned<topoccd_collisions, topoccd_collisions_free>(c);
    topoccd_error* error = nullptr;
    detail::check(topoccd_collisions_arrays(set_.get(), &arrays_, &error), error);
  }

  /// Number of collisions of all kinds (0 before the first build).
  std::size_t size() const noexcept {
    return set_.get() == nullptr
               ? 0
               : arrays_.vv_count + arrays_.ev_count + arrays_.ee_count + arrays_.fv_count;
  }
  bool empty() const noexcept { return size() == 0; }

  /// The collisions by kind (ipctk's `vv_collisions` ... `fv_collisions`), valid until the
  /// next build or destruction.
  Span<const topoccd_vv_collision> vv_collisions() const noexcept {
    return {arrays_.vv, set_.get() ? arrays_.vv_count : 0};
  }
  Span<const topoccd_ev_collision> ev_collisions() const noexcept {
    return {arrays_.ev, set_.get() ? arrays_.ev_count : 0};
  }
  Span<const topoccd_ee_collision> ee_collisions() const noexcept {
    return {arrays_.ee, set_.get() ? arrays_.ee_count : 0};
  }
  Span<const topoccd_fv_collision> fv_collisions() const noexcept {
    return {arrays_.fv, set_.get() ? arrays_.fv_count : 0};
  }

  /// The smallest squared distance over the collisions at `x` (ipctk's
  /// `compute_minimum_distance`; +inf when empty).
  double compute_minimum_distance(const CollisionMesh&, Points x) const {
    return compute_minimum_distance(x);
  }
  double compute_minimum_distance(Points x) const {
    double d = 0.0;
    topoccd_error* error = nullptr;
    detail::check(topoccd_collisions_minimum_distance(get(), x.data(), x.rows(), &d, &error),
                  error);
    return d;
  }

  /// The C set (NULL before the first build).
  const topoccd_collisions* get() const noexcept { return set_.get(); }

 private:
  Ccd ccd_;
  detail::Owned<topoccd_collisions, topoccd_collisions_free> set_;
  topoccd_collision_arrays arrays_{};
};

/// The barrier potential (ipctk's `BarrierPotential(dhat, stiffness)`).
class BarrierPotential {
 public:
  BarrierPotential(double dhat, double stiffness, bool use_physical_barrier = false)
      : c_(topoccd_barrier_potential_new(dhat, stiffness)) {
    c_.use_physical_barrier = use_physical_barrier;
  }

  double dhat() const noexcept { return c_.dhat; }
  double barrier_stiffness() const noexcept { return c_.stiffness; }
  void set_barrier_stiffness(double k) noexcept { c_.stiffness = k; }
  void set_barrier(Barrier b) noexcept { c_.barrier = static_cast<std::uint32_t>(b); }

  /// The energy (ipctk's `B(collisions, mesh, x)`).
  double operator()(const NormalCollisions& c, const CollisionMesh&, Points x) const {
    return (*this)(c, x);
  }
  double operator()(const NormalCollisions& c, Points x) const {
    double e = 0.0;
    topoccd_error* error = nullptr;
    detail::check(topoccd_barrier_energy(&c_, need(c), x.data(), x.rows(), &e, &error), error);
    return e;
  }

  /// The gradient, 3 n entries.
  std::vector<double> gradient(const NormalCollisions& c, const CollisionMesh&, Points x) const {
    return gradient(c, x);
  }
  std::vector<double> gradient(const NormalCollisions& c, Points x) const {
    std::vector<double> g(3 * x.rows());
    topoccd_error* error = nullptr;
    detail::check(topoccd_barrier_gradient(&c_, need(c), x.data(), x.rows(), g.data(), g.size(),
                                           &error),
                  error);
    return g;
  }

  /// The Hessian, 3 n square, each collision's projected by `project_hessian_to_psd`.
  Csr hessian(const NormalCollisions& c, const CollisionMesh&, Points x,
              PSDProjectionMethod project_hessian_to_psd = PSDProjectionMethod::NONE) const {
    return hessian(c, x, project_hessian_to_psd);
  }
  Csr hessian(const NormalCollisions& c, Points x,
              PSDProjectionMethod project_hessian_to_psd = PSDProjectionMethod::NONE) const {
    topoccd_sparse* m = nullptr;
    topoccd_error* error = nullptr;
    detail::check(topoccd_barrier_hessian(&c_, need(c), x.data(), x.rows(),
                                          static_cast<std::uint32_t>(project_hessian_to_psd), &m,
                                          &error),
                  error);
    return Csr::take(m);
  }

  const topoccd_barrier_potential& c() const& noexcept { return c_; }
  const topoccd_barrier_potential& c() const&& = delete;

 private:
  static const topoccd_collisions* need(const NormalCollisions& c) {
    if (c.get() == nullptr) {
      throw Error(TOPOCCD_STATUS_NULL_POINTER, "the NormalCollisions were never built");
    }
    return c.get();
  }

  topoccd_barrier_potential c_;
};

/// The tangential collisions of a normal collision set at its lagged positions (ipctk's
/// `TangentialCollisions`), with the barrier's normal forces and friction coefficients.
class TangentialCollisions {
 public:
  TangentialCollisions() = default;

  /// ipctk's `build(mesh, x, collisions, B, mu)` (static and kinetic `mu`), or `mu_s`, `mu_k`.
  void build(const CollisionMesh&, Points x, const NormalCollisions& collisions,
             const BarrierPotential& B, double mu_s, double mu_k) {
    if (collisions.get() == nullptr) {
      throw Error(TOPOCCD_STATUS_NULL_POINTER, "the NormalCollisions were never built");
    }
    topoccd_tangential_collisions* t = nullptr;
    topoccd_error* error = nullptr;
    detail::check(topoccd_tangential_collisions_build(collisions.get(), &B.c(), x.data(), x.rows(),
                                                      mu_s, mu_k, &t, &error),
                  error);
    set_ = detail::Owned<topoccd_tangential_collisions, topoccd_tangential_collisions_free>(t);
    detail::check(topoccd_tangential_collisions_arrays(set_.get(), &rows_, &count_, &error), error);
  }
  void build(const CollisionMesh& mesh, Points x, const NormalCollisions& collisions,
             const BarrierPotential& B, double mu) {
    build(mesh, x, collisions, B, mu, mu);
  }

  std::size_t size() const noexcept { return set_.get() ? count_ : 0; }
  bool empty() const noexcept { return size() == 0; }
  Span<const topoccd_tangential_collision> collisions() const noexcept { return {rows_, size()}; }
  const topoccd_tangential_collision& operator[](std::size_t i) const noexcept { return rows_[i]; }

  const topoccd_tangential_collisions* get() const noexcept { return set_.get(); }

 private:
  detail::Owned<topoccd_tangential_collisions, topoccd_tangential_collisions_free> set_;
  const topoccd_tangential_collision* rows_ = nullptr;
  std::size_t count_ = 0;
};

/// The smooth friction potential over velocities (ipctk's `FrictionPotential(eps_v)`).
class FrictionPotential {
 public:
  explicit FrictionPotential(double eps_v) noexcept : eps_v_(eps_v) {}

  double eps_v() const noexcept { return eps_v_; }

  /// The energy at velocities `v` (ipctk's `D(collisions, mesh, v)`).
  double operator()(const TangentialCollisions& t, const CollisionMesh&, Points v) const {
    return (*this)(t, v);
  }
  double operator()(const TangentialCollisions& t, Points v) const {
    double e = 0.0;
    topoccd_error* error = nullptr;
    detail::check(topoccd_friction_energy(eps_v_, need(t), v.data(), v.rows(), &e, &error), error);
    return e;
  }

  /// The gradient in the velocities, 3 n entries.
  std::vector<double> gradient(const TangentialCollisions& t, const CollisionMesh&, Points v) const {
    return gradient(t, v);
  }
  std::vector<double> gradient(const TangentialCollisions& t, Points v) const {
    std::vector<double> g(3 * v.rows());
    topoccd_error* error = nullptr;
    detail::check(topoccd_friction_gradient(eps_v_, need(t), v.data(), v.rows(), g.data(),
                                            g.size(), &error),
                  error);
    return g;
  }

  /// The Hessian in the velocities, 3 n square.
  Csr hessian(const TangentialCollisions& t, const CollisionMesh&, Points v,
              PSDProjectionMethod project_hessian_to_psd = PSDProjectionMethod::NONE) const {
    return hessian(t, v, project_hessian_to_psd);
  }
  Csr hessian(const TangentialCollisions& t, Points v,
              PSDProjectionMethod project_hessian_to_psd = PSDProjectionMethod::NONE) const {
    topoccd_sparse* m = nullptr;
    topoccd_error* error = nullptr;
    detail::check(topoccd_friction_hessian(eps_v_, need(t), v.data(), v.rows(),
                                           static_cast<std::uint32_t>(project_hessian_to_psd), &m,
                                           &error),
                  error);
    return Csr::take(m);
  }

 private:
  static const topoccd_tangential_collisions* need(const TangentialCollisions& t) {
    if (t.get() == nullptr) {
      throw Error(TOPOCCD_STATUS_NULL_POINTER, "the TangentialCollisions were never built");
    }
    return t.get();
  }

  double eps_v_;
};

/// ipctk's `initial_barrier_stiffness`: the stiffness, with its cap in `max_barrier_stiffness`.
inline double initial_barrier_stiffness(double bbox_diagonal, Barrier barrier, double dhat,
                                        double average_mass,
                                        const std::vector<double>& grad_energy,
                                        const std::vector<double>& grad_barrier,
                                        double& max_barrier_stiffness,
                                        double min_barrier_stiffness_scale = 1e11,
                                        double dmin = 0.0) {
  if (grad_energy.size() != grad_barrier.size()) {
    throw Error(TOPOCCD_STATUS_INVALID_ARGUMENT,
                "grad_energy and grad_barrier have different lengths");
  }
  double k = 0.0;
  topoccd_error* error = nullptr;
  detail::check(topoccd_initial_barrier_stiffness(
                    bbox_diagonal, static_cast<std::uint32_t>(barrier), dhat, average_mass,
                    grad_energy.data(), grad_barrier.data(), grad_energy.size(),
                    min_barrier_stiffness_scale, dmin, &k, &max_barrier_stiffness, &error),
                error);
  return k;
}

/// ipctk's `update_barrier_stiffness` (squared distances).
inline double update_barrier_stiffness(double prev_min_distance, double min_distance,
                                       double max_barrier_stiffness, double barrier_stiffness,
                                       double bbox_diagonal, double dhat_epsilon_scale = 1e-9,
                                       double dmin = 0.0) {
  topoccd_error* error = nullptr;
  detail::check(topoccd_update_barrier_stiffness(prev_min_distance, min_distance,
                                                 max_barrier_stiffness, bbox_diagonal,
                                                 dhat_epsilon_scale, dmin, &barrier_stiffness,
                                                 &error),
                error);
  return barrier_stiffness;
}

}  // namespace ipc

}  // namespace topoccd

#endif  // TOPOCCD_HPP

// The contact potential of an IPC solver through the C++ wrapper, in the IPC toolkit's names.
//
//     ipc_cpp
//
// A point 0.5e-3 above a triangle: one face-vertex collision whose energy must be the analytic
// kappa * b(d^2); then a 5x5 cloth patch over a floor: the gradient against central finite
// differences of the energy, the plain Hessian against those of the gradient, and the
// PSD-projected Hessian symmetric with v^T H v >= 0 on random vectors. The
// stiffness helpers and friction (mu = 0.5) follow. Exits with 1 on a mismatch.
#include <topoccd.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

namespace ti = topoccd::ipc;

static int failures = 0;

static void expect(bool ok, const char* what) {
  if (!ok) {
    std::fprintf(stderr, "MISMATCH: %s\n", what);
    failures++;
  }
}

int main() {
  try {
    const double dhat = 1e-3, kappa = 10.0;
    const ti::BarrierPotential B(dhat, kappa);

    // 1. A point over a triangle.
    {
      const double h = 0.5e-3;
      const std::vector<std::array<double, 3>> x = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.2, 0.2, h}};
      const std::vector<std::array<std::uint32_t, 3>> faces = {{0, 1, 2}};
      const ti::CollisionMesh mesh(x, faces);
      ti::NormalCollisions collisions;
      collisions.build(mesh, x, dhat);
      const double e = B(collisions, mesh, x);
      const double d2 = h * h, dh2 = dhat * dhat;
      const double truth = -kappa * (d2 - dh2) * (d2 - dh2) * std::log(d2 / dh2);
      std::printf("point over triangle: %zu collision(s), %zu fv; energy %.12g (analytic %.12g)\n",
                  collisions.size(), collisions.fv_collisions().size(), e, truth);
      expect(collisions.size() == 1 && collisions.fv_collisions().size() == 1, "one fv collision");
      expect(std::abs(e - truth) <= 1e-12 * truth, "the energy is kappa b(d^2)");
      const double d2min = collisions.compute_minimum_distance(mesh, x);
      expect(std::abs(d2min - d2) <= 1e-12 * d2, "the minimum distance is h^2");
    }

    // 2. A cloth patch over a floor.
    const int n = 5;
    std::vector<std::array<double, 3>> x = {{-1, -1, 0}, {2, -1, 0}, {2, 2, 0}, {-1, 2, 0}};
    std::vector<std::array<std::uint32_t, 3>> faces = {{0, 1, 2}, {0, 2, 3}};
    for (int i = 0; i < n; i++) {
      for (int j = 0; j < n; j++) {
        x.push_back({0.1 * j + 0.03, 0.1 * i, 0.4e-3 + 0.1e-3 * std::sin(1.3 * i + 0.7 * j)});
        const std::uint32_t v = 4 + i * n + j;
        if (i + 1 < n && j + 1 < n) {
          faces.push_back({v, v + 1, v + n + 1});
          faces.push_back({v, v + n + 1, v + n});
        }
      }
    }
    const ti::CollisionMesh mesh(x, faces);
    ti::NormalCollisions collisions;
    collisions.use_area_weighting = true;
    collisions.build(mesh, x, dhat);
    std::printf("cloth patch: %zu vv, %zu ev, %zu ee, %zu fv\n", collisions.vv_collisions().size(),
                collisions.ev_collisions().size(), collisions.ee_collisions().size(),
                collisions.fv_collisions().size());
    expect(collisions.fv_collisions().size() == static_cast<std::size_t>(n * n),
           "each patch vertex is over the floor");
    const std::size_t dof = 3 * x.size();
    auto coordinate = [&](std::size_t k) -> double& { return x[k / 3][k % 3]; };

    const std::vector<double> g = B.gradient(collisions, mesh, x);
    double diff = 0, norm = 0;
    for (std::size_t k = 0; k < dof; k++) {
      const double step = 1e-9, saved = coordinate(k);
      coordinate(k) = saved + step;
      const double ep = B(collisions, x);
      coordinate(k) = saved - step;
      const double em = B(collisions, x);
      coordinate(k) = saved;
      const double fd = (ep - em) / (2 * step);
      diff += (fd - g[k]) * (fd - g[k]);
      norm += g[k] * g[k];
    }
    std::printf("cloth patch: energy %.12g, gradient within %.2e of finite differences\n",
                B(collisions, x), std::sqrt(diff / norm));
    expect(std::sqrt(diff / norm) < 1e-6, "the gradient matches finite differences");

    const ti::Csr H = B.hessian(collisions, mesh, x);
    diff = 0, norm = 0;
    for (std::size_t k = 0; k < dof; k++) {
      const double step = 1e-10, saved = coordinate(k);
      coordinate(k) = saved + step;
      const std::vector<double> gp = B.gradient(collisions, x);
      coordinate(k) = saved - step;
      const std::vector<double> gm = B.gradient(collisions, x);
      coordinate(k) = saved;
      for (std::size_t i = 0; i < dof; i++) {
        const double fd = (gp[i] - gm[i]) / (2 * step);
        diff += (fd - H(i, k)) * (fd - H(i, k));
        norm += H(i, k) * H(i, k);
      }
    }
    std::printf("cloth patch: Hessian %zu nonzeros, within %.2e of finite differences\n", H.nnz(),
                std::sqrt(diff / norm));
    expect(H.size == dof && std::sqrt(diff / norm) < 1e-5, "the Hessian matches finite differences");

    const ti::Csr P = B.hessian(collisions, mesh, x, ti::PSDProjectionMethod::CLAMP);
    double scale = 0, asym = 0;
    for (std::size_t i = 0; i < dof; i++) {
      for (std::size_t k = P.indptr[i]; k < P.indptr[i + 1]; k++) {
        scale = std::max(scale, std::abs(P.data[k]));
        asym = std::max(asym, std::abs(P.data[k] - P(P.indices[k], i)));
      }
    }
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> u(-0.5, 0.5);
    double worst = INFINITY;
    for (int trial = 0; trial < 100; trial++) {
      std::vector<double> v(dof);
      double vv = 0, vpv = 0;
      for (double& c : v) c = u(rng), vv += c * c;
      const std::vector<double> pv = P * v;
      for (std::size_t k = 0; k < dof; k++) vpv += v[k] * pv[k];
      worst = std::min(worst, vpv / (vv * scale));
    }
    std::printf("cloth patch: PSD Hessian symmetric within %.1e, min v'Hv/(|v|^2 max|H|) %.3g\n",
                asym / scale, worst);
    expect(asym <= 1e-12 * scale && worst >= -1e-12, "the projected Hessian is symmetric PSD");

    double kmax = 0;
    std::vector<double> ge(dof, 0.0);
    for (std::size_t k = 2; k < dof; k += 3) ge[k] = 9.81;
    const double k0 = ti::initial_barrier_stiffness(3.0, ti::Barrier::ClampedLog, dhat, 1.0, ge, g, kmax);
    const double d2min = collisions.compute_minimum_distance(x);
    const double k1 = ti::update_barrier_stiffness(d2min, d2min / 2, kmax, k0, 3.0);
    std::printf("cloth patch: minimum distance %.6g, initial stiffness %.6g (max %.6g), updated %.6g\n",
                std::sqrt(d2min), k0, kmax, k1);
    expect(k0 > 0 && k0 <= kmax && k1 == k0, "the stiffness helpers");

    // Friction, mu = 0.5, eps_v = 1e-3: the patch sliding as one dissipates sum w N mu |P^T v|
    // (each relative velocity is +-v); on a varied field the gradient matches differences.
    ti::TangentialCollisions tc;
    tc.build(mesh, x, collisions, B, 0.5);
    const ti::FrictionPotential D(1e-3);
    std::vector<std::array<double, 3>> vel(x.size(), {0, 0, 0});
    for (std::size_t i = 4; i < vel.size(); i++) vel[i] = {0.3, -0.1, 0};
    double truth = 0;
    for (const auto& t : tc.collisions()) {
      const double* p = t.tangent_basis;
      const double a = p[0] * 0.3 - p[1] * 0.1, b = p[3] * 0.3 - p[4] * 0.1;
      truth += t.weight * t.normal_force_magnitude * t.mu_k * std::sqrt(a * a + b * b);
    }
    const double fe = D(tc, mesh, vel);
    std::printf("cloth patch: %zu tangential collisions, friction energy %.12g (sum w N mu |P'v| %.12g)\n",
                tc.size(), fe, truth);
    expect(!tc.empty() && std::abs(fe - truth) <= 1e-10 * truth, "the sliding patch's friction energy");
    for (std::size_t k = 12; k < dof; k++) vel[k / 3][k % 3] = 1e-3 * std::sin(0.37 * k);
    const std::vector<double> fg = D.gradient(tc, mesh, vel);
    diff = 0, norm = 0;
    for (std::size_t k = 0; k < dof; k++) {
      const double step = 1e-8, saved = vel[k / 3][k % 3];
      vel[k / 3][k % 3] = saved + step;
      const double ep = D(tc, vel);
      vel[k / 3][k % 3] = saved - step;
      const double em = D(tc, vel);
      vel[k / 3][k % 3] = saved;
      diff += ((ep - em) / (2 * step) - fg[k]) * ((ep - em) / (2 * step) - fg[k]);
      norm += fg[k] * fg[k];
    }
    const ti::Csr FH = D.hessian(tc, mesh, vel, ti::PSDProjectionMethod::CLAMP);
    std::printf("cloth patch: friction gradient within %.2e of finite differences, Hessian %zu nonzeros\n",
                std::sqrt(diff / norm), FH.nnz());
    expect(std::sqrt(diff / norm) < 1e-6 && FH.size == dof && FH.nnz() > 0, "the friction gradient");
  } catch (const topoccd::Error& e) {
    std::fprintf(stderr, "error: %s (%s)\n", e.what(), e.status_name());
    return 2;
  }
  if (failures > 0) {
    std::fprintf(stderr, "%d mismatch(es)\n", failures);
    return 1;
  }
  std::printf("all checks passed\n");
  return 0;
}

/* The contact potential of an IPC solver, in C: the normal collisions, the barrier energy, its
 * gradient and its PSD-projected Hessian, the minimum distance and the stiffness helpers.
 *
 *     ipc
 *
 * Two scenes, each checked here against independent truth, exiting with 1 on a mismatch:
 *  - a point 0.5e-3 above a triangle: one face-vertex collision, whose energy must be the
 *    analytic kappa * b(d^2) = -kappa (d^2 - dhat^2)^2 ln(d^2 / dhat^2);
 *  - a 5x5 cloth patch 0.4e-3 above a floor of two triangles (rest positions: the patch
 *    flat at z = 0.5): the gradient must match central finite differences of the energy, the
 *    plain Hessian central differences of the gradient, and the projected Hessian must be
 *    symmetric and positive semi-definite along random directions;
 *  - friction (mu = 0.5) over both: the lagged normal force of the point is the barrier's push
 *    |dE/dz|, a sliding motion dissipates mu N |v|, and the friction gradient matches central
 *    differences. */
#include <topoccd.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define N 5 /* the patch's vertices per side */
#define NV (4 + N * N)

static int failures = 0;

static void expect(int ok, const char *what) {
    if (!ok) {
        fprintf(stderr, "MISMATCH: %s\n", what);
        failures++;
    }
}

static int check(topoccd_status s, topoccd_error **error, const char *what) {
    if (s == TOPOCCD_STATUS_OK) return 1;
    fprintf(stderr, "%s: %s (%s)\n", what, topoccd_error_message(*error), topoccd_status_name(s));
    topoccd_error_free(error);
    exit(2);
}

static double energy(const topoccd_barrier_potential *b, const topoccd_collisions *c,
                     const double *x, size_t n) {
    topoccd_error *error = NULL;
    double e = 0;
    check(topoccd_barrier_energy(b, c, x, n, &e, &error), &error, "energy");
    return e;
}

/* y = H v */
static void multiply(const topoccd_csr *h, const double *v, double *y) {
    for (size_t i = 0; i < h->size; i++) {
        y[i] = 0;
        for (size_t k = h->indptr[i]; k < h->indptr[i + 1]; k++) y[i] += h->data[k] * v[h->indices[k]];
    }
}

static double entry(const topoccd_csr *h, size_t i, size_t j) {
    for (size_t k = h->indptr[i]; k < h->indptr[i + 1]; k++)
        if (h->indices[k] == j) return h->data[k];
    return 0;
}

int main(void) {
    topoccd_ccd *ccd = topoccd_ccd_new();
    topoccd_error *error = NULL;
    const double dhat = 1e-3, kappa = 10.0;
    topoccd_collision_options options = topoccd_collision_options_default();
    options.dhat = dhat;
    topoccd_barrier_potential barrier = topoccd_barrier_potential_new(dhat, kappa);

    /* 1. A point over a triangle. */
    {
        const double h = 0.5e-3;
        const double x[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0.2, 0.2, h};
        const uint32_t triangles[] = {0, 1, 2};
        topoccd_configuration config = {0};
        config.x = x; config.vertex_count = 4;
        config.triangles = triangles; config.triangle_count = 1;
        topoccd_collisions *c = NULL;
        if (topoccd_collisions_build(ccd, &config, x, 4, &options, &c) != TOPOCCD_STATUS_OK) {
            fprintf(stderr, "build: %s\n", topoccd_ccd_last_error(ccd));
            return 2;
        }
        topoccd_collision_arrays a;
        check(topoccd_collisions_arrays(c, &a, &error), &error, "arrays");
        const double e = energy(&barrier, c, x, 4);
        const double d2 = h * h, dh2 = dhat * dhat;
        const double truth = -kappa * (d2 - dh2) * (d2 - dh2) * log(d2 / dh2);
        printf("point over triangle: %zu vv, %zu ev, %zu ee, %zu fv; energy %.12g (analytic %.12g)\n",
               a.vv_count, a.ev_count, a.ee_count, a.fv_count, e, truth);
        expect(a.fv_count == 1 && a.vv_count + a.ev_count + a.ee_count == 0, "one fv collision");
        expect(a.fv_count == 1 && a.fv[0].vertex == 3 && a.fv[0].face == 0 && a.fv[0].weight == 1,
               "the fv collision is vertex 3 over face 0, weight 1");
        expect(fabs(e - truth) <= 1e-12 * truth, "the energy is kappa b(d^2)");
        double g[12];
        check(topoccd_barrier_gradient(&barrier, c, x, 4, g, 12, &error), &error, "gradient");
        /* d/dz of kappa b(z^2) = kappa b'(d^2) 2 z, with b'(s) = -2 (s - t) ln(s / t) - (s - t)^2 / s */
        const double db = -2 * (d2 - dh2) * log(d2 / dh2) - (d2 - dh2) * (d2 - dh2) / d2;
        const double gz = kappa * db * 2 * h;
        printf("point over triangle: dE/dz of the point %.12g (analytic %.12g)\n", g[11], gz);
        expect(fabs(g[11] - gz) <= 1e-10 * fabs(gz), "the gradient's z is kappa b'(d^2) 2 d");
        expect(fabs(g[9]) + fabs(g[10]) <= 1e-12 * fabs(gz), "no tangential gradient");
        double d2min = 0;
        check(topoccd_collisions_minimum_distance(c, x, 4, &d2min, &error), &error, "minimum distance");
        printf("point over triangle: minimum squared distance %.12g (analytic %.12g)\n", d2min, d2);
        expect(d2min <= d2 * (1 + 1e-12) && d2min >= d2 * (1 - 1e-12), "the minimum distance is h^2");

        /* Friction, mu = 0.5: the lagged normal force is the barrier's push |dE/dz|, and the
         * point sliding at speed 2 (above eps_v) dissipates mu N |v|. */
        topoccd_tangential_collisions *t = NULL;
        check(topoccd_tangential_collisions_build(c, &barrier, x, 4, 0.5, 0.5, &t, &error), &error,
              "tangential collisions");
        const topoccd_tangential_collision *rows = NULL;
        size_t count = 0;
        check(topoccd_tangential_collisions_arrays(t, &rows, &count, &error), &error, "arrays");
        const double v[12] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 2, 0, 0};
        double fe = 0;
        check(topoccd_friction_energy(1e-3, t, v, 4, &fe, &error), &error, "friction energy");
        printf("point over triangle: %zu tangential collision, normal force %.12g (|dE/dz| %.12g), "
               "friction energy %.12g (mu N |v| %.12g)\n",
               count, count ? rows[0].normal_force_magnitude : 0.0, fabs(gz), fe, 0.5 * fabs(gz) * 2);
        expect(count == 1 && fabs(rows[0].normal_force_magnitude - fabs(gz)) <= 1e-10 * fabs(gz),
               "the normal force is the barrier's push");
        expect(fabs(fe - 0.5 * fabs(gz) * 2) <= 1e-10 * fe, "the friction energy is mu N |v|");
        topoccd_tangential_collisions_free(&t);
        topoccd_collisions_free(&c);
    }

    /* 2. A cloth patch over a floor. */
    {
        double x[3 * NV], rest[3 * NV];
        const double floor_x[] = {-1, -1, 0, 2, -1, 0, 2, 2, 0, -1, 2, 0};
        memcpy(x, floor_x, sizeof floor_x);
        memcpy(rest, floor_x, sizeof floor_x);
        uint32_t triangles[3 * (2 + 2 * (N - 1) * (N - 1))];
        size_t t = 0;
        triangles[t++] = 0; triangles[t++] = 1; triangles[t++] = 2;
        triangles[t++] = 0; triangles[t++] = 2; triangles[t++] = 3;
        for (int i = 0; i < N; i++) {
            for (int j = 0; j < N; j++) {
                const int v = 4 + i * N + j;
                /* A little wavy, so that the vertices are at different heights. */
                x[3 * v] = 0.1 * j + 0.03; /* off the floor's diagonal */
                x[3 * v + 1] = 0.1 * i;
                x[3 * v + 2] = 0.4e-3 + 0.1e-3 * sin(1.3 * i + 0.7 * j);
                rest[3 * v] = 0.1 * j + 0.03;
                rest[3 * v + 1] = 0.1 * i;
                rest[3 * v + 2] = 0.5;
                if (i + 1 < N && j + 1 < N) {
                    triangles[t++] = v; triangles[t++] = v + 1; triangles[t++] = v + N + 1;
                    triangles[t++] = v; triangles[t++] = v + N + 1; triangles[t++] = v + N;
                }
            }
        }
        topoccd_configuration config = {0};
        config.x = x; config.vertex_count = NV;
        config.triangles = triangles; config.triangle_count = t / 3;
        topoccd_collision_options weighted = options;
        weighted.use_area_weighting = true;
        topoccd_collisions *c = NULL;
        if (topoccd_collisions_build(ccd, &config, rest, NV, &weighted, &c) != TOPOCCD_STATUS_OK) {
            fprintf(stderr, "build: %s\n", topoccd_ccd_last_error(ccd));
            return 2;
        }
        topoccd_collision_arrays a;
        check(topoccd_collisions_arrays(c, &a, &error), &error, "arrays");
        printf("cloth patch: %zu vv, %zu ev, %zu ee, %zu fv\n", a.vv_count, a.ev_count,
               a.ee_count, a.fv_count);
        expect(a.fv_count == N * N, "each patch vertex is over the floor");
        const double e = energy(&barrier, c, x, NV);
        printf("cloth patch: energy %.12g\n", e);
        expect(e > 0 && isfinite(e), "a positive energy");

        /* The gradient against central differences of the energy. */
        double g[3 * NV];
        check(topoccd_barrier_gradient(&barrier, c, x, NV, g, 3 * NV, &error), &error, "gradient");
        double diff = 0, norm = 0;
        for (int k = 0; k < 3 * NV; k++) {
            const double step = 1e-9, saved = x[k];
            x[k] = saved + step;
            const double ep = energy(&barrier, c, x, NV);
            x[k] = saved - step;
            const double em = energy(&barrier, c, x, NV);
            x[k] = saved;
            const double fd = (ep - em) / (2 * step);
            diff += (fd - g[k]) * (fd - g[k]);
            norm += g[k] * g[k];
        }
        printf("cloth patch: |gradient| %.6g, finite differences within %.2e relative\n", sqrt(norm),
               sqrt(diff / norm));
        expect(sqrt(diff / norm) < 1e-6, "the gradient matches finite differences");

        /* The plain Hessian against central differences of the gradient. */
        topoccd_sparse *hessian = NULL;
        check(topoccd_barrier_hessian(&barrier, c, x, NV, TOPOCCD_PSD_PROJECTION_NONE, &hessian, &error),
              &error, "hessian");
        topoccd_csr h;
        check(topoccd_sparse_csr(hessian, &h, &error), &error, "csr");
        double gp[3 * NV], gm[3 * NV];
        diff = 0, norm = 0;
        for (size_t k = 0; k < 3 * NV; k++) {
            const double step = 1e-10, saved = x[k];
            x[k] = saved + step;
            check(topoccd_barrier_gradient(&barrier, c, x, NV, gp, 3 * NV, &error), &error, "gradient");
            x[k] = saved - step;
            check(topoccd_barrier_gradient(&barrier, c, x, NV, gm, 3 * NV, &error), &error, "gradient");
            x[k] = saved;
            for (size_t i = 0; i < 3 * NV; i++) {
                const double fd = (gp[i] - gm[i]) / (2 * step), hi = entry(&h, i, k);
                diff += (fd - hi) * (fd - hi);
                norm += hi * hi;
            }
        }
        printf("cloth patch: Hessian %zu x %zu, %zu nonzeros, finite differences within %.2e relative\n",
               h.size, h.size, h.nnz, sqrt(diff / norm));
        expect(h.size == 3 * NV && sqrt(diff / norm) < 1e-5, "the Hessian matches finite differences");
        topoccd_sparse_free(&hessian);

        /* The projected Hessian: symmetric, and v^T H v >= 0. */
        check(topoccd_barrier_hessian(&barrier, c, x, NV, TOPOCCD_PSD_PROJECTION_CLAMP, &hessian, &error),
              &error, "hessian");
        check(topoccd_sparse_csr(hessian, &h, &error), &error, "csr");
        double asym = 0, scale = 0, worst = INFINITY;
        for (size_t i = 0; i < h.size; i++)
            for (size_t k = h.indptr[i]; k < h.indptr[i + 1]; k++) {
                asym = fmax(asym, fabs(h.data[k] - entry(&h, h.indices[k], i)));
                scale = fmax(scale, fabs(h.data[k]));
            }
        srand(1);
        double v[3 * NV], hv[3 * NV];
        for (int trial = 0; trial < 100; trial++) {
            double vv = 0, vhv = 0;
            for (int k = 0; k < 3 * NV; k++) v[k] = rand() / (double)RAND_MAX - 0.5, vv += v[k] * v[k];
            multiply(&h, v, hv);
            for (int k = 0; k < 3 * NV; k++) vhv += v[k] * hv[k];
            worst = fmin(worst, vhv / (vv * scale));
        }
        printf("cloth patch: PSD Hessian %zu nonzeros, symmetric within %.1e, min v'Hv/(|v|^2 max|H|) %.3g\n",
               h.nnz, asym / scale, worst);
        expect(asym <= 1e-12 * scale && worst >= -1e-12, "the projected Hessian is symmetric PSD");
        topoccd_sparse_free(&hessian);

        /* The stiffness helpers, from the squared minimum distance. */
        double d2min = 0, k0 = 0, kmax = 0;
        check(topoccd_collisions_minimum_distance(c, x, NV, &d2min, &error), &error, "minimum distance");
        double ge[3 * NV];
        for (int k = 0; k < 3 * NV; k++) ge[k] = (k % 3 == 2) ? 9.81 : 0; /* gravity's gradient */
        check(topoccd_initial_barrier_stiffness(3.0, TOPOCCD_BARRIER_CLAMPED_LOG, dhat, 1.0, ge, g,
                                                3 * NV, 1e11, 0.0, &k0, &kmax, &error),
              &error, "initial stiffness");
        double k1 = k0;
        check(topoccd_update_barrier_stiffness(d2min, d2min / 2, kmax, 3.0, 1e-9, 0.0, &k1, &error),
              &error, "update stiffness");
        printf("cloth patch: minimum distance %.6g, initial stiffness %.6g (max %.6g), updated %.6g\n",
               sqrt(d2min), k0, kmax, k1);
        expect(k0 > 0 && k0 <= kmax, "the initial stiffness is in range");
        /* The minimum distance is far above 1e-9 of the diagonal: no doubling. */
        expect(k1 == k0, "no update when the gap is wide");

        /* Friction over the patch, mu = 0.5, eps_v = 1e-3. */
        topoccd_tangential_collisions *tc = NULL;
        check(topoccd_tangential_collisions_build(c, &barrier, x, NV, 0.5, 0.5, &tc, &error), &error,
              "tangential collisions");
        const topoccd_tangential_collision *rows = NULL;
        size_t count = 0;
        check(topoccd_tangential_collisions_arrays(tc, &rows, &count, &error), &error, "arrays");
        /* The patch sliding as one (the floor fixed): every relative velocity is +-v, so the
         * energy is sum w N mu |P^T v| (all above eps_v). */
        double vel[3 * NV] = {0}, fe = 0, truth = 0;
        for (int k = 12; k < 3 * NV; k += 3) vel[k] = 0.3, vel[k + 1] = -0.1;
        for (size_t i = 0; i < count; i++) {
            const double *p = rows[i].tangent_basis;
            const double a = p[0] * 0.3 - p[1] * 0.1, b = p[3] * 0.3 - p[4] * 0.1;
            truth += rows[i].weight * rows[i].normal_force_magnitude * rows[i].mu_k * sqrt(a * a + b * b);
        }
        check(topoccd_friction_energy(1e-3, tc, vel, NV, &fe, &error), &error, "friction energy");
        printf("cloth patch: %zu tangential collisions, friction energy %.12g (sum w N mu |P'v| %.12g)\n",
               count, fe, truth);
        expect(count > 0 && count <= a.vv_count + a.ev_count + a.ee_count + a.fv_count,
               "tangential collisions");
        expect(fabs(fe - truth) <= 1e-10 * truth, "the sliding patch's friction energy");
        /* A varied velocity field: the gradient against central differences. */
        for (int k = 12; k < 3 * NV; k++) vel[k] = 1e-3 * sin(0.37 * k);
        double fg[3 * NV];
        check(topoccd_friction_gradient(1e-3, tc, vel, NV, fg, 3 * NV, &error), &error, "friction gradient");
        diff = 0, norm = 0;
        for (int k = 0; k < 3 * NV; k++) {
            const double step = 1e-8, saved = vel[k];
            double ep = 0, em = 0;
            vel[k] = saved + step;
            check(topoccd_friction_energy(1e-3, tc, vel, NV, &ep, &error), &error, "friction energy");
            vel[k] = saved - step;
            check(topoccd_friction_energy(1e-3, tc, vel, NV, &em, &error), &error, "friction energy");
            vel[k] = saved;
            const double fd = (ep - em) / (2 * step);
            diff += (fd - fg[k]) * (fd - fg[k]);
            norm += fg[k] * fg[k];
        }
        printf("cloth patch: friction gradient within %.2e of finite differences\n", sqrt(diff / norm));
        expect(sqrt(diff / norm) < 1e-6, "the friction gradient matches finite differences");
        check(topoccd_friction_hessian(1e-3, tc, vel, NV, TOPOCCD_PSD_PROJECTION_CLAMP, &hessian, &error), &error,
              "friction hessian");
        check(topoccd_sparse_csr(hessian, &h, &error), &error, "csr");
        printf("cloth patch: friction Hessian %zu nonzeros\n", h.nnz);
        expect(h.size == 3 * NV && h.nnz > 0, "a friction Hessian");
        topoccd_sparse_free(&hessian);
        topoccd_tangential_collisions_free(&tc);
        topoccd_collisions_free(&c);
    }
    topoccd_ccd_free(&ccd);
    if (failures > 0) {
        fprintf(stderr, "%d mismatch(es)\n", failures);
        return 1;
    }
    printf("all checks passed\n");
    return 0;
}

/* Tests of the C API, run under AddressSanitizer and UndefinedBehaviorSanitizer by
 * scripts/test-c.sh: results on steps with analytic answers, then every error path (NULL
 * pointers, mismatched lengths, out-of-range indices, NaN, invalid options, files that cannot be
 * read, a destroyed or foreign handle, a handle used by two threads at once). Any leak or
 * invalid access is an ASan error; the last line says how many checks passed and failed. */
#define _POSIX_C_SOURCE 200809L
#include <topoccd.h>

#include <math.h>
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

static int passed, failed;

#define CHECK(cond, ...)                                                        \
    do {                                                                        \
        if (cond) {                                                             \
            passed++;                                                           \
        } else {                                                                \
            failed++;                                                           \
            fprintf(stderr, "FAILED %s:%d: %s: ", __FILE__, __LINE__, #cond);   \
            fprintf(stderr, __VA_ARGS__);                                       \
            fprintf(stderr, "\n");                                              \
        }                                                                       \
    } while (0)

#define CHECK_STATUS(call, want, ...)                                                     \
    do {                                                                                  \
        topoccd_status got_ = (call);                                                     \
        CHECK(got_ == (want), __VA_ARGS__);                                               \
        if (got_ != (want))                                                               \
            fprintf(stderr, "  (%s, expected %s)\n", topoccd_status_name(got_),            \
                    topoccd_status_name(want));                                           \
    } while (0)

static int contains(const char *text, const char *part) { return text && strstr(text, part) != NULL; }

/* A triangle (3 4 5) falls 2 units through a fixed one (0 1 2): vertex 3 crosses it at
 * t = 0.5, vertices 4 and 5 at t = 0.75; nothing else touches. */
static const double FALL_X0[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0.2, 0.2, 1, 0.3, 0.2, 1.5, 0.2, 0.3, 1.5};
static const double FALL_X1[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0.2, 0.2, -1, 0.3, 0.2, -0.5, 0.2, 0.3, -0.5};
static const uint32_t FALL_TRIS[] = {0, 1, 2, 3, 4, 5};

static topoccd_step fall_step(void) {
    topoccd_step s = {0};
    s.x0 = FALL_X0;
    s.x0_count = 6;
    s.x1 = FALL_X1;
    s.x1_count = 6;
    s.triangles = FALL_TRIS;
    s.triangle_count = 2;
    return s;
}

/* Contacts compared field by field (their structs have padding, which memcmp would read). */
static int same_vf(const topoccd_vf_contact *a, const topoccd_vf_contact *b, size_t n) {
    for (size_t i = 0; i < n; i++) {
        if (a[i].vertex != b[i].vertex || a[i].face != b[i].face || a[i].toi != b[i].toi ||
            a[i].certainty != b[i].certainty || a[i].has_geometry != b[i].has_geometry)
            return 0;
    }
    return 1;
}

static const topoccd_report *report_of(topoccd_ccd *ccd) {
    const topoccd_report *r = NULL;
    topoccd_status s = topoccd_ccd_report(ccd, &r);
    CHECK_STATUS(s, TOPOCCD_STATUS_OK, "report");
    return r;
}

static void test_version_and_names(void) {
    CHECK(strlen(topoccd_version()) >= 5, "version %s", topoccd_version());
    CHECK(strcmp(topoccd_status_name(TOPOCCD_STATUS_INVALID_STEP), "TOPOCCD_STATUS_INVALID_STEP") == 0, "name");
    CHECK(strcmp(topoccd_status_name(12345), "TOPOCCD_STATUS_UNKNOWN") == 0, "an unknown code has a name");
}

static void test_options(void) {
    topoccd_query_options o;
    memset(&o, 0xAB, sizeof o);
    CHECK_STATUS(topoccd_query_options_default(&o), TOPOCCD_STATUS_OK, "default");
    CHECK(o.size == sizeof o, "size %zu", o.size);
    CHECK(o.method == TOPOCCD_METHOD_AUTO && o.mode == TOPOCCD_MODE_ALL, "method %u mode %u", o.method, o.mode);
    CHECK(o.tolerance == 1e-6 && o.max_iterations == 1000000 && o.k == 18, "narrow defaults");
    CHECK(o.min_distance == 0 && o.tmax == 1 && o.threads == 0, "more defaults");
    CHECK(!o.geometry && o.crack_filter && o.growth == TOPOCCD_GROWTH_CERTIFICATE, "flags");
    CHECK_STATUS(topoccd_query_options_init(NULL, sizeof o), TOPOCCD_STATUS_NULL_POINTER, "NULL options");
    CHECK_STATUS(topoccd_query_options_init(&o, 3), TOPOCCD_STATUS_INVALID_ARGUMENT, "a size no version has");
    CHECK_STATUS(topoccd_query_options_init(&o, sizeof o + 8), TOPOCCD_STATUS_INVALID_ARGUMENT,
                 "a newer header's size");
}

static void test_falling_triangle(void) {
    topoccd_ccd *ccd = topoccd_ccd_new();
    topoccd_step s = fall_step();
    const topoccd_report *r = report_of(ccd);
    CHECK(r->vf_count == 0 && r->earliest_kind == TOPOCCD_CONTACT_KIND_NONE && isnan(r->earliest_toi),
          "empty before the first query");

    CHECK_STATUS(topoccd_ccd_query(ccd, &s, NULL), TOPOCCD_STATUS_OK, "%s", topoccd_ccd_last_error(ccd));
    CHECK(strcmp(topoccd_ccd_last_error(ccd), "") == 0, "no message after success");
    r = report_of(ccd);
    CHECK(r->vf_count == 3 && r->ee_count == 0, "%zu vf %zu ee", r->vf_count, r->ee_count);
    const uint32_t want[3][2] = {{3, 0}, {4, 0}, {5, 0}};
    const double toi[3] = {0.5, 0.75, 0.75};
    for (size_t i = 0; i < 3 && i < r->vf_count; i++) {
        const topoccd_vf_contact *c = &r->vf[i];
        CHECK(c->vertex == want[i][0] && c->face == want[i][1], "contact %zu: %u %u", i, c->vertex, c->face);
        CHECK(c->toi <= toi[i] && c->toi > toi[i] - 1e-6, "toi %.17g, exact %g", c->toi, toi[i]);
        CHECK(c->certainty == TOPOCCD_CERTAINTY_RESOLVED && !c->has_geometry, "certainty, no geometry");
    }
    CHECK(r->earliest_kind == TOPOCCD_CONTACT_KIND_VF && r->earliest_index == 0, "earliest is vf[0]");
    CHECK(r->earliest_toi == r->vf[0].toi && r->unresolved == 0, "earliest toi, unresolved");
    CHECK(r->stats.method == TOPOCCD_METHOD_BVH, "auto runs bvh on a small step: %u", r->stats.method);
    CHECK(r->stats.vf_tests >= 3 && !r->stats.has_cluster && isnan(r->stats.seconds.clustering), "stats");

    /* Every method and thread count reports the same contacts as the brute-force oracle. */
    topoccd_vf_contact oracle[3];
    topoccd_query_options o;
    topoccd_query_options_default(&o);
    o.method = TOPOCCD_METHOD_BRUTE;
    CHECK_STATUS(topoccd_ccd_query(ccd, &s, &o), TOPOCCD_STATUS_OK, "brute");
    r = report_of(ccd);
    CHECK(r->vf_count == 3, "brute finds %zu", r->vf_count);
    memcpy(oracle, r->vf, sizeof oracle);
    const uint32_t methods[] = {TOPOCCD_METHOD_BVH, TOPOCCD_METHOD_CLUSTER, TOPOCCD_METHOD_AUTO};
    const uint32_t threads[] = {0, 1, 2};
    for (int m = 0; m < 3; m++) {
        for (int t = 0; t < 3; t++) {
            o.method = methods[m];
            o.threads = threads[t];
            CHECK_STATUS(topoccd_ccd_query(ccd, &s, &o), TOPOCCD_STATUS_OK, "method %u", methods[m]);
            r = report_of(ccd);
            CHECK(r->vf_count == 3 && same_vf(r->vf, oracle, 3),
                  "method %u on %u threads differs from the oracle", methods[m], threads[t]);
        }
    }
    CHECK(r->stats.method == TOPOCCD_METHOD_BVH, "auto chose %u", r->stats.method);

    /* Geometry: vertex 3 meets face 0 (the plane z = 0) at (0.2, 0.2, 0), from above. */
    topoccd_query_options_default(&o);
    o.geometry = true;
    CHECK_STATUS(topoccd_ccd_query(ccd, &s, &o), TOPOCCD_STATUS_OK, "geometry");
    r = report_of(ccd);
    const topoccd_vf_geometry *g = &r->vf[0].geometry;
    CHECK(r->vf[0].has_geometry, "geometry requested");
    CHECK(g->normal[0] == 0 && g->normal[1] == 0 && g->normal[2] == 1, "normal %g %g %g", g->normal[0],
          g->normal[1], g->normal[2]);
    CHECK(fabs(g->point[0] - 0.2) < 1e-9 && fabs(g->point[1] - 0.2) < 1e-9 && fabs(g->point[2]) < 1e-9,
          "point %g %g %g", g->point[0], g->point[1], g->point[2]);
    CHECK(fabs(g->barycentric[0] + g->barycentric[1] + g->barycentric[2] - 1) < 1e-12 &&
              fabs(g->barycentric[1] - 0.2) < 1e-9 && g->distance < 1e-5,
          "barycentric %g %g %g distance %g", g->barycentric[0], g->barycentric[1], g->barycentric[2],
          g->distance);

    /* Earliest: only vertex 3's contact (the others are 0.25 later). */
    topoccd_query_options_default(&o);
    o.mode = TOPOCCD_MODE_EARLIEST;
    CHECK_STATUS(topoccd_ccd_query(ccd, &s, &o), TOPOCCD_STATUS_OK, "earliest");
    r = report_of(ccd);
    CHECK(r->vf_count == 1 && r->vf[0].vertex == 3 && r->earliest_toi == oracle[0].toi, "earliest pairs %zu",
          r->vf_count);

    /* A cap of two contacts: the report keeps the first two of its fixed order and says it
     * stopped; without the cap (or a cap the step does not reach) it is complete. */
    CHECK(report_of(ccd)->truncated == TOPOCCD_STOP_REASON_NONE, "a complete report");
    topoccd_query_options_default(&o);
    CHECK(o.max_contacts == 1000000 && o.timeout == 0, "a million contacts, no timeout by default");
    o.max_contacts = 2;
    CHECK_STATUS(topoccd_ccd_query(ccd, &s, &o), TOPOCCD_STATUS_OK, "max_contacts");
    r = report_of(ccd);
    CHECK(r->vf_count == 2 && r->truncated == TOPOCCD_STOP_REASON_MAX_CONTACTS, "%zu vf, truncated %u",
          r->vf_count, r->truncated);
    for (size_t i = 0; i < r->vf_count; i++) {
        int known = 0;
        for (size_t j = 0; j < 3; j++)
            known |= same_vf(&r->vf[i], &oracle[j], 1);
        CHECK(known, "kept contact %zu is one of the step's", i);
    }
    o.max_contacts = 3;
    o.timeout = 60;
    CHECK_STATUS(topoccd_ccd_query(ccd, &s, &o), TOPOCCD_STATUS_OK, "a cap the step does not pass");
    r = report_of(ccd);
    CHECK(r->vf_count == 3 && r->truncated == TOPOCCD_STOP_REASON_NONE && same_vf(r->vf, oracle, 3),
          "%zu vf, truncated %u", r->vf_count, r->truncated);

    /* tmax = 0.6 leaves out the contacts at 0.75. */
    topoccd_query_options_default(&o);
    o.tmax = 0.6;
    CHECK_STATUS(topoccd_ccd_query(ccd, &s, &o), TOPOCCD_STATUS_OK, "tmax");
    CHECK(report_of(ccd)->vf_count == 1, "tmax 0.6");

    /* Groups: one group for everything tests nothing; the fixed and the falling triangle in
     * two groups keep every contact. */
    const uint32_t one[6] = {7, 7, 7, 7, 7, 7};
    const uint32_t two[6] = {0, 0, 0, 1, 1, 1};
    s.groups = one;
    s.group_count = 6;
    CHECK_STATUS(topoccd_ccd_query(ccd, &s, NULL), TOPOCCD_STATUS_OK, "groups");
    CHECK(report_of(ccd)->vf_count == 0, "one group");
    s.groups = two;
    CHECK_STATUS(topoccd_ccd_query(ccd, &s, NULL), TOPOCCD_STATUS_OK, "groups");
    CHECK(report_of(ccd)->vf_count == 3, "two groups");
    topoccd_ccd_free(&ccd);
    CHECK(ccd == NULL, "free sets the pointer to NULL");
    topoccd_ccd_free(&ccd); /* freeing NULL again: nothing */
    topoccd_ccd_free(NULL);
}

/* The README's step across a cut: a folded-up flap is cut off along the edge 1-2 (vertices 4
 * and 5 are the copies of 1 and 2), and its tip, vertex 3, swings down through triangle 0 at
 * t = 0.5. With the crack filter off, the two sides of the fresh cut touch from t = 0. */
static void test_cut(void) {
    const double x0[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0.8, 0.8, 1};
    const double x1[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, -1, 1, 0, 0, 0, 1, 0};
    const uint32_t tris[] = {0, 1, 2, 4, 3, 5};
    const uint32_t parents[] = {4, 1, 5, 2};
    topoccd_step s = {0};
    s.x0 = x0;
    s.x0_count = 4;
    s.x1 = x1;
    s.x1_count = 6;
    s.triangles = tris;
    s.triangle_count = 2;
    s.parents = parents;
    s.parent_count = 2;
    topoccd_ccd *ccd = topoccd_ccd_new();
    CHECK_STATUS(topoccd_ccd_query(ccd, &s, NULL), TOPOCCD_STATUS_OK, "%s", topoccd_ccd_last_error(ccd));
    const topoccd_report *r = report_of(ccd);
    CHECK(r->vf_count + r->ee_count == 1 && r->vf_count == 1, "%zu vf %zu ee", r->vf_count, r->ee_count);
    CHECK(r->vf[0].vertex == 3 && r->vf[0].face == 0 && fabs(r->vf[0].toi - 0.5) < 1e-6, "the tip at 0.5");

    topoccd_query_options o;
    topoccd_query_options_default(&o);
    o.crack_filter = false;
    CHECK_STATUS(topoccd_ccd_query(ccd, &s, &o), TOPOCCD_STATUS_OK, "no crack filter");
    r = report_of(ccd);
    int vertex4 = 0;
    for (size_t i = 0; i < r->vf_count; i++) vertex4 |= r->vf[i].vertex == 4 && r->vf[i].face == 0 && r->vf[i].toi == 0;
    CHECK(r->earliest_toi == 0 && vertex4, "vertex 4 sits on triangle 0's corner from t=0");

    /* Parents given but empty: new vertices without a parent start where they end. */
    s.parent_count = 0;
    CHECK_STATUS(topoccd_ccd_query(ccd, &s, NULL), TOPOCCD_STATUS_OK, "empty parents");
    topoccd_ccd_free(&ccd);
}

static void expect_step_error(topoccd_ccd *ccd, const topoccd_step *s, const topoccd_query_options *o,
                              topoccd_status want, const char *message, const char *what) {
    topoccd_status got = topoccd_ccd_query(ccd, s, o);
    CHECK_STATUS(got, want, "%s", what);
    const char *text = topoccd_ccd_last_error(ccd);
    CHECK(contains(text, message), "%s: message '%s' lacks '%s'", what, text, message);
    const topoccd_report *r = report_of(ccd);
    CHECK(r->vf_count == 0 && r->ee_count == 0 && r->earliest_kind == TOPOCCD_CONTACT_KIND_NONE,
          "%s: the report is empty after a failure", what);
}

static void test_query_errors(void) {
    topoccd_ccd *ccd = topoccd_ccd_new();
    topoccd_step s = fall_step();
    CHECK_STATUS(topoccd_ccd_query(NULL, &s, NULL), TOPOCCD_STATUS_NULL_POINTER, "NULL ccd");
    CHECK(strcmp(topoccd_ccd_last_error(NULL), "ccd is NULL") == 0, "message for NULL");
    const topoccd_report *r = NULL;
    CHECK_STATUS(topoccd_ccd_report(NULL, &r), TOPOCCD_STATUS_NULL_POINTER, "NULL ccd report");
    CHECK_STATUS(topoccd_ccd_report(ccd, NULL), TOPOCCD_STATUS_NULL_POINTER, "NULL report");
    CHECK(contains(topoccd_ccd_last_error(ccd), "report is NULL"), "%s", topoccd_ccd_last_error(ccd));

    CHECK_STATUS(topoccd_ccd_query(ccd, &s, NULL), TOPOCCD_STATUS_OK, "a good query first");
    expect_step_error(ccd, NULL, NULL, TOPOCCD_STATUS_NULL_POINTER, "step is NULL", "NULL step");

    topoccd_step bad = s;
    bad.x0 = NULL;
    expect_step_error(ccd, &bad, NULL, TOPOCCD_STATUS_NULL_POINTER, "x0 is NULL but x0_count is 6", "NULL x0");
    bad = s;
    bad.triangles = NULL;
    expect_step_error(ccd, &bad, NULL, TOPOCCD_STATUS_NULL_POINTER, "triangles is NULL", "NULL triangles");
    bad = s;
    bad.x1_count = 5;
    expect_step_error(ccd, &bad, NULL, TOPOCCD_STATUS_INVALID_STEP, "6 vertices at t=0 but 5 at t=1",
                      "mismatched lengths");
    bad = s;
    bad.x0_count = 0;
    bad.x0 = NULL;
    expect_step_error(ccd, &bad, NULL, TOPOCCD_STATUS_INVALID_STEP, "0 vertices at t=0 but 6",
                      "no positions at t=0");
    const uint32_t far[] = {0, 1, 2, 3, 4, 99};
    bad = s;
    bad.triangles = far;
    expect_step_error(ccd, &bad, NULL, TOPOCCD_STATUS_INVALID_STEP,
                      "triangle 1 names vertex 99, but there are only 6 vertices", "out-of-range index");
    const uint32_t twice[] = {0, 1, 2, 3, 3, 5};
    bad = s;
    bad.triangles = twice;
    expect_step_error(ccd, &bad, NULL, TOPOCCD_STATUS_INVALID_STEP, "triangle 1 uses vertex 3 more than once",
                      "repeated vertex");
    double nan_x1[18];
    memcpy(nan_x1, FALL_X1, sizeof nan_x1);
    nan_x1[13] = NAN;
    bad = s;
    bad.x1 = nan_x1;
    expect_step_error(ccd, &bad, NULL, TOPOCCD_STATUS_INVALID_STEP, "vertex 4 has a non-finite coordinate at t=1",
                      "NaN");
    nan_x1[13] = INFINITY;
    expect_step_error(ccd, &bad, NULL, TOPOCCD_STATUS_INVALID_STEP, "vertex 4 has a non-finite coordinate",
                      "infinity");

    /* Parents and groups. */
    const uint32_t bad_parent[] = {4, 9};
    bad = s;
    bad.parents = bad_parent;
    bad.parent_count = 1;
    expect_step_error(ccd, &bad, NULL, TOPOCCD_STATUS_INVALID_STEP, "parent row 0 [4, 9]", "parent out of range");
    bad.parents = NULL;
    bad.parent_count = 2;
    expect_step_error(ccd, &bad, NULL, TOPOCCD_STATUS_NULL_POINTER, "parents is NULL but parents_count is 2",
                      "NULL parents");
    bad = s;
    bad.x1_count = 7; /* more vertices at t=1 than given: refused before any read */
    bad.x1 = NULL;
    expect_step_error(ccd, &bad, NULL, TOPOCCD_STATUS_NULL_POINTER, "x1 is NULL", "NULL x1");
    const double shrunk_x0[21] = {0};
    bad = s;
    bad.x0 = shrunk_x0;
    bad.x0_count = 7;
    bad.parents = bad_parent;
    bad.parent_count = 0;
    expect_step_error(ccd, &bad, NULL, TOPOCCD_STATUS_INVALID_STEP, "7 vertices at t=0, more than the 6",
                      "vertex count shrinks");
    const uint32_t groups[5] = {0};
    bad = s;
    bad.groups = groups;
    bad.group_count = 5;
    expect_step_error(ccd, &bad, NULL, TOPOCCD_STATUS_INVALID_STEP, "5 group ids for 6 vertices",
                      "groups of the wrong length");
    bad.groups = NULL;
    expect_step_error(ccd, &bad, NULL, TOPOCCD_STATUS_NULL_POINTER, "groups is NULL", "NULL groups");

    /* Arrays the library cannot read: misaligned, or more than memory holds. */
    double *buffer = malloc(sizeof FALL_X0 + sizeof(double));
    memcpy((char *)buffer + 1, FALL_X0, sizeof FALL_X0 - 8);
    bad = s;
    bad.x0 = (const double *)((const char *)buffer + 1);
    expect_step_error(ccd, &bad, NULL, TOPOCCD_STATUS_INVALID_ARGUMENT, "x0 is not aligned", "misaligned");
    free(buffer);
    bad = s;
    bad.x0_count = SIZE_MAX / 2;
    bad.x1_count = SIZE_MAX / 2;
    expect_step_error(ccd, &bad, NULL, TOPOCCD_STATUS_INVALID_ARGUMENT, "more than memory can hold", "huge count");

    /* Options out of range, each named with its range. */
    topoccd_query_options o;
#define OPTION_CASE(stmt, message)                                                                     \
    do {                                                                                               \
        topoccd_query_options_default(&o);                                                             \
        stmt;                                                                                          \
        expect_step_error(ccd, &s, &o, TOPOCCD_STATUS_INVALID_OPTIONS, message, #stmt);                \
    } while (0)
    OPTION_CASE(o.tolerance = 0, "tolerance must be in (0, 1), got 0");
    OPTION_CASE(o.tolerance = NAN, "tolerance must be in (0, 1), got NaN");
    OPTION_CASE(o.max_iterations = 0, "max_iterations must be at least 1");
    OPTION_CASE(o.min_distance = -1, "min_distance must be finite and >= 0, got -1");
    OPTION_CASE(o.min_distance = INFINITY, "min_distance must be finite");
    OPTION_CASE(o.tmax = 1.5, "tmax must be in (0, 1], got 1.5");
    OPTION_CASE(o.k = 7, "k must be 6, 14, 18 or 26, got 7");
    OPTION_CASE(o.method = 42, "method 42 is not a topoccd_method");
    OPTION_CASE(o.mode = 9, "mode 9 is not a topoccd_mode");
    OPTION_CASE(o.growth = 5, "growth 5 is not a topoccd_growth");
    OPTION_CASE(o.threads = 5000, "threads must be 0 (one per core) or in [1, 4096], got 5000");
    OPTION_CASE(o.timeout = -1, "timeout must be finite and >= 0 (0: no limit), got -1");
    OPTION_CASE(o.timeout = NAN, "timeout must be finite and >= 0");
    OPTION_CASE(memset(&o, 0, sizeof o), "initialise the options with topoccd_query_options_default");
    OPTION_CASE(o.size = sizeof o + 64, "not the size of a topoccd_query_options");
    topoccd_ccd_free(&ccd);
}

/* A query through a destroyed or foreign handle is refused. */
static void test_handles(void) {
    topoccd_ccd *ccd = topoccd_ccd_new();
    topoccd_step s = fall_step();
    topoccd_ccd_free(&ccd);
    CHECK_STATUS(topoccd_ccd_query(ccd, &s, NULL), TOPOCCD_STATUS_NULL_POINTER, "a freed handle is NULL");

    /* Another kind of object, and memory that is no object at all. */
    topoccd_error *error = NULL;
    topoccd_mesh *mesh = NULL;
    CHECK_STATUS(topoccd_mesh_read("no-such-file.ply", &mesh, &error), TOPOCCD_STATUS_IO, "missing file");
    topoccd_ccd *foreign = (topoccd_ccd *)error;
    CHECK_STATUS(topoccd_ccd_query(foreign, &s, NULL), TOPOCCD_STATUS_INVALID_HANDLE, "an error is not a ccd");
    CHECK(contains(topoccd_ccd_last_error(foreign), "not a live topoccd_ccd"), "%s",
          topoccd_ccd_last_error(foreign));
    topoccd_mesh_view v;
    CHECK_STATUS(topoccd_mesh_data((topoccd_mesh *)error, &v), TOPOCCD_STATUS_INVALID_HANDLE, "error as a mesh");
    topoccd_ccd_free(&foreign); /* not a ccd: left alone */
    CHECK(foreign == (topoccd_ccd *)error, "free does not touch a foreign object");
    uint64_t zeros[8] = {0};
    CHECK_STATUS(topoccd_ccd_query((topoccd_ccd *)zeros, &s, NULL), TOPOCCD_STATUS_INVALID_HANDLE, "zeros");
    CHECK_STATUS(topoccd_error_status((topoccd_error *)zeros), TOPOCCD_STATUS_INVALID_HANDLE, "zeros");
    CHECK(contains(topoccd_error_message((topoccd_error *)zeros), "not a live"), "message of zeros");
    CHECK_STATUS(topoccd_ccd_query((topoccd_ccd *)((char *)zeros + 4), &s, NULL), TOPOCCD_STATUS_INVALID_HANDLE,
                 "misaligned handle");
    topoccd_error_free(&error);
    CHECK(error == NULL, "error freed");
}

/* One topoccd_ccd used by two threads at once: the second call is refused with BUSY, never
 * run concurrently. Two topoccd_ccds in two threads share nothing. */
struct busy_state {
    topoccd_ccd *ccd;
    topoccd_step step;
    volatile int stop;
    int queries, failures;
};

static void *busy_worker(void *arg) {
    struct busy_state *b = arg;
    while (!b->stop) {
        topoccd_status s = topoccd_ccd_query(b->ccd, &b->step, NULL);
        b->queries++;
        if (s != TOPOCCD_STATUS_OK && s != TOPOCCD_STATUS_BUSY) b->failures++;
    }
    return NULL;
}

/* A sheet of n x n quads folded onto itself: a step with many contacts and some work. */
static void folded_sheet(int n, double **x0, double **x1, uint32_t **tris, size_t *nv, size_t *nt) {
    *nv = (size_t)((n + 1) * (n + 1));
    *nt = (size_t)(2 * n * n);
    *x0 = malloc(*nv * 3 * sizeof(double));
    *x1 = malloc(*nv * 3 * sizeof(double));
    *tris = malloc(*nt * 3 * sizeof(uint32_t));
    for (int i = 0; i <= n; i++) {
        for (int j = 0; j <= n; j++) {
            size_t v = (size_t)(i * (n + 1) + j);
            double x = (double)i / n, y = (double)j / n;
            (*x0)[3 * v] = x;
            (*x0)[3 * v + 1] = y;
            (*x0)[3 * v + 2] = 0.3 * x;
            (*x1)[3 * v] = x < 0.5 ? x : 1 - x; /* the right half folds over the left one */
            (*x1)[3 * v + 1] = y;
            (*x1)[3 * v + 2] = x < 0.5 ? 0.3 * x : -0.2 + 0.1 * x;
        }
    }
    size_t t = 0;
    for (int i = 0; i < n; i++) {
        for (int j = 0; j < n; j++) {
            uint32_t a = (uint32_t)(i * (n + 1) + j), b = a + 1, c = a + (uint32_t)n + 1, d = c + 1;
            uint32_t *r = *tris + 3 * t;
            r[0] = a, r[1] = c, r[2] = b, r[3] = b, r[4] = c, r[5] = d;
            t += 2;
        }
    }
}

static void *private_query(void *arg) {
    /* Each thread its own topoccd_ccd on the same input: identical reports. */
    struct busy_state *b = arg;
    topoccd_ccd *ccd = topoccd_ccd_new();
    for (int i = 0; i < 3; i++) {
        if (topoccd_ccd_query(ccd, &b->step, NULL) != TOPOCCD_STATUS_OK) b->failures++;
    }
    const topoccd_report *r = NULL;
    topoccd_ccd_report(ccd, &r);
    b->queries = (int)(r->vf_count + r->ee_count);
    topoccd_ccd_free(&ccd);
    return NULL;
}

static void test_threads(void) {
    double *x0, *x1;
    uint32_t *tris;
    size_t nv, nt;
    folded_sheet(40, &x0, &x1, &tris, &nv, &nt);
    struct busy_state b = {0};
    b.ccd = topoccd_ccd_new();
    b.step.x0 = x0;
    b.step.x0_count = nv;
    b.step.x1 = x1;
    b.step.x1_count = nv;
    b.step.triangles = tris;
    b.step.triangle_count = nt;
    CHECK_STATUS(topoccd_ccd_query(b.ccd, &b.step, NULL), TOPOCCD_STATUS_OK, "%s", topoccd_ccd_last_error(b.ccd));
    size_t contacts = report_of(b.ccd)->vf_count + report_of(b.ccd)->ee_count;
    CHECK(contacts > 0, "the folded sheet has contacts");

    pthread_t worker;
    pthread_create(&worker, NULL, busy_worker, &b);
    int busy = 0, other = 0;
    struct timespec start, now;
    clock_gettime(CLOCK_MONOTONIC, &start);
    do { /* at most 20 s, until a call has met the worker's query */
        const topoccd_report *r = NULL;
        topoccd_status s = topoccd_ccd_report(b.ccd, &r);
        if (s == TOPOCCD_STATUS_BUSY) {
            busy++;
            CHECK(contains(topoccd_ccd_last_error(b.ccd), "in use by another thread"), "busy message");
        } else if (s != TOPOCCD_STATUS_OK) {
            other++;
        }
        clock_gettime(CLOCK_MONOTONIC, &now);
    } while (busy == 0 && now.tv_sec - start.tv_sec < 20);
    b.stop = 1;
    pthread_join(worker, NULL);
    CHECK(busy > 0 && other == 0 && b.failures == 0, "busy %d, other %d, worker failures %d", busy, other,
          b.failures);
    topoccd_ccd_free(&b.ccd);

    struct busy_state p[2];
    pthread_t threads[2];
    for (int i = 0; i < 2; i++) {
        p[i] = b;
        p[i].failures = 0;
        pthread_create(&threads[i], NULL, private_query, &p[i]);
    }
    for (int i = 0; i < 2; i++) pthread_join(threads[i], NULL);
    CHECK(p[0].failures == 0 && p[1].failures == 0, "private queries failed");
    CHECK((size_t)p[0].queries == contacts && (size_t)p[1].queries == contacts, "%d and %d contacts, not %zu",
          p[0].queries, p[1].queries, contacts);
    free(x0);
    free(x1);
    free(tris);
}

static void test_pairs(void) {
    topoccd_vertex_face vf = {
        .v_t0 = {0.2, 0.2, 1}, .f1_t0 = {1, 0, 0}, .f2_t0 = {0, 1, 0},
        .v_t1 = {0.2, 0.2, -1}, .f1_t1 = {1, 0, 0}, .f2_t1 = {0, 1, 0},
    };
    topoccd_outcome out;
    topoccd_error *error = (topoccd_error *)0x1; /* never read */
    CHECK_STATUS(topoccd_pair_vertex_face(&vf, NULL, &out, &error), TOPOCCD_STATUS_OK, "vf");
    CHECK(error == NULL, "no error object on success");
    CHECK(out.contact && out.toi <= 0.5 && out.toi > 0.5 - 1e-6 && out.certainty == TOPOCCD_CERTAINTY_RESOLVED,
          "vf toi %.17g", out.toi);
    vf.v_t1[2] = 0.5; /* stays above the plane */
    CHECK_STATUS(topoccd_pair_vertex_face(&vf, NULL, &out, NULL), TOPOCCD_STATUS_OK, "separated");
    CHECK(!out.contact && isnan(out.toi), "separated");
    topoccd_query_options o;
    topoccd_query_options_default(&o);
    o.min_distance = 0.5; /* ... by 0.5 at the end: touching within 0.5 */
    CHECK_STATUS(topoccd_pair_vertex_face(&vf, &o, &out, NULL), TOPOCCD_STATUS_OK, "min_distance");
    CHECK(out.contact && out.toi <= 1 && out.toi > 1 - 1e-6, "within min_distance at the end: %.17g", out.toi);
    vf.v_t0[0] = NAN; /* NaN is not an error for a per-pair test: a conservative contact at 0 */
    CHECK_STATUS(topoccd_pair_vertex_face(&vf, NULL, &out, NULL), TOPOCCD_STATUS_OK, "NaN");
    CHECK(out.contact && out.toi == 0 && out.certainty == TOPOCCD_CERTAINTY_INVALID_INPUT, "NaN gives %d %g",
          out.certainty, out.toi);

    topoccd_edge_edge ee = {
        .ea0_t0 = {-1, 0, 0}, .ea1_t0 = {1, 0, 0}, .eb0_t0 = {0, -1, 1}, .eb1_t0 = {0, 1, 1},
        .ea0_t1 = {-1, 0, 0}, .ea1_t1 = {1, 0, 0}, .eb0_t1 = {0, -1, -1}, .eb1_t1 = {0, 1, -1},
    };
    CHECK_STATUS(topoccd_pair_edge_edge(&ee, NULL, &out, NULL), TOPOCCD_STATUS_OK, "ee");
    CHECK(out.contact && out.toi <= 0.5 && out.toi > 0.5 - 1e-6, "ee toi %.17g", out.toi);

    topoccd_query_options_default(&o);
    o.tolerance = 2;
    CHECK_STATUS(topoccd_pair_edge_edge(&ee, &o, &out, &error), TOPOCCD_STATUS_INVALID_OPTIONS, "bad tolerance");
    CHECK(contains(topoccd_error_message(error), "tolerance must be in (0, 1), got 2"), "%s",
          topoccd_error_message(error));
    CHECK_STATUS(topoccd_error_status(error), TOPOCCD_STATUS_INVALID_OPTIONS, "error status");
    topoccd_error_free(&error);
    CHECK_STATUS(topoccd_pair_edge_edge(&ee, &o, &out, NULL), TOPOCCD_STATUS_INVALID_OPTIONS, "without error");
    CHECK_STATUS(topoccd_pair_edge_edge(NULL, NULL, &out, &error), TOPOCCD_STATUS_NULL_POINTER, "NULL query");
    CHECK(contains(topoccd_error_message(error), "query is NULL"), "%s", topoccd_error_message(error));
    topoccd_error_free(&error);
    CHECK_STATUS(topoccd_pair_vertex_face(&vf, NULL, NULL, NULL), TOPOCCD_STATUS_NULL_POINTER, "NULL outcome");
    CHECK(strcmp(topoccd_error_message(NULL), "") == 0 && topoccd_error_status(NULL) == TOPOCCD_STATUS_OK,
          "NULL error");
}

static char dir[64];

static const char *file(const char *name, const char *text) {
    static char path[128];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    if (text) {
        FILE *f = fopen(path, "w");
        fputs(text, f);
        fclose(f);
    }
    return path;
}

static void expect_error(topoccd_status got, topoccd_status want, topoccd_error **error, const char *message,
                         const char *what) {
    CHECK_STATUS(got, want, "%s", what);
    CHECK(contains(topoccd_error_message(*error), message), "%s: '%s' lacks '%s'", what,
          topoccd_error_message(*error), message);
    CHECK(topoccd_error_status(*error) == want, "%s: status of the error", what);
    topoccd_error_free(error);
}

static const char *TRIANGLE_OBJ = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
static const char *SQUARE_OBJ = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";

static void test_files(void) {
    snprintf(dir, sizeof dir, "/tmp/topoccd-c-test-XXXXXX");
    if (!mkdtemp(dir)) {
        CHECK(0, "cannot make a temporary folder");
        return;
    }
    topoccd_error *error = NULL;
    topoccd_mesh *mesh = (topoccd_mesh *)0x1;
    expect_error(topoccd_mesh_read(NULL, &mesh, &error), TOPOCCD_STATUS_NULL_POINTER, &error, "path is NULL",
                 "NULL path");
    CHECK(mesh == NULL, "*mesh is NULL after a failure");
    expect_error(topoccd_mesh_read(file("a.obj", SQUARE_OBJ), NULL, &error), TOPOCCD_STATUS_NULL_POINTER, &error,
                 "mesh is NULL", "NULL out");
    expect_error(topoccd_mesh_read(file("missing.ply", NULL), &mesh, &error), TOPOCCD_STATUS_IO, &error,
                 "missing.ply: cannot open", "missing file");
    expect_error(topoccd_mesh_read(file("a.txt", "x"), &mesh, &error), TOPOCCD_STATUS_FORMAT, &error,
                 "unknown mesh format", "unknown extension");
    expect_error(topoccd_mesh_read(file("bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"), &mesh, &error),
                 TOPOCCD_STATUS_FORMAT, &error, "bad.obj", "index out of range in a file");
    expect_error(topoccd_mesh_read(file("bad.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                                                   "property float y\nproperty float z\nelement face 1\n"
                                                   "property list uchar int vertex_indices\nend_header\n"
                                                   "0 0 0\n1 0 0\n"),
                                   &mesh, &error),
                 TOPOCCD_STATUS_FORMAT, &error, "bad.ply", "truncated PLY");
    CHECK_STATUS(topoccd_mesh_read(file("missing.ply", NULL), &mesh, NULL), TOPOCCD_STATUS_IO, "no error object");

    /* A quad is split into two triangles, mapped back to face 0, with a note. */
    CHECK_STATUS(topoccd_mesh_read(file("square.obj", SQUARE_OBJ), &mesh, &error), TOPOCCD_STATUS_OK, "%s",
                 topoccd_error_message(error));
    topoccd_mesh_view v;
    CHECK_STATUS(topoccd_mesh_data(mesh, &v), TOPOCCD_STATUS_OK, "data");
    CHECK(v.vertex_count == 4 && v.triangle_count == 2 && v.positions[6] == 1 && v.positions[7] == 1,
          "square: %zu vertices %zu triangles", v.vertex_count, v.triangle_count);
    CHECK(v.face_origin && v.face_origin[0] == 0 && v.face_origin[1] == 0 && v.face_origin[2] == 0 &&
              v.face_origin[3] == 1,
          "face origin");
    size_t notes = 0;
    const char *note = NULL;
    CHECK_STATUS(topoccd_mesh_note_count(mesh, &notes), TOPOCCD_STATUS_OK, "notes");
    CHECK(notes == 1, "%zu notes", notes);
    CHECK_STATUS(topoccd_mesh_note(mesh, 0, &note), TOPOCCD_STATUS_OK, "note 0");
    CHECK(contains(note, "split into 2 triangles"), "%s", note);
    CHECK_STATUS(topoccd_mesh_note(mesh, 1, &note), TOPOCCD_STATUS_OUT_OF_RANGE, "note 1");
    CHECK_STATUS(topoccd_mesh_note(mesh, SIZE_MAX, &note), TOPOCCD_STATUS_OUT_OF_RANGE, "note SIZE_MAX");
    CHECK_STATUS(topoccd_mesh_note(mesh, 0, NULL), TOPOCCD_STATUS_NULL_POINTER, "NULL note");
    CHECK_STATUS(topoccd_mesh_data(mesh, NULL), TOPOCCD_STATUS_NULL_POINTER, "NULL view");
    CHECK_STATUS(topoccd_mesh_data(NULL, &v), TOPOCCD_STATUS_NULL_POINTER, "NULL mesh");
    topoccd_mesh_free(&mesh);
    CHECK(mesh == NULL, "mesh freed");

    /* One step from two files, across a cut given by a parents file. */
    const char *t0 = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0.8 0.8 1\nf 1 2 3\nf 2 4 3\n";
    const char *t1 = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 -1\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 5 4 6\n";
    char p0[128], p1[128], pp[128];
    snprintf(p0, sizeof p0, "%s", file("0000.obj", t0));
    snprintf(p1, sizeof p1, "%s", file("0001.obj", t1));
    snprintf(pp, sizeof pp, "%s", file("0001.parents", "# NEW_ID PARENT_ID\n4 1\n5 2\n"));
    topoccd_frames *frames = NULL;
    CHECK_STATUS(topoccd_frames_read(p0, p1, pp, &frames, &error), TOPOCCD_STATUS_OK, "%s",
                 topoccd_error_message(error));
    topoccd_step s;
    CHECK_STATUS(topoccd_frames_step(frames, &s), TOPOCCD_STATUS_OK, "step");
    CHECK(s.x0_count == 4 && s.x1_count == 6 && s.parents != NULL && s.parent_count == 2 && s.groups == NULL,
          "frames step");
    topoccd_ccd *ccd = topoccd_ccd_new();
    CHECK_STATUS(topoccd_ccd_query(ccd, &s, NULL), TOPOCCD_STATUS_OK, "%s", topoccd_ccd_last_error(ccd));
    const topoccd_report *r = report_of(ccd);
    CHECK(r->vf_count == 1 && r->ee_count == 0 && r->vf[0].vertex == 3 && fabs(r->vf[0].toi - 0.5) < 1e-6,
          "the cut read from files: %zu vf %zu ee", r->vf_count, r->ee_count);
    const uint32_t *origin = (const uint32_t *)0x1;
    CHECK_STATUS(topoccd_frames_face_origin(frames, &origin), TOPOCCD_STATUS_OK, "origin");
    CHECK(origin == NULL, "triangles are the file's faces");
    CHECK_STATUS(topoccd_frames_note_count(frames, &notes), TOPOCCD_STATUS_OK, "notes");
    CHECK(notes == 0, "no notes");
    CHECK_STATUS(topoccd_frames_note(frames, 0, &note), TOPOCCD_STATUS_OUT_OF_RANGE, "no note 0");
    topoccd_frames_free(&frames);
    CHECK_STATUS(topoccd_frames_step(frames, &s), TOPOCCD_STATUS_NULL_POINTER, "freed frames");

    /* Without the parents file the new vertices do not move: still a valid step. */
    CHECK_STATUS(topoccd_frames_read(p0, p1, NULL, &frames, &error), TOPOCCD_STATUS_OK, "no parents");
    topoccd_frames_step(frames, &s);
    CHECK(s.parents != NULL && s.parent_count == 0, "a topology change without parent rows");
    topoccd_frames_free(&frames);
    expect_error(topoccd_frames_read(p1, p0, NULL, &frames, &error), TOPOCCD_STATUS_INVALID_STEP, &error,
                 "fewer than the 6 of the previous frame", "shrinking frames");
    expect_error(topoccd_frames_read(p0, p1, file("bad.parents", "4 1\n5 7\n"), &frames, &error),
                 TOPOCCD_STATUS_FORMAT, &error, "bad.parents:2: PARENT_ID 7 is out of range", "bad parents");
    expect_error(topoccd_frames_read(p0, NULL, NULL, &frames, &error), TOPOCCD_STATUS_NULL_POINTER, &error,
                 "t1 is NULL", "NULL t1");
    CHECK(frames == NULL, "no frames after a failure");

    /* Free edges from the files (OBJ l lines): a particle falls across a rod at t=0.5. */
    CHECK_STATUS(topoccd_frames_read(p0, p1, pp, &frames, &error), TOPOCCD_STATUS_OK, "again");
    topoccd_frames_step(frames, &s);
    CHECK(s.edges == NULL && s.edge_count == 0, "files without edges give no edges");
    topoccd_frames_free(&frames);
    const char *r0 = file("rod-a.obj", "v 0 0 0\nv 1 0 0\nv 0.5 0 1\nl 1 2\n");
    char q0[128];
    snprintf(q0, sizeof q0, "%s", r0);
    const char *q1 = file("rod-b.obj", "v 0 0 0\nv 1 0 0\nv 0.5 0 -1\nl 1 2\n");
    CHECK_STATUS(topoccd_frames_read(q0, q1, NULL, &frames, &error), TOPOCCD_STATUS_OK, "%s",
                 topoccd_error_message(error));
    topoccd_frames_step(frames, &s);
    CHECK(s.edge_count == 1 && s.edges != NULL && s.edges[0] == 0 && s.edges[1] == 1, "the rod's edge");
    CHECK_STATUS(topoccd_ccd_query(ccd, &s, NULL), TOPOCCD_STATUS_OK, "%s", topoccd_ccd_last_error(ccd));
    r = report_of(ccd);
    CHECK(r->ve_count == 1 && r->ve[0].vertex == 2 && r->ve[0].toi <= 0.5 && r->ve[0].toi > 0.5 - 1e-6,
          "the particle crosses the rod read from files: %zu ve", r->ve_count);
    topoccd_frames_free(&frames);

    /* A sequence: the folder holds 0000.obj, 0001.obj and 0001.parents. */
    topoccd_sequence *seq = NULL;
    expect_error(topoccd_sequence_open(file("no-such-folder", NULL), &seq, &error), TOPOCCD_STATUS_IO, &error,
                 "cannot list the folder", "missing folder");
    /* The folder itself is a sequence: 0000.obj, 0001.obj (and 0001.parents); the other files
     * have no number. */
    CHECK_STATUS(topoccd_sequence_open(dir, &seq, &error), TOPOCCD_STATUS_OK, "%s", topoccd_error_message(error));
    topoccd_sequence_free(&seq);
    file("b_0001.obj", TRIANGLE_OBJ);
    CHECK_STATUS(topoccd_sequence_open(dir, &seq, &error), TOPOCCD_STATUS_FORMAT, "two prefixes");
    CHECK(seq == NULL && contains(topoccd_error_message(error), "different prefixes"), "%s",
          topoccd_error_message(error));
    topoccd_error_free(&error);
    char sub[128];
    snprintf(sub, sizeof sub, "%s/seq", dir);
    mkdir(sub, 0700);
    file("seq/0000.obj", t0);
    file("seq/0001.obj", t1);
    file("seq/0001.parents", "4 1\n5 2\n");
    CHECK_STATUS(topoccd_sequence_open(sub, &seq, &error), TOPOCCD_STATUS_OK, "%s", topoccd_error_message(error));
    size_t steps = 0;
    CHECK_STATUS(topoccd_sequence_step_count(seq, &steps), TOPOCCD_STATUS_OK, "steps");
    CHECK(steps == 1, "%zu steps", steps);
    expect_error(topoccd_sequence_load(seq, 1, &frames, &error), TOPOCCD_STATUS_OUT_OF_RANGE, &error,
                 "no step 1: the sequence has 1 steps", "step out of range");
    CHECK_STATUS(topoccd_sequence_load(seq, 0, &frames, &error), TOPOCCD_STATUS_OK, "load");
    topoccd_frames_step(frames, &s);
    CHECK_STATUS(topoccd_ccd_query(ccd, &s, NULL), TOPOCCD_STATUS_OK, "sequence step");
    CHECK(report_of(ccd)->vf_count == 1, "the sequence's step is the cut");
    topoccd_sequence_free(&seq);
    topoccd_frames_free(&frames);
    CHECK_STATUS(topoccd_sequence_step_count(seq, &steps), TOPOCCD_STATUS_NULL_POINTER, "freed sequence");
    unlink(file("seq/0000.obj", NULL));
    CHECK_STATUS(topoccd_sequence_open(sub, &seq, &error), TOPOCCD_STATUS_FORMAT, "one frame");
    CHECK(contains(topoccd_error_message(error), "at least two frames"), "%s", topoccd_error_message(error));
    topoccd_error_free(&error);
    topoccd_ccd_free(&ccd);

    const char *names[] = {"a.obj", "a.txt", "bad.obj", "bad.ply", "square.obj", "0000.obj", "0001.obj",
                           "0001.parents", "bad.parents", "b_0001.obj", "seq/0001.obj", "seq/0001.parents"};
    for (size_t i = 0; i < sizeof names / sizeof *names; i++) unlink(file(names[i], NULL));
    rmdir(sub);
    rmdir(dir);
}

/* The line-search helpers: the falling triangle's first contact is vertex 3 on face 0 at
 * t=0.5 (analytic), so the step size is 0.8 x 0.5 and the report names that pair; a piercing
 * start is refused with check_start; a timeout that passes gives no step size. */
static void test_line_search(void) {
    topoccd_ccd *ccd = topoccd_ccd_new();
    topoccd_step s = fall_step();
    double alpha = -1;
    CHECK_STATUS(topoccd_collision_free_stepsize(ccd, &s, NULL, &alpha), TOPOCCD_STATUS_OK, "defaults");
    CHECK(alpha <= 0.8 * 0.5 && alpha >= 0.8 * (0.5 - 1e-6), "alpha %.17g", alpha);
    const topoccd_report *r = report_of(ccd);
    CHECK(r->earliest_kind == TOPOCCD_CONTACT_KIND_VF && r->vf[r->earliest_index].vertex == 3 &&
              r->vf[r->earliest_index].face == 0 && alpha == 0.8 * r->earliest_toi,
          "earliest kind %u", (unsigned)r->earliest_kind);

    topoccd_line_search_options ls;
    topoccd_line_search_options_default(&ls);
    CHECK(ls.conservative_rescaling == 0.8 && !ls.check_start && ls.query == NULL, "defaults");
    topoccd_query_options q;
    topoccd_query_options_default(&q);
    q.tmax = 0.4; /* before the first contact: the whole interval is free */
    ls.query = &q;
    ls.conservative_rescaling = 0.5;
    CHECK_STATUS(topoccd_collision_free_stepsize(ccd, &s, &ls, &alpha), TOPOCCD_STATUS_OK, "tmax");
    CHECK(alpha == 0.4, "alpha %.17g is tmax", alpha);
    bool free_step = false;
    CHECK_STATUS(topoccd_is_step_collision_free(ccd, &s, &ls, &free_step), TOPOCCD_STATUS_OK, "free");
    CHECK(free_step, "nothing touches in [0, 0.4]");
    CHECK(report_of(ccd)->earliest_kind == TOPOCCD_CONTACT_KIND_NONE, "no earliest contact");
    q.tmax = 1;
    CHECK_STATUS(topoccd_collision_free_stepsize(ccd, &s, &ls, &alpha), TOPOCCD_STATUS_OK, "rescaling");
    CHECK(alpha == 0.5 * report_of(ccd)->earliest_toi, "alpha %.17g", alpha);
    CHECK_STATUS(topoccd_is_step_collision_free(ccd, &s, NULL, &free_step), TOPOCCD_STATUS_OK, "collides");
    CHECK(!free_step && report_of(ccd)->vf[0].vertex == 3, "the step collides");

    /* Triangle 1 pierces triangle 0 and stays: no contact starts, so the step is taken whole,
     * unless check_start looks at the start. */
    const double pierce[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0.2, 0.2, -1, 0.3, 0.2, 1, 0.2, 0.3, 1};
    topoccd_step p = fall_step();
    p.x0 = pierce;
    p.x1 = pierce;
    topoccd_line_search_options_default(&ls);
    CHECK_STATUS(topoccd_collision_free_stepsize(ccd, &p, &ls, &alpha), TOPOCCD_STATUS_OK, "unchecked");
    CHECK(alpha == 1.0, "alpha %.17g without check_start", alpha);
    ls.check_start = true;
    CHECK_STATUS(topoccd_collision_free_stepsize(ccd, &p, &ls, &alpha), TOPOCCD_STATUS_START_INTERSECTS,
                 "check_start");
    CHECK(alpha == 0 && contains(topoccd_ccd_last_error(ccd), "triangles 0 and 1 intersect at t=0"), "%s",
          topoccd_ccd_last_error(ccd));
    CHECK_STATUS(topoccd_is_step_collision_free(ccd, &p, &ls, &free_step), TOPOCCD_STATUS_START_INTERSECTS,
                 "check_start");
    CHECK(!free_step, "no answer is free");
    CHECK_STATUS(topoccd_collision_free_stepsize(ccd, &s, &ls, &alpha), TOPOCCD_STATUS_OK, "apart at t=0");

    /* Errors: options out of range, NULL outputs, an unknown size. */
    ls.conservative_rescaling = 1.5;
    CHECK_STATUS(topoccd_collision_free_stepsize(ccd, &s, &ls, &alpha), TOPOCCD_STATUS_INVALID_OPTIONS, "1.5");
    CHECK(contains(topoccd_ccd_last_error(ccd), "conservative_rescaling must be in (0, 1], got 1.5"), "%s",
          topoccd_ccd_last_error(ccd));
    topoccd_line_search_options_default(&ls);
    topoccd_query_options_default(&q);
    q.min_distance = -1;
    ls.query = &q;
    CHECK_STATUS(topoccd_collision_free_stepsize(ccd, &s, &ls, &alpha), TOPOCCD_STATUS_INVALID_OPTIONS, "query");
    CHECK(contains(topoccd_ccd_last_error(ccd), "min_distance"), "%s", topoccd_ccd_last_error(ccd));
    CHECK_STATUS(topoccd_collision_free_stepsize(ccd, &s, NULL, NULL), TOPOCCD_STATUS_NULL_POINTER, "alpha");
    CHECK_STATUS(topoccd_is_step_collision_free(ccd, NULL, NULL, &free_step), TOPOCCD_STATUS_NULL_POINTER, "step");
    CHECK_STATUS(topoccd_line_search_options_init(&ls, 8), TOPOCCD_STATUS_INVALID_ARGUMENT, "size");
    memset(&ls, 0, sizeof ls);
    CHECK_STATUS(topoccd_collision_free_stepsize(ccd, &s, &ls, &alpha), TOPOCCD_STATUS_INVALID_OPTIONS, "zeroed");
    CHECK(contains(topoccd_ccd_last_error(ccd), "topoccd_line_search_options_default"), "%s",
          topoccd_ccd_last_error(ccd));

    /* A timeout that passes at once: the earliest contact is not known, so no step size. */
    double *x0, *x1;
    uint32_t *tris;
    size_t nv, nt;
    folded_sheet(40, &x0, &x1, &tris, &nv, &nt);
    topoccd_step sheet = {0};
    sheet.x0 = x0, sheet.x0_count = nv, sheet.x1 = x1, sheet.x1_count = nv;
    sheet.triangles = tris, sheet.triangle_count = nt;
    topoccd_line_search_options_default(&ls);
    topoccd_query_options_default(&q);
    q.timeout = 1e-9;
    ls.query = &q;
    alpha = -1;
    CHECK_STATUS(topoccd_collision_free_stepsize(ccd, &sheet, &ls, &alpha), TOPOCCD_STATUS_TIMEOUT, "timeout");
    CHECK(alpha == 0 && contains(topoccd_ccd_last_error(ccd), "timeout"), "alpha %g: %s", alpha,
          topoccd_ccd_last_error(ccd));
    q.timeout = 0;
    q.max_contacts = 1; /* a cap keeps the earliest time exact: a step size is known */
    CHECK_STATUS(topoccd_collision_free_stepsize(ccd, &sheet, &ls, &alpha), TOPOCCD_STATUS_OK, "max_contacts");
    double capped = alpha;
    CHECK_STATUS(topoccd_collision_free_stepsize(ccd, &sheet, NULL, &alpha), TOPOCCD_STATUS_OK, "no cap");
    CHECK(capped == alpha && alpha > 0 && alpha < 0.8, "alpha %.17g with a cap, %.17g without", capped, alpha);
    free(x0);
    free(x1);
    free(tris);
    topoccd_ccd_free(&ccd);
}

/* Proximity: a vertex above a triangle, a rod crossing over two of its edges, two particles;
 * each pair's kind, distance and type against the analytic values; refitted on the second
 * call; errors named. */
static void test_proximity(void) {
    const double x[] = {0, 0, 0, 1, 0, 0, 0, 1, 0,      /* triangle 0 1 2 */
                        0.2, 0.2, 0.5e-3,              /* 3: a particle above the interior */
                        0.5, -0.5, 0.2e-3, 0.6, 0.5, 0.2e-3, /* 4-5: a rod */
                        3, 3, 3, 3, 3, 3.0004};         /* 6-7: two particles */
    const uint32_t tris[] = {0, 1, 2};
    const uint32_t edges[] = {5, 4};
    topoccd_configuration config = {0};
    config.x = x; config.vertex_count = 8;
    config.triangles = tris; config.triangle_count = 1;
    config.edges = edges; config.edge_count = 1;
    topoccd_proximity_options options = topoccd_proximity_options_default();
    /* The proximity cap's default is the query's (1,000,000), no longer 0 (unbounded). */
    CHECK(options.dhat == 1e-3 && options.dmin == 0 && options.max_contacts == 1000000, "defaults");
    topoccd_ccd *ccd = topoccd_ccd_new();
    const topoccd_proximity_report *r = NULL;
    CHECK_STATUS(topoccd_proximity(ccd, &config, &options, &r), TOPOCCD_STATUS_OK, "proximity");
    CHECK(r->vf_count == 1 && r->vf[0].vertex == 3 && r->vf[0].face == 0 && r->vf[0].type == 6,
          "vf: %zu", r->vf_count);
    CHECK(fabs(r->vf[0].distance - 0.5e-3) < 1e-15, "vf distance %g", r->vf[0].distance);
    CHECK(r->ee_count == 2, "ee: %zu", r->ee_count);
    for (size_t i = 0; i < r->ee_count; i++) {
        CHECK(r->ee[i].b[0] == 4 && r->ee[i].b[1] == 5 && r->ee[i].type == 8, "ee %zu", i);
        CHECK(fabs(r->ee[i].distance - 0.2e-3) < 1e-15, "ee distance %g", r->ee[i].distance);
    }
    CHECK(r->vv_count == 1 && r->vv[0].a == 6 && r->vv[0].b == 7, "vv: %zu", r->vv_count);
    CHECK(fabs(r->vv[0].distance - 0.4e-3) < 1e-12, "vv distance %g", r->vv[0].distance);
    CHECK(r->ve_count == 0 && !r->truncated && !r->refitted, "ve, first build");
    CHECK_STATUS(topoccd_proximity(ccd, &config, NULL, &r), TOPOCCD_STATUS_OK, "again");
    CHECK(r->refitted && r->vf_count == 1, "refitted");
    options.max_contacts = 1;
    CHECK_STATUS(topoccd_proximity(ccd, &config, &options, &r), TOPOCCD_STATUS_OK, "capped");
    CHECK(r->truncated && r->vf_count + r->ee_count + r->vv_count == 1, "truncated");
    options = topoccd_proximity_options_default();
    options.dhat = -1;
    CHECK_STATUS(topoccd_proximity(ccd, &config, &options, &r), TOPOCCD_STATUS_INVALID_OPTIONS, "dhat");
    CHECK(contains(topoccd_ccd_last_error(ccd), "dhat"), "%s", topoccd_ccd_last_error(ccd));
    const uint32_t bad[] = {5, 9};
    config.edges = bad;
    CHECK_STATUS(topoccd_proximity(ccd, &config, NULL, &r), TOPOCCD_STATUS_INVALID_STEP, "edge");
    CHECK(contains(topoccd_ccd_last_error(ccd), "edge 0 names vertex 9"), "%s", topoccd_ccd_last_error(ccd));
    CHECK_STATUS(topoccd_proximity(ccd, NULL, NULL, &r), TOPOCCD_STATUS_NULL_POINTER, "no config");
    topoccd_ccd_free(&ccd);
}

/* Codimensional geometry: a free edge (0 1) on the x axis, a point (2) falling across it at
 * t = 0.5, a point (3) falling onto a fixed point (4) at t = 0.25. No triangles. */
static void test_codim(void) {
    static const double x0[] = {0, 0, 0, 1, 0, 0, 0.5, 0, 1, 3, 0, 0.5, 3, 0, 0};
    static const double x1[] = {0, 0, 0, 1, 0, 0, 0.5, 0, -1, 3, 0, -1.5, 3, 0, 0};
    static const uint32_t edges[] = {0, 1};
    topoccd_step s = {0};
    s.x0 = x0;
    s.x0_count = 5;
    s.x1 = x1;
    s.x1_count = 5;
    s.edges = edges;
    s.edge_count = 1;
    topoccd_ccd *ccd = topoccd_ccd_new();
    topoccd_query_options o;
    topoccd_query_options_default(&o);
    o.geometry = true;
    CHECK_STATUS(topoccd_ccd_query(ccd, &s, &o), TOPOCCD_STATUS_OK, "%s", topoccd_ccd_last_error(ccd));
    const topoccd_report *r = report_of(ccd);
    CHECK(r->vf_count == 0 && r->ee_count == 0 && r->ve_count == 1 && r->vv_count == 1,
          "%zu vf %zu ee %zu ve %zu vv", r->vf_count, r->ee_count, r->ve_count, r->vv_count);
    if (r->ve_count == 1) {
        const topoccd_ve_contact *c = &r->ve[0];
        CHECK(c->vertex == 2 && c->edge[0] == 0 && c->edge[1] == 1, "ve %u [%u %u]", c->vertex, c->edge[0],
              c->edge[1]);
        CHECK(c->toi <= 0.5 && c->toi > 0.5 - 1e-6, "ve toi %.17g, exact 0.5", c->toi);
        CHECK(c->certainty == TOPOCCD_CERTAINTY_RESOLVED && c->has_geometry, "ve certainty, geometry");
        CHECK(fabs(c->geometry.b_param - 0.5) < 1e-6 && fabs(c->geometry.point[0] - 0.5) < 1e-6,
              "ve geometry: the middle of the edge (%g)", c->geometry.b_param);
    }
    if (r->vv_count == 1) {
        const topoccd_vv_contact *c = &r->vv[0];
        CHECK(c->a == 3 && c->b == 4, "vv %u %u", c->a, c->b);
        CHECK(c->toi <= 0.25 && c->toi > 0.25 - 1e-6, "vv toi %.17g, exact 0.25", c->toi);
        CHECK(c->certainty == TOPOCCD_CERTAINTY_RESOLVED && c->has_geometry, "vv certainty, geometry");
    }
    CHECK(r->earliest_kind == TOPOCCD_CONTACT_KIND_VV && r->earliest_index == 0, "earliest is vv[0]: %u",
          r->earliest_kind);
    CHECK(r->vv_count == 1 && r->earliest_toi == r->vv[0].toi, "earliest toi");

    /* The oracle agrees; Earliest keeps the vv contact only. */
    o.method = TOPOCCD_METHOD_BRUTE;
    o.geometry = false;
    CHECK_STATUS(topoccd_ccd_query(ccd, &s, &o), TOPOCCD_STATUS_OK, "brute");
    r = report_of(ccd);
    CHECK(r->ve_count == 1 && r->vv_count == 1, "brute: %zu ve %zu vv", r->ve_count, r->vv_count);
    o.method = TOPOCCD_METHOD_AUTO;
    o.mode = TOPOCCD_MODE_EARLIEST;
    CHECK_STATUS(topoccd_ccd_query(ccd, &s, &o), TOPOCCD_STATUS_OK, "earliest");
    r = report_of(ccd);
    CHECK(r->ve_count == 0 && r->vv_count == 1 && r->earliest_kind == TOPOCCD_CONTACT_KIND_VV,
          "earliest: %zu ve %zu vv", r->ve_count, r->vv_count);

    /* Only the point falling across the edge: the earliest contact is ve[0]. */
    s.x0_count = 3;
    s.x1_count = 3;
    CHECK_STATUS(topoccd_ccd_query(ccd, &s, NULL), TOPOCCD_STATUS_OK, "%s", topoccd_ccd_last_error(ccd));
    r = report_of(ccd);
    CHECK(r->ve_count == 1 && r->vv_count == 0 && r->earliest_kind == TOPOCCD_CONTACT_KIND_VE &&
              r->earliest_index == 0,
          "ve only: %zu ve %zu vv, kind %u", r->ve_count, r->vv_count, r->earliest_kind);

    /* Without edges, a vertex in no triangle is ignored, as before. */
    s.edges = NULL;
    s.edge_count = 0;
    CHECK_STATUS(topoccd_ccd_query(ccd, &s, NULL), TOPOCCD_STATUS_OK, "no edges");
    r = report_of(ccd);
    CHECK(r->ve_count == 0 && r->vv_count == 0 && r->earliest_kind == TOPOCCD_CONTACT_KIND_NONE, "no edges");

    /* Bad edges are refused with the edge named. */
    s.x0_count = 5;
    s.x1_count = 5;
    static const uint32_t far[] = {0, 7};
    static const uint32_t loop[] = {0, 1, 2, 2};
    s.edges = far;
    s.edge_count = 1;
    expect_step_error(ccd, &s, NULL, TOPOCCD_STATUS_INVALID_STEP,
                      "edge 0 names vertex 7, but there are only 5 vertices", "edge out of range");
    s.edges = loop;
    s.edge_count = 2;
    expect_step_error(ccd, &s, NULL, TOPOCCD_STATUS_INVALID_STEP, "edge 1 joins vertex 2 to itself",
                      "degenerate edge");
    s.edges = NULL;
    expect_step_error(ccd, &s, NULL, TOPOCCD_STATUS_NULL_POINTER, "edges is NULL but edges_count is 2",
                      "NULL edges");
    topoccd_ccd_free(&ccd);
}

/* The contact potential: a point 0.5e-3 above a triangle (one face-vertex collision), then
 * every error path of the collision set, the potentials, the sparse matrix and the helpers. */
static void test_ipc(void) {
    const double x[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0.2, 0.2, 0.5e-3};
    const uint32_t tris[] = {0, 1, 2};
    topoccd_configuration config = {0};
    config.x = x;
    config.vertex_count = 4;
    config.triangles = tris;
    config.triangle_count = 1;
    topoccd_ccd *ccd = topoccd_ccd_new();
    topoccd_collisions *c = NULL;
    topoccd_error *error = NULL;
    CHECK_STATUS(topoccd_collisions_build(ccd, &config, x, 4, NULL, &c), TOPOCCD_STATUS_OK, "build");
    topoccd_collision_arrays a;
    CHECK_STATUS(topoccd_collisions_arrays(c, &a, &error), TOPOCCD_STATUS_OK, "arrays");
    CHECK(a.fv_count == 1 && a.vv_count == 0 && a.ev_count == 0 && a.ee_count == 0 && a.vertex_count == 4,
          "one fv collision, got %zu %zu %zu %zu", a.vv_count, a.ev_count, a.ee_count, a.fv_count);
    CHECK(a.fv_count == 1 && a.fv[0].vertex == 3 && a.fv[0].triangle[2] == 2, "the fv collision's ids");
    CHECK(a.edge_count == 3, "the triangle's 3 edges, got %zu", a.edge_count);
    topoccd_barrier_potential b = topoccd_barrier_potential_new(1e-3, 1.0);
    double e = 0, g[12], d2 = 0;
    CHECK_STATUS(topoccd_barrier_energy(&b, c, x, 4, &e, &error), TOPOCCD_STATUS_OK, "energy");
    const double s = 0.25e-6, t = 1e-6;
    CHECK(fabs(e + (s - t) * (s - t) * log(s / t)) <= 1e-12 * e, "energy %g", e);
    CHECK_STATUS(topoccd_collisions_minimum_distance(c, x, 4, &d2, &error), TOPOCCD_STATUS_OK, "min distance");
    CHECK(fabs(d2 - s) <= 1e-12 * s, "minimum squared distance %g", d2);

    /* The build's errors, with the message on the ccd. */
    topoccd_collisions *none = (topoccd_collisions *)&config;
    CHECK_STATUS(topoccd_collisions_build(ccd, NULL, x, 4, NULL, &none), TOPOCCD_STATUS_NULL_POINTER, "NULL config");
    CHECK(none == NULL, "the output is NULL after a failure");
    CHECK(contains(topoccd_ccd_last_error(ccd), "config is NULL"), "%s", topoccd_ccd_last_error(ccd));
    CHECK_STATUS(topoccd_collisions_build(ccd, &config, x, 4, NULL, NULL), TOPOCCD_STATUS_NULL_POINTER, "NULL out");
    CHECK_STATUS(topoccd_collisions_build(NULL, &config, x, 4, NULL, &none), TOPOCCD_STATUS_NULL_POINTER, "NULL ccd");
    CHECK_STATUS(topoccd_collisions_build(ccd, &config, NULL, 4, NULL, &none), TOPOCCD_STATUS_NULL_POINTER,
                 "NULL rest positions");
    CHECK_STATUS(topoccd_collisions_build(ccd, &config, x, 3, NULL, &none), TOPOCCD_STATUS_INVALID_ARGUMENT,
                 "rest positions of the wrong count");
    CHECK(contains(topoccd_ccd_last_error(ccd), "rest positions have 3 rows"), "%s", topoccd_ccd_last_error(ccd));
    const uint32_t bad_tris[] = {0, 1, 9};
    topoccd_configuration bad = config;
    bad.triangles = bad_tris;
    CHECK_STATUS(topoccd_collisions_build(ccd, &bad, x, 4, NULL, &none), TOPOCCD_STATUS_INVALID_STEP, "bad index");
    CHECK(contains(topoccd_ccd_last_error(ccd), "vertex 9"), "%s", topoccd_ccd_last_error(ccd));
    double nan_x[12];
    memcpy(nan_x, x, sizeof nan_x);
    nan_x[4] = NAN;
    bad = config;
    bad.x = nan_x;
    CHECK_STATUS(topoccd_collisions_build(ccd, &bad, x, 4, NULL, &none), TOPOCCD_STATUS_INVALID_STEP, "NaN position");
    CHECK_STATUS(topoccd_collisions_build(ccd, &config, nan_x, 4, NULL, &none), TOPOCCD_STATUS_INVALID_STEP,
                 "NaN rest position");
    CHECK(contains(topoccd_ccd_last_error(ccd), "rest position 1"), "%s", topoccd_ccd_last_error(ccd));
    topoccd_collision_options o = topoccd_collision_options_default();
    o.dhat = -1;
    CHECK_STATUS(topoccd_collisions_build(ccd, &config, x, 4, &o, &none), TOPOCCD_STATUS_INVALID_OPTIONS, "dhat < 0");
    CHECK(contains(topoccd_ccd_last_error(ccd), "dhat"), "%s", topoccd_ccd_last_error(ccd));
    o = topoccd_collision_options_default();
    o.dmin = NAN;
    CHECK_STATUS(topoccd_collisions_build(ccd, &config, x, 4, &o, &none), TOPOCCD_STATUS_INVALID_OPTIONS, "dmin NaN");
    o = topoccd_collision_options_default();
    o.collision_set_type = 7;
    CHECK_STATUS(topoccd_collisions_build(ccd, &config, x, 4, &o, &none), TOPOCCD_STATUS_INVALID_OPTIONS,
                 "unknown set type");
    CHECK(contains(topoccd_ccd_last_error(ccd), "collision_set_type"), "%s", topoccd_ccd_last_error(ccd));
    CHECK(none == NULL, "no set after the failures");

    /* The potentials' errors, with the message in a topoccd_error. */
    expect_error(topoccd_barrier_energy(NULL, c, x, 4, &e, &error), TOPOCCD_STATUS_NULL_POINTER, &error,
                 "potential is NULL", "NULL potential");
    expect_error(topoccd_barrier_energy(&b, NULL, x, 4, &e, &error), TOPOCCD_STATUS_NULL_POINTER, &error,
                 "collisions is NULL", "NULL collisions");
    expect_error(topoccd_barrier_energy(&b, (const topoccd_collisions *)ccd, x, 4, &e, &error),
                 TOPOCCD_STATUS_INVALID_HANDLE, &error, "not a live topoccd_collisions", "a ccd as collisions");
    expect_error(topoccd_barrier_energy(&b, c, NULL, 4, &e, &error), TOPOCCD_STATUS_NULL_POINTER, &error,
                 "x is NULL", "NULL x");
    expect_error(topoccd_barrier_energy(&b, c, x, 4, NULL, &error), TOPOCCD_STATUS_NULL_POINTER, &error,
                 "energy is NULL", "NULL energy");
    expect_error(topoccd_barrier_energy(&b, c, x, 5, &e, &error), TOPOCCD_STATUS_INVALID_ARGUMENT, &error,
                 "x has 5 rows, but the collision set has 4 vertices", "x of the wrong count");
    expect_error(topoccd_barrier_energy(&b, c, nan_x, 4, &e, &error), TOPOCCD_STATUS_INVALID_STEP, &error,
                 "vertex 1 is not finite", "NaN x");
    topoccd_barrier_potential bad_b = b;
    bad_b.stiffness = 0;
    expect_error(topoccd_barrier_energy(&bad_b, c, x, 4, &e, &error), TOPOCCD_STATUS_INVALID_OPTIONS, &error,
                 "stiffness must be finite and > 0", "zero stiffness");
    bad_b = b;
    bad_b.dhat = NAN;
    expect_error(topoccd_barrier_energy(&bad_b, c, x, 4, &e, &error), TOPOCCD_STATUS_INVALID_OPTIONS, &error,
                 "dhat must be finite", "NaN dhat");
    bad_b = b;
    bad_b.barrier = 9;
    expect_error(topoccd_barrier_energy(&bad_b, c, x, 4, &e, &error), TOPOCCD_STATUS_INVALID_OPTIONS, &error,
                 "barrier must be", "unknown barrier");
    expect_error(topoccd_barrier_gradient(&b, c, x, 4, g, 11, &error), TOPOCCD_STATUS_INVALID_ARGUMENT, &error,
                 "gradient_len is 11", "short gradient");
    expect_error(topoccd_barrier_gradient(&b, c, x, 4, NULL, 12, &error), TOPOCCD_STATUS_NULL_POINTER, &error,
                 "gradient is NULL", "NULL gradient");
    CHECK_STATUS(topoccd_barrier_gradient(&b, c, x, 4, g, 12, &error), TOPOCCD_STATUS_OK, "gradient");
    CHECK(g[11] < 0 && fabs(g[2] + g[5] + g[8] + g[11]) <= 1e-12 * fabs(g[11]), "the point is pushed up, the triangle down");
    topoccd_sparse *h = (topoccd_sparse *)&config;
    expect_error(topoccd_barrier_hessian(&b, c, x, 4, 3, &h, &error), TOPOCCD_STATUS_INVALID_OPTIONS, &error,
                 "projection must be", "unknown projection");
    CHECK(h == NULL, "the output is NULL after a failure");
    expect_error(topoccd_barrier_hessian(&b, c, x, 4, TOPOCCD_PSD_PROJECTION_ABS, NULL, &error),
                 TOPOCCD_STATUS_NULL_POINTER, &error, "hessian is NULL", "NULL hessian");
    CHECK_STATUS(topoccd_barrier_hessian(&b, c, x, 4, TOPOCCD_PSD_PROJECTION_ABS, &h, &error), TOPOCCD_STATUS_OK,
                 "hessian");
    topoccd_csr csr;
    CHECK_STATUS(topoccd_sparse_csr(h, &csr, &error), TOPOCCD_STATUS_OK, "csr");
    CHECK(csr.size == 12 && csr.nnz == csr.indptr[12] && csr.nnz == 144, "a dense 12x12 block, nnz %zu", csr.nnz);
    expect_error(topoccd_sparse_csr(h, NULL, &error), TOPOCCD_STATUS_NULL_POINTER, &error, "csr is NULL", "NULL csr");
    expect_error(topoccd_sparse_csr((const topoccd_sparse *)c, &csr, &error), TOPOCCD_STATUS_INVALID_HANDLE, &error,
                 "not a live topoccd_sparse", "collisions as a matrix");
    topoccd_sparse_free(&h);
    CHECK(h == NULL, "free sets NULL");
    topoccd_sparse_free(&h);
    topoccd_sparse_free(NULL);
    expect_error(topoccd_collisions_minimum_distance(c, x, 4, NULL, &error), TOPOCCD_STATUS_NULL_POINTER, &error,
                 "distance_squared is NULL", "NULL distance");
    expect_error(topoccd_collisions_arrays(c, NULL, &error), TOPOCCD_STATUS_NULL_POINTER, &error, "arrays is NULL",
                 "NULL arrays");

    /* The stiffness helpers. */
    double k = 0, kmax = 0;
    const double ge[] = {0, 0, 1}, gb[] = {0, 0, -2};
    CHECK_STATUS(topoccd_initial_barrier_stiffness(1, TOPOCCD_BARRIER_CLAMPED_LOG, 1e-3, 1, ge, gb, 3, 1e11, 0, &k,
                                                   &kmax, &error),
                 TOPOCCD_STATUS_OK, "initial stiffness");
    /* The balance -ge.gb/|gb|^2 = 0.5 is far below kappa_min: clamped up to it, kmax / 100. */
    CHECK(k > 0.5 && fabs(100 * k - kmax) <= 1e-12 * kmax, "initial stiffness %g, max %g", k, kmax);
    expect_error(topoccd_initial_barrier_stiffness(NAN, 0, 1e-3, 1, ge, gb, 3, 1e11, 0, &k, &kmax, &error),
                 TOPOCCD_STATUS_INVALID_OPTIONS, &error, "bbox_diagonal", "NaN diagonal");
    expect_error(topoccd_initial_barrier_stiffness(1, 0, 1e-3, 1, NULL, gb, 3, 1e11, 0, &k, &kmax, &error),
                 TOPOCCD_STATUS_NULL_POINTER, &error, "grad_energy is NULL", "NULL grad_energy");
    expect_error(topoccd_initial_barrier_stiffness(1, 0, 1e-3, 1, ge, gb, 3, 1e11, 0, NULL, &kmax, &error),
                 TOPOCCD_STATUS_NULL_POINTER, &error, "stiffness is NULL", "NULL stiffness");
    k = 1;
    CHECK_STATUS(topoccd_update_barrier_stiffness(1e-20, 1e-21, 100, 1, 1e-9, 0, &k, &error), TOPOCCD_STATUS_OK,
                 "update");
    CHECK(k == 2, "doubled, got %g", k);
    expect_error(topoccd_update_barrier_stiffness(NAN, 1e-21, 100, 1, 1e-9, 0, &k, &error),
                 TOPOCCD_STATUS_INVALID_OPTIONS, &error, "prev_min_distance", "NaN distance");
    expect_error(topoccd_update_barrier_stiffness(1, 1, 100, 1, 1e-9, 0, NULL, &error), TOPOCCD_STATUS_NULL_POINTER,
                 &error, "stiffness is NULL", "NULL stiffness");

    /* Friction. */
    topoccd_tangential_collisions *tc = (topoccd_tangential_collisions *)&config;
    expect_error(topoccd_tangential_collisions_build(c, &b, x, 4, -0.5, 0.5, &tc, &error),
                 TOPOCCD_STATUS_INVALID_OPTIONS, &error, "friction coefficient", "negative mu");
    CHECK(tc == NULL, "the output is NULL after a failure");
    expect_error(topoccd_tangential_collisions_build(c, NULL, x, 4, 0.5, 0.5, &tc, &error),
                 TOPOCCD_STATUS_NULL_POINTER, &error, "potential is NULL", "NULL barrier");
    expect_error(topoccd_tangential_collisions_build(c, &b, nan_x, 4, 0.5, 0.5, &tc, &error),
                 TOPOCCD_STATUS_INVALID_STEP, &error, "not finite", "NaN lagged positions");
    expect_error(topoccd_tangential_collisions_build(c, &b, x, 3, 0.5, 0.5, &tc, &error),
                 TOPOCCD_STATUS_INVALID_ARGUMENT, &error, "x has 3 rows", "lagged positions of the wrong count");
    CHECK_STATUS(topoccd_tangential_collisions_build(c, &b, x, 4, 0.5, 0.5, &tc, &error), TOPOCCD_STATUS_OK,
                 "tangential build");
    const topoccd_tangential_collision *rows = NULL;
    size_t count = 0;
    CHECK_STATUS(topoccd_tangential_collisions_arrays(tc, &rows, &count, &error), TOPOCCD_STATUS_OK, "arrays");
    CHECK(count == 1 && rows[0].kind == 3 && rows[0].vertices[0] == 3 && rows[0].vertex_count == 4,
          "one face-vertex tangential collision");
    /* The normal force: the barrier's push on the point, |dE/dz|. */
    CHECK(count == 1 && fabs(rows[0].normal_force_magnitude + g[11]) <= 1e-12 * fabs(g[11]), "normal force %g",
          count ? rows[0].normal_force_magnitude : 0.0);
    const double v[12] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0};
    double fe = 0, fg[12];
    CHECK_STATUS(topoccd_friction_energy(1e-3, tc, v, 4, &fe, &error), TOPOCCD_STATUS_OK, "friction energy");
    CHECK(fabs(fe - 0.5 * rows[0].normal_force_magnitude) <= 1e-12 * fe, "mu N |v|, got %g", fe);
    expect_error(topoccd_friction_energy(0, tc, v, 4, &fe, &error), TOPOCCD_STATUS_INVALID_OPTIONS, &error,
                 "eps_v", "zero eps_v");
    expect_error(topoccd_friction_energy(1e-3, (const topoccd_tangential_collisions *)c, v, 4, &fe, &error),
                 TOPOCCD_STATUS_INVALID_HANDLE, &error, "not a live topoccd_tangential_collisions",
                 "collisions as tangential");
    expect_error(topoccd_friction_gradient(1e-3, tc, v, 4, fg, 3, &error), TOPOCCD_STATUS_INVALID_ARGUMENT, &error,
                 "gradient_len is 3", "short friction gradient");
    expect_error(topoccd_friction_gradient(1e-3, tc, nan_x, 4, fg, 12, &error), TOPOCCD_STATUS_INVALID_STEP,
                 &error, "velocities: vertex 1 is not finite", "NaN velocity");
    topoccd_sparse *fh = NULL;
    expect_error(topoccd_friction_hessian(1e-3, tc, v, 4, 5, &fh, &error), TOPOCCD_STATUS_INVALID_OPTIONS, &error,
                 "projection", "unknown projection");
    CHECK_STATUS(topoccd_friction_hessian(1e-3, tc, v, 4, TOPOCCD_PSD_PROJECTION_NONE, &fh, &error),
                 TOPOCCD_STATUS_OK, "friction hessian");
    topoccd_sparse_free(&fh);
    topoccd_tangential_collisions_free(&tc);
    CHECK(tc == NULL, "free sets NULL");
    topoccd_tangential_collisions_free(&tc);

    topoccd_collisions_free(&c);
    CHECK(c == NULL, "free sets NULL");
    topoccd_collisions_free(&c);
    topoccd_collisions_free(NULL);
    topoccd_ccd_free(&ccd);
}

int main(void) {
    test_version_and_names();
    test_options();
    test_falling_triangle();
    test_cut();
    test_codim();
    test_query_errors();
    test_handles();
    test_threads();
    test_pairs();
    test_line_search();
    test_files();
    test_proximity();
    test_ipc();
    printf("%d passed, %d failed\n", passed, failed);
    return failed != 0;
}

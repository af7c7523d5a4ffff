/* The C API with its caps lifted, under a 1 GiB address-space limit (issue 51, item 7): on
 * triangles whose vertices all sit at one point (every pair touches), `topoccd_ccd_query`
 * with `max_contacts = 0` and `topoccd_proximity` with `max_contacts = 0` return
 * TOPOCCD_STATUS_OUT_OF_MEMORY with a message naming the buffer, instead of aborting; the same
 * `topoccd_ccd` then answers a capped query, a capped proximity query and a small one, and
 * `topoccd_mesh_read` of a file whose vertices do not fit returns the same status. Run by
 * scripts/test-c.sh (without sanitizers, whose shadow memory does not fit the limit); the last
 * line says how many checks passed. */
#define _POSIX_C_SOURCE 200809L
#include <topoccd.h>

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/types.h>
#include <unistd.h>

static int passed, failed;

#define CHECK(cond, ...)                                                      \
    do {                                                                      \
        if (cond) {                                                           \
            passed++;                                                         \
        } else {                                                              \
            failed++;                                                         \
            fprintf(stderr, "FAILED %s:%d: %s: ", __FILE__, __LINE__, #cond); \
            fprintf(stderr, __VA_ARGS__);                                     \
            fprintf(stderr, "\n");                                            \
        }                                                                     \
    } while (0)

static int contains(const char *text, const char *part) { return text && strstr(text, part) != NULL; }

int main(void) {
    /* 8,000 triangles sharing no vertex, all at the origin: 190 million vertex-face pairs. */
    enum { N = 8000 };
    double *x = calloc(3 * 3 * (size_t)N, sizeof(double));
    uint32_t *tris = malloc(3 * (size_t)N * sizeof(uint32_t));
    if (!x || !tris)
        return 2;
    for (uint32_t i = 0; i < 3 * N; i++)
        tris[i] = i;
    struct rlimit limit = {1024UL * 1024 * 1024, 1024UL * 1024 * 1024};
    if (setrlimit(RLIMIT_AS, &limit) != 0) {
        perror("setrlimit");
        return 2;
    }
    topoccd_ccd *ccd = topoccd_ccd_new();
    topoccd_step s = {0};
    s.x0 = x; s.x0_count = 3 * N;
    s.x1 = x; s.x1_count = 3 * N;
    s.triangles = tris; s.triangle_count = N;
    topoccd_query_options o;
    topoccd_query_options_default(&o);
    o.max_contacts = 0;
    topoccd_status st = topoccd_ccd_query(ccd, &s, &o);
    CHECK(st == TOPOCCD_STATUS_OUT_OF_MEMORY, "query: %s", topoccd_status_name(st));
    CHECK(contains(topoccd_ccd_last_error(ccd), "out of memory: could not allocate"), "%s",
          topoccd_ccd_last_error(ccd));
    printf("query: %s\n", topoccd_ccd_last_error(ccd));
    const topoccd_report *r = NULL;
    topoccd_ccd_report(ccd, &r);
    CHECK(r && r->vf_count == 0, "a failed query's report is empty");
    topoccd_query_options_default(&o);
    st = topoccd_ccd_query(ccd, &s, &o);
    CHECK(st == TOPOCCD_STATUS_OK, "capped query: %s", topoccd_status_name(st));
    topoccd_ccd_report(ccd, &r);
    CHECK(r->truncated == TOPOCCD_STOP_REASON_MAX_CONTACTS, "truncated %u", r->truncated);

    topoccd_configuration c = {0};
    c.x = x; c.vertex_count = 3 * N;
    c.triangles = tris; c.triangle_count = N;
    topoccd_proximity_options p = topoccd_proximity_options_default();
    CHECK(p.max_contacts == o.max_contacts, "one default cap: %llu", (unsigned long long)p.max_contacts);
    p.max_contacts = 0;
    const topoccd_proximity_report *pr = NULL;
    st = topoccd_proximity(ccd, &c, &p, &pr);
    CHECK(st == TOPOCCD_STATUS_OUT_OF_MEMORY, "proximity: %s", topoccd_status_name(st));
    printf("proximity: %s\n", topoccd_ccd_last_error(ccd));
    /* The object stays usable: with the default cap the same configuration answers, truncated. */
    p = topoccd_proximity_options_default();
    st = topoccd_proximity(ccd, &c, &p, &pr);
    CHECK(st == TOPOCCD_STATUS_OK && pr->truncated && pr->vf_count + pr->ee_count == p.max_contacts,
          "capped proximity: %s", topoccd_status_name(st));
    c.vertex_count = 3;
    c.triangle_count = 1;
    st = topoccd_proximity(ccd, &c, NULL, &pr);
    CHECK(st == TOPOCCD_STATUS_OK && pr->vf_count == 0 && !pr->truncated, "proximity after: %s",
          topoccd_status_name(st));
    topoccd_ccd_free(&ccd);
    free(x);
    free(tris);

    /* A mesh file as large as its header says (sparse: no disk space), whose 200 million
     * vertices do not fit under the limit: an out-of-memory status naming the file. */
    char path[64];
    snprintf(path, sizeof path, "/tmp/topoccd-c-memory-%ld.ply", (long)getpid());
    const char *header = "ply\nformat binary_little_endian 1.0\nelement vertex 200000000\n"
                         "property float x\nproperty float y\nproperty float z\n"
                         "element face 0\nproperty list uchar int vertex_indices\nend_header\n";
    FILE *f = fopen(path, "wb");
    CHECK(f != NULL, "cannot create %s", path);
    if (f) {
        fputs(header, f);
        fclose(f);
        CHECK(truncate(path, (off_t)strlen(header) + (off_t)12 * 200000000) == 0, "truncate");
        topoccd_mesh *mesh = NULL;
        topoccd_error *error = NULL;
        st = topoccd_mesh_read(path, &mesh, &error);
        CHECK(st == TOPOCCD_STATUS_OUT_OF_MEMORY, "mesh read: %s", topoccd_status_name(st));
        CHECK(mesh == NULL, "no mesh");
        const char *message = error ? topoccd_error_message(error) : NULL;
        CHECK(contains(message, path) && contains(message, "out of memory reading the vertex positions"),
              "%s", message ? message : "(no error)");
        printf("mesh read: %s\n", message ? message : "(no error)");
        topoccd_error_free(&error);
        remove(path);
    }
    printf("%d passed, %d failed\n", passed, failed);
    return failed != 0;
}

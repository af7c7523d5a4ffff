/* A query through a copy of a freed topoccd_ccd: undefined behaviour in C, which the object's
 * tag (cleared by topoccd_ccd_free) turns into TOPOCCD_STATUS_INVALID_HANDLE as long as the
 * allocator has not reused the memory. This program checks that best effort on this platform;
 * it reads freed memory on purpose, so scripts/test-c.sh builds it without AddressSanitizer
 * (api.c, which runs under it, checks the defined cases: a NULL pointer after free, another
 * kind of object, memory that is no object). */
#include <topoccd.h>

#include <stdio.h>
#include <string.h>

int main(void) {
    int passed = 0, failed = 0;
    const double x[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const uint32_t tri[] = {0, 1, 2};
    topoccd_step step = {0};
    step.x0 = x;
    step.x0_count = 3;
    step.x1 = x;
    step.x1_count = 3;
    step.triangles = tri;
    step.triangle_count = 1;

    topoccd_ccd *ccd = topoccd_ccd_new();
    topoccd_ccd *copy = ccd;
    if (topoccd_ccd_query(ccd, &step, NULL) == TOPOCCD_STATUS_OK) passed++; else failed++;
    topoccd_ccd_free(&ccd);
    topoccd_status s = topoccd_ccd_query(copy, &step, NULL);
    if (s == TOPOCCD_STATUS_INVALID_HANDLE) {
        passed++;
    } else {
        failed++;
        fprintf(stderr, "FAILED: a query through a freed copy gave %s\n", topoccd_status_name(s));
    }
    if (strstr(topoccd_ccd_last_error(copy), "not a live topoccd_ccd") != NULL) passed++; else failed++;
    topoccd_ccd_free(&copy); /* no tag: nothing is freed twice */
    if (copy != NULL) passed++; else failed++;
    printf("%d passed, %d failed\n", passed, failed);
    return failed != 0;
}

/* One CCD step between two mesh files, across a cut when a parents file is given: the C API.
 *
 *     step T0 T1 [PARENTS]
 *
 * T0 gives the positions at t=0, T1 the positions at t=1 and the triangles (PLY, OBJ or STL);
 * PARENTS (one line "NEW_ID PARENT_ID" per vertex that T1 adds) makes the step a topology
 * change. Prints "N contacts (V vf, E ee), earliest toi T" and then one line per contact, as
 * `topoccd step T0 T1 [--parents PARENTS] --pairs -` does: vf,VERTEX,FACE,TOI (with
 * ,FILE_FACE,SUB when T1's polygons were split into triangles) or ee,A0,A1,B0,B1,TOI. */
#include <topoccd.h>

#include <stdio.h>

int main(int argc, char **argv) {
    if (argc < 3 || argc > 4) {
        fprintf(stderr, "usage: %s T0 T1 [PARENTS]\n", argv[0]);
        return 2;
    }
    topoccd_frames *frames = NULL;
    topoccd_error *error = NULL;
    if (topoccd_frames_read(argv[1], argv[2], argc == 4 ? argv[3] : NULL, &frames, &error)
        != TOPOCCD_STATUS_OK) {
        fprintf(stderr, "error: %s\n", topoccd_error_message(error));
        topoccd_error_free(&error);
        return 2;
    }
    size_t notes = 0;
    topoccd_frames_note_count(frames, &notes);
    for (size_t i = 0; i < notes; i++) {
        const char *note = NULL;
        topoccd_frames_note(frames, i, &note);
        fprintf(stderr, "note: %s\n", note);
    }

    topoccd_step step;
    const uint32_t *face_origin = NULL;
    topoccd_frames_step(frames, &step);
    topoccd_frames_face_origin(frames, &face_origin);

    topoccd_ccd *ccd = topoccd_ccd_new();
    const topoccd_report *r = NULL;
    int exit_code = 0;
    if (topoccd_ccd_query(ccd, &step, NULL) != TOPOCCD_STATUS_OK
        || topoccd_ccd_report(ccd, &r) != TOPOCCD_STATUS_OK) {
        fprintf(stderr, "error: %s\n", topoccd_ccd_last_error(ccd));
        exit_code = 2;
    } else {
        printf("%zu contacts (%zu vf, %zu ee), earliest toi ", r->vf_count + r->ee_count,
               r->vf_count, r->ee_count);
        if (r->earliest_kind == TOPOCCD_CONTACT_KIND_NONE)
            printf("none\n");
        else
            printf("%.17g\n", r->earliest_toi);
        for (size_t i = 0; i < r->vf_count; i++) {
            const topoccd_vf_contact *c = &r->vf[i];
            printf("vf,%u,%u,%.17g", c->vertex, c->face, c->toi);
            if (face_origin != NULL)
                printf(",%u,%u", face_origin[2 * c->face], face_origin[2 * c->face + 1]);
            printf("\n");
        }
        for (size_t i = 0; i < r->ee_count; i++) {
            const topoccd_ee_contact *c = &r->ee[i];
            printf("ee,%u,%u,%u,%u,%.17g\n", c->a[0], c->a[1], c->b[0], c->b[1], c->toi);
        }
        if (r->unresolved > 0)
            fprintf(stderr, "warning: %zu contacts unresolved (their times are lower bounds)\n",
                    r->unresolved);
    }
    topoccd_ccd_free(&ccd);
    topoccd_frames_free(&frames);
    return exit_code;
}

/* A simulator's line search over a frame sequence: the C API.
 *
 *     line_search SEQ_DIR
 *
 * SEQ_DIR holds frames 0000.ply, 0001.ply, ... (and .parents files where a frame cuts or
 * fractures the mesh). For each step, topoccd_collision_free_stepsize gives the fraction ALPHA
 * of the step the simulator may take: 0.8 times the first time of impact t (all of it when
 * nothing collides). Its Earliest query's report names the contact that cut the step short. One topoccd_ccd serves
 * every step: its buffers are reused, whatever the topology.
 * Prints one line per step: "step K: earliest toi T (V vf, E ee), take ALPHA of the step", and
 * for a step cut short, the earliest contact. */
#include <topoccd.h>

#include <stdio.h>

int main(int argc, char **argv) {
    if (argc != 2) {
        fprintf(stderr, "usage: %s SEQ_DIR\n", argv[0]);
        return 2;
    }
    topoccd_error *error = NULL;
    topoccd_sequence *seq = NULL;
    if (topoccd_sequence_open(argv[1], &seq, &error) != TOPOCCD_STATUS_OK) {
        fprintf(stderr, "error: %s\n", topoccd_error_message(error));
        topoccd_error_free(&error);
        return 2;
    }
    size_t steps = 0;
    topoccd_sequence_step_count(seq, &steps);

    topoccd_line_search_options options;
    topoccd_line_search_options_default(&options);
    /* options.check_start = true would refuse a step whose start has intersecting triangles:
     * the generated sequences have such frames by design (see the guide's getting-started). */
    topoccd_ccd *ccd = topoccd_ccd_new();
    int exit_code = 0;
    for (size_t k = 0; k < steps && exit_code == 0; k++) {
        topoccd_frames *frames = NULL;
        if (topoccd_sequence_load(seq, k, &frames, &error) != TOPOCCD_STATUS_OK) {
            fprintf(stderr, "error: %s\n", topoccd_error_message(error));
            topoccd_error_free(&error);
            exit_code = 2;
            break;
        }
        topoccd_step step;
        const topoccd_report *r = NULL;
        double alpha = 0;
        topoccd_frames_step(frames, &step);
        if (topoccd_collision_free_stepsize(ccd, &step, &options, &alpha) != TOPOCCD_STATUS_OK
            || topoccd_ccd_report(ccd, &r) != TOPOCCD_STATUS_OK) {
            fprintf(stderr, "error: step %zu: %s\n", k, topoccd_ccd_last_error(ccd));
            exit_code = 2;
        } else if (r->earliest_kind == TOPOCCD_CONTACT_KIND_NONE) {
            printf("step %zu: earliest toi none (0 vf, 0 ee), take %.17g of the step\n", k, alpha);
        } else {
            printf("step %zu: earliest toi %.17g (%zu vf, %zu ee), take %.17g of the step\n", k,
                   r->earliest_toi, r->vf_count, r->ee_count, alpha);
            if (r->earliest_kind == TOPOCCD_CONTACT_KIND_VF) {
                const topoccd_vf_contact *c = &r->vf[r->earliest_index];
                printf("  earliest: vertex %u, face %u\n", c->vertex, c->face);
            } else {
                const topoccd_ee_contact *c = &r->ee[r->earliest_index];
                printf("  earliest: edge %u-%u, edge %u-%u\n", c->a[0], c->a[1], c->b[0], c->b[1]);
            }
        }
        topoccd_frames_free(&frames);
    }
    topoccd_ccd_free(&ccd);
    topoccd_sequence_free(&seq);
    return exit_code;
}

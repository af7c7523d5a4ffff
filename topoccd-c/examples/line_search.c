/* A simulator's line search over a frame sequence: the C API.
 *
 *     line_search SEQ_DIR
 *
 * SEQ_DIR holds frames 0000.ply, 0001.ply, ... (and .parents files where a frame cuts or
 * fractures the mesh). For each step, an earliest-time query (TOPOCCD_MODE_EARLIEST) gives the
 * first time of impact t, and the simulator may take 0.8 t of the step (all of it when nothing
 * collides). One topoccd_ccd serves every step: its buffers are reused, whatever the topology.
 * Prints one line per step: "step K: earliest toi T (V vf, E ee), take ALPHA of the step". */
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

    topoccd_query_options options;
    topoccd_query_options_default(&options);
    options.mode = TOPOCCD_MODE_EARLIEST;
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
        topoccd_frames_step(frames, &step);
        if (topoccd_ccd_query(ccd, &step, &options) != TOPOCCD_STATUS_OK
            || topoccd_ccd_report(ccd, &r) != TOPOCCD_STATUS_OK) {
            fprintf(stderr, "error: step %zu: %s\n", k, topoccd_ccd_last_error(ccd));
            exit_code = 2;
        } else if (r->earliest_kind == TOPOCCD_CONTACT_KIND_NONE) {
            printf("step %zu: earliest toi none (0 vf, 0 ee), take 1 of the step\n", k);
        } else {
            double alpha = 0.8 * r->earliest_toi;
            printf("step %zu: earliest toi %.17g (%zu vf, %zu ee), take %.17g of the step\n", k,
                   r->earliest_toi, r->vf_count, r->ee_count, alpha);
        }
        topoccd_frames_free(&frames);
    }
    topoccd_ccd_free(&ccd);
    topoccd_sequence_free(&seq);
    return exit_code;
}

/* The proximity set of one frame, as an IPC solver asks for it every iteration: the C API.
 *
 *     proximity MESH DHAT
 *
 * Reads MESH (PLY, OBJ or STL) and prints how many primitive pairs are closer than DHAT, per
 * kind, and the closest vertex-face and edge-edge pairs. A second call on the same
 * topoccd_ccd (as the solver's next iteration) refits the hierarchy instead of building it. */
#include <topoccd.h>

#include <stdio.h>
#include <stdlib.h>

int main(int argc, char **argv) {
    if (argc != 3) {
        fprintf(stderr, "usage: %s MESH DHAT\n", argv[0]);
        return 2;
    }
    topoccd_error *error = NULL;
    topoccd_mesh *mesh = NULL;
    if (topoccd_mesh_read(argv[1], &mesh, &error) != TOPOCCD_STATUS_OK) {
        fprintf(stderr, "error: %s\n", topoccd_error_message(error));
        topoccd_error_free(&error);
        return 2;
    }
    topoccd_mesh_view view;
    topoccd_mesh_data(mesh, &view);
    topoccd_configuration config = {0};
    config.x = view.positions;
    config.vertex_count = view.vertex_count;
    config.triangles = view.triangles;
    config.triangle_count = view.triangle_count;
    topoccd_proximity_options options = topoccd_proximity_options_default();
    options.dhat = atof(argv[2]);

    topoccd_ccd *ccd = topoccd_ccd_new();
    const topoccd_proximity_report *r = NULL;
    int exit_code = 0;
    for (int iteration = 0; iteration < 2 && exit_code == 0; iteration++) {
        if (topoccd_proximity(ccd, &config, &options, &r) != TOPOCCD_STATUS_OK) {
            fprintf(stderr, "error: %s\n", topoccd_ccd_last_error(ccd));
            exit_code = 2;
            break;
        }
        printf("iteration %d: %zu vf, %zu ee, %zu ve, %zu vv (%s)\n", iteration, r->vf_count,
               r->ee_count, r->ve_count, r->vv_count, r->refitted ? "refitted" : "built");
    }
    if (exit_code == 0) {
        size_t best = 0;
        for (size_t i = 1; i < r->vf_count; i++)
            if (r->vf[i].distance < r->vf[best].distance) best = i;
        if (r->vf_count > 0)
            printf("closest vertex-face: vertex %u, face %u, distance %.6g, type %u\n",
                   r->vf[best].vertex, r->vf[best].face, r->vf[best].distance, r->vf[best].type);
        best = 0;
        for (size_t i = 1; i < r->ee_count; i++)
            if (r->ee[i].distance < r->ee[best].distance) best = i;
        if (r->ee_count > 0)
            printf("closest edge-edge: (%u %u) (%u %u), distance %.6g, type %u\n", r->ee[best].a[0],
                   r->ee[best].a[1], r->ee[best].b[0], r->ee[best].b[1], r->ee[best].distance,
                   r->ee[best].type);
    }
    topoccd_ccd_free(&ccd);
    topoccd_mesh_free(&mesh);
    return exit_code;
}

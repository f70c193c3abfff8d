/* Sample: load a model, make a body, shape and pose it, read its vertices. Plain C99.
 * usage: sample_c_synthesize [MODEL.sscape]   (no argument: the default model built into the library) */
#include <sscape/sscape.h>

#include <stdio.h>
#include <stdlib.h>

static int check(ssc_status s, const char* what) {
    if (s != SSC_OK) {
        fprintf(stderr, "%s failed: %s: %s\n", what, ssc_status_name(s), ssc_last_error());
        return 0;
    }
    return 1;
}

int main(int argc, char** argv) {
    ssc_context_def def;
    ssc_context* ctx = NULL;
    ssc_model* model = NULL;
    ssc_body* body = NULL;
    float* verts = NULL;
    float shape[3] = {1.0f, -0.5f, 0.25f};
    float* pose = NULL;
    uint32_t V, J, v, elbow;
    float lo[3] = {1e9f, 1e9f, 1e9f}, hi[3] = {-1e9f, -1e9f, -1e9f};
    int ok = 0;

    if (argc > 2) {
        fprintf(stderr, "usage: %s [MODEL.sscape]\n", argv[0]);
        return 2;
    }
    if (ssc_version() != SSC_VERSION_NUMBER) {
        fprintf(stderr, "library version %u differs from header %u\n", ssc_version(), SSC_VERSION_NUMBER);
        return 1;
    }
    ssc_context_def_init(&def, sizeof def);
    def.worker_count = 1;
    if (!check(ssc_context_create(&def, &ctx), "ssc_context_create")) goto done;
    if (argc == 2) {
        if (!check(ssc_model_load_file(ctx, argv[1], &model), "ssc_model_load_file")) goto done;
    } else {
        if (!check(ssc_model_load_default(ctx, &model), "ssc_model_load_default")) goto done;
    }
    if (!check(ssc_body_create(model, NULL, &body), "ssc_body_create")) goto done;

    V = ssc_model_vertex_count(model);
    J = ssc_model_joint_count(model);
    verts = (float*)malloc(sizeof(float) * 3 * V);
    pose = (float*)calloc(3 * (size_t)J, sizeof(float));
    if (!verts || !pose) goto done;
    /* Bend the first joint whose name we know, if the model has it. */
    if (ssc_model_find_joint(model, "lowerarm_l", &elbow) == SSC_OK) pose[3 * elbow + 2] = 1.2f;

    if (!check(ssc_body_set_shape(body, shape, 3), "ssc_body_set_shape")) goto done;
    if (!check(ssc_body_set_pose_axis_angle(body, pose, J, NULL), "ssc_body_set_pose_axis_angle")) goto done;
    if (!check(ssc_body_get_vertices(body, verts, V, 0), "ssc_body_get_vertices")) goto done;
    for (v = 0; v < V; ++v) {
        int a;
        for (a = 0; a < 3; ++a) {
            if (verts[3 * v + a] < lo[a]) lo[a] = verts[3 * v + a];
            if (verts[3 * v + a] > hi[a]) hi[a] = verts[3 * v + a];
        }
    }
    printf("%u vertices, %u joints; body height %.3f m, width %.3f m\n", V, J, hi[1] - lo[1], hi[0] - lo[0]);
    ok = hi[1] - lo[1] > 0.0f;

done:
    free(verts);
    free(pose);
    ssc_body_destroy(body);
    ssc_model_release(model);
    ssc_context_destroy(ctx);
    return ok ? 0 : 1;
}

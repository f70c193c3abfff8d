/* The bindings' common scenario through the C API: each binding (C#, Rust, JavaScript) runs the same
 * steps through its own layer and writes the same file, which must equal this program's byte for
 * byte (tests/bindings/run.sh compares them).
 *
 * Steps, on the default model:
 *   1. a body with shape (0.8, -0.5, 1.2, 0.3, -1.0), upperarm_l and lowerarm_r rotated (the quaternions
 *      below), translation (0.1, 0, -0.2): its vertices (vertex_count * 3 floats);
 *   2. its measurements, all of them (ssc_measurement_count floats);
 *   3. its landmarks (landmark_count * 3 floats);
 *   4. a fitter (default def) given those landmarks by name, solved: shape (shape_count floats),
 *      rotations (joint_count * 4), translation (3), scale (1);
 *   5. ssc_model_sample_shapes(seed 7, 3 bodies, truncation 2) and those bodies synthesized in one
 *      batch in the rest pose (3 * vertex_count * 3 floats).
 * The file is those floats in that order, as the machine stores them (little-endian here).
 * usage: scenario OUT.bin */
#include <sscape/sscape.h>

#include <stdio.h>
#include <stdlib.h>

static int check(ssc_status status, const char* what) {
    if (status == SSC_OK) return 1;
    fprintf(stderr, "scenario: %s: %s: %s\n", what, ssc_status_name(status), ssc_last_error());
    return 0;
}

static int write_floats(FILE* file, const float* values, size_t count) {
    return fwrite(values, sizeof(float), count, file) == count;
}

int main(int argc, char** argv) {
    if (argc != 2) { fprintf(stderr, "usage: scenario OUT.bin\n"); return 2; }
    ssc_model* model = NULL;
    ssc_body* body = NULL;
    ssc_fitter* fitter = NULL;
    float *vertices = NULL, *measurements = NULL, *landmarks = NULL, *rotations = NULL, *shape = NULL;
    float *samples = NULL, *batch = NULL;
    const char** names = NULL;
    FILE* out = NULL;
    int ok = 0;
    if (!check(ssc_model_load_default(NULL, &model), "load the default model")) goto done;
    const uint32_t V = ssc_model_vertex_count(model), J = ssc_model_joint_count(model);
    const uint32_t L = ssc_model_landmark_count(model), K = ssc_model_shape_count(model);
    const uint32_t M = ssc_measurement_count();
    vertices = malloc(sizeof(float) * V * 3);
    measurements = malloc(sizeof(float) * M);
    landmarks = malloc(sizeof(float) * L * 3);
    rotations = malloc(sizeof(float) * J * 4);
    shape = malloc(sizeof(float) * K);
    samples = malloc(sizeof(float) * 3 * K);
    batch = malloc(sizeof(float) * 3 * V * 3);
    names = malloc(sizeof(char*) * L);
    out = fopen(argv[1], "wb");
    if (!vertices || !measurements || !landmarks || !rotations || !shape || !samples || !batch || !names || !out) {
        fprintf(stderr, "scenario: out of memory or cannot write %s\n", argv[1]);
        goto done;
    }

    /* 1. A shaped, posed body. */
    if (!check(ssc_body_create(model, NULL, &body), "create a body")) goto done;
    const float coefficients[5] = {0.8f, -0.5f, 1.2f, 0.3f, -1.0f};
    if (!check(ssc_body_set_shape(body, coefficients, 5), "set the shape")) goto done;
    for (uint32_t j = 0; j < J; ++j) {
        rotations[j * 4 + 0] = rotations[j * 4 + 1] = rotations[j * 4 + 2] = 0.0f;
        rotations[j * 4 + 3] = 1.0f;
    }
    uint32_t upperarm = 0, lowerarm = 0;
    if (!check(ssc_model_find_joint(model, "upperarm_l", &upperarm), "find upperarm_l")) goto done;
    if (!check(ssc_model_find_joint(model, "lowerarm_r", &lowerarm), "find lowerarm_r")) goto done;
    const float arm[4] = {0.0f, 0.0f, 0.25881904f, 0.96592583f};  /* 30 degrees about z */
    const float elbow[4] = {0.0f, -0.17364818f, 0.0f, 0.98480775f}; /* -20 degrees about y */
    for (int c = 0; c < 4; ++c) { rotations[upperarm * 4 + c] = arm[c]; rotations[lowerarm * 4 + c] = elbow[c]; }
    const float translation[3] = {0.1f, 0.0f, -0.2f};
    if (!check(ssc_body_set_pose(body, rotations, J, translation), "set the pose")) goto done;
    if (!check(ssc_body_get_vertices(body, vertices, V, 0), "get the vertices")) goto done;
    /* 2. Its measurements. */
    if (!check(ssc_body_measure(body, measurements, M), "measure")) goto done;
    /* 3. Its landmarks. */
    if (!check(ssc_body_get_landmarks(body, landmarks, L, 0), "get the landmarks")) goto done;
    /* 4. A fit to those landmarks, by name. */
    for (uint32_t l = 0; l < L; ++l)
        if (!check(ssc_model_get_landmark_name(model, l, &names[l]), "landmark name")) goto done;
    if (!check(ssc_fitter_create(model, NULL, &fitter), "create a fitter")) goto done;
    if (!check(ssc_fitter_add_landmarks_by_name(fitter, 0, names, landmarks, NULL, L), "add landmarks")) goto done;
    ssc_fit_report report;
    report.struct_size = sizeof report;
    if (!check(ssc_fitter_solve(fitter, NULL, NULL, &report), "solve")) goto done;
    float fit_translation[3], fit_scale = 0.0f;
    if (!check(ssc_fitter_get_shape(fitter, shape, K), "fitted shape")) goto done;
    if (!check(ssc_fitter_get_pose(fitter, 0, rotations, J, fit_translation, &fit_scale), "fitted pose")) goto done;
    /* 5. A batch of sampled bodies. */
    if (!check(ssc_model_sample_shapes(model, 7, 3, 2.0f, samples, 3 * K), "sample shapes")) goto done;
    ssc_batch_desc desc;
    ssc_batch_desc_init(&desc, sizeof desc);
    desc.body_count = 3;
    desc.shapes = samples;
    desc.shape_count = K;
    desc.vertices = batch;
    desc.vertices_capacity = (size_t)3 * V;
    if (!check(ssc_model_synthesize_batch(model, &desc), "synthesize the batch")) goto done;

    ok = write_floats(out, vertices, (size_t)V * 3) && write_floats(out, measurements, M) &&
         write_floats(out, landmarks, (size_t)L * 3) && write_floats(out, shape, K) &&
         write_floats(out, rotations, (size_t)J * 4) && write_floats(out, fit_translation, 3) &&
         write_floats(out, &fit_scale, 1) && write_floats(out, batch, (size_t)3 * V * 3);
    if (!ok) fprintf(stderr, "scenario: cannot write %s\n", argv[1]);
done:
    if (out && fclose(out) != 0) ok = 0;
    ssc_fitter_destroy(fitter);
    ssc_body_destroy(body);
    ssc_model_release(model);
    free(vertices); free(measurements); free(landmarks); free(rotations); free(shape); free(samples); free(batch);
    free((void*)names);
    return ok ? 0 : 1;
}

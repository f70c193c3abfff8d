/* Enum arguments from C outside their enumerators (-1, 42) give SSC_ERROR_INVALID_ARGUMENT.
 * Written in C on purpose: a C caller may pass any int where the header says enum, and the library
 * must read it as an integer (in C++ such a value in the enum type is undefined behaviour, which the
 * sanitizer build reports). Exit status 0 when every case is refused, 1 otherwise. */
#include <sscape/sscape.h>

#include <stdio.h>
#include <string.h>

static int failures = 0;

static void expect_invalid(ssc_status s, const char* what) {
    if (s != SSC_ERROR_INVALID_ARGUMENT) {
        fprintf(stderr, "FAIL %s: %s (%s)\n", what, ssc_status_name(s), ssc_last_error());
        ++failures;
    } else {
        printf("ok   %s: %s\n", what, ssc_last_error());
    }
}

int main(void) {
    static const int bad[2] = {-1, 42};
    ssc_model* model = NULL;
    ssc_body* body = NULL;
    ssc_fitter* fitter = NULL;
    float rotations[4 * 64];
    float vertices[3];
    unsigned short depth[25];
    const char* text = NULL;
    uint32_t J, j, count = 0;
    int i;
    if (ssc_model_load_default(NULL, &model) != SSC_OK || ssc_body_create(model, NULL, &body) != SSC_OK ||
        ssc_fitter_create(model, NULL, &fitter) != SSC_OK) {
        fprintf(stderr, "setup failed: %s\n", ssc_last_error());
        return 1;
    }
    J = ssc_model_joint_count(model);
    for (j = 0; j < J && j < 64; ++j) {
        rotations[4 * j] = rotations[4 * j + 1] = rotations[4 * j + 2] = 0.f;
        rotations[4 * j + 3] = 1.f;
    }
    memset(depth, 0, sizeof depth);
    for (i = 0; i < 2; ++i) {
        ssc_context_def cdef;
        ssc_context* ctx = NULL;
        ssc_batch_desc desc;
        ssc_depth_image_def image;
        ssc_context_def_init(&cdef, sizeof cdef);
        cdef.log_level = (ssc_log_level)bad[i];
        expect_invalid(ssc_context_create(&cdef, &ctx), "ssc_context_create log_level");
        expect_invalid(ssc_model_get_metadata(model, (ssc_metadata_key)bad[i], &text), "ssc_model_get_metadata key");
        expect_invalid(ssc_body_set_pose_limited(body, rotations, J, NULL, (ssc_limit_mode)bad[i], &count),
                       "ssc_body_set_pose_limited mode");
        ssc_batch_desc_init(&desc, sizeof desc);
        desc.body_count = 1;
        desc.pose_format = (ssc_rotation_format)bad[i];
        desc.vertices = vertices;
        desc.vertices_capacity = 1;
        expect_invalid(ssc_model_synthesize_batch(model, &desc), "ssc_model_synthesize_batch pose_format");
        ssc_depth_image_def_init(&image, sizeof image);
        image.format = (ssc_depth_format)bad[i];
        image.samples = depth;
        image.width = image.height = 5;
        image.fx = image.fy = 5.f;
        expect_invalid(ssc_fitter_add_depth_image(fitter, 0, &image, &count), "ssc_fitter_add_depth_image format");
    }
    ssc_fitter_destroy(fitter);
    ssc_body_destroy(body);
    ssc_model_release(model);
    return failures ? 1 : 0;
}

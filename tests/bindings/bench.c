/* What the same calls cost from C, for the bindings' examples/bench: a trivial call, and a body's
 * vertices after a shape change, as medians of 5 runs.  usage: bench */
#define _POSIX_C_SOURCE 199309L
#include <sscape/sscape.h>

#include <stdio.h>
#include <stdlib.h>
#include <time.h>

static double now_ns(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec * 1e9 + (double)t.tv_nsec;
}

static int by_value(const void* a, const void* b) {
    const double x = *(const double*)a, y = *(const double*)b;
    return (x > y) - (x < y);
}

int main(void) {
    ssc_model* model = NULL;
    ssc_body* body = NULL;
    if (ssc_model_load_default(NULL, &model) != SSC_OK || ssc_body_create(model, NULL, &body) != SSC_OK) {
        fprintf(stderr, "bench: %s\n", ssc_last_error());
        return 1;
    }
    const uint32_t V = ssc_model_vertex_count(model), K = ssc_model_shape_count(model);
    float* shapes = malloc(sizeof(float) * 16 * K);
    float* out = malloc(sizeof(float) * 3 * V);
    if (!shapes || !out || ssc_model_sample_shapes(model, 1, 16, 2.5f, shapes, 16 * K) != SSC_OK) return 1;
    double call[5], vertices[5];
    volatile uint32_t sink = 0;
    for (int r = 0; r < 5; ++r) {
        double start = now_ns();
        for (int i = 0; i < 100000; ++i) sink += ssc_model_vertex_count(model);
        call[r] = (now_ns() - start) / 100000;
        start = now_ns();
        for (int i = 0; i < 300; ++i) {
            ssc_body_set_shape(body, shapes + (i % 16) * K, K);
            ssc_body_get_vertices(body, out, V, 0);
        }
        vertices[r] = (now_ns() - start) / 300;
    }
    qsort(call, 5, sizeof(double), by_value);
    qsort(vertices, 5, sizeof(double), by_value);
    printf("c: call %.0f ns, shape+vertices %.1f us\n", call[2], vertices[2] / 1000);
    free(shapes);
    free(out);
    ssc_body_destroy(body);
    ssc_model_release(model);
    return sink == 0;
}

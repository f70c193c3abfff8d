/* The browser package (src/sscape.mjs) reads and writes these structs by byte offset on wasm32:
 * a header change that moves a field fails the WebAssembly build here instead of corrupting a call. */
#include <sscape/sscape.h>

#include <stddef.h>

_Static_assert(sizeof(void*) == 4 && sizeof(size_t) == 4, "the browser package assumes wasm32");
_Static_assert(sizeof(ssc_slider_info) == 28 && offsetof(ssc_slider_info, name) == 4 && offsetof(ssc_slider_info, unit) == 8 &&
                   offsetof(ssc_slider_info, description) == 12 && offsetof(ssc_slider_info, mean) == 16 &&
                   offsetof(ssc_slider_info, minimum) == 20 && offsetof(ssc_slider_info, maximum) == 24,
               "SLIDER_INFO in src/sscape.mjs");
_Static_assert(sizeof(ssc_level_info) == 20 && offsetof(ssc_level_info, name) == 4 && offsetof(ssc_level_info, vertex_count) == 8 &&
                   offsetof(ssc_level_info, triangle_count) == 12 && offsetof(ssc_level_info, uv_count) == 16,
               "LEVEL_INFO in src/sscape.mjs");
_Static_assert(sizeof(ssc_export_def) == 20 && offsetof(ssc_export_def, format) == 4 && offsetof(ssc_export_def, level) == 8 &&
                   offsetof(ssc_export_def, morphs) == 12 && offsetof(ssc_export_def, morph_count) == 16,
               "EXPORT_DEF in src/sscape.mjs");
_Static_assert(sizeof(ssc_made_to_measure_def) == 20 && offsetof(ssc_made_to_measure_def, sex) == 4 &&
                   offsetof(ssc_made_to_measure_def, age) == 8,
               "MADE_TO_MEASURE_DEF in src/sscape.mjs");
_Static_assert(sizeof(ssc_batch_desc) == 48 && offsetof(ssc_batch_desc, body_count) == 4 && offsetof(ssc_batch_desc, shapes) == 8 &&
                   offsetof(ssc_batch_desc, shape_count) == 12 && offsetof(ssc_batch_desc, poses) == 20 &&
                   offsetof(ssc_batch_desc, translations) == 24 && offsetof(ssc_batch_desc, vertices) == 28 &&
                   offsetof(ssc_batch_desc, vertices_capacity) == 32 && offsetof(ssc_batch_desc, normals) == 36 &&
                   offsetof(ssc_batch_desc, normals_capacity) == 40 && offsetof(ssc_batch_desc, level) == 44,
               "BATCH_DESC in src/sscape.mjs");
_Static_assert(sizeof(ssc_fitter_def) == 48 && offsetof(ssc_fitter_def, shape_count) == 4 && offsetof(ssc_fitter_def, max_iterations) == 12 &&
                   offsetof(ssc_fitter_def, seed) == 36 && offsetof(ssc_fitter_def, joint_limits) == 40 &&
                   offsetof(ssc_fitter_def, fit_segments) == 44,
               "FITTER_DEF in src/sscape.mjs");
_Static_assert(sizeof(ssc_fit_report) == 60 && offsetof(ssc_fit_report, iterations) == 4 && offsetof(ssc_fit_report, converged) == 8 &&
                   offsetof(ssc_fit_report, landmark_rms) == 24 && offsetof(ssc_fit_report, point_mean) == 28 &&
                   offsetof(ssc_fit_report, seconds) == 36 && offsetof(ssc_fit_report, restarts) == 40 &&
                   offsetof(ssc_fit_report, unexplained_fraction) == 44 && offsetof(ssc_fit_report, implausible) == 48 &&
                   offsetof(ssc_fit_report, problem) == 52,
               "FIT_REPORT in src/sscape.mjs");

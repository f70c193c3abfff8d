/* A program outside the project that uses an installed libsscape_offline: lists a folder's scans
 * (the offline tools' API) and loads the default model (the runtime API the same library holds).
 * usage: offline_consumer FOLDER */
#include <sscape/sscape_offline.h>

#include <stdio.h>

int main(int argc, char** argv) {
    ssc_scan_list* list = NULL;
    ssc_model* model = NULL;
    uint32_t i;
    if (argc != 2) {
        fprintf(stderr, "usage: %s FOLDER\n", argv[0]);
        return 2;
    }
    if (ssc_scan_list_create(argv[1], &list) != SSC_OK) {
        fprintf(stderr, "%s\n", ssc_last_error());
        return 1;
    }
    for (i = 0; i < ssc_scan_list_count(list); ++i) {
        const char *name = NULL, *path = NULL, *landmarks = NULL;
        if (ssc_scan_list_get(list, i, &name, &path, &landmarks) != SSC_OK) return 1;
        printf("scan %s%s\n", name, landmarks && *landmarks ? " with landmarks" : "");
    }
    ssc_scan_list_destroy(list);
    if (ssc_model_load_default(NULL, &model) != SSC_OK) return 1;
    printf("default model: %u vertices\n", ssc_model_vertex_count(model));
    ssc_model_release(model);
    return 0;
}

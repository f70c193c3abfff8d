/* The public header must compile as strict C99 (built with -std=c99 -pedantic -Werror). */
#include <sscape/sscape.h>

int sscape_header_compiles_as_c99(void) {
    ssc_context_def def;
    ssc_context_def_init(&def, sizeof def);
    return (int)def.worker_count + (int)SSC_VERSION_NUMBER + (int)sizeof(ssc_batch_desc);
}

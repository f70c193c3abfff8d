// The public header must compile as C++ (built with -pedantic -Werror).
#include <sscape/sscape.h>

int sscape_header_compiles_as_cpp() {
    ssc_body_def def;
    ssc_body_def_init(&def, sizeof def);
    return static_cast<int>(def.struct_size) + static_cast<int>(SSC_OK);
}

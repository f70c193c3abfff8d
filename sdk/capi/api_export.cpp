// Body files (export/body_export.hpp) through the C API.
#include "export/body_export.hpp"
#include "guard.hpp"
#include "handles.hpp"

using namespace ssc;
using namespace ssc::capi;

ssc_status ssc_body_write_file(ssc_body* body, const char* path, ssc_file_format format) {
    return guarded(__func__, [&] {
        need(body, "body");
        need(path, "path");
        const int32_t f = enum_value(format);
        SSC_REQUIRE_ARG_S(f >= SSC_FILE_FORMAT_BY_EXTENSION && f <= SSC_FILE_GLB,
                          "format " << f << " is not an ssc_file_format (0 by extension, 1 OBJ, 2 PLY, 3 GLB)");
        const exporters::BodyFormat which = f == SSC_FILE_OBJ   ? exporters::BodyFormat::Obj
                                            : f == SSC_FILE_PLY ? exporters::BodyFormat::Ply
                                            : f == SSC_FILE_GLB ? exporters::BodyFormat::Glb
                                                                : exporters::format_of(path);
        exporters::write_body(body->body, path, which);
    });
}

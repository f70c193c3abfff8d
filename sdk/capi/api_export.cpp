// Body files (export/body_export.hpp) through the C API.
#include "export/body_export.hpp"
#include "guard.hpp"
#include "handles.hpp"

#include <cstring>

using namespace ssc;
using namespace ssc::capi;

namespace {

exporters::BodyFormat body_format(ssc_file_format format, const char* path) {
    const int32_t f = enum_value(format);
    SSC_REQUIRE_ARG_S(f >= SSC_FILE_FORMAT_BY_EXTENSION && f <= SSC_FILE_GLB,
                      "format " << f << " is not an ssc_file_format (0 by extension, 1 OBJ, 2 PLY, 3 GLB)");
    return f == SSC_FILE_OBJ ? exporters::BodyFormat::Obj : f == SSC_FILE_PLY ? exporters::BodyFormat::Ply
                             : f == SSC_FILE_GLB ? exporters::BodyFormat::Glb : exporters::format_of(path);
}

static_assert(SSC_LEVEL_ALL == exporters::kAllLevels, "the C API's every-level value is the exporter's");

// The guarded body of every body-file function: write_body checks the level and the options.
void write_body_file(ssc_body* body, const char* path, ssc_file_format format, const exporters::ExportOptions& options) {
    need(body, "body");
    need(path, "path");
    exporters::write_body(body->body, path, body_format(format, path), options);
}

}  // namespace

extern "C" {

ssc_status ssc_body_write_file(ssc_body* body, const char* path, ssc_file_format format) {
    return guarded(__func__, [&] { write_body_file(body, path, format, {}); });
}

ssc_status ssc_body_write_level_file(ssc_body* body, uint32_t level, const char* path, ssc_file_format format) {
    return guarded(__func__, [&] {
        exporters::ExportOptions options;
        options.level = level;
        write_body_file(body, path, format, options);
    });
}

void ssc_export_def_init(ssc_export_def* def, size_t size) {
    if (!def || size < sizeof(uint32_t)) return;
    ssc_export_def d{};
    d.struct_size = static_cast<uint32_t>(size < sizeof d ? size : sizeof d);
    d.format = SSC_FILE_FORMAT_BY_EXTENSION;
    d.level = 0;
    d.morphs = SSC_MORPHS_NONE;
    d.morph_count = 0;
    std::memcpy(def, &d, d.struct_size);
}

ssc_status ssc_body_export(ssc_body* body, const char* path, const ssc_export_def* def) {
    return guarded(__func__, [&] {
        need(body, "body");
        const ssc_export_def d = read_def(def, ssc_export_def_init, "def");
        const int32_t kind = enum_value(d.morphs);
        SSC_REQUIRE_ARG_S(kind >= SSC_MORPHS_NONE && kind <= SSC_MORPHS_SLIDERS,
                          "def->morphs " << kind << " is not an ssc_morphs (0 none, 1 components, 2 sliders)");
        SSC_REQUIRE_ARG(kind != SSC_MORPHS_NONE || d.morph_count == 0, "def->morph_count without def->morphs");
        exporters::ExportOptions options;
        options.level = d.level;
        if (kind != SSC_MORPHS_NONE)
            options.morphs = exporters::morph_targets(body->body.model(), body->model->attributes,
                                                      kind == SSC_MORPHS_COMPONENTS ? exporters::MorphKind::Components : exporters::MorphKind::Sliders,
                                                      d.morph_count);
        write_body_file(body, path, d.format, options);
    });
}

}  // extern "C"

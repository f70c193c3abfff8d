// Bootstrapping a folder of scans (sscape_offline.h): the settings read once into a
// learning::BootstrapSpec, each round's registrations as file jobs (for callers that run them
// elsewhere), and the rounds themselves (learning/bootstrap.hpp does the work).
#include "capi/cpp_access.hpp"
#include "capi/guard.hpp"
#include "capi/registration_report.hpp"
#include "common/folder_lock.hpp"
#include "learning/bootstrap.hpp"
#include "learning/model_choice.hpp"
#include <sscape/sscape_offline.h>

#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>

using namespace ssc;
using namespace ssc::capi;

struct ssc_bootstrap {
    learning::BootstrapSpec spec;
    std::vector<unsigned char> initial_model;  // the starting model file's bytes
    std::string units, up;                     // as given (the file jobs carry them)
    std::string job_mesh, job_model;           // the last job's strings
    std::unique_ptr<FolderLock> lock;          // the output folder's, from the first call that writes until destroy

    void lock_output() {
        if (!lock) lock = std::make_unique<FolderLock>(spec.out_dir, "bootstrap");
    }
    // A failed call ends the run: the folder is released (and removed if the run wrote nothing
    // into it); a later call takes the lock again.
    template <class F>
    void unlocked_on_failure(F&& work) {
        try {
            work();
        } catch (...) {
            lock.reset();
            throw;
        }
    }
};

namespace {

// The built-in model's file, as compiled in (verified with the others by learning/model_choice.hpp).
std::vector<unsigned char> builtin_model() {
    const FileBytes file = default_model_file();
    return std::vector<unsigned char>(file.data, file.data + file.size);
}

std::optional<std::string> optional_path(const char* path) { return path ? std::optional<std::string>(path) : std::nullopt; }

}  // namespace

extern "C" {

void ssc_bootstrap_def_init(ssc_bootstrap_def* def, size_t size) {
    if (!def || size < sizeof(uint32_t)) return;
    const learning::LearnSpec learn;
    ssc_bootstrap_def d{};
    d.struct_size = static_cast<uint32_t>(size < sizeof d ? size : sizeof d);
    d.components = learn.components;
    d.posture = SSC_POSTURE_SKELETON;
    d.segment_components = learn.segment_components;
    d.segment_band = float(learn.segment_band);
    d.contact_sheet_entries = 12;
    d.fit_segments = registration::RegistrationOptions().segments ? 1u : 0u;
    std::memcpy(def, &d, d.struct_size);
}

ssc_status ssc_bootstrap_create(ssc_context* ctx, const ssc_bootstrap_def* def, ssc_bootstrap** out) {
    static_cast<void>(ctx);  // kept for the ABI: the threads come from def, the built-in model's bytes as compiled in
    return guarded(__func__, [&] {
        need(out, "out");
        need(def, "def");
        const ssc_bootstrap_def d = read_def(def, ssc_bootstrap_def_init, "def");
        need(d.scans_dir, "def->scans_dir");
        need(d.out_dir, "def->out_dir");
        SSC_REQUIRE_ARG_S(d.components >= 1 && d.components <= 1000, "def->components " << d.components << " is not 1..1000");
        SSC_REQUIRE_ARG_S(d.segment_components <= 1000, "def->segment_components " << d.segment_components << " is not 0..1000");
        SSC_REQUIRE_ARG_S(std::isfinite(d.segment_band) && d.segment_band >= 0.005f && d.segment_band <= 0.5f,
                          "def->segment_band " << d.segment_band << " m is not 0.005..0.5");
        SSC_REQUIRE_ARG_S(d.threads <= 256, "def->threads " << d.threads << " is not 0..256");
        SSC_REQUIRE_ARG_S(d.contact_sheet_entries <= 100, "def->contact_sheet_entries " << d.contact_sheet_entries << " is not 0..100");
        const int32_t posture = enum_value(d.posture);
        SSC_REQUIRE_ARG_S(posture == SSC_POSTURE_SKELETON || posture == SSC_POSTURE_NONE || posture == SSC_POSTURE_LAPLACIAN, "def->posture " << posture << " is unknown");

        auto b = std::make_unique<ssc_bootstrap>();
        learning::BootstrapSpec& spec = b->spec;
        spec.scans = scan_files::find_scans(d.scans_dir, &spec.skipped);
        SSC_REQUIRE_ARG_S(spec.scans.size() >= 3, d.scans_dir << " holds " << spec.scans.size() << " scans (.ply or .obj); bootstrapping needs at least 3");
        spec.out_dir = d.out_dir;
        spec.threads = d.threads;
        ssc_registration_def registration;  // the defaults, as a file job's registration has them
        ssc_registration_def_init(&registration, sizeof registration);
        registration.fit_segments = d.fit_segments ? 1u : 0u;
        spec.registration = registration_options(registration);
        b->units = optional_string(d.units);
        b->up = optional_string(d.up);
        spec.reading = scan_files::scan_reading(b->units, b->up);
        spec.learn.components = d.components;
        spec.learn.posture = posture == SSC_POSTURE_SKELETON  ? learning::Posture::Skeleton
                             : posture == SSC_POSTURE_LAPLACIAN ? learning::Posture::Laplacian
                                                                : learning::Posture::None;
        spec.learn.scale = d.scale != 0;
        spec.learn.segment_components = d.segment_components;
        spec.learn.segment_band = d.segment_band;
        if (d.name) spec.learn.name = d.name;
        if (d.license) spec.learn.license = d.license;
        spec.sheet_entries = int(d.contact_sheet_entries);
        if (d.decisions_path) spec.decisions = learning::read_decisions(d.decisions_path);
        if (d.attributes_path) spec.attributes = learning::read_attribute_table(d.attributes_path);
        const std::vector<unsigned char> builtin = builtin_model();
        b->initial_model = learning::starting_model_file(optional_path(d.init_model_path), d.template_only != 0, builtin);
        spec.posture_model = learning::posture_model_file(spec.learn.posture, optional_path(d.posture_model_path), b->initial_model, builtin);
        *out = b.release();
    });
}

void ssc_bootstrap_destroy(ssc_bootstrap* bootstrap) { delete bootstrap; }

uint32_t ssc_bootstrap_scan_count(const ssc_bootstrap* bootstrap) { return bootstrap ? uint32_t(bootstrap->spec.scans.size()) : 0; }

ssc_status ssc_bootstrap_get_scan(const ssc_bootstrap* bootstrap, uint32_t index, const char** name, const char** path, const char** landmarks) {
    return guarded(__func__, [&] {
        need(bootstrap, "bootstrap");
        const auto& scans = bootstrap->spec.scans;
        SSC_REQUIRE_ARG_S(index < scans.size(), "index " << index << " is beyond the " << scans.size() << " scans");
        if (name) *name = scans[index].name.c_str();
        if (path) *path = scans[index].path.c_str();
        if (landmarks) *landmarks = scans[index].landmarks.c_str();
    });
}

ssc_status ssc_bootstrap_prepare(ssc_bootstrap* bootstrap) {
    return guarded(__func__, [&] {
        need(bootstrap, "bootstrap");
        bootstrap->lock_output();
        bootstrap->unlocked_on_failure([&] { learning::prepare_bootstrap(bootstrap->initial_model, bootstrap->spec); });
    });
}

ssc_status ssc_bootstrap_get_job(ssc_bootstrap* bootstrap, uint32_t round, uint32_t index, ssc_scan_file_job* job, const char** model_path) {
    return guarded(__func__, [&] {
        need(bootstrap, "bootstrap");
        need(job, "job");
        SSC_REQUIRE_ARG(job->struct_size >= sizeof(uint32_t) && job->struct_size <= sizeof(ssc_scan_file_job),
                        "job->struct_size must be set (ssc_scan_file_job_init)");
        SSC_REQUIRE_ARG_S(round >= 1 && round <= 100, "round " << round << " is not 1..100");
        const auto& scans = bootstrap->spec.scans;
        SSC_REQUIRE_ARG_S(index < scans.size(), "index " << index << " is beyond the " << scans.size() << " scans");
        const scan_files::ScanFileJob w = learning::round_registration_job(bootstrap->spec, round, scans[index]);
        std::error_code ec;  // the round's folder, for the job to write into
        std::filesystem::create_directories(std::filesystem::path(w.mesh_path).parent_path(), ec);
        if (ec) fail(SSC_ERROR_IO, "cannot make the folder of " + w.mesh_path + ": " + ec.message());
        bootstrap->job_mesh = w.mesh_path;
        bootstrap->job_model = learning::round_model_path(bootstrap->spec.out_dir, round - 1);
        ssc_scan_file_job j;
        ssc_scan_file_job_init(&j, sizeof j);
        j.scan_path = scans[index].path.c_str();
        j.landmarks_path = scans[index].landmarks.empty() ? nullptr : scans[index].landmarks.c_str();
        j.units = bootstrap->units.empty() ? nullptr : bootstrap->units.c_str();
        j.up = bootstrap->up.empty() ? nullptr : bootstrap->up.c_str();
        j.mesh_path = bootstrap->job_mesh.c_str();
        j.write_report = w.write_report ? 1 : 0;
        j.reuse = w.reuse ? 1 : 0;
        const uint32_t size = job->struct_size;
        std::memcpy(job, &j, size);
        job->struct_size = size;
        if (model_path) *model_path = bootstrap->job_model.c_str();
    });
}

ssc_status ssc_bootstrap_run(ssc_bootstrap* bootstrap, uint32_t rounds, ssc_line_fn progress, void* user) {
    return guarded(__func__, [&] {
        need(bootstrap, "bootstrap");
        SSC_REQUIRE_ARG_S(rounds >= 1 && rounds <= 100, "rounds " << rounds << " is not 1..100");
        bootstrap->lock_output();
        learning::BootstrapSpec spec = bootstrap->spec;
        spec.rounds = rounds;
        learning::BootstrapProgress say;
        if (progress) say = [&](const std::string& line) { return progress(user, line.c_str()) == 0; };
        bootstrap->unlocked_on_failure([&] { learning::bootstrap(bootstrap->initial_model, spec, say); });
    });
}

}  // extern "C"

// Scan registrations: a scan (and landmarks) in, the template deformed onto it out (sdk/registration
// does the work).
#include "fitting/fitted_segment_shape.hpp"
#include "guard.hpp"
#include "handles.hpp"
#include "registration_report.hpp"

#include <cstring>

using namespace ssc;
using namespace ssc::capi;

namespace ssc::capi {

void copy_quality(const registration::DistanceSummary& d, const std::array<double, 4>& below, ssc_registration_quality& q) {
    q.scan_mean = float(d.mean), q.scan_median = float(d.median), q.scan_p95 = float(d.p95);
    for (int k = 0; k < 4; ++k) q.within[k] = float(below[std::size_t(k)]);
}

void write_report(uint32_t rounds, uint32_t solves, std::size_t valid, double seconds, double fit_seconds,
                  const registration::RegistrationQuality& quality, std::size_t scan_points, std::size_t landmarks,
                  ssc_registration_report* report) {
    ssc_registration_report out{};
    out.struct_size = sizeof out;
    out.rounds = rounds;
    out.solves = solves;
    out.valid_vertices = uint32_t(valid);
    out.seconds = float(seconds);
    out.fit_seconds = float(fit_seconds);
    copy_quality(quality.scan_to_registration, quality.below, out.quality);
    out.scan_points = uint32_t(scan_points);
    out.landmarks = uint32_t(landmarks);
    const uint32_t n = report->struct_size < sizeof out ? report->struct_size : uint32_t(sizeof out);
    std::memcpy(report, &out, n);
    report->struct_size = n;
}

registration::RegistrationOptions registration_options(const ssc_registration_def& d) {
    registration::RegistrationOptions o;
    const int32_t start = enum_value(d.start), schedule = enum_value(d.schedule);
    SSC_REQUIRE_ARG_S(start >= SSC_REGISTRATION_START_MODEL && start <= SSC_REGISTRATION_START_RBF, "def->start " << start << " is unknown");
    SSC_REQUIRE_ARG_S(schedule == SSC_REGISTRATION_RELAXED || schedule == SSC_REGISTRATION_CONSTANT,
                      "def->schedule " << schedule << " is unknown");
    o.initialisation = start == SSC_REGISTRATION_START_MODEL   ? registration::Initialisation::Model
                       : start == SSC_REGISTRATION_START_RIGID ? registration::Initialisation::Rigid
                                                               : registration::Initialisation::Rbf;
    o.schedule = schedule == SSC_REGISTRATION_RELAXED ? registration::Schedule::Relaxed : registration::Schedule::Constant;
    o.stiffness = d.stiffness;
    o.landmarks = d.landmark_weight;
    o.gamma = d.gamma;
    o.max_iterations = d.max_iterations;  // the registrar checks the values
    const int32_t kernel = enum_value(d.rbf_kernel);
    SSC_REQUIRE_ARG_S(kernel >= SSC_RBF_THIN_PLATE && kernel <= SSC_RBF_GAUSSIAN, "def->rbf_kernel " << kernel << " is unknown");
    o.rbf_kernel = kernel == SSC_RBF_THIN_PLATE     ? registration::RbfKernel::ThinPlate
                   : kernel == SSC_RBF_MULTIQUADRIC ? registration::RbfKernel::Multiquadric
                                                    : registration::RbfKernel::Gaussian;
    o.rbf_scale = d.rbf_scale;
    o.segments = d.fit_segments != 0;
    return o;
}

}  // namespace ssc::capi

extern "C" {

void ssc_registration_def_init(ssc_registration_def* def, size_t size) {
    if (!def || size < sizeof(uint32_t)) return;
    const registration::RegistrationOptions o;
    ssc_registration_def d{};
    d.struct_size = static_cast<uint32_t>(size < sizeof d ? size : sizeof d);
    d.start = SSC_REGISTRATION_START_MODEL;
    d.schedule = SSC_REGISTRATION_RELAXED;
    d.stiffness = float(o.stiffness);
    d.landmark_weight = float(o.landmarks);
    d.gamma = float(o.gamma);
    d.max_iterations = o.max_iterations;
    d.rbf_kernel = SSC_RBF_THIN_PLATE;
    d.rbf_scale = float(o.rbf_scale);
    d.fit_segments = o.segments ? 1u : 0u;
    std::memcpy(def, &d, d.struct_size);
}

ssc_status ssc_registration_create(ssc_model* model, const ssc_registration_def* def, ssc_registration** out) {
    return guarded(__func__, [&] {
        need(model, "model");
        need(out, "out");
        const ssc_registration_def d = read_def(def, ssc_registration_def_init, "def");
        const registration::RegistrationOptions o = registration_options(d);
        ssc_registration* r = make<ssc_registration>(allocator_of(model), model, o);
        ssc_model_retain(model);
        *out = r;
    });
}

void ssc_registration_destroy(ssc_registration* registration) {
    if (!registration) return;
    ssc_model* model = registration->model;
    unmake(registration);
    ssc_model_release(model);
}

ssc_status ssc_registration_set_scan(ssc_registration* registration, const float* points, const float* normals, uint32_t count,
                                     size_t stride, const uint32_t* triangles, uint32_t triangle_count) {
    return guarded(__func__, [&] {
        need(registration, "registration");
        if (triangle_count) need(triangles, "triangles");
        std::vector<uint32_t> t(triangles, triangles + 3 * std::size_t(triangle_count));
        registration->registrar.set_scan(copy_cloud(points, normals, nullptr, count, stride), std::move(t));  // checks every value
    });
}

ssc_status ssc_registration_set_landmarks_by_name(ssc_registration* registration, const char* const* names, const float* positions,
                                                  uint32_t count) {
    return guarded(__func__, [&] {
        need(registration, "registration");
        if (count) {
            need(names, "names");
            need(positions, "positions");
        }
        std::vector<fitting::LandmarkTarget> marks(count);
        for (uint32_t i = 0; i < count; ++i) {
            SSC_REQUIRE_ARG_S(names[i] != nullptr, "names[" << i << "] is NULL");
            const int64_t l = registration->registrar.model().find_landmark(names[i]);
            if (l < 0) fail(SSC_ERROR_NOT_FOUND, std::string("names[") + std::to_string(i) + "]: no landmark named \"" + names[i] + "\"");
            marks[i].landmark = uint32_t(l);
            marks[i].position = Eigen::Vector3d(positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]);
        }
        registration->registrar.set_landmarks(std::move(marks));  // checks the positions
    });
}

ssc_status ssc_registration_run(ssc_registration* registration, ssc_stage_progress_fn progress, void* user,
                                ssc_registration_report* report) {
    return guarded(__func__, [&] {
        need(registration, "registration");
        if (report)
            SSC_REQUIRE_ARG(report->struct_size >= sizeof(uint32_t), "report->struct_size must be set to sizeof(ssc_registration_report)");
        registration::RegistrationProgress cb;
        if (progress) cb = [&](const char* stage, uint32_t done, uint32_t total) { return progress(user, stage, done, total) == 0; };
        const registration::Registration& r = registration->registrar.run(cb, &registration->model->context->pool);
        if (r.report.scan_points_given > r.report.scan_points)
            registration->model->context->message(SSC_LOG_WARNING, "registration: the scan's " + std::to_string(r.report.scan_points_given) + " points; registered from " +
                                                                       std::to_string(r.report.scan_points) + " of them, evenly spread (the registration's memory bound)");
        if (report) write_report(r.report.rounds, r.report.solves, r.report.valid, r.report.seconds, r.report.fit_seconds, r.report.quality,
                                 r.report.scan_points, r.report.landmarks, report);
    });
}

ssc_status ssc_registration_get_vertices(const ssc_registration* registration, float* out, uint32_t capacity, size_t stride) {
    return guarded(__func__, [&] {
        need(registration, "registration");
        const std::vector<Eigen::Vector3d>& x = registration->registrar.result().vertices;
        stride = check_output(out, capacity, x.size(), stride, 12);
        auto* base = reinterpret_cast<unsigned char*>(out);
        for (std::size_t v = 0; v < x.size(); ++v) {
            float* o = reinterpret_cast<float*>(base + v * stride);
            o[0] = float(x[v].x()), o[1] = float(x[v].y()), o[2] = float(x[v].z());
        }
    });
}

ssc_status ssc_registration_get_valid(const ssc_registration* registration, uint8_t* out, uint32_t capacity) {
    return guarded(__func__, [&] {
        need(registration, "registration");
        const std::vector<uint8_t>& valid = registration->registrar.result().valid;
        check_output(out, capacity, valid.size(), 0, 1);
        std::memcpy(out, valid.data(), valid.size());
    });
}

ssc_status ssc_registration_get_vertex_distances(const ssc_registration* registration, float* out, uint32_t capacity) {
    return guarded(__func__, [&] {
        need(registration, "registration");
        const std::vector<double>& d = registration->registrar.result().report.quality.vertex_distance;
        check_output(out, capacity, d.size(), 0, 4);
        for (std::size_t v = 0; v < d.size(); ++v) out[v] = float(d[v]);
    });
}

ssc_status ssc_registration_get_fit(const ssc_registration* registration, float* shape, uint32_t shape_capacity, float* rotations,
                                    uint32_t joint_capacity, float* translation, float* scale) {
    return guarded(__func__, [&] {
        need(registration, "registration");
        const registration::Registration& r = registration->registrar.result();
        SSC_REQUIRE_ARG(!r.fit.frames.empty(), "registration: no model fit (the run started from landmarks)");
        const Model& m = registration->registrar.model();
        const fitting::FitState& s = r.fit.frames[0];
        const uint32_t K = m.component_count(), J = m.joint_count();
        if (shape) check_output(shape, shape_capacity, K, 0, 4);
        if (rotations) check_output(rotations, joint_capacity, J, 0, 16);
        if (shape)
            for (uint32_t k = 0; k < K; ++k) shape[k] = k < r.fit.shape.size() ? float(r.fit.shape[k]) : 0.f;
        if (rotations)
            for (uint32_t j = 0; j < J; ++j) {
                const Eigen::Quaterniond q = s.pose[j].normalized();
                rotations[4 * j] = float(q.x()), rotations[4 * j + 1] = float(q.y());
                rotations[4 * j + 2] = float(q.z()), rotations[4 * j + 3] = float(q.w());
            }
        if (translation)
            for (int a = 0; a < 3; ++a) translation[a] = float(s.translation[a]);
        if (scale) *scale = float(s.scale);
    });
}

ssc_status ssc_registration_get_fit_segment_shape(const ssc_registration* registration, uint32_t segment, float* out, uint32_t capacity) {
    return guarded(__func__, [&] {
        need(registration, "registration");
        need(out, "out");
        const registration::Registration& r = registration->registrar.result();
        SSC_REQUIRE_ARG(!r.fit.frames.empty(), "registration: no model fit (the run started from landmarks)");
        const std::vector<float> coefficients = fitting::fitted_segment_shape(registration->registrar.model(), r.fit.frames[0].shape, segment);
        check_output(out, capacity, uint32_t(coefficients.size()), 0, 4);
        std::memcpy(out, coefficients.data(), sizeof(float) * coefficients.size());
    });
}

uint32_t ssc_registration_region_count(const ssc_registration* registration) {
    return registration && registration->registrar.done() ? uint32_t(registration->registrar.result().report.quality.regions.size()) : 0;
}

ssc_status ssc_registration_get_region(const ssc_registration* registration, uint32_t index, const char** name,
                                       ssc_registration_quality* quality) {
    return guarded(__func__, [&] {
        need(registration, "registration");
        const auto& regions = registration->registrar.result().report.quality.regions;
        SSC_REQUIRE_ARG_S(index < regions.size(), "index " << index << " is beyond the " << regions.size() << " regions");
        if (name) *name = regions[index].region.c_str();
        if (quality) copy_quality(regions[index].scan_to_registration, regions[index].below, *quality);
    });
}

}  // extern "C"

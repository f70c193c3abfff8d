// Fitters: observations in, shape and per-frame pose out (sdk/fitting does the work).
#include "fitting/fitted_segment_shape.hpp"
#include "fitting/judgement.hpp"
#include "guard.hpp"
#include "handles.hpp"

#include <cmath>
#include <cstring>

using namespace ssc;
using namespace ssc::capi;

// A frame report's problem and region go out as the library's own values.
static_assert(uint32_t(fitting::FitProblemKind::JointPastRange) == SSC_FIT_PROBLEM_JOINT_PAST_RANGE &&
                  uint32_t(fitting::FitProblemKind::ScanUnexplained) == SSC_FIT_PROBLEM_SCAN_UNEXPLAINED &&
                  uint32_t(fitting::FitProblemKind::LimbOffScan) == SSC_FIT_PROBLEM_LIMB_OFF_SCAN &&
                  uint32_t(fitting::FitProblemKind::LimbInside) == SSC_FIT_PROBLEM_LIMB_INSIDE &&
                  uint32_t(fitting::FitProblemKind::ArmOffPoints) == SSC_FIT_PROBLEM_ARM_OFF_POINTS &&
                  uint32_t(fitting::FitProblemKind::HandOffPoints) == SSC_FIT_PROBLEM_HAND_OFF_POINTS,
              "ssc_fit_problem is fitting::FitProblemKind");
static_assert(int32_t(fitting::BodyRegion::Head) == SSC_BODY_REGION_HEAD && int32_t(fitting::BodyRegion::RightLeg) == SSC_BODY_REGION_RIGHT_LEG,
              "ssc_body_region is fitting::BodyRegion");

namespace {

void add_landmarks(ssc_fitter* f, uint32_t frame, const std::vector<uint32_t>& indices, const float* positions, const float* weights) {
    need(positions, "positions");
    std::vector<fitting::LandmarkTarget> add(indices.size());
    for (std::size_t i = 0; i < indices.size(); ++i) {
        add[i].landmark = indices[i];
        add[i].position = Eigen::Vector3d(positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]);
        add[i].weight = weights ? weights[i] : 1.0;
    }
    f->fitter.add_landmarks(frame, add);
}

// The C view of a frame's report; its strings point into `fr`.
ssc_fit_frame_report frame_report(const fitting::FrameReport& fr) {
    ssc_fit_frame_report out{};
    out.struct_size = sizeof out;
    out.failed = fr.failed;
    out.left_out = fr.left_out;
    out.problem = uint32_t(fr.problem);
    out.joint = fr.joint_excess > 0 ? fr.joint : -1;
    out.region = fr.region;
    out.unexplained_fraction = float(fr.unexplained);
    out.joint_excess_degrees = float(fr.joint_excess * 180.0 / 3.14159265358979323846);
    out.problem_text = fr.problem_text.c_str();
    out.unscanned = fr.unscanned.c_str();
    return out;
}

}  // namespace

namespace ssc::capi {

fitting::PointCloud copy_cloud(const float* points, const float* normals, const float* confidence, uint32_t count, size_t stride) {
    need(points, "points");
    if (stride == 0) stride = 12;
    SSC_REQUIRE_ARG_S(stride >= 12 && stride % 4 == 0, "stride " << stride << " must be 0 or a multiple of 4 that is >= 12");
    auto at = [&](const float* base, std::size_t i) {
        const float* p = reinterpret_cast<const float*>(reinterpret_cast<const unsigned char*>(base) + i * stride);
        return Eigen::Vector3d(p[0], p[1], p[2]);
    };
    fitting::PointCloud c;
    c.points.reserve(count);
    for (uint32_t i = 0; i < count; ++i) {
        c.points.push_back(at(points, i));
        if (normals) c.normals.push_back(at(normals, i));
        if (confidence) c.confidence.push_back(confidence[i]);
    }
    return c;
}

}  // namespace ssc::capi

extern "C" {

void ssc_fitter_def_init(ssc_fitter_def* def, size_t size) {
    if (!def || size < sizeof(uint32_t)) return;
    const fitting::FitOptions o;
    ssc_fitter_def d{};
    d.struct_size = static_cast<uint32_t>(size < sizeof d ? size : sizeof d);
    d.shape_count = 0;
    d.fit_scale = o.fit_scale;
    d.max_iterations = o.max_iterations;
    d.landmark_sigma = float(o.landmark_sigma);
    d.point_sigma = float(o.point_sigma);
    d.shape_prior = float(o.shape_prior);
    d.pose_prior = float(o.pose_prior);
    d.max_points = o.max_points;
    d.seed = o.seed;
    d.joint_limits = o.joint_limits;
    d.fit_segments = o.segments;
    std::memcpy(def, &d, d.struct_size);
}

ssc_status ssc_fitter_create(ssc_model* model, const ssc_fitter_def* def, ssc_fitter** out) {
    return guarded(__func__, [&] {
        need(model, "model");
        need(out, "out");
        const ssc_fitter_def d = read_def(def, ssc_fitter_def_init, "def");
        fitting::FitOptions o;
        o.components = d.shape_count ? d.shape_count : model->model.component_count();
        o.fit_scale = d.fit_scale != 0;
        o.max_iterations = d.max_iterations;
        o.landmark_sigma = d.landmark_sigma;
        o.point_sigma = d.point_sigma;
        o.shape_prior = d.shape_prior;
        o.pose_prior = d.pose_prior;
        o.max_points = d.max_points;
        o.seed = d.seed;
        o.joint_limits = d.joint_limits != 0;  // the fitter checks the values
        o.segments = d.fit_segments != 0;
        ssc_fitter* f = make<ssc_fitter>(allocator_of(model), model, o);
        ssc_model_retain(model);
        *out = f;
    });
}

void ssc_fitter_destroy(ssc_fitter* fitter) {
    if (!fitter) return;
    ssc_model* model = fitter->model;
    unmake(fitter);
    ssc_model_release(model);
}

ssc_status ssc_fitter_clear(ssc_fitter* fitter) {
    return guarded(__func__, [&] {
        need(fitter, "fitter");
        fitter->fitter.clear();
    });
}

uint32_t ssc_fitter_frame_count(const ssc_fitter* fitter) { return fitter ? fitter->fitter.frame_count() : 0; }

ssc_status ssc_fitter_add_landmarks(ssc_fitter* fitter, uint32_t frame, const uint32_t* indices, const float* positions,
                                    const float* weights, uint32_t count) {
    return guarded(__func__, [&] {
        need(fitter, "fitter");
        need(indices, "indices");
        add_landmarks(fitter, frame, std::vector<uint32_t>(indices, indices + count), positions, weights);
    });
}

ssc_status ssc_fitter_add_landmarks_by_name(ssc_fitter* fitter, uint32_t frame, const char* const* names,
                                            const float* positions, const float* weights, uint32_t count) {
    return guarded(__func__, [&] {
        need(fitter, "fitter");
        need(names, "names");
        std::vector<uint32_t> indices(count);
        for (uint32_t i = 0; i < count; ++i) {
            SSC_REQUIRE_ARG_S(names[i] != nullptr, "names[" << i << "] is NULL");
            const int64_t l = fitter->fitter.model().find_landmark(names[i]);
            if (l < 0) fail(SSC_ERROR_NOT_FOUND, std::string("names[") + std::to_string(i) + "]: no landmark named \"" + names[i] + "\"");
            indices[i] = uint32_t(l);
        }
        add_landmarks(fitter, frame, indices, positions, weights);
    });
}

ssc_status ssc_fitter_add_points(ssc_fitter* fitter, uint32_t frame, const float* points, const float* normals,
                                 const float* confidence, uint32_t count, size_t stride) {
    return guarded(__func__, [&] {
        need(fitter, "fitter");
        fitter->fitter.add_cloud(frame, copy_cloud(points, normals, confidence, count, stride));  // checks every value
    });
}

void ssc_depth_image_def_init(ssc_depth_image_def* def, size_t size) {
    if (!def || size < sizeof(uint32_t)) return;
    ssc_depth_image_def d{};
    d.struct_size = static_cast<uint32_t>(size < sizeof d ? size : sizeof d);
    d.format = SSC_DEPTH_U16_MM;
    std::memcpy(def, &d, d.struct_size);
}

ssc_status ssc_fitter_add_depth_image(ssc_fitter* fitter, uint32_t frame, const ssc_depth_image_def* image,
                                      uint32_t* points_added) {
    return guarded(__func__, [&] {
        need(fitter, "fitter");
        need(image, "image");
        const ssc_depth_image_def d = read_def(image, ssc_depth_image_def_init, "image");
        need(d.samples, "image->samples");
        const int32_t format = enum_value(d.format);
        SSC_REQUIRE_ARG_S(format == SSC_DEPTH_U16_MM || format == SSC_DEPTH_F32_M, "image->format " << format << " is unknown");
        fitting::DepthView view;
        view.width = d.width;
        view.height = d.height;
        view.mask = d.mask;
        view.camera.fx = d.fx, view.camera.fy = d.fy, view.camera.cx = d.cx, view.camera.cy = d.cy;
        view.min_depth = d.min_depth, view.max_depth = d.max_depth;
        if (d.camera_to_world) {
            const float* m = d.camera_to_world;  // column-major: element (row r, column c) at m[4c + r]
            for (int r = 0; r < 3; ++r) {
                for (int c = 0; c < 3; ++c) view.camera.rotation(r, c) = m[4 * c + r];
                view.camera.position[r] = m[12 + r];
            }
            SSC_REQUIRE_ARG(m[3] == 0 && m[7] == 0 && m[11] == 0 && m[15] == 1,
                            "image->camera_to_world: the last row must be 0 0 0 1 (a rigid transform)");
        }
        const std::vector<float> depth = fitting::depth_in_metres(
            d.samples, d.width, d.height, d.row_stride, format == SSC_DEPTH_U16_MM ? fitting::DepthFormat::U16Millimetres : fitting::DepthFormat::F32Metres);
        view.depth = depth.data();
        const uint32_t n = fitter->fitter.add_depth_image(frame, view);
        if (points_added) *points_added = n;
    });
}

ssc_status ssc_fitter_solve(ssc_fitter* fitter, ssc_progress_fn progress, void* user, ssc_fit_report* report) {
    return guarded(__func__, [&] {
        need(fitter, "fitter");
        if (report) SSC_REQUIRE_ARG(report->struct_size >= sizeof(uint32_t), "report->struct_size must be set to sizeof(ssc_fit_report)");
        fitting::FitProgress cb;
        if (progress) cb = [&](uint32_t it, double cost) { return progress(user, it, float(cost)) == 0; };
        fitting::FrameDone frame_done;
        if (fitter->frame_callback)
            frame_done = [&](uint32_t frame, const fitting::FrameReport& fr) {
                const ssc_fit_frame_report out = frame_report(fr);
                return fitter->frame_callback(fitter->frame_user, frame, &out) == 0;
            };
        const fitting::FitReport& r = fitter->fitter.solve(cb, &fitter->model->context->pool, frame_done);
        if (report) {
            ssc_fit_report out{};
            out.struct_size = sizeof out;
            out.iterations = r.iterations;
            out.converged = r.converged;
            out.initial_cost = float(r.initial_cost);
            out.final_cost = float(r.final_cost);
            out.landmark_rms = float(r.landmark_rms);
            out.point_mean = float(r.point_mean);
            out.inlier_fraction = float(r.inlier_fraction);
            out.seconds = float(r.seconds);
            out.restarts = r.restarts;
            out.unexplained_fraction = float(r.unexplained);
            out.implausible = r.implausible;
            out.problem = uint32_t(r.problem);
            out.failed_frames = r.failed_frames;
            const uint32_t n = report->struct_size < sizeof out ? report->struct_size : uint32_t(sizeof out);
            std::memcpy(report, &out, n);
            report->struct_size = n;
        }
        if (r.cancelled) fail(SSC_ERROR_CANCELLED, "cancelled by the progress callback");
    });
}

ssc_status ssc_fitter_get_frame_report(const ssc_fitter* fitter, uint32_t frame, ssc_fit_frame_report* out) {
    return guarded(__func__, [&] {
        need(fitter, "fitter");
        need(out, "out");
        SSC_REQUIRE_ARG(out->struct_size >= sizeof(uint32_t), "out->struct_size must be set to sizeof(ssc_fit_frame_report)");
        fitter->fitter.frame_state(frame);  // checks the solve and the frame
        const ssc_fit_frame_report r = frame_report(fitter->fitter.solution().report.frames.at(frame));
        const uint32_t n = out->struct_size < sizeof r ? out->struct_size : uint32_t(sizeof r);
        std::memcpy(out, &r, n);
        out->struct_size = n;
    });
}

ssc_status ssc_fitter_set_frame_callback(ssc_fitter* fitter, ssc_frame_fn callback, void* user) {
    return guarded(__func__, [&] {
        need(fitter, "fitter");
        fitter->frame_callback = callback;
        fitter->frame_user = callback ? user : nullptr;
    });
}

ssc_status ssc_fitter_get_shape(const ssc_fitter* fitter, float* out, uint32_t capacity) {
    return guarded(__func__, [&] {
        need(fitter, "fitter");
        const std::vector<double>& shape = fitter->fitter.solution().shape;
        const uint32_t K = fitter->fitter.model().component_count();
        check_output(out, capacity, K, 0, 4);
        for (uint32_t k = 0; k < K; ++k) out[k] = k < shape.size() ? float(shape[k]) : 0.f;
    });
}

ssc_status ssc_fitter_get_segment_shape(const ssc_fitter* fitter, uint32_t segment, float* out, uint32_t capacity) {
    return guarded(__func__, [&] {
        need(fitter, "fitter");
        need(out, "out");
        const std::vector<float> coefficients = fitting::fitted_segment_shape(fitter->fitter.model(), fitter->fitter.solution().shape, segment);
        check_output(out, capacity, uint32_t(coefficients.size()), 0, 4);
        std::memcpy(out, coefficients.data(), sizeof(float) * coefficients.size());
    });
}

ssc_status ssc_fitter_get_pose(const ssc_fitter* fitter, uint32_t frame, float* rotations, uint32_t joint_capacity,
                               float* translation, float* scale) {
    return guarded(__func__, [&] {
        need(fitter, "fitter");
        const fitting::FitState& s = fitter->fitter.frame_state(frame);
        const uint32_t J = fitter->fitter.model().joint_count();
        if (rotations) check_output(rotations, joint_capacity, J, 0, 16);
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

ssc_status ssc_fitter_get_vertices(const ssc_fitter* fitter, uint32_t frame, float* out, uint32_t capacity, size_t stride) {
    return guarded(__func__, [&] {
        need(fitter, "fitter");
        fitter->fitter.frame_state(frame);  // solved, in range: before the output is checked
        const uint32_t V = fitter->fitter.model().vertex_count();
        stride = check_output(out, capacity, V, stride, 12);
        const std::vector<Eigen::Vector3d> posed = fitter->fitter.vertices(frame);
        auto* base = reinterpret_cast<unsigned char*>(out);
        for (uint32_t v = 0; v < V; ++v) {
            const Eigen::Vector3d& p = posed[v];
            float* o = reinterpret_cast<float*>(base + std::size_t(v) * stride);
            o[0] = float(p.x()), o[1] = float(p.y()), o[2] = float(p.z());
        }
    });
}

ssc_status ssc_fitter_get_point_residuals(const ssc_fitter* fitter, uint32_t frame, float* out, uint32_t capacity) {
    return guarded(__func__, [&] {
        need(fitter, "fitter");
        const std::vector<float>& r = fitter->fitter.point_residuals(frame);
        if (r.empty()) return;
        check_output(out, capacity, r.size(), 0, 4);
        std::memcpy(out, r.data(), 4 * r.size());
    });
}

uint32_t ssc_fitter_point_count(const ssc_fitter* fitter, uint32_t frame) { return fitter ? fitter->fitter.point_count(frame) : 0; }

}  // extern "C"

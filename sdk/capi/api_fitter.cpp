// Fitters: observations in, shape and per-frame pose out (sdk/fitting does the work).
#include "guard.hpp"
#include "handles.hpp"
#include "fitting/depth_image.hpp"
#include "fitting/nearest.hpp"
#include "fitting/posed_surface.hpp"

#include <cmath>
#include <cstring>

using namespace ssc;
using namespace ssc::capi;

namespace {

fitting::Frame& frame_for_adding(ssc_fitter* f, uint32_t frame) {
    SSC_REQUIRE_ARG_S(frame <= f->frames.size(), "frame " << frame << " is beyond the next new frame (" << f->frames.size() << ")");
    if (frame == f->frames.size()) f->frames.emplace_back();
    return f->frames[frame];
}

void require_solved(const ssc_fitter* f, uint32_t frame) {
    SSC_REQUIRE_ARG(f->solved, "no successful ssc_fitter_solve yet");
    SSC_REQUIRE_ARG_S(frame < f->solution.frames.size(), "frame " << frame << " out of range (" << f->solution.frames.size() << " frames)");
}

void add_landmarks(ssc_fitter* f, uint32_t frame, const std::vector<uint32_t>& indices, const float* positions, const float* weights) {
    need(positions, "positions");
    const uint32_t L = uint32_t(f->model->model.data().landmarks.size());
    std::vector<fitting::LandmarkTarget> add;
    for (std::size_t i = 0; i < indices.size(); ++i) {
        SSC_REQUIRE_ARG_S(indices[i] < L, "indices[" << i << "] is " << indices[i] << "; the model has " << L << " landmarks");
        fitting::LandmarkTarget t;
        t.landmark = indices[i];
        t.position = Eigen::Vector3d(positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]);
        SSC_REQUIRE_ARG_S(fitting::measured_point(t.position),
                          "positions of landmark " << i << " are not finite or beyond " << fitting::kMaxCoordinate);
        t.weight = weights ? weights[i] : 1.0;
        SSC_REQUIRE_ARG_S(std::isfinite(t.weight) && t.weight > 0, "weights[" << i << "] must be positive");
        add.push_back(t);
    }
    auto& fr = frame_for_adding(f, frame);
    fr.landmarks.insert(fr.landmarks.end(), add.begin(), add.end());
    f->solved = false;
}

}  // namespace

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
    std::memcpy(def, &d, d.struct_size);
}

ssc_status ssc_fitter_create(ssc_model* model, const ssc_fitter_def* def, ssc_fitter** out) {
    return guarded(__func__, [&] {
        need(model, "model");
        need(out, "out");
        const ssc_fitter_def d = read_def(def, ssc_fitter_def_init, "def");
        fitting::FitOptions o;
        o.components = d.shape_count ? d.shape_count : model->model.component_count();
        SSC_REQUIRE_ARG_S(o.components <= model->model.component_count(),
                          "def->shape_count is " << d.shape_count << "; the model has " << model->model.component_count());
        o.fit_scale = d.fit_scale != 0;
        SSC_REQUIRE_ARG(d.max_iterations >= 3, "def->max_iterations must be at least 3");
        o.max_iterations = d.max_iterations;
        SSC_REQUIRE_ARG(std::isfinite(d.landmark_sigma) && d.landmark_sigma > 0, "def->landmark_sigma must be positive");
        SSC_REQUIRE_ARG(std::isfinite(d.point_sigma) && d.point_sigma > 0, "def->point_sigma must be positive");
        SSC_REQUIRE_ARG(std::isfinite(d.shape_prior) && d.shape_prior >= 0, "def->shape_prior must be >= 0");
        SSC_REQUIRE_ARG(std::isfinite(d.pose_prior) && d.pose_prior >= 0, "def->pose_prior must be >= 0");
        SSC_REQUIRE_ARG(d.max_points >= 16, "def->max_points must be at least 16");
        o.landmark_sigma = d.landmark_sigma;
        o.point_sigma = d.point_sigma;
        o.shape_prior = d.shape_prior;
        o.pose_prior = d.pose_prior;
        o.max_points = d.max_points;
        o.seed = d.seed;
        o.joint_limits = d.joint_limits != 0;
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
        fitter->frames.clear();
        fitter->solved = false;
        fitter->solution = {};
        fitter->residuals.clear();
    });
}

uint32_t ssc_fitter_frame_count(const ssc_fitter* fitter) { return fitter ? uint32_t(fitter->frames.size()) : 0; }

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
            const int64_t l = fitter->model->model.find_landmark(names[i]);
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
        need(points, "points");
        SSC_REQUIRE_ARG_S(count >= 16, "count is " << count << "; a cloud needs at least 16 points");
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
            SSC_REQUIRE_ARG_S(fitting::measured_point(c.points.back()), "point " << i << " is not finite or beyond " << fitting::kMaxCoordinate);
            if (normals) {
                c.normals.push_back(at(normals, i));
                const Eigen::Vector3d& n = c.normals.back();
                SSC_REQUIRE_ARG_S(n.allFinite() && (n.squaredNorm() == 0 || std::abs(n.norm() - 1) < 1e-3),
                                  "normal " << i << " is neither a unit vector nor zero (unknown)");
            }
            if (confidence) {
                SSC_REQUIRE_ARG_S(confidence[i] >= 0 && confidence[i] <= 1, "confidence[" << i << "] is not in [0, 1]");
                c.confidence.push_back(confidence[i]);
            }
        }
        frame_for_adding(fitter, frame).clouds.push_back(std::move(c));
        fitter->solved = false;
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
        SSC_REQUIRE_ARG_S(d.width >= 5 && d.height >= 5 && d.width <= 16384 && d.height <= 16384,
                          "image size " << d.width << " x " << d.height << " (5..16384 each)");
        const std::size_t sample = d.format == SSC_DEPTH_U16_MM ? 2 : 4;
        const std::size_t stride = d.row_stride ? d.row_stride : sample * d.width;
        SSC_REQUIRE_ARG_S(stride >= sample * d.width && stride % sample == 0,
                          "image->row_stride " << d.row_stride << " must be 0 or a multiple of " << sample << " >= " << sample * d.width);
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
        // Samples as metres in one packed float image.
        std::vector<float> depth(std::size_t(d.width) * d.height);
        const auto* base = static_cast<const unsigned char*>(d.samples);
        for (uint32_t v = 0; v < d.height; ++v) {
            const unsigned char* row = base + std::size_t(v) * stride;
            for (uint32_t u = 0; u < d.width; ++u) {
                float z;
                if (d.format == SSC_DEPTH_U16_MM) {
                    uint16_t mm;
                    std::memcpy(&mm, row + 2 * std::size_t(u), 2);
                    z = float(mm) * 1e-3f;
                } else {
                    std::memcpy(&z, row + 4 * std::size_t(u), 4);
                }
                depth[std::size_t(v) * d.width + u] = z;
            }
        }
        view.depth = depth.data();
        fitting::PointCloud cloud = fitting::depth_to_cloud(view);
        const uint32_t n = uint32_t(cloud.points.size());
        frame_for_adding(fitter, frame).clouds.push_back(std::move(cloud));
        fitter->solved = false;
        if (points_added) *points_added = n;
    });
}

ssc_status ssc_fitter_solve(ssc_fitter* fitter, ssc_progress_fn progress, void* user, ssc_fit_report* report) {
    return guarded(__func__, [&] {
        need(fitter, "fitter");
        if (report) SSC_REQUIRE_ARG(report->struct_size >= sizeof(uint32_t), "report->struct_size must be set to sizeof(ssc_fit_report)");
        fitting::FitProgress cb;
        if (progress) cb = [&](uint32_t it, double cost) { return progress(user, it, float(cost)) == 0; };
        fitter->solved = false;
        fitter->solution = fitting::fit(fitter->linear, fitter->frames, fitter->options, nullptr, cb, &fitter->model->context->pool);
        // Residuals: distance of each point to the fitted surface along the nearest vertex's normal.
        fitter->residuals.assign(fitter->frames.size(), {});
        Body body(fitter->model->model, nullptr);
        std::vector<Eigen::Vector3d> posed, normals;
        for (std::size_t f = 0; f < fitter->frames.size(); ++f) {
            if (fitter->frames[f].clouds.empty()) continue;
            fitting::posed_surface(body, fitter->solution.frames[f], posed, &normals);
            const fitting::PointIndex index(posed);
            for (const auto& c : fitter->frames[f].clouds)
                for (const auto& p : c.points) {
                    const uint32_t v = index.nearest(p, nullptr);
                    fitter->residuals[f].push_back(float(std::abs(normals[v].dot(p - posed[v]))));
                }
        }
        fitter->solved = true;
        if (report) {
            const auto& r = fitter->solution.report;
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
            const uint32_t n = report->struct_size < sizeof out ? report->struct_size : uint32_t(sizeof out);
            std::memcpy(report, &out, n);
            report->struct_size = n;
        }
        if (fitter->solution.report.cancelled) fail(SSC_ERROR_CANCELLED, "cancelled by the progress callback");
    });
}

ssc_status ssc_fitter_get_shape(const ssc_fitter* fitter, float* out, uint32_t capacity) {
    return guarded(__func__, [&] {
        need(fitter, "fitter");
        require_solved(fitter, 0);
        const uint32_t K = fitter->model->model.component_count();
        check_output(out, capacity, K, 0, 4);
        for (uint32_t k = 0; k < K; ++k) out[k] = k < fitter->solution.shape.size() ? float(fitter->solution.shape[k]) : 0.f;
    });
}

ssc_status ssc_fitter_get_pose(const ssc_fitter* fitter, uint32_t frame, float* rotations, uint32_t joint_capacity,
                               float* translation, float* scale) {
    return guarded(__func__, [&] {
        need(fitter, "fitter");
        require_solved(fitter, frame);
        const auto& s = fitter->solution.frames[frame];
        const uint32_t J = fitter->model->model.joint_count();
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
        require_solved(fitter, frame);
        const uint32_t V = fitter->model->model.vertex_count();
        stride = check_output(out, capacity, V, stride, 12);
        Body body(fitter->model->model, nullptr);
        std::vector<Eigen::Vector3d> posed;
        fitting::posed_surface(body, fitter->solution.frames[frame], posed);
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
        require_solved(fitter, frame);
        const auto& r = fitter->residuals[frame];
        if (r.empty()) return;
        check_output(out, capacity, r.size(), 0, 4);
        std::memcpy(out, r.data(), 4 * r.size());
    });
}

uint32_t ssc_fitter_point_count(const ssc_fitter* fitter, uint32_t frame) {
    if (!fitter || frame >= fitter->frames.size()) return 0;
    std::size_t n = 0;
    for (const auto& c : fitter->frames[frame].clouds) n += c.points.size();
    return uint32_t(n);
}

}  // extern "C"

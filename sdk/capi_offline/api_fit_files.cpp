// Fitting to files (sscape_offline.h): scan and landmark files read into a fitter, and a solved
// fit's parameters written (scan_files/fit_params.hpp's format), as `sscape fit` does. Built on the public fitter functions with the
// same float arrays the command line gave them, so the command line and callers of these functions
// (the Python pipeline) fit the same way.
#include "capi/guard.hpp"
#include "capi/cpp_access.hpp"
#include "common/files.hpp"
#include "fitting/fitter.hpp"
#include "fitting/solver.hpp"
#include "io/readers.hpp"
#include "io/units.hpp"
#include "scan_files/fit_params.hpp"
#include "scan_files/scan_input.hpp"
#include "synthesis/model.hpp"

#include <sscape/sscape_offline.h>

#include <nlohmann/json.hpp>


using namespace ssc;
using namespace ssc::capi;

namespace {

void ok(ssc_status status) {
    if (status != SSC_OK) fail(status, ssc_last_error());
}

ssc_fit_file_def read_file_def(const ssc_fit_file_def* def) {
    need(def, "def");
    const ssc_fit_file_def d = read_def(def, ssc_fit_file_def_init, "def");
    need(d.path, "def->path");
    return d;
}

void write_info(ssc_fit_file_info* info, uint32_t used, uint32_t left_out, uint32_t unknown, double span) {
    if (!info) return;
    SSC_REQUIRE_ARG(info->struct_size >= sizeof(uint32_t), "info->struct_size must be set to sizeof(ssc_fit_file_info)");
    ssc_fit_file_info out{sizeof out, used, left_out, unknown, float(span)};
    const uint32_t n = info->struct_size < sizeof out ? info->struct_size : uint32_t(sizeof out);
    std::memcpy(info, &out, n);
    info->struct_size = n;
}

std::string option_of(const ssc_fit_file_def& d) { return d.units_option ? d.units_option : ""; }

}  // namespace

extern "C" {

void ssc_fit_file_def_init(ssc_fit_file_def* def, size_t size) {
    if (!def || size < sizeof(uint32_t)) return;
    ssc_fit_file_def d{};
    d.struct_size = static_cast<uint32_t>(size < sizeof d ? size : sizeof d);
    std::memcpy(def, &d, d.struct_size);
}

ssc_status ssc_fitter_add_points_file(ssc_fitter* fitter, uint32_t frame, const ssc_fit_file_def* def, ssc_fit_file_info* info) {
    return guarded(__func__, [&] {
        need(fitter, "fitter");
        const ssc_fit_file_def d = read_file_def(def);
        const double to_metres = d.units ? io::units_to_metres(d.units) : 1.0;
        const io::PointFile pf = io::read_points(d.path);
        std::vector<Eigen::Vector3d> metres;
        for (const auto& p : pf.points) metres.push_back(p * to_metres);
        const double span = io::checked_body_span(d.path, metres, to_metres, d.units != nullptr, option_of(d));
        std::vector<float> pts, nrm;
        for (const auto& p : metres)
            for (int a = 0; a < 3; ++a) pts.push_back(float(p[a]));
        std::size_t unknown = pf.normals.empty() ? pf.points.size() : 0;
        for (const auto& n : pf.normals) {
            for (int a = 0; a < 3; ++a) nrm.push_back(float(n[a]));
            unknown += n.squaredNorm() == 0;
        }
        ok(ssc_fitter_add_points(fitter, frame, pts.data(), nrm.empty() ? nullptr : nrm.data(), nullptr, uint32_t(pf.points.size()), 0));
        write_info(info, uint32_t(pf.points.size()), uint32_t(unknown), 0, span);
    });
}

ssc_status ssc_fitter_add_landmarks_file(ssc_fitter* fitter, uint32_t frame, const ssc_fit_file_def* def, ssc_fit_file_info* info) {
    return guarded(__func__, [&] {
        need(fitter, "fitter");
        const ssc_fit_file_def d = read_file_def(def);
        const double to_metres = d.units ? io::units_to_metres(d.units) : 1e-3;  // the .lnd format's millimetres
        const ssc_model* model = model_of(fitter);
        std::vector<uint32_t> indices;
        std::vector<float> positions;
        std::vector<std::string> unknown_names;
        uint32_t hands = 0;
        for (const auto& [index, r] : scan_files::match_landmarks(io::read_lnd(d.path), model_of(model).data(), &unknown_names)) {  // the file's numbers / 1000
            if (!d.use_hands && fitting::is_hand_landmark(r.name)) {
                ++hands;
                continue;
            }
            indices.push_back(index);
            for (int a = 0; a < 3; ++a) positions.push_back(float(r.position[a]));
        }
        for (const std::string& name : unknown_names)
            log_message(model, SSC_LOG_WARNING, std::string(d.path) + ": landmark '" + name + "' is not one of the model's; ignored");
        const uint32_t unknown = uint32_t(unknown_names.size());
        SSC_REQUIRE_ARG(indices.size() >= 3, std::string(d.path) + ": fewer than 3 usable landmarks");
        const double to_given = to_metres / 1e-3;
        std::vector<Eigen::Vector3d> metres;
        for (std::size_t i = 0; i < indices.size(); ++i) {
            for (int a = 0; a < 3; ++a) positions[3 * i + std::size_t(a)] = float(positions[3 * i + std::size_t(a)] * to_given);
            metres.emplace_back(positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]);
        }
        const double span = io::checked_body_span(d.path, metres, to_metres, d.units != nullptr, option_of(d));
        ok(ssc_fitter_add_landmarks(fitter, frame, indices.data(), positions.data(), nullptr, uint32_t(indices.size())));
        write_info(info, uint32_t(indices.size()), hands, unknown, span);
    });
}

ssc_status ssc_model_get_digest(const ssc_model* model, const char** out) {
    return guarded(__func__, [&] {
        need(model, "model");
        need(out, "out");
        *out = digest_of(model).c_str();
    });
}

ssc_status ssc_fitter_write_params(ssc_fitter* fitter, const ssc_fit_report* report, const char* path) {
    return guarded(__func__, [&] {
        need(fitter, "fitter");
        need(report, "report");
        need(path, "path");
        SSC_REQUIRE_ARG(report->struct_size >= sizeof(ssc_fit_report), "report->struct_size must be sizeof(ssc_fit_report), as solve filled it");
        // The solution in double precision, every frame with the shared shape (segments included).
        const fitting::Fitter& solved = fitter_of(fitter);
        const fitting::FitSolution& solution = solved.solution();  // INVALID_ARGUMENT before a solve
        std::vector<fitting::FitState> frames;
        for (uint32_t f = 0; f < solved.frame_count(); ++f) {
            fitting::FitState s = solved.frame_state(f);
            s.shape = solution.shape;
            for (Eigen::Quaterniond& q : s.pose) q.normalize();
            frames.push_back(std::move(s));
        }
        nlohmann::ordered_json j = scan_files::fit_params_to_json(model_of(model_of(fitter)), frames, digest_of(model_of(fitter)));
        const ssc_fit_report& r = *report;
        j["report"] = {{"converged", bool(r.converged)},   {"iterations", r.iterations},
                       {"restarts", r.restarts},            {"landmark_rms_m", r.landmark_rms},
                       {"point_mean_m", r.point_mean},      {"inlier_fraction", r.inlier_fraction},
                       {"unexplained_fraction", r.unexplained_fraction}, {"seconds", r.seconds}};
        const std::string text = j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
        write_file_atomically(path, text.data(), text.size());
    });
}

}  // extern "C"

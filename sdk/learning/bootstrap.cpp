#include "learning/bootstrap.hpp"

#include "common/error.hpp"
#include "common/files.hpp"
#include "common/rigid.hpp"
#include "common/text.hpp"
#include "learning/posture_fit.hpp"
#include "learning/scan_tables.hpp"
#include "registration/registrar.hpp"
#include "runtime/runtime_model.hpp"
#include "render/registration_picture.hpp"
#include "scan_files/cached_result.hpp"
#include "sscape_format/model_io.hpp"

#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>
#include <sstream>

namespace ssc::learning {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

std::string round_dir(const std::string& out, uint32_t round) { return (fs::path(out) / ("round_" + std::to_string(round))).string(); }

void write_text(const std::string& path, const std::string& text) { write_file_atomically(path, text.data(), text.size()); }

std::vector<unsigned char> read_bytes(const std::string& path) {
    const std::string s = read_regular_file(path, 1ull << 30);
    return std::vector<unsigned char>(s.begin(), s.end());
}

struct ScanState {
    bool ok = false;         // registered (now or before)
    std::string failure;     // why not
    scan_files::RegistrationRecord record;
    Inspection inspection;
    bool accepted = false, by_person = false;
    std::string reason;
    fitting::FitState posture_fit;  // with a posture model, when accepted
};

void check_spec(const BootstrapSpec& spec) {
    SSC_REQUIRE_ARG_S(spec.scans.size() >= 3, "bootstrap: " << spec.scans.size() << " scans; a model needs at least 3");
    SSC_REQUIRE_ARG(spec.rounds >= 1 && spec.rounds <= 100, "bootstrap: rounds must be 1 to 100");
    SSC_REQUIRE_ARG(!spec.out_dir.empty(), "bootstrap: no output folder");
    SSC_REQUIRE_ARG(std::isfinite(spec.reading.scan_units_to_metres) && spec.reading.scan_units_to_metres > 0 &&
                        spec.reading.scan_units_to_metres <= 1,
                    "bootstrap: the scans' units must be metres or smaller");
    std::set<std::string> names;
    for (const auto& s : spec.scans) {
        SSC_REQUIRE_ARG(!s.name.empty() && s.name.find_first_of("/\\,\"\n") == std::string::npos,
                        "bootstrap: a scan name must be a file stem (no /, comma or quote): '" + s.name + "'");
        SSC_REQUIRE_ARG_S(names.insert(s.name).second, "bootstrap: two scans are named " << s.name << " (names come from file stems)");
    }
    for (const auto& [name, d] : spec.decisions)
        SSC_REQUIRE_ARG_S(names.count(name), "bootstrap: the decisions name scan '" << name << "', which is not in the collection");
    if (!spec.attributes.names.empty())
        for (const auto& s : spec.scans)
            SSC_REQUIRE_ARG_S(spec.attributes.rows.count(s.name), "bootstrap: " << spec.attributes.source << " has no row for scan " << s.name);
}

}  // namespace

std::string round_model_path(const std::string& out_dir, uint32_t round) { return round_dir(out_dir, round) + "/model.sscape"; }

std::string round_registration_path(const std::string& out_dir, uint32_t round, const std::string& scan_name) {
    return round_dir(out_dir, round) + "/registrations/" + scan_name + ".ply";
}

void prepare_bootstrap(const std::vector<unsigned char>& initial_model, const BootstrapSpec& spec) {
    check_spec(spec);
    const std::string start_path = round_model_path(spec.out_dir, 0);
    const format::ModelData start = format::read_model(initial_model.data(), initial_model.size());  // refuses a bad model before anything is written
    if (!spec.posture_model.empty() && spec.learn.posture == Posture::Skeleton) check_posture_model(start, read_posture_model(spec.posture_model));
    fs::create_directories(round_dir(spec.out_dir, 0));
    if (!fs::exists(start_path) || read_bytes(start_path) != initial_model) write_file_atomically(start_path, initial_model.data(), initial_model.size());
}

scan_files::ScanFileJob round_registration_job(const BootstrapSpec& spec, uint32_t round, const scan_files::ScanInput& scan) {
    scan_files::ScanFileJob job;
    job.scan = scan;
    job.reading = spec.reading;
    job.mesh_path = round_registration_path(spec.out_dir, round, scan.name);
    job.reuse = true;
    return job;
}

namespace {

using Say = std::function<void(const std::string&)>;

// A round's starting model (the previous round's), loaded as the C API loads a model (a runtime
// model, its anatomy shared). With the C API's registration options (ssc_bootstrap_create sets
// them) a registration made here is the one ssc_registration_run_file makes elsewhere, to the bit.
struct RoundModel {
    RoundModel(const BootstrapSpec& spec, uint32_t round)
        : bytes(read_bytes(round_model_path(spec.out_dir, round - 1))),
          digest(scan_files::model_digest(bytes)),
          runtime(format::read_model(bytes.data(), bytes.size()), &heap),
          registrar(runtime.model(), spec.registration, runtime.anatomy()) {}
    const Model& model() const { return runtime.model(); }

    const std::vector<unsigned char> bytes;
    const std::string digest;
    const Allocator heap;
    const RuntimeModel runtime;
    registration::Registrar registrar;
};

// Registers (or reuses) scan i and decides on it: the inspection's verdict, a person's where the
// decisions name the scan, and with a posture model its fit (a scan it cannot fit is rejected).
ScanState register_and_decide(const BootstrapSpec& spec, uint32_t round, std::size_t i, RoundModel& start, const PostureModel* posture, ThreadPool& pool,
                              RoundReport& rep, const Say& say) {
    const scan_files::ScanInput& in = spec.scans[i];
    ScanState st;
    std::string how = "reused";
    try {
        scan_files::ScanFileResult r = scan_files::register_scan_file(start.registrar, start.digest, round_registration_job(spec, round, in), {}, &pool);
        st.record = std::move(r.record);
        st.ok = true;
        for (const std::string& name : r.ignored_landmarks) say(in.name + ": landmark '" + name + "' is not one of the model's; ignored");
        if (!r.reused) how = "registered", ++rep.registered;
        else ++rep.reused;
    } catch (const Error& e) {
        if (e.status() != SSC_ERROR_INVALID_ARGUMENT) throw;  // I/O, memory, cancel: stop (resumable)
        st.failure = e.what();
        ++rep.failed;
    }
    if (st.ok) {
        st.inspection = inspect_registration(start.model(), st.record, spec.rules);
        st.accepted = st.inspection.accepted;
        for (const auto& r : st.inspection.reasons) st.reason += (st.reason.empty() ? "" : "; ") + r;
    } else {
        st.reason = "registration failed: " + st.failure;
    }
    const auto person = spec.decisions.find(in.name);
    if (person != spec.decisions.end()) {
        st.by_person = true;
        st.accepted = person->second.accept && st.ok;  // a failed registration has nothing to learn from
        st.reason = person->second.reason.empty() ? "decided by a person" : person->second.reason;
    }
    if (st.accepted && posture) {
        // The round's own fit is the posture fit when the round registered with the posture model.
        const fitting::FitState* known = start.digest == posture->digest() && st.record.registered.has_fit ? &st.record.registered.fit : nullptr;
        try {
            bool reused = false;
            st.posture_fit = posture->fit(in, spec.reading, posture_fit_path(spec.out_dir, in.name), known, &pool, &reused);
            if (!reused) ++rep.posture_fitted;
        } catch (const Error& e) {
            if (e.status() != SSC_ERROR_INVALID_ARGUMENT) throw;
            st.accepted = false;
            st.reason = std::string("the posture model could not be fitted: ") + e.what();
        }
    }
    st.accepted ? ++rep.accepted : ++rep.rejected;
    const std::string line = format_text("round %u: %s %zu of %zu: %s %s", round, in.name.c_str(), i + 1, spec.scans.size(), st.ok ? how.c_str() : "failed",
                                         st.accepted ? "accepted" : "rejected");
    say(line + (st.accepted || st.reason.empty() ? "" : " (" + st.reason + ")"));
    return st;
}

// The verdicts, then the figures they were drawn from (for review; read_decisions reads the first
// four columns).
std::string decisions_table(const BootstrapSpec& spec, const std::vector<ScanState>& states) {
    std::string decisions = "scan,decision,reason,by,lowest_region,lowest_within_20mm,most_unexplained_pct,folded_pct,stretched_pct,worst_joint,joint_excess_deg\n";
    for (std::size_t i = 0; i < states.size(); ++i) {
        const ScanState& st = states[i];
        decisions += spec.scans[i].name + "," + (st.accepted ? "accept" : "reject") + "," + csv_cell(st.reason) + "," + (st.by_person ? "person" : "auto");
        if (st.ok) {
            const registration::RegionQuality* low = nullptr;
            double unexplained = 0;
            const double all = double(std::max<std::size_t>(1, st.record.quality.scan_to_registration.count));
            for (const auto& q : st.record.quality.regions) {
                if (!low || q.below[3] < low->below[3]) low = &q;
                unexplained = std::max(unexplained, double(q.scan_to_registration.beyond_20mm) / all);
            }
            char figures[200];
            std::snprintf(figures, sizeof figures, ",%s,%.3f,%.2f,%.3f,%.3f,%s,%.1f", low ? low->region.c_str() : "", low ? low->below[3] : 0.0, 100 * unexplained,
                          100 * st.inspection.folded, 100 * st.inspection.stretched, st.inspection.worst_joint.c_str(), st.inspection.joint_excess * 180 / M_PI);
            decisions += figures;
        }
        decisions += "\n";
    }
    return decisions;
}

// Writes the round's decisions.csv; true when it already held these verdicts (the contact sheets
// drawn from them are then current: a resumed run skips them).
bool write_decisions(const BootstrapSpec& spec, const std::string& dir, const std::string& decisions) {
    bool current = false;
    if (fs::exists(dir + "/decisions.csv") && spec.sheet_entries > 0) {
        try {
            current = read_regular_file(dir + "/decisions.csv", 64ull << 20) == decisions;
        } catch (const Error&) {
            current = false;
        }
    }
    write_text(dir + "/decisions.csv", decisions);
    return current;
}

// Contact sheets, a page at a time (each page reads its scans again: memory stays flat); pages
// already drawn from the same verdicts are kept. Returns the pages' paths.
std::vector<std::string> write_contact_sheets(const BootstrapSpec& spec, uint32_t round, const std::string& dir, const Model& model,
                                              const std::vector<ScanState>& states, bool current, const RoundReport& rep) {
    std::vector<std::string> sheets;
    const std::size_t per = std::size_t(spec.sheet_entries), pages = (states.size() + per - 1) / per;
    for (std::size_t page = 0; page < pages; ++page) {
        char name[40];
        std::snprintf(name, sizeof name, "/contact_sheet_%02zu.png", page + 1);
        if (current && fs::exists(dir + name)) {
            sheets.push_back(dir + name);
            continue;
        }
        std::vector<render::SheetEntry> entries;
        for (std::size_t i = page * per; i < std::min(states.size(), (page + 1) * per); ++i) {
            render::SheetEntry e;
            e.name = spec.scans[i].name;
            e.accepted = states[i].accepted;
            e.reason = states[i].reason;
            if (states[i].ok) {
                const scan_files::RegistrationRecord& rec = states[i].record;
                e.frame = render::fit_picture_frame(model, rec.registered.fit);
                e.points = scan_files::load_scan(spec.scans[i], model, spec.reading).cloud.points;
                e.registered = rec.registered.vertices;
                e.error = rec.quality.vertex_distance;
                e.error.resize(e.registered.size(), -1.0);
            }
            entries.push_back(std::move(e));
        }
        char title[120];
        std::snprintf(title, sizeof title, "round %u, page %zu of %zu: %zu accepted, %zu rejected", round, page + 1, pages, rep.accepted, rep.rejected);
        render::write_contact_sheet(dir + name, model, entries, title);
        sheets.push_back(dir + name);
    }
    return sheets;
}

// Learns the round's model from the accepted registrations, or reuses the one learned from the
// same ones (round.json); fills the report's learning figures.
void learn_round(const BootstrapSpec& spec, uint32_t round, const std::string& dir, const RoundModel& start, const std::vector<ScanState>& states,
                 const PostureModel* posture, const ThreadPool& pool, RoundReport& rep, const Say& say) {
    // Learn from the accepted registrations (or reuse the model learned from the same ones).
    std::vector<scan_files::RegisteredScan> accepted;
    std::vector<std::string> accepted_names;
    for (std::size_t i = 0; i < states.size(); ++i)
        if (states[i].accepted) {
            accepted.push_back(states[i].record.registered), accepted_names.push_back(spec.scans[i].name);
            if (posture) accepted.back().fit = states[i].posture_fit;
        }
    if (accepted.size() < 3)
        throw Error(SSC_ERROR_INVALID_ARGUMENT, "bootstrap: round " + std::to_string(round) + " accepted " + std::to_string(accepted.size()) + " of " +
                                                    std::to_string(states.size()) + " registrations; a model needs at least 3 (see " + dir +
                                                    "/decisions.csv: edit it and pass it with --decisions)");
    LearnSpec learn = spec.learn;
    learn.components = std::min<uint32_t>(learn.components, uint32_t(accepted.size() - 1));
    learn.segment_components = std::min<uint32_t>(learn.segment_components, uint32_t(accepted.size() - 1));
    if (!spec.attributes.names.empty()) learn.attributes = attributes_for(spec.attributes, accepted_names);
    std::ostringstream prov;
    // Not the run's planned rounds: a round's model is the same whether more rounds follow.
    prov << "bootstrap round " << round << "; " << accepted.size() << " of " << states.size() << " registrations accepted";
    learn.provenance = prov.str();
    learn.threads = pool.size();
    learn.posture_model = posture ? posture->data() : nullptr;  // the fits in `accepted` are its
    nlohmann::ordered_json settings{{"start_model_digest", start.digest}, {"accepted", accepted_names}, {"components", learn.components},
                                    {"posture", posture_name(learn.posture)}, {"name", learn.name}, {"license", learn.license},
                                    {"provenance", learn.provenance}, {"segment_components", learn.segment_components},
                                    {"segment_band", learn.segment_band}, {"scale", learn.scale}};
    for (const auto& a : learn.attributes) settings["attributes"][a.name] = a.values;
    if (posture) settings["posture_model_digest"] = posture->digest();
    // The registrations themselves: one made again (another reading of its scan) relearns the model.
    for (const auto& name : accepted_names)
        settings["registrations"].push_back(scan_files::file_digest(read_regular_file(scan_files::record_report_path(round_registration_path(spec.out_dir, round, name)), 64ull << 20)));
    const std::string model_path = round_model_path(spec.out_dir, round), round_json = dir + "/round.json";
    const auto t_learn = Clock::now();
    // Reused when learned from the same settings and registrations, and its file is the one learned then.
    const scan_files::CachedResult kept(round_json, settings, "settings");
    if (const auto old = fs::exists(model_path) ? kept.find() : std::nullopt)
        rep.model_reused = old->contains("model_digest") && old->at("model_digest") == scan_files::model_digest(read_bytes(model_path));
    if (!rep.model_reused) {
        say("round " + std::to_string(round) + ": learning from " + std::to_string(accepted.size()) + " registrations");
        LearnReport lr;
        const std::vector<unsigned char> bytes = format::write_model(learn_model(start.model().data(), accepted, learn, &lr));
        write_file_atomically(model_path, bytes.data(), bytes.size());
        kept.store({{"round", round}, {"model_digest", scan_files::model_digest(bytes)}, {"explained", lr.explained}, {"components", lr.components}});
    }
    rep.learn_seconds = since(t_learn);
    rep.components = learn.components;
    rep.model_path = model_path;
}

}  // namespace

std::vector<RoundReport> bootstrap(const std::vector<unsigned char>& initial_model, const BootstrapSpec& spec, const BootstrapProgress& progress) {
    prepare_bootstrap(initial_model, spec);
    const Say say = [&](const std::string& line) {
        if (progress && !progress(line)) throw Error(SSC_ERROR_CANCELLED, "bootstrap: stopped; run it again to resume");
    };
    for (const std::string& entry : spec.skipped) say("left out of the scans: " + entry);
    ThreadPool pool(spec.threads ? spec.threads : std::max(1u, std::thread::hardware_concurrency()));

    // The posture model (Posture::Skeleton only): its fits unpose every round's registrations.
    std::unique_ptr<const PostureModel> posture;
    if (!spec.posture_model.empty() && spec.learn.posture == Posture::Skeleton) posture = std::make_unique<const PostureModel>(spec.posture_model, spec.registration);

    std::vector<RoundReport> reports;
    std::string rounds_csv = "round,scans,registered,reused,failed,accepted,rejected,register_seconds,learn_seconds,components\n";
    for (uint32_t round = 1; round <= spec.rounds; ++round) {
        RoundReport rep;
        rep.round = round;
        const std::string dir = round_dir(spec.out_dir, round);
        fs::create_directories(dir + "/registrations");
        RoundModel start(spec, round);

        const auto t_register = Clock::now();
        std::vector<ScanState> states;
        for (std::size_t i = 0; i < spec.scans.size(); ++i) states.push_back(register_and_decide(spec, round, i, start, posture.get(), pool, rep, say));
        rep.register_seconds = since(t_register);
        if (spec.learn.posture == Posture::Skeleton && !posture)
            say("round " + std::to_string(round) + ": the accepted scans posed by their own fits (no posture model)");
        if (posture)
            say("round " + std::to_string(round) + ": the accepted scans posed by '" + posture->data()->metadata.name + "' (" + std::to_string(rep.posture_fitted) +
                " new fits, the others' found in " + (fs::path(spec.out_dir) / "posture_fits").string() + ")");

        const bool sheets_current = write_decisions(spec, dir, decisions_table(spec, states));
        if (spec.sheet_entries > 0) rep.sheets = write_contact_sheets(spec, round, dir, start.model(), states, sheets_current, rep);
        learn_round(spec, round, dir, start, states, posture.get(), pool, rep, say);
        say(format_text("round %u: %zu registered, %zu reused, %zu failed; %zu accepted, %zu rejected; model %s (%u components)%s", round,
                        rep.registered, rep.reused, rep.failed, rep.accepted, rep.rejected, rep.model_path.c_str(), rep.components,
                        rep.model_reused ? ", reused" : ""));
        rounds_csv += format_text("%u,%zu,%zu,%zu,%zu,%zu,%zu,%.1f,%.1f,%u\n", round, states.size(), rep.registered, rep.reused, rep.failed,
                                  rep.accepted, rep.rejected, rep.register_seconds, rep.learn_seconds, rep.components);
        reports.push_back(rep);
    }
    const std::vector<unsigned char> last = read_bytes(reports.back().model_path);
    write_file_atomically((fs::path(spec.out_dir) / "model.sscape").string(), last.data(), last.size());
    write_text((fs::path(spec.out_dir) / "rounds.csv").string(), rounds_csv);
    return reports;
}

}  // namespace ssc::learning

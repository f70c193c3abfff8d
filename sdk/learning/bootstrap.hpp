// Bootstrapping (the reference paper's passes over a scan collection): register every scan with
// the current model, inspect each registration (acceptance.hpp), learn a model from the accepted
// ones (learn_model.hpp), and register again with it. docs/learning.md walks through it.
//
// Everything stays on disk under the output folder, one folder per round:
//   round_0/model.sscape                the starting model
//   round_N/registrations/NAME.ply|json  each scan registered with round N-1's model (sscape register's format)
//   round_N/decisions.csv               scan,decision,reason,by: the verdicts (by: auto, or person)
//   round_N/contact_sheet_NN.png        each scan beside its registration, rejected ones marked
//   round_N/model.sscape, round.json    the model learned from the accepted registrations
//   posture_fits/NAME.json              with a posture model: its fit to each accepted scan (posture_fit.hpp)
//   model.sscape, rounds.csv            the last round's model; a line per round
// A run that stops (interrupted, a full disk, too few accepted scans) resumes where it stopped: a
// registration is reused when its report names the digests of the model and the scan (with its
// landmarks) it was made from and the same units and up axis, a round's model when it was learned
// from the same registrations and settings. Every file
// is written atomically, so a stop leaves no partial file.
#pragma once

#include "learning/acceptance.hpp"
#include "scan_files/register_scan_file.hpp"
#include "learning/learn_model.hpp"
#include "learning/scan_tables.hpp"
#include "registration/register_scan.hpp"

#include <functional>
#include <map>
#include <string>
#include <vector>

namespace ssc::learning {

// A person's verdict on a scan (PersonDecision, scan_tables.hpp, from an edited decisions file)
// holds in every round.

struct BootstrapSpec {
    std::vector<scan_files::ScanInput> scans;
    std::vector<std::string> skipped;  // entries of the scans' folder that cannot be scans (scan_files::find_scans), said at the start
    std::string out_dir;
    uint32_t rounds = 3;
    scan_files::ScanReading reading;              // the scans' and landmark files' units, the axis that is up
    registration::RegistrationOptions registration;  // ssc_bootstrap_create: the C API's defaults (floats)
    AcceptanceRules rules;
    LearnSpec learn;                  // components (capped at accepted - 1), posture, name, licence (its posture_model is set from below)
    // Posture::Skeleton: each accepted registration is unposed with this model's fit to its scan
    // (posture_fit.hpp; made once per scan and kept in posture_fits/), not with the round's own
    // fit. A model file's bytes sharing the starting model's mesh, skeleton and skinning; empty:
    // the rounds' own fits.
    std::vector<unsigned char> posture_model;
    AttributeTable attributes;        // known per-scan attributes (optional; every scan needs a row)
    std::map<std::string, PersonDecision> decisions;  // by scan name
    uint32_t threads = 0;             // 0: every hardware thread
    int sheet_entries = 12;           // registrations per contact sheet page; 0: no contact sheets
};

struct RoundReport {
    uint32_t round = 0;
    std::size_t registered = 0, reused = 0, failed = 0, accepted = 0, rejected = 0;
    std::size_t posture_fitted = 0;   // posture model fits made this round (not found on disk)
    double register_seconds = 0, learn_seconds = 0;  // register: with the inspection and posture fits
    uint32_t components = 0;
    bool model_reused = false;
    std::string model_path;
    std::vector<std::string> sheets;
};

// Called with each line worth telling (a scan registered, a round's summary); returning false
// stops the run (ssc::Error, CANCELLED) after the file being written.
using BootstrapProgress = std::function<bool(const std::string& line)>;

// The files of a round (round 0: the starting model).
std::string round_model_path(const std::string& out_dir, uint32_t round);
std::string round_registration_path(const std::string& out_dir, uint32_t round, const std::string& scan_name);

// Checks the spec and writes round 0's starting model (unless the same bytes are there): what
// bootstrap() does first, and what a distributed run does before it registers round 1's scans.
// Throws ssc::Error (INVALID_ARGUMENT for bad settings, a bad model or posture model, IO).
void prepare_bootstrap(const std::vector<unsigned char>& initial_model, const BootstrapSpec& spec);

// The registration of one scan in a round, as bootstrap() makes it (reused when current): what a
// distributed run's tasks call with round - 1's model, before bootstrap() finds them all done.
scan_files::ScanFileJob round_registration_job(const BootstrapSpec& spec, uint32_t round, const scan_files::ScanInput& scan);

// Runs (or resumes) the rounds from the starting model's file bytes. Throws ssc::Error:
// INVALID_ARGUMENT for bad settings (fewer than 3 scans, duplicate names, decisions naming no scan,
// a posture model that is not one or does not share the starting model's rig)
// or a round with fewer than 3 accepted registrations (its decisions and sheets are on disk: edit
// and pass the decisions, then run again); IO; CANCELLED.
std::vector<RoundReport> bootstrap(const std::vector<unsigned char>& initial_model, const BootstrapSpec& spec,
                                   const BootstrapProgress& progress = {});

}  // namespace ssc::learning

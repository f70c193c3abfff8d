/*
 * sscape offline tools: scan collections on disk, registered one scan file at a time and learned
 * into models by bootstrapping (what `sscape register` and `sscape bootstrap` do), for callers that
 * spread a collection over many processes or machines (the Python package's Dask pipeline).
 *
 * These functions live in libsscape_offline.so, which holds the whole C API of sscape.h as well
 * (one library: handles from it work with every function of both headers). libsscape.so, the
 * runtime, stays without them: it neither reads scan files nor learns models. Conventions are
 * sscape.h's. Everything here is SSC_EXPERIMENTAL. The objects made here (scan lists,
 * bootstrappings) and the work of these functions use the process heap, not a context's allocator:
 * these are tools for machines that process scans, not for engines that place their memory.
 *
 * Files written here are written atomically (a file on disk is complete) and a run that stops
 * resumes: a registration whose report names the same model, scan, landmarks, units and up axis is
 * reused rather than made again.
 */
#ifndef SSCAPE_SSCAPE_OFFLINE_H
#define SSCAPE_SSCAPE_OFFLINE_H

#include "sscape/sscape.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---------------------------------------------------------------------------------------------- */
/* Scan files                                                                                      */

/** A folder's scans: every .ply and .obj file in it (any case; not in its subfolders, not hidden ones), sorted
 *  by name, each with its landmark file NAME.lnd beside it (or PREFIX.lnd for the simulator's
 *  PREFIX_scan.ply) when there is one. Every such file counts as a scan, so keep other meshes (a
 *  simulator's true meshes, earlier results) in another folder, as `sscape simulate --count` does. */
typedef struct ssc_scan_list ssc_scan_list;

/** Lists the folder. @return SSC_ERROR_IO when it cannot be listed; SSC_ERROR_INVALID_ARGUMENT for NULL. */
SSC_EXPERIMENTAL ssc_status ssc_scan_list_create(const char* folder, ssc_scan_list** out);
SSC_EXPERIMENTAL void ssc_scan_list_destroy(ssc_scan_list* list);
SSC_EXPERIMENTAL uint32_t ssc_scan_list_count(const ssc_scan_list* list);
/** One scan: its name (the file's stem), its path and its landmark file's path ("" when none);
 *  strings owned by the list. Any output may be NULL. */
SSC_EXPERIMENTAL ssc_status ssc_scan_list_get(const ssc_scan_list* list, uint32_t index, const char** name, const char** path,
                                              const char** landmarks);
/** Entries named as scans that cannot be read as one and were left out of the list: a link to
 *  nothing, a loop of links, one the user may not look at. One such entry does not stop a collection;
 *  show them to the user. In name order. */
SSC_EXPERIMENTAL uint32_t ssc_scan_list_skipped_count(const ssc_scan_list* list);
/** One skipped entry: its path and why it was left out; strings owned by the list. Any output may be NULL. */
SSC_EXPERIMENTAL ssc_status ssc_scan_list_get_skipped(const ssc_scan_list* list, uint32_t index, const char** path, const char** reason);

/** One scan file to register, and where its registration goes. */
typedef struct ssc_scan_file_job {
    uint32_t struct_size;        /**< sizeof(ssc_scan_file_job), set by ssc_scan_file_job_init. */
    const char* scan_path;       /**< PLY or OBJ points or mesh (normals used where given). Required. */
    const char* landmarks_path;  /**< CAESAR .lnd on the scan, matched to the model's landmarks by name; NULL: none. */
    const char* units;           /**< "m", "cm" or "mm" for the scan and the .lnd; NULL: metres for the scan,
                                      millimetres for the .lnd (the format's). */
    const char* up;              /**< The scan's up axis: "x", "y", "z", "-x", "-y", "-z"; NULL: "y". */
    const char* mesh_path;       /**< The registered mesh, .ply or .obj, in the scan's frame and units. Required. */
    uint32_t write_report;       /**< Write the JSON report beside the mesh (its path with .json). Default 1. */
    uint32_t reuse;              /**< Keep a registration already there when its report names this model, scan,
                                      landmarks, units and up axis (needs write_report); a scan that could not
                                      be registered with them before (NAME.failed.json beside the mesh) fails
                                      again at once with the same reason. Default 0. */
    const char* picture_path;    /**< A PNG of the scan beside the registration, coloured by distance; NULL: none. */
} ssc_scan_file_job;

/** Fills job with defaults; size = sizeof(*job). Threads: any. */
SSC_EXPERIMENTAL void ssc_scan_file_job_init(ssc_scan_file_job* job, size_t size);

/**
 * Reads the scan (and landmarks), registers it with the registration's model and options, and
 * writes the mesh and report (the format `sscape register` writes and `sscape learn` reads).
 * @param report      NULL or a report to fill (struct_size set by the caller); from the report on
 *                    disk when reused.
 * @param out_reused  NULL, or receives 1 when a current registration was kept (nothing run; the
 *                    registration then holds no result), else 0.
 * @return SSC_ERROR_INVALID_ARGUMENT for a bad job, a scan that cannot be read as a body (its
 *         extent in the given units is not 5 cm to 3 m), or one that cannot be registered;
 *         SSC_ERROR_IO; SSC_ERROR_CANCELLED (nothing written).
 * Threads: the registration's thread; the work also uses the worker threads of the model's context.
 */
SSC_EXPERIMENTAL ssc_status ssc_registration_run_file(ssc_registration* registration, const ssc_scan_file_job* job,
                                                      ssc_stage_progress_fn progress, void* user, ssc_registration_report* report,
                                                      uint32_t* out_reused);

/* ---------------------------------------------------------------------------------------------- */
/* Fitting to files (what `sscape fit` reads and writes)                                          */

/** A measurement file for a fitter. */
typedef struct ssc_fit_file_def {
    uint32_t struct_size;        /**< sizeof(ssc_fit_file_def), set by ssc_fit_file_def_init. */
    const char* path;            /**< A PLY or OBJ scan, or a CAESAR .lnd. Required. */
    const char* units;           /**< "m", "cm" or "mm"; NULL: metres for scans, millimetres for .lnd. */
    uint32_t use_hands;          /**< .lnd: use the hand landmarks too (left out by default: scanned hands are
                                      rarely posed like the model's). Default 0. */
    const char* units_option;    /**< How messages name the setting of the units (the command line's
                                      "--units"); NULL: they say "units". */
} ssc_fit_file_def;

/** What a file gave. Fill struct_size (sizeof) before the call. */
typedef struct ssc_fit_file_info {
    uint32_t struct_size;  /**< sizeof(ssc_fit_file_info), set by the caller. */
    uint32_t used;         /**< Points or landmarks added. */
    uint32_t left_out;     /**< Scans: points whose normals are estimated; .lnd: hand landmarks left out. */
    uint32_t unknown;      /**< .lnd: landmarks whose names are not the model's (ignored). */
    float span;            /**< Metres: the largest extent of what was read. */
} ssc_fit_file_info;

/** Fills def with defaults; size = sizeof(*def). Threads: any. */
SSC_EXPERIMENTAL void ssc_fit_file_def_init(ssc_fit_file_def* def, size_t size);

/**
 * Adds a scan file's points (normals where the file gives them, estimated elsewhere) to a frame.
 * @param frame  an existing frame or ssc_fitter_frame_count (a new frame).
 * @param info   NULL or what the file gave.
 * @return SSC_ERROR_INVALID_ARGUMENT for a malformed file, one that read in its units spans no body
 *         (5 cm to 3 m; the message names the units that would fit), unknown units; SSC_ERROR_IO.
 * Threads: the fitter's thread.
 */
SSC_EXPERIMENTAL ssc_status ssc_fitter_add_points_file(ssc_fitter* fitter, uint32_t frame, const ssc_fit_file_def* def,
                                                       ssc_fit_file_info* info);

/** Adds a .lnd file's landmarks, matched to the model's by name as CAESAR files spell them, to a
 *  frame; as ssc_fitter_add_points_file, and SSC_ERROR_INVALID_ARGUMENT with fewer than 3 usable. */
SSC_EXPERIMENTAL ssc_status ssc_fitter_add_landmarks_file(ssc_fitter* fitter, uint32_t frame, const ssc_fit_file_def* def,
                                                          ssc_fit_file_info* info);

/**
 * The model's digest: 16 hex digits of the file bytes it was loaded from (the built-in model's as
 * compiled in). Every result file records it (fit parameters as "model_digest", registration
 * reports), so a tool reading a result with another model refuses it instead of making another
 * body. *out is owned by the model. @return SSC_ERROR_INVALID_ARGUMENT for NULL.
 */
SSC_EXPERIMENTAL ssc_status ssc_model_get_digest(const ssc_model* model, const char** out);

/**
 * Writes a solved fit's parameters as JSON, atomically, in the format "sscape fit parameters 2"
 * (the one a registration's report holds its model fit in): the model's name and digest
 * ("model_digest"), the whole-body shape ("shape"), the segment coefficients when the fit had them
 * ("segment_shape"), each frame's per-joint rotations (by joint name), translation and scale, all
 * in double precision, and the report given (as ssc_fitter_solve filled it): what
 * `sscape fit --params` writes and `sscape synth --params` reads (refusing parameters of another
 * model; files of version 1 still read).
 * @return SSC_ERROR_INVALID_ARGUMENT for NULL or a fitter not solved; SSC_ERROR_IO.
 */
SSC_EXPERIMENTAL ssc_status ssc_fitter_write_params(ssc_fitter* fitter, const ssc_fit_report* report, const char* path);

/* ---------------------------------------------------------------------------------------------- */
/* Bootstrapping: rounds of registration, inspection and learning over a folder of scans          */

typedef enum ssc_posture_normalization {
    SSC_POSTURE_SKELETON = 0, /**< Each registration unposed by its fitted skeleton before PCA. */
    SSC_POSTURE_NONE = 1,     /**< PCA of the registrations as they are. */
    SSC_POSTURE_LAPLACIAN = 2,/**< Each registration rebuilt at rest from posture-free differential coordinates (no fit needed). */
    SSC_POSTURE_FORCE32 = 0x7fffffff
} ssc_posture_normalization;

typedef struct ssc_bootstrap_def {
    uint32_t struct_size;             /**< sizeof(ssc_bootstrap_def), set by ssc_bootstrap_def_init. */
    const char* scans_dir;            /**< The scans (as ssc_scan_list_create lists them); at least 3. Required. */
    const char* out_dir;              /**< round_N/ per round, model.sscape, rounds.csv (docs/learning.md). Required. */
    const char* init_model_path;      /**< The starting model; NULL: the built-in model. */
    uint32_t template_only;           /**< Start from its template alone (no shape components). Default 0. */
    uint32_t components;              /**< Shape components of each learned model, 1..1000. Default 20. */
    ssc_posture_normalization posture;/**< Default SSC_POSTURE_SKELETON. */
    uint32_t scale;                   /**< Procrustes alignment with scale. Default 0. */
    uint32_t segment_components;      /**< Components per body segment shape space, 0..1000. Default 0. */
    float segment_band;               /**< Metres each side of a segment border, [0.005, 0.5]. Default 0.08. */
    const char* units;                /**< As ssc_scan_file_job's. */
    const char* up;                   /**< As ssc_scan_file_job's. */
    const char* decisions_path;       /**< A person's verdicts (an edited decisions.csv); NULL: none. */
    const char* attributes_path;      /**< Known per-scan attributes (CSV scan,NAME,...); NULL: none. */
    const char* name;                 /**< The learned models' name; NULL: "sscape-learned". */
    const char* license;              /**< Their licence; NULL: unspecified. */
    uint32_t threads;                 /**< Worker threads of ssc_bootstrap_run, 0..256; 0: all. */
    uint32_t contact_sheet_entries;   /**< Registrations per contact sheet page, 0..100; 0: none. Default 12. */
    uint32_t fit_segments;            /**< Each round's model fits with its segment shape spaces (as
                                           ssc_registration_def.fit_segments), where it has them. Default 1. */
    const char* posture_model_path;   /**< SSC_POSTURE_SKELETON: each accepted registration is unposed with this
                                           model's fit to its scan (made once per scan, kept in posture_fits/), not
                                           with the round's own fit; the model must share the starting model's mesh,
                                           skeleton and skinning. NULL (default): the built-in model where it shares
                                           them, else the rounds' own fits; "": the rounds' own fits. A model whose
                                           shape space holds no posture poses bodies better than one learned from
                                           posed scans (docs/learning.md, "Posture fits"). */
} ssc_bootstrap_def;

typedef struct ssc_bootstrap ssc_bootstrap;

/** Fills def with defaults; size = sizeof(*def). Threads: any. */
SSC_EXPERIMENTAL void ssc_bootstrap_def_init(ssc_bootstrap_def* def, size_t size);

/**
 * Reads a bootstrapping's inputs: lists the scans, reads the starting model, the decisions and the
 * attributes, and checks the settings. Writes nothing.
 * @param ctx  NULL: a context of its own.
 * @return SSC_ERROR_INVALID_ARGUMENT for a bad def, fewer than 3 scans, duplicate names, decisions
 *         naming no scan, an attribute table without a row for a scan, a bad model; SSC_ERROR_IO.
 */
SSC_EXPERIMENTAL ssc_status ssc_bootstrap_create(ssc_context* ctx, const ssc_bootstrap_def* def, ssc_bootstrap** out);
/** Ends the bootstrapping and releases its output folder (see ssc_bootstrap_prepare). NULL is ignored. */
SSC_EXPERIMENTAL void ssc_bootstrap_destroy(ssc_bootstrap* bootstrap);

/** The scans, as ssc_scan_list_get gives them; strings owned by the bootstrap. */
SSC_EXPERIMENTAL uint32_t ssc_bootstrap_scan_count(const ssc_bootstrap* bootstrap);
SSC_EXPERIMENTAL ssc_status ssc_bootstrap_get_scan(const ssc_bootstrap* bootstrap, uint32_t index, const char** name,
                                                   const char** path, const char** landmarks);

/** Writes round 0's starting model (unless the same bytes are there): the first step of a run
 *  whose registrations are made elsewhere. The first of prepare and run locks the output folder
 *  until ssc_bootstrap_destroy: a second bootstrapping into it (in any process) gets SSC_ERROR_IO
 *  naming the folder, instead of both succeeding and the folder keeping one result. Threads: one
 *  at a time per bootstrap. */
SSC_EXPERIMENTAL ssc_status ssc_bootstrap_prepare(ssc_bootstrap* bootstrap);

/**
 * The registration that round `round` (1..100) makes of scan `index`, as ssc_bootstrap_run makes it:
 * run it with ssc_registration_run_file on a registration of the model at *model_path (round - 1's)
 * with default options but fit_segments as the def's, in any process that sees the same files;
 * ssc_bootstrap_run then reuses it.
 * Makes the round's registrations folder. Strings are owned by the bootstrap and valid until its
 * next call. @return SSC_ERROR_IO when the folder cannot be made.
 */
SSC_EXPERIMENTAL ssc_status ssc_bootstrap_get_job(ssc_bootstrap* bootstrap, uint32_t round, uint32_t index, ssc_scan_file_job* job,
                                                  const char** model_path);

/** Called with each line worth telling (a scan registered, a round's summary); non-zero stops. */
typedef int (*ssc_line_fn)(void* user, const char* line);

/**
 * Runs (or resumes) rounds 1..rounds (1..100): registers what is not registered yet, inspects
 * every registration, writes decisions and contact sheets, learns each round's model; then
 * OUT/model.sscape (the last round's) and OUT/rounds.csv.
 * @return SSC_ERROR_INVALID_ARGUMENT when a round accepts fewer than 3 registrations (its decisions
 *         are on disk to be edited); SSC_ERROR_IO; SSC_ERROR_CANCELLED (resumable).
 * Threads: one at a time per bootstrap.
 */
SSC_EXPERIMENTAL ssc_status ssc_bootstrap_run(ssc_bootstrap* bootstrap, uint32_t rounds, ssc_line_fn progress, void* user);

#ifdef __cplusplus
}
#endif

#endif /* SSCAPE_SSCAPE_OFFLINE_H */

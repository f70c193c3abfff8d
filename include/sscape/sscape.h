/*
 * sscape: statistical 3D human body models (S-SCAPE) behind a stable C ABI.
 *
 * This header is the reference documentation of the library. It compiles as C99 and as C++.
 *
 * Conventions (the whole API, no exceptions):
 *   - Lengths in metres. Right-handed coordinates, +Y up, the body faces +Z, its left is +X
 *     (the glTF convention).
 *   - 4x4 matrices are column-major: 16 floats, m[col * 4 + row]; translation in m[12..14].
 *   - Quaternions are 4 floats x y z w. Axis-angle rotations are 3 floats: unit axis times the
 *     angle in radians.
 *   - A joint's pose rotation is applied in the joint's local frame after its rest orientation:
 *     local = translate(rest offset from parent) * rest_orientation * pose_rotation.
 *     The zero pose (identity rotations, zero translation) gives the rest (unposed) body.
 *   - Shape coefficients are in units of each component's standard deviation.
 *   - Every fallible function returns ssc_status: SSC_OK (0) or a negative error. On error nothing
 *     is written to output arguments, and ssc_last_error() describes what was wrong.
 *   - Output arrays belong to the caller: the caller queries the count, allocates, and passes a
 *     pointer, a capacity in elements and, where given, a stride in bytes (0 = tightly packed).
 *     A capacity smaller than needed gives SSC_ERROR_BUFFER_TOO_SMALL and writes nothing.
 *   - Strings are UTF-8, owned by the object they come from, valid while it lives.
 *   - Booleans are uint32_t (0 = false, anything else = true).
 *
 * Stability (what the version promises):
 *   - Declared with SSC_API: stable. Within one major version (SSC_VERSION_MAJOR, the soname
 *     libsscape.so.MAJOR) a function keeps its name, parameters and meaning, enum values and status
 *     codes are never changed or reused, and structs only grow at their end (struct_size tells the
 *     library which fields a caller knows). A program built against an older minor version runs
 *     against a newer library unchanged.
 *   - Declared with SSC_EXPERIMENTAL: works, is tested and is supported, but its shape may still
 *     change in a minor version (parameters, option fields, defaults, results): fitting, semantic
 *     sliders, bodies made to measure, and what comes next (scan registration). Callers that need a
 *     frozen interface pin the exact library version; SSC_EXPERIMENTAL marks each such declaration
 *     (as meshoptimizer's MESHOPTIMIZER_EXPERIMENTAL does), and a function leaves the experimental
 *     set only by becoming stable.
 *   - Before 1.0 the major version is 0, and the stable set is the one described above: a change to
 *     it would come with a new soname, libsscape.so.1.
 *   - The model file format has its own version (model_format/README.md); any library reads every
 *     file of its container major version.
 *
 * Objects:
 *   ssc_context  allocator, log callback, worker threads. Thread-safe.
 *   ssc_model    an immutable, reference-counted body model. Thread-safe: share it freely.
 *   ssc_body     one body's shape, pose and outputs. Use from one thread at a time; many bodies may
 *                share one model on many threads. A body keeps its model alive, and a model keeps
 *                its context alive, so handles may be released in any order.
 */
#ifndef SSCAPE_SSCAPE_H
#define SSCAPE_SSCAPE_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ---------------------------------------------------------------------------------------------- */
/* Export and version                                                                              */

#if defined(_WIN32)
#  if defined(SSC_BUILD_SHARED)
#    define SSC_API __declspec(dllexport)
#  elif defined(SSC_USE_SHARED)
#    define SSC_API __declspec(dllimport)
#  else
#    define SSC_API
#  endif
#else
#  define SSC_API __attribute__((visibility("default")))
#endif

/** Marks a declaration whose shape may still change in a minor version (see Stability above). */
#define SSC_EXPERIMENTAL SSC_API

#define SSC_VERSION_MAJOR 0
#define SSC_VERSION_MINOR 1
#define SSC_VERSION_PATCH 0
/** The version as one number: major * 10000 + minor * 100 + patch. */
#define SSC_VERSION_NUMBER (SSC_VERSION_MAJOR * 10000 + SSC_VERSION_MINOR * 100 + SSC_VERSION_PATCH)

/**
 * The version of the library actually loaded, as SSC_VERSION_NUMBER. Bindings compare it with the
 * header they were built against.
 * Ownership: none. Threads: any.
 */
SSC_API uint32_t ssc_version(void);

/* ---------------------------------------------------------------------------------------------- */
/* Status and errors                                                                               */

/** Result of every fallible call. Values are fixed forever and never reused. */
typedef enum ssc_status {
    SSC_OK = 0,
    SSC_ERROR_INVALID_ARGUMENT = -1,     /**< NULL where not allowed, NaN/Inf, out of range, bad count. */
    SSC_ERROR_OUT_OF_MEMORY = -2,        /**< An allocation failed. */
    SSC_ERROR_BUFFER_TOO_SMALL = -3,     /**< An output capacity is smaller than needed; nothing written. */
    SSC_ERROR_IO = -4,                   /**< A file could not be opened, read or written. */
    SSC_ERROR_MODEL_CORRUPT = -5,        /**< A model file failed verification (message says where). */
    SSC_ERROR_UNSUPPORTED_VERSION = -6,  /**< A model file of a container version this library cannot read. */
    SSC_ERROR_NOT_FOUND = -7,            /**< An unknown name (joint, landmark, vertex set). */
    SSC_ERROR_CANCELLED = -8,            /**< A progress callback asked to stop. */
    SSC_ERROR_INTERNAL = -9,             /**< A bug in sscape; please report it with ssc_last_error(). */
    SSC_STATUS_FORCE32 = 0x7FFFFFFF
} ssc_status;

/**
 * A static, human-readable name for a status ("SSC_ERROR_MODEL_CORRUPT"); "SSC_UNKNOWN_STATUS" for
 * values this version does not know.
 * Ownership: static storage, never freed. Threads: any.
 */
SSC_API const char* ssc_status_name(ssc_status status);

/**
 * Detail about the last error raised on the calling thread: what was wrong, which argument, which
 * file offset. "" if no call on this thread has failed yet. Successful calls do not clear it.
 * Ownership: thread-local storage of the library, valid until the next failing call on this thread.
 * Threads: each thread has its own message.
 */
SSC_API const char* ssc_last_error(void);

/* ---------------------------------------------------------------------------------------------- */
/* Context                                                                                         */

typedef struct ssc_context ssc_context;

/** Log severities, in increasing order. */
typedef enum ssc_log_level {
    SSC_LOG_DEBUG = 0,
    SSC_LOG_INFO = 1,
    SSC_LOG_WARNING = 2,
    SSC_LOG_ERROR = 3,
    SSC_LOG_LEVEL_FORCE32 = 0x7FFFFFFF
} ssc_log_level;

/**
 * Allocates size bytes aligned to align (a power of two, at most 64). Returns NULL on failure.
 * Called from any thread that uses objects of the context: it must be thread-safe.
 */
typedef void* (*ssc_alloc_fn)(void* user, size_t size, size_t align);
/** Frees memory from the matching ssc_alloc_fn. ptr is never NULL. Must be thread-safe. */
typedef void (*ssc_free_fn)(void* user, void* ptr);
/** Receives a log message (UTF-8, valid only during the call). Must be thread-safe. */
typedef void (*ssc_log_fn)(void* user, ssc_log_level level, const char* message);

/** Options of ssc_context_create. Fill with ssc_context_def_init, then change what you need. */
typedef struct ssc_context_def {
    uint32_t struct_size;       /**< sizeof(ssc_context_def), set by ssc_context_def_init. */
    uint32_t worker_count;      /**< Threads for batch work, caller included. 0 (default) = one per
                                     hardware thread; 1 = run everything on the calling thread. */
    ssc_alloc_fn alloc;         /**< Allocator for model and body storage; NULL (default) = the C heap. */
    ssc_free_fn free;           /**< Required when alloc is set. */
    void* alloc_user;           /**< Passed to alloc and free. */
    ssc_log_fn log;             /**< Log sink; NULL (default) = no logging. */
    void* log_user;             /**< Passed to log. */
    ssc_log_level log_level;    /**< Lowest level passed to log. Default SSC_LOG_WARNING. */
    uint64_t max_model_bytes;   /**< Largest decompressed model accepted, in bytes. 0 (default) = 256 MiB. */
} ssc_context_def;

/**
 * Fills def with defaults. size must be sizeof(*def) as the caller compiled it; the library writes
 * only that many bytes, so callers built against an older header keep working.
 * Ownership: none. Threads: any.
 */
SSC_API void ssc_context_def_init(ssc_context_def* def, size_t size);

/**
 * Creates a context.
 * @param def  options; NULL = all defaults. Only def->struct_size bytes are read.
 * @param out  receives the new context; set only on success.
 * @return SSC_OK, SSC_ERROR_INVALID_ARGUMENT (out NULL, alloc without free, bad struct_size),
 *         SSC_ERROR_OUT_OF_MEMORY.
 * Ownership: the caller owns *out and ends it with ssc_context_destroy. Threads: any.
 */
SSC_API ssc_status ssc_context_create(const ssc_context_def* def, ssc_context** out);

/**
 * Releases the caller's reference to a context. Models loaded with it keep it alive until they are
 * released; its worker threads stop when the last reference goes. NULL is ignored.
 * Ownership: ctx must not be used by the caller afterwards. Threads: any, once per context.
 */
SSC_API void ssc_context_destroy(ssc_context* ctx);

/* ---------------------------------------------------------------------------------------------- */
/* Model                                                                                           */

typedef struct ssc_model ssc_model;

/**
 * Loads a .sscape model file. The file is untrusted: it is verified completely (container,
 * checksum, schema, semantic checks) before the model exists.
 * @param ctx   context for allocation, logging and batch threads; NULL = a private default context.
 * @param path  UTF-8 path of a regular file (a directory, FIFO or device gives SSC_ERROR_IO at once).
 * @param out   receives the model with one reference; set only on success.
 * @return SSC_OK, SSC_ERROR_INVALID_ARGUMENT, SSC_ERROR_IO, SSC_ERROR_MODEL_CORRUPT,
 *         SSC_ERROR_UNSUPPORTED_VERSION, SSC_ERROR_OUT_OF_MEMORY.
 * Ownership: the caller owns one reference to *out, ended by ssc_model_release. Threads: any.
 */
SSC_API ssc_status ssc_model_load_file(ssc_context* ctx, const char* path, ssc_model** out);

/**
 * Loads a model from a .sscape file image in memory; as ssc_model_load_file otherwise.
 * @param data  the bytes; not retained after the call.
 * @param size  their count.
 */
SSC_API ssc_status ssc_model_load_memory(ssc_context* ctx, const void* data, size_t size, ssc_model** out);

/**
 * Loads the default model compiled into the library: an adult body shape space with the 53-bone
 * game-engine skeleton, trained from the CC0 MakeHuman assets (its metadata names the sources).
 * No file is needed. As ssc_model_load_memory otherwise; it is verified like any file.
 * @param ctx  context; NULL = a private default context.
 * @param out  receives the model with one reference; set only on success.
 * Ownership: the caller owns one reference to *out. Threads: any.
 */
SSC_API ssc_status ssc_model_load_default(ssc_context* ctx, ssc_model** out);

/**
 * The default model's .sscape file image, as compiled into the library (what ssc_model_load_default
 * loads; write it out to get the file). Read-only; valid as long as the library is loaded.
 * @param out_data  receives the first byte.
 * @param out_size  receives the size in bytes.
 * Threads: any.
 */
SSC_EXPERIMENTAL ssc_status ssc_default_model_file(const void** out_data, size_t* out_size);

/** Adds a reference. NULL is ignored. Threads: any. */
SSC_API void ssc_model_retain(ssc_model* model);

/** Drops a reference; the model is freed with the last one (bodies hold references). NULL is ignored.
 *  Threads: any. */
SSC_API void ssc_model_release(ssc_model* model);

/* Counts. A NULL model gives 0. Ownership: none. Threads: any. */
SSC_API uint32_t ssc_model_vertex_count(const ssc_model* model);    /**< Body surface vertices. */
SSC_API uint32_t ssc_model_triangle_count(const ssc_model* model);  /**< Triangles of the render mesh. */
SSC_API uint32_t ssc_model_quad_count(const ssc_model* model);      /**< Quads of the authoring mesh, 0 if none. */
SSC_API uint32_t ssc_model_uv_count(const ssc_model* model);        /**< Texture coordinates, 0 if none. */
SSC_API uint32_t ssc_model_joint_count(const ssc_model* model);     /**< Skeleton joints. */
SSC_API uint32_t ssc_model_shape_count(const ssc_model* model);     /**< Shape components. */
SSC_API uint32_t ssc_model_landmark_count(const ssc_model* model);  /**< Named landmarks. */
SSC_API uint32_t ssc_model_vertex_set_count(const ssc_model* model);/**< Named vertex sets. */

/**
 * Copies the triangles: 3 vertex indices each, counter-clockwise seen from outside.
 * @param out       3 * capacity uint32 values.
 * @param capacity  triangles out can hold; at least ssc_model_triangle_count.
 * Ownership: out is the caller's. Threads: any.
 */
SSC_API ssc_status ssc_model_get_triangles(const ssc_model* model, uint32_t* out, uint32_t capacity);

/** Copies the quads: 4 vertex indices each; capacity in quads. As ssc_model_get_triangles. */
SSC_API ssc_status ssc_model_get_quads(const ssc_model* model, uint32_t* out, uint32_t capacity);

/**
 * Copies the texture coordinates, 2 floats (u, v) each; capacity in coordinates. UVs are
 * face-varying: see ssc_model_get_triangle_uvs. SSC_ERROR_NOT_FOUND if the model has none.
 * Ownership: out is the caller's. Threads: any.
 */
SSC_API ssc_status ssc_model_get_uvs(const ssc_model* model, float* out, uint32_t capacity);

/** Copies 3 indices into the UVs per triangle (same order as the triangles); capacity in triangles.
 *  SSC_ERROR_NOT_FOUND if the model has no UVs. Ownership: out is the caller's. Threads: any. */
SSC_API ssc_status ssc_model_get_triangle_uvs(const ssc_model* model, uint32_t* out, uint32_t capacity);

/**
 * Copies the parent of every joint (-1 for the root). Parents precede their children.
 * @param capacity  joints out can hold.
 * Ownership: out is the caller's. Threads: any.
 */
SSC_API ssc_status ssc_model_get_joint_parents(const ssc_model* model, int32_t* out, uint32_t capacity);

/**
 * Gives the name of joint index.
 * @param out  receives a string owned by the model.
 * @return SSC_ERROR_INVALID_ARGUMENT for an index out of range.
 * Ownership: *out lives as long as the model. Threads: any.
 */
SSC_API ssc_status ssc_model_get_joint_name(const ssc_model* model, uint32_t index, const char** out);

/** Finds a joint by exact name. SSC_ERROR_NOT_FOUND if there is none. Threads: any. */
SSC_API ssc_status ssc_model_find_joint(const ssc_model* model, const char* name, uint32_t* out_index);

/** Gives the name of landmark index; as ssc_model_get_joint_name. */
SSC_API ssc_status ssc_model_get_landmark_name(const ssc_model* model, uint32_t index, const char** out);

/** Finds a landmark by exact name. SSC_ERROR_NOT_FOUND if there is none. Threads: any. */
SSC_API ssc_status ssc_model_find_landmark(const ssc_model* model, const char* name, uint32_t* out_index);

/**
 * Copies the landmark positions on the mean shape in the rest pose (metres), 3 floats each.
 * @param capacity  landmarks out can hold. @param stride bytes between landmarks; 0 = 12.
 * Ownership: out is the caller's. Threads: any.
 */
SSC_API ssc_status ssc_model_get_landmark_positions(const ssc_model* model, float* out, uint32_t capacity,
                                                    size_t stride);

/**
 * Gives the name and size of vertex set index (a body part such as "head").
 * @param out_name  receives a string owned by the model; may be NULL.
 * @param out_size  receives the number of vertices; may be NULL.
 * Threads: any.
 */
SSC_API ssc_status ssc_model_get_vertex_set(const ssc_model* model, uint32_t index, const char** out_name,
                                            uint32_t* out_size);

/** Copies the sorted vertex indices of vertex set index; capacity in indices. Threads: any. */
SSC_API ssc_status ssc_model_get_vertex_set_indices(const ssc_model* model, uint32_t index, uint32_t* out,
                                                    uint32_t capacity);

/** Copies each shape component's standard deviation (metres, for a unit-length basis vector);
 *  capacity in components. Threads: any. */
SSC_API ssc_status ssc_model_get_shape_stddevs(const ssc_model* model, float* out, uint32_t capacity);

/** Metadata keys. */
typedef enum ssc_metadata_key {
    SSC_METADATA_NAME = 0,
    SSC_METADATA_VERSION = 1,      /**< The model's own version string. */
    SSC_METADATA_UNITS = 2,        /**< Always "m". */
    SSC_METADATA_AXES = 3,         /**< Always "right-handed, +Y up, +Z forward". */
    SSC_METADATA_LICENSE = 4,
    SSC_METADATA_PROVENANCE = 5,   /**< Where the model came from: data, tools, settings. */
    SSC_METADATA_DESCRIPTION = 6,
    SSC_METADATA_KEY_FORCE32 = 0x7FFFFFFF
} ssc_metadata_key;

/**
 * Gives a metadata string ("" when the file has none).
 * @return SSC_ERROR_INVALID_ARGUMENT for an unknown key.
 * Ownership: *out lives as long as the model. Threads: any.
 */
SSC_API ssc_status ssc_model_get_metadata(const ssc_model* model, ssc_metadata_key key, const char** out);

/* ---------------------------------------------------------------------------------------------- */
/* Body                                                                                            */

typedef struct ssc_body ssc_body;

/** Options of ssc_body_create. Fill with ssc_body_def_init. No options yet: reserved for growth. */
typedef struct ssc_body_def {
    uint32_t struct_size;  /**< sizeof(ssc_body_def), set by ssc_body_def_init. */
    uint32_t reserved;     /**< Must be 0. */
} ssc_body_def;

/** Fills def with defaults; size = sizeof(*def). Threads: any. */
SSC_API void ssc_body_def_init(ssc_body_def* def, size_t size);

/**
 * Creates a body on a model, with the mean shape in the rest pose.
 * @param model  the model; the body takes a reference to it.
 * @param def    options; NULL = defaults.
 * @param out    receives the body; set only on success.
 * Ownership: the caller owns *out, ended by ssc_body_destroy. Threads: any; the body itself is
 * used from one thread at a time.
 */
SSC_API ssc_status ssc_body_create(ssc_model* model, const ssc_body_def* def, ssc_body** out);

/** Destroys a body and drops its model reference. NULL is ignored. Threads: the body's thread. */
SSC_API void ssc_body_destroy(ssc_body* body);

/**
 * The accepted range of a shape coefficient: [-SSC_SHAPE_COEFFICIENT_LIMIT, SSC_SHAPE_COEFFICIENT_LIMIT]
 * standard deviations. A population spans about +-3; beyond a few, bodies stop looking human, and
 * far beyond they grow without bound. Every function that takes shape coefficients refuses values
 * outside this range (SSC_ERROR_INVALID_ARGUMENT, the message gives the range), and every function
 * that computes them (fitting, sliders, made to measure) returns values inside it.
 */
#define SSC_SHAPE_COEFFICIENT_LIMIT 20.0f

/**
 * Sets the shape.
 * @param coefficients  count values in standard deviations, finite and within
 *                      +-SSC_SHAPE_COEFFICIENT_LIMIT; may be NULL when count is 0.
 * @param count         at most ssc_model_shape_count; the remaining components are set to 0.
 * @return SSC_ERROR_INVALID_ARGUMENT for NULL, a count too large or a value out of range; the body
 *         is unchanged then.
 * Threads: the body's thread.
 */
SSC_API ssc_status ssc_body_set_shape(ssc_body* body, const float* coefficients, uint32_t count);

/** Copies the current shape coefficients (standard deviations); capacity in components, at least
 *  ssc_model_shape_count. Threads: the body's thread. */
SSC_API ssc_status ssc_body_get_shape(const ssc_body* body, float* out, uint32_t capacity);

/**
 * Sets the pose from quaternions.
 * @param rotations    4 floats (x y z w) per joint, joint_count joints, in joint order; each is
 *                     normalised; non-finite values or a zero quaternion are an error.
 *                     NULL = identity for every joint.
 * @param joint_count  must equal ssc_model_joint_count (0 allowed when rotations is NULL).
 * @param translation  3 floats added to the whole body (metres); NULL = zero.
 * @return SSC_ERROR_INVALID_ARGUMENT; the body is unchanged on error.
 * Threads: the body's thread.
 */
SSC_API ssc_status ssc_body_set_pose(ssc_body* body, const float* rotations, uint32_t joint_count,
                                     const float* translation);

/**
 * Random plausible shapes: every coefficient standard normal, drawn again while beyond
 * +-truncation standard deviations. The same seed gives the same shapes (what `sscape synth
 * --random N --seed S` writes).
 * @param count       shapes, one after another, each ssc_model_shape_count floats.
 * @param truncation  in (0, SSC_SHAPE_COEFFICIENT_LIMIT]; 2.5 keeps every body plausible.
 * @param out         count * ssc_model_shape_count floats; capacity in floats.
 * Threads: any.
 */
SSC_EXPERIMENTAL ssc_status ssc_model_sample_shapes(const ssc_model* model, uint32_t seed, uint32_t count, float truncation,
                                                    float* out, uint32_t capacity);

/** The unit quaternion (x y z w) of an axis-angle vector (axis times angle, radians), as
 *  ssc_body_set_pose_axis_angle reads them. SSC_ERROR_INVALID_ARGUMENT for non-finite input.
 *  Threads: any. */
SSC_EXPERIMENTAL ssc_status ssc_rotation_from_axis_angle(const float* axis_angle, float* out_xyzw);

/** Sets the pose from axis-angle vectors, 3 floats per joint; otherwise as ssc_body_set_pose. */
SSC_API ssc_status ssc_body_set_pose_axis_angle(ssc_body* body, const float* rotations, uint32_t joint_count,
                                                const float* translation);

/**
 * Copies the posed vertices (metres), 3 floats each, computing what the last shape and pose
 * changes require.
 * @param capacity  vertices out can hold, at least ssc_model_vertex_count.
 * @param stride    bytes from one vertex to the next; 0 = 12; otherwise >= 12 and a multiple of 4.
 * Threads: the body's thread.
 */
SSC_API ssc_status ssc_body_get_vertices(ssc_body* body, float* out, uint32_t capacity, size_t stride);

/** Copies unit vertex normals of the posed mesh (area-weighted over the triangles); as
 *  ssc_body_get_vertices. */
SSC_API ssc_status ssc_body_get_normals(ssc_body* body, float* out, uint32_t capacity, size_t stride);

/** Copies the shaped, unposed vertices; as ssc_body_get_vertices. */
SSC_API ssc_status ssc_body_get_rest_vertices(ssc_body* body, float* out, uint32_t capacity, size_t stride);

/** Copies the posed landmark positions, 3 floats each; capacity in landmarks; as
 *  ssc_body_get_vertices. */
SSC_API ssc_status ssc_body_get_landmarks(ssc_body* body, float* out, uint32_t capacity, size_t stride);

/**
 * Copies each joint's world transform (column-major 4x4, 16 floats per joint): the joint's frame
 * in the posed body. capacity in joints.
 * Threads: the body's thread.
 */
SSC_API ssc_status ssc_body_get_joint_transforms(ssc_body* body, float* out, uint32_t capacity);

/**
 * Copies each joint's inverse bind matrix: the inverse of its world transform in the rest pose of
 * the current shape (column-major 4x4). capacity in joints. Threads: the body's thread.
 */
SSC_API ssc_status ssc_body_get_inverse_bind_matrices(ssc_body* body, float* out, uint32_t capacity);

/**
 * Copies the skinning matrices (world transform x inverse bind, column-major 4x4) for engines that
 * skin on the GPU: posed vertex = sum_i weight_i * M[joint_i] * rest vertex. capacity in joints.
 * Threads: the body's thread.
 */
SSC_API ssc_status ssc_body_get_skinning_matrices(ssc_body* body, float* out, uint32_t capacity);

/**
 * Copies the skin: 4 joint indices and 4 weights (summing to 1) per vertex.
 * @param joints   4 * capacity values; may be NULL. @param weights 4 * capacity values; may be NULL.
 * @param capacity vertices the arrays can hold.
 * Threads: any.
 */
SSC_API ssc_status ssc_model_get_skin(const ssc_model* model, uint16_t* joints, float* weights, uint32_t capacity);

/* ---------------------------------------------------------------------------------------------- */
/* Body files (SSC_EXPERIMENTAL: may change in a minor version)                                    */
/* ---------------------------------------------------------------------------------------------- */

/** File formats of ssc_body_write_file. */
typedef enum ssc_file_format {
    SSC_FILE_FORMAT_BY_EXTENSION = 0, /**< From the path: .obj, .ply or .glb (any case). */
    SSC_FILE_OBJ = 1,  /**< Wavefront OBJ: posed positions, normals, UVs when the model has them. */
    SSC_FILE_PLY = 2,  /**< Binary little-endian PLY: posed positions, normals, triangles. */
    SSC_FILE_GLB = 3,  /**< Binary glTF 2.0: the shaped body in its bind pose with normals and UVs, the
                            skeleton as nodes posed by the body's pose, and the skin; engines and
                            Blender import a rigged, posed character. */
    SSC_FILE_FORMAT_FORCE32 = 0x7FFFFFFF
} ssc_file_format;

/**
 * Writes the body, with its current shape and pose, to a file.
 * @param path    UTF-8 file path; written through a temporary file, so it appears whole or not at all.
 * @param format  an ssc_file_format; SSC_FILE_FORMAT_BY_EXTENSION takes it from the path.
 * @return SSC_ERROR_INVALID_ARGUMENT for NULL, an unknown format or extension (the message names
 *         the formats); SSC_ERROR_IO when the file cannot be written.
 * Ownership: none kept. Threads: the body's thread.
 */
SSC_EXPERIMENTAL ssc_status ssc_body_write_file(ssc_body* body, const char* path, ssc_file_format format);

/* ---------------------------------------------------------------------------------------------- */
/* Named poses                                                                                     */

/** Number of named poses this library version knows ("a_pose", "t_pose", "sitting",
 *  "arms_raised", ...); indices 0 .. count-1 are stable, new poses are appended. Threads: any. */
SSC_API uint32_t ssc_named_pose_count(void);

/**
 * Describes a named pose.
 * @param index            below ssc_named_pose_count().
 * @param out_name         out, may be NULL: snake_case name, as ssc_model_get_named_pose takes.
 * @param out_description  out, may be NULL: one sentence.
 * Ownership: static strings, never freed. Threads: any.
 */
SSC_API ssc_status ssc_named_pose_get_info(uint32_t index, const char** out_name, const char** out_description);

/**
 * The local joint rotations of a named pose for this model's rig, as ssc_body_set_pose takes them
 * (4 floats x y z w per joint; identity for joints the pose does not move). The poses are defined
 * by anatomical joint angles within the joints' ranges of motion.
 * @param name            a named pose; SSC_ERROR_NOT_FOUND for an unknown one.
 * @param rotations       out: 4 * joint_capacity floats.
 * @param joint_capacity  at least ssc_model_joint_count.
 * Threads: any.
 */
SSC_API ssc_status ssc_model_get_named_pose(const ssc_model* model, const char* name, float* rotations,
                                            uint32_t joint_capacity);

/**
 * Closes the hands of a pose: sets the finger joints' rotations (thumb, index, middle, ring,
 * pinky; 4 floats x y z w per joint, as ssc_body_set_pose takes) to each hand closed by its
 * closure, 0 the model's open hand, 1 a loose fist; every other joint is left as it is, so it
 * composes with a named pose. Each finger segment flexes towards the palm about the axis across it.
 * @param left_closure, right_closure  in [0, 1]; SSC_ERROR_INVALID_ARGUMENT otherwise.
 * @param rotations       in/out: 4 * joint_count floats.
 * @param joint_count     ssc_model_joint_count.
 * A rig without the game-engine hand joints (hand_l, index_01_l, pinky_01_l, ...) is left
 * unchanged. Threads: any.
 */
SSC_EXPERIMENTAL ssc_status ssc_model_close_hands(const ssc_model* model, float left_closure, float right_closure,
                                                  float* rotations, uint32_t joint_count);

/* ---------------------------------------------------------------------------------------------- */
/* Joint limits                                                                                    */

/**
 * The anatomical range of motion of a joint, as the model file stores it. A local joint rotation
 * (relative to the rest orientation) with rotation vector r (axis times angle, radians, angle in
 * [0, pi]) has the anatomical angles a = frame * r: a[0] flexion (+) / extension (-), a[1] axial
 * rotation about the bone, a[2] abduction / adduction; right-side joints are mirrored so that one
 * convention serves both sides. The rotation is within the limit when lower[i] <= a[i] <= upper[i].
 * The default model's ranges follow the AAOS average ranges of motion (Greene & Heckman, The
 * Clinical Measurement of Joint Motion, 1994), measured from the rest pose (the A-pose).
 */
typedef struct ssc_joint_limit {
    uint32_t limited;   /**< 0: the joint has no limit (the other fields are then zero). */
    float frame[9];     /**< Row-major 3x3 rotation from the rotation vector to anatomical angles. */
    float lower[3];     /**< Radians: flexion, axial rotation, abduction. */
    float upper[3];     /**< Radians, >= lower. */
} ssc_joint_limit;

/**
 * A joint's limit.
 * @param joint  below ssc_model_joint_count.
 * @param out    out: written whole; out->limited = 0 for a joint without a limit (fingers, root).
 * Threads: any.
 */
SSC_API ssc_status ssc_model_get_joint_limit(const ssc_model* model, uint32_t joint, ssc_joint_limit* out);

/** What ssc_body_set_pose_limited does with rotations beyond the joints' limits. */
typedef enum ssc_limit_mode {
    SSC_LIMITS_REJECT = 0,  /**< Sets nothing and returns SSC_ERROR_INVALID_ARGUMENT naming the first joint and angle. */
    SSC_LIMITS_CLAMP = 1,   /**< Clamps each anatomical angle into its range, then sets the pose. */
    SSC_LIMIT_MODE_FORCE32 = 0x7FFFFFFF
} ssc_limit_mode;

/**
 * Sets the pose as ssc_body_set_pose does, enforcing the joint limits.
 * @param rotations            4 floats (x y z w) per joint, joint_count joints; must not be NULL.
 * @param joint_count          must equal ssc_model_joint_count.
 * @param translation          3 floats (metres); NULL = zero.
 * @param mode                 reject or clamp.
 * @param out_violation_count  out, may be NULL: joints that were outside their limits (also written
 *                             when the pose is rejected).
 * @return SSC_ERROR_INVALID_ARGUMENT for bad input or a rejected pose; the body is unchanged then.
 * Threads: the body's thread.
 */
SSC_API ssc_status ssc_body_set_pose_limited(ssc_body* body, const float* rotations, uint32_t joint_count,
                                             const float* translation, ssc_limit_mode mode,
                                             uint32_t* out_violation_count);

/* ---------------------------------------------------------------------------------------------- */
/* Body measurements                                                                               */

/**
 * The measurements a body gives, as a tailor or an anthropometric survey takes them (definitions
 * after ISO 8559-1 and ISO 7250-1; ssc_measurement_get_info returns each one's definition). Taken on
 * the body's shape in the rest pose, whatever its current pose; limbs on the right side. Girths are
 * tape girths: the convex hull of the body's section, as a tape spans concavities.
 * Values are fixed forever; new measurements are appended.
 */
typedef enum ssc_measurement {
    SSC_MEASUREMENT_STATURE = 0,           /**< Floor to the top of the head, m. */
    SSC_MEASUREMENT_CHEST_GIRTH = 1,       /**< Bust/chest girth at bust point height, m. */
    SSC_MEASUREMENT_UNDERBUST_GIRTH = 2,   /**< Girth just below the breasts, m. */
    SSC_MEASUREMENT_WAIST_GIRTH = 3,       /**< Girth midway between lowest rib and iliac crest, m. */
    SSC_MEASUREMENT_HIP_GIRTH = 4,         /**< Girth at the greatest buttock protrusion, m. */
    SSC_MEASUREMENT_NECK_GIRTH = 5,        /**< Neck girth perpendicular to the neck, m. */
    SSC_MEASUREMENT_THIGH_GIRTH = 6,       /**< Right thigh just below the gluteal fold, m. */
    SSC_MEASUREMENT_CALF_GIRTH = 7,        /**< Right calf, maximum, m. */
    SSC_MEASUREMENT_UPPER_ARM_GIRTH = 8,   /**< Right upper arm midway acromion-olecranon, m. */
    SSC_MEASUREMENT_WRIST_GIRTH = 9,       /**< Right wrist over the styloid processes, m. */
    SSC_MEASUREMENT_INSEAM = 10,           /**< Crotch height above the floor, m. */
    SSC_MEASUREMENT_ARM_LENGTH = 11,       /**< Right acromion over the elbow to the wrist, m. */
    SSC_MEASUREMENT_SHOULDER_BREADTH = 12, /**< Biacromial breadth, m. */
    SSC_MEASUREMENT_SURFACE_AREA = 13,     /**< Body surface area, m^2. */
    SSC_MEASUREMENT_VOLUME = 14,           /**< Enclosed volume, m^3. */
    SSC_MEASUREMENT_MASS = 15,             /**< Volume x 1010 kg/m^3, kg. */
    SSC_MEASUREMENT_FORCE32 = 0x7FFFFFFF
} ssc_measurement;

/** Units of measurements. */
typedef enum ssc_unit {
    SSC_UNIT_METRE = 0,
    SSC_UNIT_SQUARE_METRE = 1,
    SSC_UNIT_CUBIC_METRE = 2,
    SSC_UNIT_KILOGRAM = 3,
    SSC_UNIT_FORCE32 = 0x7FFFFFFF
} ssc_unit;

/** Number of measurements this library version knows (values 0 .. count-1). Threads: any. */
SSC_API uint32_t ssc_measurement_count(void);

/**
 * Describes a measurement.
 * @param measurement an ssc_measurement value below ssc_measurement_count().
 * @param out_name       out, may be NULL: snake_case name ("waist_girth"), as sscape measure prints.
 * @param out_unit       out, may be NULL.
 * @param out_definition out, may be NULL: how it is taken and after which standard, one sentence or two.
 * Ownership: static strings, never freed. Threads: any.
 */
SSC_API ssc_status ssc_measurement_get_info(uint32_t measurement, const char** out_name, ssc_unit* out_unit,
                                            const char** out_definition);

/** Finds a measurement by its name; SSC_ERROR_NOT_FOUND for an unknown one. Threads: any. */
SSC_API ssc_status ssc_measurement_find(const char* name, uint32_t* out_measurement);

/**
 * Measures the body: every measurement, out[m] for measurement m, in the units of ssc_unit (SI).
 * @param out       capacity floats; at least ssc_measurement_count().
 * Errors: SSC_ERROR_NOT_FOUND when the model lacks the landmarks, joints or body-part vertex sets the
 * definitions need (the message names them); SSC_ERROR_INVALID_ARGUMENT for a body larger than 5 m
 * along any axis of its rest pose (a shape far outside the population, or a model in other units).
 * Nothing is written on error. The work is bounded by the mesh, whatever the body's size.
 * Threads: the body's thread.
 */
SSC_API ssc_status ssc_body_measure(ssc_body* body, float* out, uint32_t capacity);

/** Measures one measurement given by name (as ssc_measurement_find); otherwise as ssc_body_measure.
 *  Threads: the body's thread. */
SSC_API ssc_status ssc_body_measure_by_name(ssc_body* body, const char* name, float* out);

/* ---------------------------------------------------------------------------------------------- */
/* Semantic sliders (SSC_EXPERIMENTAL: may change in a minor version)                              */

/**
 * Sliders set a body by what people understand (stature, mass, age, sex, muscularity, proportions)
 * instead of anonymous shape coefficients. The model file stores them, learned over its training
 * population: each slider is a direction in the shape space (coefficients per unit of the slider,
 * the other sliders held), so moving one slider changes that slider's value and leaves the others'
 * values where they were. A body's slider values are read from its shape by least squares; a
 * shape made by sliders reads back exactly. A model may have none (count 0).
 */
typedef struct ssc_slider_info {
    uint32_t struct_size;     /**< Set by the caller: sizeof(ssc_slider_info). */
    const char* name;         /**< snake_case ("stature", "mass", "age", "sex", "muscle", ...). */
    const char* unit;         /**< "m", "kg", "years", or "" for a fraction (sex: 0 female, 1 male). */
    const char* description;  /**< One sentence. */
    float mean;               /**< The training population's mean: the mean body's value. */
    float minimum;            /**< 0.5th percentile of the population: a slider's useful range ... */
    float maximum;            /**< ... to the 99.5th percentile. Values beyond extrapolate, within the
                                   accepted range: minimum - (maximum - minimum) to
                                   maximum + (maximum - minimum). */
} ssc_slider_info;

/** Number of sliders the model has. Threads: any. */
SSC_EXPERIMENTAL uint32_t ssc_model_slider_count(const ssc_model* model);

/**
 * Describes a slider.
 * @param index  below ssc_model_slider_count.
 * @param out    out: out->struct_size must be set; only that many bytes are written.
 * Ownership: strings owned by the model. Threads: any.
 */
SSC_EXPERIMENTAL ssc_status ssc_model_get_slider_info(const ssc_model* model, uint32_t index, ssc_slider_info* out);

/** Finds a slider by name; SSC_ERROR_NOT_FOUND for a name the model lacks. Threads: any. */
SSC_EXPERIMENTAL ssc_status ssc_model_find_slider(const ssc_model* model, const char* name, uint32_t* out_index);

/**
 * The body's slider values (read from its shape), in slider order.
 * @param out       capacity floats; at least ssc_model_slider_count.
 * Threads: the body's thread.
 */
SSC_EXPERIMENTAL ssc_status ssc_body_get_sliders(const ssc_body* body, float* out, uint32_t capacity);

/**
 * Moves one slider to a value, keeping the rest of the body's shape (and the other sliders' values).
 * @param index  below ssc_model_slider_count.
 * @param value  in the slider's unit, within its accepted range (ssc_slider_info: the population's
 *               range widened by its own width on each side; stature 1.5 to 1.95 m accepts 1.05 to 2.4 m).
 * @return SSC_ERROR_INVALID_ARGUMENT for a value outside the accepted range (the message gives the
 *         range) or one that would take a shape coefficient beyond SSC_SHAPE_COEFFICIENT_LIMIT; the
 *         body is unchanged then.
 * Threads: the body's thread.
 */
SSC_EXPERIMENTAL ssc_status ssc_body_set_slider(ssc_body* body, uint32_t index, float value);

/**
 * Replaces the body's shape by the one the slider values give (every slider, in slider order): the
 * population's typical body with those values.
 * @param values  count values, each within its slider's accepted range (as ssc_body_set_slider).
 * @param count   must equal ssc_model_slider_count.
 * Threads: the body's thread.
 */
SSC_EXPERIMENTAL ssc_status ssc_body_set_sliders(ssc_body* body, const float* values, uint32_t count);

/* ---------------------------------------------------------------------------------------------- */
/* Levels of detail (SSC_EXPERIMENTAL: may change in a minor version)                              */

/**
 * Levels of detail: coarser meshes of the same body for engines (a simplified template, MakeHuman's
 * proxy meshes). Level 0 is the full mesh; levels 1 .. count-1 the model's, finest first. Every
 * vertex of a level is a fixed affine combination of at most 4 body vertices (the same for every
 * body), so a level follows every shape exactly; it is posed by its own skin of at most 4
 * influences, as an engine poses it, and costs in proportion to its vertices. The functions below
 * all accept level 0 and then give what the full mesh's functions give.
 */
typedef struct ssc_level_info {
    uint32_t struct_size;     /**< Set by the caller: sizeof(ssc_level_info). */
    const char* name;         /**< "full" for level 0, else the level's ("simplified", "proxy741"; owned by the model). */
    uint32_t vertex_count;    /**< Vertices of the level. */
    uint32_t triangle_count;  /**< Triangles of the level. */
    uint32_t uv_count;        /**< Texture coordinates (face-varying), 0 if none. */
} ssc_level_info;

/** Number of levels, the full mesh included (so at least 1). 0 for NULL. Threads: any. */
SSC_EXPERIMENTAL uint32_t ssc_model_level_count(const ssc_model* model);

/**
 * Describes a level.
 * @param level  below ssc_model_level_count.
 * @param out    out: out->struct_size must be set; only that many bytes are written.
 * Threads: any.
 */
SSC_EXPERIMENTAL ssc_status ssc_model_get_level_info(const ssc_model* model, uint32_t level, ssc_level_info* out);

/** A level's triangles, 3 vertex indices each (counter-clockwise from outside); capacity in
 *  triangles. As ssc_model_get_triangles. Threads: any. */
SSC_EXPERIMENTAL ssc_status ssc_model_get_level_triangles(const ssc_model* model, uint32_t level, uint32_t* out, uint32_t capacity);

/** A level's texture coordinates, 2 floats each; capacity in coordinates. SSC_ERROR_NOT_FOUND if
 *  the level has none. Threads: any. */
SSC_EXPERIMENTAL ssc_status ssc_model_get_level_uvs(const ssc_model* model, uint32_t level, float* out, uint32_t capacity);

/** A level's 3 UV indices per triangle; capacity in triangles. SSC_ERROR_NOT_FOUND if the level has
 *  no UVs. Threads: any. */
SSC_EXPERIMENTAL ssc_status ssc_model_get_level_triangle_uvs(const ssc_model* model, uint32_t level, uint32_t* out, uint32_t capacity);

/**
 * A level's skin: 4 joint indices and 4 weights (summing to 1) per level vertex.
 * @param joints  4 * capacity values; may be NULL. @param weights 4 * capacity values; may be NULL.
 * @param capacity  level vertices the arrays can hold.
 * Threads: any.
 */
SSC_EXPERIMENTAL ssc_status ssc_model_get_level_skin(const ssc_model* model, uint32_t level, uint16_t* joints, float* weights,
                                                     uint32_t capacity);

/**
 * How a level is made of the body: 4 body vertex indices and 4 weights (summing to 1; unused slots
 * 0) per level vertex; level vertex = sum of weight x body vertex. Level 0 gives each vertex itself.
 * What tools need to carry data between levels.
 * @param vertices  4 * capacity values; may be NULL. @param weights 4 * capacity values; may be NULL.
 * Threads: any.
 */
SSC_EXPERIMENTAL ssc_status ssc_model_get_level_sources(const ssc_model* model, uint32_t level, uint32_t* vertices, float* weights,
                                                        uint32_t capacity);

/**
 * Where each of the model's landmarks lies on a level: the level's triangle and 3 barycentric
 * weights (summing to 1) per landmark, in the model's landmark order. Level 0 gives each landmark's
 * place on the full mesh (a vertex landmark as a corner of one of its triangles).
 * @param triangles    capacity values; may be NULL. @param barycentric 3 * capacity values; may be NULL.
 * @param capacity     landmarks the arrays hold, at least ssc_model_landmark_count.
 * Threads: any.
 */
SSC_EXPERIMENTAL ssc_status ssc_model_get_level_landmarks(const ssc_model* model, uint32_t level, uint32_t* triangles, float* barycentric,
                                                          uint32_t capacity);

/** The posed vertices of a level (metres), 3 floats each; capacity in the level's vertices; as
 *  ssc_body_get_vertices. Threads: the body's thread. */
SSC_EXPERIMENTAL ssc_status ssc_body_get_level_vertices(ssc_body* body, uint32_t level, float* out, uint32_t capacity, size_t stride);

/** Unit normals of a level's posed mesh (area-weighted); as ssc_body_get_level_vertices. */
SSC_EXPERIMENTAL ssc_status ssc_body_get_level_normals(ssc_body* body, uint32_t level, float* out, uint32_t capacity, size_t stride);

/** The shaped, unposed vertices of a level; as ssc_body_get_level_vertices. */
SSC_EXPERIMENTAL ssc_status ssc_body_get_level_rest_vertices(ssc_body* body, uint32_t level, float* out, uint32_t capacity,
                                                             size_t stride);

/** ssc_body_write_level_file's level for every level in one GLB file. */
#define SSC_LEVEL_ALL 0xFFFFFFFFu

/**
 * Writes a level of the body as ssc_body_write_file writes the full mesh (its triangles, UVs and,
 * in GLB, its skin). level SSC_LEVEL_ALL writes every level into one GLB file, one node per level
 * on the one skeleton, named NAME_LOD0 (the full mesh), NAME_LOD1, ... as engines' importers expect;
 * SSC_ERROR_INVALID_ARGUMENT for OBJ or PLY. Ownership: none kept. Threads: the body's thread.
 */
SSC_EXPERIMENTAL ssc_status ssc_body_write_level_file(ssc_body* body, uint32_t level, const char* path, ssc_file_format format);

/** Shape morph targets in a GLB file (ssc_export_def::morphs). */
typedef enum ssc_morphs {
    SSC_MORPHS_NONE = 0,       /**< None (the default). */
    SSC_MORPHS_COMPONENTS = 1, /**< The first morph_count whole-body shape components; weight 1 = +1
                                    standard deviation of the component. */
    SSC_MORPHS_SLIDERS = 2,    /**< The semantic sliders (ssc_model_slider_count; morph_count 0: all, else
                                    the first morph_count); weight 1 = +1 population standard deviation
                                    of the slider's attribute, the other sliders held. */
    SSC_MORPHS_FORCE32 = 0x7FFFFFFF
} ssc_morphs;

/** Options of ssc_body_export. Fill with ssc_export_def_init; append-only. */
typedef struct ssc_export_def {
    uint32_t struct_size;   /**< Set by ssc_export_def_init. */
    ssc_file_format format; /**< Default SSC_FILE_FORMAT_BY_EXTENSION. */
    uint32_t level;         /**< Default 0 (the full mesh); a level of detail, or SSC_LEVEL_ALL (GLB only). */
    ssc_morphs morphs;      /**< Default SSC_MORPHS_NONE; morph targets are GLB only. */
    uint32_t morph_count;   /**< How many components, or sliders (0: all); default 0. */
} ssc_export_def;

/** Fills def with the defaults (size: sizeof *def). Threads: any. */
SSC_EXPERIMENTAL void ssc_export_def_init(ssc_export_def* def, size_t size);

/**
 * Writes the body as ssc_body_write_level_file does, with options; def NULL: the defaults.
 * With morph targets every mesh of the GLB carries one target per component or slider around the
 * body's shape (positions exactly, as the shape is linear in its coefficients; normals to first
 * order), named in the mesh's extras.targetNames ("component_1", ..., or the sliders' attribute
 * names), weights 0. An engine that changes the weights moves the joints with the shape from
 * skins[0].extras.sscape_morphs: per target, each joint node's translation change and each
 * inverse bind matrix's translation change per unit of weight (docs/engines.md). Every GLB vertex
 * carries _MODEL_VERTEX, the index of the level's vertex it was split from at a UV seam.
 * SSC_ERROR_INVALID_ARGUMENT for morph targets in OBJ or PLY, more components or sliders than the
 * model has, or sliders of a model without them; nothing is written then.
 * Ownership: none kept. Threads: the body's thread.
 */
SSC_EXPERIMENTAL ssc_status ssc_body_export(ssc_body* body, const char* path, const ssc_export_def* def);

/* ---------------------------------------------------------------------------------------------- */
/* Segment shape spaces (SSC_EXPERIMENTAL: may change in a minor version)                          */

/**
 * A model may hold, beside its whole-body shape space, one shape space per body segment (trained
 * models: head, arm_l, arm_r, torso, leg_l, leg_r), each a PCA over that segment's vertices alone:
 * an arm's own variation, which the whole-body components mix with the rest of the body. Segments
 * overlap in bands around their borders where each vertex's weights blend smoothly from one
 * segment to the next, so bodies made from segment coefficients have no seams. Each segment's
 * shape is its own (learned in its own rigid frame, anchored where it attaches): a longer leg keeps
 * its hip where it was and reaches lower; the torso's components carry the head and limbs along
 * where they attach. A body's rest shape
 * is the whole-body shape (ssc_body_set_shape) plus every segment's blended shape; segment
 * coefficients start at 0, stay until set again, and are not changed by whole-body setters, sliders,
 * made to measure or fitting. A model may have no segments (count 0).
 */
typedef struct ssc_segment_info {
    uint32_t struct_size;    /**< Set by the caller: sizeof(ssc_segment_info). */
    const char* name;        /**< "head", "arm_l", ... (owned by the model). */
    uint32_t shape_count;    /**< The segment's components (standard deviations, as the body's). */
    uint32_t vertex_count;   /**< Vertices its components move: its own and its blend bands; for the
                                  torso the whole body, whose limbs and head ride on it. */
} ssc_segment_info;

/** Number of segment shape spaces. Threads: any. */
SSC_EXPERIMENTAL uint32_t ssc_model_segment_count(const ssc_model* model);

/**
 * Describes segment index (below ssc_model_segment_count).
 * @param out  out: out->struct_size must be set; only that many bytes are written.
 * Threads: any.
 */
SSC_EXPERIMENTAL ssc_status ssc_model_get_segment_info(const ssc_model* model, uint32_t index, ssc_segment_info* out);

/** Finds a segment by name; SSC_ERROR_NOT_FOUND for a name the model lacks. Threads: any. */
SSC_EXPERIMENTAL ssc_status ssc_model_find_segment(const ssc_model* model, const char* name, uint32_t* out_index);

/**
 * Copies the vertices segment index moves and their blend weights: how much of each vertex belongs
 * to the segment, in [0, 1] (0 where it only rides along; a vertex's weights over all segments sum
 * to 1): vertex_count entries (ssc_segment_info) each. What to colour to show the segments.
 * @param vertices  out, may be NULL: sorted vertex indices.
 * @param weights   out, may be NULL: blend weights, in the same order.
 * @param capacity  entries each array holds.
 * Threads: any.
 */
SSC_EXPERIMENTAL ssc_status ssc_model_get_segment_vertices(const ssc_model* model, uint32_t index, uint32_t* vertices,
                                                           float* weights, uint32_t capacity);

/**
 * Sets one segment's coefficients.
 * @param segment       below ssc_model_segment_count.
 * @param coefficients  count values in standard deviations, finite and within
 *                      +-SSC_SHAPE_COEFFICIENT_LIMIT; may be NULL when count is 0.
 * @param count         at most the segment's shape_count; its remaining components are set to 0.
 * @return SSC_ERROR_INVALID_ARGUMENT for a bad segment, count or value; the body is unchanged then.
 * Threads: the body's thread.
 */
SSC_EXPERIMENTAL ssc_status ssc_body_set_segment_shape(ssc_body* body, uint32_t segment, const float* coefficients,
                                                       uint32_t count);

/** Copies one segment's coefficients; capacity at least its shape_count. Threads: the body's thread. */
SSC_EXPERIMENTAL ssc_status ssc_body_get_segment_shape(const ssc_body* body, uint32_t segment, float* out,
                                                       uint32_t capacity);

/* ---------------------------------------------------------------------------------------------- */
/* Bodies made to measure (SSC_EXPERIMENTAL: may change in a minor version)                        */

/** Options of ssc_body_make_to_measure. Initialise with ssc_made_to_measure_def_init. */
typedef struct ssc_made_to_measure_def {
    uint32_t struct_size;     /**< Set by ssc_made_to_measure_def_init. */
    float sex;                /**< 0 female, 1 male; NaN (the default) = unknown. */
    float age;                /**< Years; NaN (the default) = unknown. */
    uint32_t max_iterations;  /**< Refinement iterations; default 15. */
    float tolerance;          /**< Metres: stop when every requested length is this close; default 0.0005. */
} ssc_made_to_measure_def;

/** Fills def with the defaults; size = sizeof *def. Threads: any. */
SSC_EXPERIMENTAL void ssc_made_to_measure_def_init(ssc_made_to_measure_def* def, size_t size);

/**
 * Sets the body's shape to reproduce the requested measurements (any subset, each at most once).
 * A regression learned over the training population (from the requested measurements, and sex and
 * age when given) gives the start; Levenberg-Marquardt on the measurement functions refines it.
 * On the default model, stature, chest, waist and hip girth of held-out bodies are reached within a
 * millimetre (sscape train prints the figures).
 * @param measurements  count ssc_measurement values.
 * @param values        count targets, in the measurements' units (SI). Where the model's attributes
 *                      describe the measurement (stature, girths, mass: the sliders' statistics), within
 *                      the population's range widened by its width on each side, as for sliders;
 *                      otherwise positive and at most 5 m, 10 m^2, 1 m^3 or 1000 kg. Values outside
 *                      give SSC_ERROR_INVALID_ARGUMENT with the accepted range.
 * @param count         at least 1.
 * @param def           may be NULL (defaults).
 * @param achieved      out, may be NULL: every measurement of the result (as ssc_body_measure).
 * @param achieved_capacity  0 when achieved is NULL, else at least ssc_measurement_count.
 * @param out_converged out, may be NULL: 1 when every requested value was reached within the tolerance.
 *                      Not reaching it is not an error (the request may be impossible for a body).
 * @return SSC_ERROR_INVALID_ARGUMENT for bad input, SSC_ERROR_NOT_FOUND when the model lacks what the
 *         measurements need; the body is unchanged on error.
 * Threads: the body's thread. Takes about 0.1 s on one core (the measurements are re-taken per step).
 */
SSC_EXPERIMENTAL ssc_status ssc_body_make_to_measure(ssc_body* body, const uint32_t* measurements, const float* values,
                                            uint32_t count, const ssc_made_to_measure_def* def, float* achieved,
                                            uint32_t achieved_capacity, uint32_t* out_converged);

/* ---------------------------------------------------------------------------------------------- */
/* Batch synthesis                                                                                 */

/** Rotation formats of pose arrays. */
typedef enum ssc_rotation_format {
    SSC_ROTATION_QUATERNION = 0,  /**< 4 floats x y z w per joint. */
    SSC_ROTATION_AXIS_ANGLE = 1,  /**< 3 floats per joint. */
    SSC_ROTATION_FORMAT_FORCE32 = 0x7FFFFFFF
} ssc_rotation_format;

/**
 * Describes a batch: body_count bodies, body i built from its shape, pose and translation.
 * Fill with ssc_batch_desc_init. All arrays are the caller's and are only used during the call.
 * Batches take whole-body shapes only; segment shapes are set per body (ssc_body_set_segment_shape).
 */
typedef struct ssc_batch_desc {
    uint32_t struct_size;            /**< sizeof(ssc_batch_desc), set by ssc_batch_desc_init. */
    uint32_t body_count;             /**< Number of bodies. */
    const float* shapes;             /**< body_count * shape_count coefficients; NULL = mean shapes. */
    uint32_t shape_count;            /**< Coefficients per body, <= ssc_model_shape_count. */
    ssc_rotation_format pose_format; /**< Format of poses. Default SSC_ROTATION_QUATERNION. */
    const float* poses;              /**< body_count * joint_count rotations; NULL = rest pose. */
    const float* translations;       /**< body_count * 3 floats; NULL = zero. */
    float* vertices;                 /**< Out: body_count * vertex_count * 3 floats, body after body (the level's vertex count with level). */
    size_t vertices_capacity;        /**< Vertices the buffer holds: >= body_count * vertex_count. */
    float* normals;                  /**< Optional out (NULL = skip), laid out like vertices. */
    size_t normals_capacity;         /**< Vertices normals holds. */
    uint32_t level;                  /**< Level of detail (ssc_model_level_count): 0 the full mesh (default);
                                          the outputs then hold the level's vertices, as
                                          ssc_body_get_level_vertices / _normals give them. */
} ssc_batch_desc;

/** Fills desc with defaults (no bodies); size = sizeof(*desc). Threads: any. */
SSC_API void ssc_batch_desc_init(ssc_batch_desc* desc, size_t size);

/**
 * Synthesizes many bodies on the worker threads of the model's context. The results equal what
 * ssc_body_get_vertices / ssc_body_get_normals give for the same parameters.
 * All inputs are checked before anything is written: on error the outputs are untouched.
 * Threads: any; concurrent batches on one context share its workers.
 */
SSC_API ssc_status ssc_model_synthesize_batch(const ssc_model* model, const ssc_batch_desc* desc);


/* ---------------------------------------------------------------------------------------------- */
/* Fitting (SSC_EXPERIMENTAL: may change in a minor version)                                       */

/**
 * A fitter finds the shape, pose (per-joint rotations), translation and optionally a global scale
 * that best explain measurements of one person: landmarks, point clouds or scans, in one or more
 * frames. All frames share one shape; each has its own pose. Observations are added, then
 * ssc_fitter_solve runs; results are read per frame. Many fitters may share one model.
 */
typedef struct ssc_fitter ssc_fitter;

/** Options of ssc_fitter_create. Fill with ssc_fitter_def_init; append-only. */
typedef struct ssc_fitter_def {
    uint32_t struct_size;     /**< sizeof(ssc_fitter_def), set by ssc_fitter_def_init. */
    uint32_t shape_count;     /**< Shape components solved for; 0 (default) = all of the model's. */
    uint32_t fit_scale;       /**< Non-zero: solve a global scale too (data in unknown units). Default 0. */
    uint32_t max_iterations;  /**< Levenberg-Marquardt iterations over all stages. Default 60. */
    float landmark_sigma;     /**< Expected landmark placement error, metres (> 0). Default 0.01. */
    float point_sigma;        /**< Expected scan noise plus model error, metres (> 0). Default 0.004. */
    float shape_prior;        /**< Weight of the Gaussian shape prior (>= 0; 1 = the model's own). Default 1. */
    float pose_prior;         /**< Weight of the joint rotation prior (>= 0). Default 1. */
    uint32_t max_points;      /**< Scan points used per iteration, a fixed random subset (>= 16). Default 3000. */
    uint32_t seed;            /**< Seed of that subset. Default 1. */
    uint32_t joint_limits;    /**< Non-zero: keep joints within anatomical ranges of motion (AAOS averages;
                                   soft walls in the pose prior). Default 1. */
    uint32_t fit_segments;    /**< Non-zero: the model's segment shape spaces (ssc_model_segment_count), when it
                                   has them and shape_count is all of its components, join the whole body's
                                   in the fit's last stages, for people whose proportions the whole body's
                                   cannot hold (ssc_fitter_get_segment_shape reads them). Default 1; 0: the
                                   whole body's alone (docs/fitting.md). */
} ssc_fitter_def;

/** Fills def with defaults; size = sizeof(*def). Threads: any. */
SSC_EXPERIMENTAL void ssc_fitter_def_init(ssc_fitter_def* def, size_t size);

/**
 * Creates a fitter with no observations.
 * @param model  the model; the fitter takes a reference to it.
 * @param def    options; NULL = defaults.
 * @param out    receives the fitter; set only on success.
 * Ownership: the caller owns *out, ended by ssc_fitter_destroy. The fitter keeps a double-precision
 * copy of the shape basis it uses (24 bytes per vertex and component). Threads: any; the fitter
 * itself is used from one thread at a time.
 */
SSC_EXPERIMENTAL ssc_status ssc_fitter_create(ssc_model* model, const ssc_fitter_def* def, ssc_fitter** out);

/** Destroys a fitter and drops its model reference. NULL is ignored. Threads: the fitter's thread. */
SSC_EXPERIMENTAL void ssc_fitter_destroy(ssc_fitter* fitter);

/** Removes every observation and result (the fitter is as created). Threads: the fitter's thread. */
SSC_EXPERIMENTAL ssc_status ssc_fitter_clear(ssc_fitter* fitter);

/** Frames that have observations or results (the highest frame index used plus one). */
SSC_EXPERIMENTAL uint32_t ssc_fitter_frame_count(const ssc_fitter* fitter);

/**
 * Adds landmark observations to a frame.
 * @param frame      frame index: an existing frame or ssc_fitter_frame_count (a new frame).
 * @param indices    count model landmark indices (ssc_model_find_landmark).
 * @param positions  3 * count floats, metres, any frame of reference (the fit finds the rigid motion).
 * @param weights    count relative confidences (> 0), or NULL for all 1.
 * @return SSC_ERROR_INVALID_ARGUMENT for NULL, a bad frame, an index out of range, non-finite
 *         values or coordinates beyond 1e6 in magnitude, or non-positive weights; nothing is
 *         added then.
 * Ownership: the arrays are copied. Threads: the fitter's thread.
 */
SSC_EXPERIMENTAL ssc_status ssc_fitter_add_landmarks(ssc_fitter* fitter, uint32_t frame, const uint32_t* indices,
                                            const float* positions, const float* weights, uint32_t count);

/**
 * As ssc_fitter_add_landmarks, by name (the CAESAR names of the default model, e.g. "Sellion").
 * @return SSC_ERROR_NOT_FOUND (nothing added) when a name is not one of the model's landmarks; the
 *         message names it.
 */
SSC_EXPERIMENTAL ssc_status ssc_fitter_add_landmarks_by_name(ssc_fitter* fitter, uint32_t frame, const char* const* names,
                                                    const float* positions, const float* weights, uint32_t count);

/**
 * Adds a point cloud (scan vertices, depth samples) to a frame.
 * @param points      count points, 3 floats each at stride bytes (0 = packed), metres.
 * @param normals     NULL, or count normals (outward) at the same stride: unit vectors, or (0, 0, 0)
 *                    where a point's normal is unknown. Unknown normals (all of them when NULL) are
 *                    estimated from the neighbouring points and oriented like the known ones near them.
 * @param confidence  NULL, or count weights in [0, 1] (packed floats).
 * @param count       at least 16 points.
 * @return SSC_ERROR_INVALID_ARGUMENT for NULL, a bad frame or stride, too few points, non-finite
 *         values or coordinates beyond 1e6 in magnitude, normals neither unit nor zero, confidences outside
 *         [0, 1]; nothing is added then.
 * Ownership: the arrays are copied. Threads: the fitter's thread.
 */
SSC_EXPERIMENTAL ssc_status ssc_fitter_add_points(ssc_fitter* fitter, uint32_t frame, const float* points, const float* normals,
                                         const float* confidence, uint32_t count, size_t stride);

/** Sample formats of depth images. */
typedef enum ssc_depth_format {
    SSC_DEPTH_U16_MM = 0,  /**< uint16_t millimetres (Kinect, RealSense, 16-bit PGM); 0 = no reading. */
    SSC_DEPTH_F32_M = 1,   /**< float metres; <= 0, NaN or infinite = no reading. */
    SSC_DEPTH_FORMAT_FORCE32 = 0x7FFFFFFF
} ssc_depth_format;

/**
 * A depth image seen through a pinhole camera (no lens distortion). Depth is measured along the
 * optical axis. Camera frame as depth-sensor SDKs (and OpenCV) use it: x right, y down, z forward;
 * pixel (u, v) with depth z is the camera point ((u - cx) z / fx, (v - cy) z / fy, z), pixel
 * centres at integer coordinates, v = 0 the top row. Fill with ssc_depth_image_def_init.
 */
typedef struct ssc_depth_image_def {
    uint32_t struct_size;           /**< sizeof(ssc_depth_image_def), set by ssc_depth_image_def_init. */
    uint32_t width, height;         /**< Pixels, 5..16384 each. */
    ssc_depth_format format;        /**< Sample format. Default SSC_DEPTH_U16_MM. */
    const void* samples;            /**< height rows of width samples, top row first. Required. */
    size_t row_stride;              /**< Bytes from one row to the next; 0 = packed. */
    const uint8_t* mask;            /**< NULL, or width * height bytes (packed): 0 = ignore the pixel. */
    float fx, fy;                   /**< Focal lengths, pixels (> 0). Required. */
    float cx, cy;                   /**< Principal point, pixels. Required. */
    const float* camera_to_world;   /**< NULL (camera = world frame) or a column-major 4x4 rigid transform
                                         taking camera points to the frame's world (metres). */
    float min_depth, max_depth;     /**< Metres: readings outside are ignored (background, sensor range);
                                         max_depth 0 = no limit. Default 0 and 0. */
} ssc_depth_image_def;

/** Fills def with defaults (no samples, no intrinsics); size = sizeof(*def). Threads: any. */
SSC_EXPERIMENTAL void ssc_depth_image_def_init(ssc_depth_image_def* def, size_t size);

/**
 * Adds a depth image to a frame as a point cloud: each usable pixel is back-projected into the
 * world with a normal estimated from its 5 x 5 neighbourhood and turned towards the camera. A pixel
 * is usable when it has a reading inside the depth limits, is not masked out and at least 6 of its
 * neighbours lie on the same surface (isolated readings and mixed pixels at depth edges are
 * dropped). Images of one person from several cameras at one instant go in one frame; images
 * taken at different times (the person turned around) go in frames of their own.
 * @param frame         an existing frame or ssc_fitter_frame_count (a new frame).
 * @param image         the image and its camera; the samples and mask are read during the call only.
 * @param points_added  NULL, or receives the number of points added (the pixels used; residuals of
 *                      ssc_fitter_get_point_residuals come in row-major pixel order of those).
 * @return SSC_ERROR_INVALID_ARGUMENT for NULL, a bad frame, a bad size, format or stride, degenerate
 *         intrinsics (fx or fy not positive, non-finite values), a camera_to_world that is not a
 *         rigid transform, or fewer than 16 usable pixels; nothing is added then.
 * Ownership: nothing is kept of the caller's arrays. Threads: the fitter's thread.
 */
SSC_EXPERIMENTAL ssc_status ssc_fitter_add_depth_image(ssc_fitter* fitter, uint32_t frame, const ssc_depth_image_def* image,
                                              uint32_t* points_added);

/** Called once per solver iteration with the current cost; return non-zero to cancel. */
typedef int (*ssc_progress_fn)(void* user, uint32_t iteration, float cost);

/** What a solve did. Fill struct_size (sizeof) before the call; fields beyond it are not written. */
typedef struct ssc_fit_report {
    uint32_t struct_size;     /**< sizeof(ssc_fit_report), set by the caller. */
    uint32_t iterations;      /**< Levenberg-Marquardt iterations run. */
    uint32_t converged;       /**< Non-zero when the cost stopped decreasing before the iteration limit
                                   and the fit explains its scans (see unexplained_fraction and
                                   implausible). */
    uint32_t reserved;        /**< 0. */
    float initial_cost;       /**< Cost at the start (robust, in units of the sigmas). */
    float final_cost;         /**< Cost at the end. */
    float landmark_rms;       /**< RMS distance of landmarks to their model landmarks, metres (0 if none). */
    float point_mean;         /**< Mean distance of accepted scan correspondences, metres (0 if none). */
    float inlier_fraction;    /**< Share of correspondence candidates accepted (0 if no points). */
    float seconds;            /**< Wall time of the solve. */
    uint32_t restarts;        /**< Fits redone from another automatic start candidate because the one
                                   before ended in an implausible pose or left over 3 % of the scan
                                   unexplained (one frame, no given start); iterations counts them all. */
    float unexplained_fraction; /**< Share of scan points farther than 5 cm from the fitted surface that
                                   lie on a surface (3 other points within 3 cm; isolated outliers and
                                   sparse clutter do not count): the worst frame's; 0 without points. Above SSC_FIT_UNEXPLAINED_LIMIT
                                   the fit has not found the person (a limb or the body in the wrong
                                   place) and converged is 0. */
    uint32_t implausible;     /**< Non-zero when a frame's fit, after every restart, is still judged
                                   wrong (see ssc_fit_problem): a limb or the body is likely in the
                                   wrong place. One frame: converged is then 0. Several frames: the
                                   failed frames are left out of the shared shape and reported by
                                   ssc_fitter_get_frame_report; converged speaks for the others. */
    uint32_t problem;         /**< ssc_fit_problem of the first failed frame (SSC_FIT_PROBLEM_NONE: none). */
    uint32_t failed_frames;   /**< Frames whose fit failed (each: ssc_fitter_get_frame_report). */
} ssc_fit_report;

/** What is wrong with a frame's fit (the judgement of docs/fitting.md, "Judging a fit"). */
typedef enum ssc_fit_problem {
    SSC_FIT_PROBLEM_NONE = 0,
    SSC_FIT_PROBLEM_JOINT_PAST_RANGE = 1, /**< a joint lies over 20 degrees past its anatomical range */
    SSC_FIT_PROBLEM_SCAN_UNEXPLAINED = 2, /**< over 0.5 % of the scan lies farther than 5 cm from the fit */
    SSC_FIT_PROBLEM_LIMB_OFF_SCAN = 3,    /**< a limb, the head or the trunk lies where the scan saw empty space */
    SSC_FIT_PROBLEM_LIMB_INSIDE = 4,      /**< a forearm or lower leg passes through the body (over 20 % of it
                                               more than 2 cm inside the trunk, the head or another limb) */
    SSC_FIT_PROBLEM_ARM_OFF_POINTS = 5,   /**< an arm lies off its own points, placed wrong as a whole: over 5 %
                                               of the scan nearest it more than 8 mm from the fit, on both sides
                                               of its surface (a bump of clothing lies on one) */
    SSC_FIT_PROBLEM_HAND_OFF_POINTS = 6,  /**< a hand lies off its own points, turned about the wrist or laid on
                                               the body in another place: over 25 % of the scan nearest it more
                                               than 8 mm from the fit (region names its arm) */
    SSC_FIT_PROBLEM_FORCE32 = 0x7FFFFFFF
} ssc_fit_problem;

/** The parts of the body a frame report names. */
typedef enum ssc_body_region {
    SSC_BODY_REGION_NONE = -1,
    SSC_BODY_REGION_HEAD = 0,
    SSC_BODY_REGION_TRUNK = 1,
    SSC_BODY_REGION_LEFT_ARM = 2,
    SSC_BODY_REGION_RIGHT_ARM = 3,
    SSC_BODY_REGION_LEFT_LEG = 4,
    SSC_BODY_REGION_RIGHT_LEG = 5,
    SSC_BODY_REGION_FORCE32 = 0x7FFFFFFF
} ssc_body_region;

/** How one frame's fit was judged. Fill struct_size (sizeof) before the call. */
typedef struct ssc_fit_frame_report {
    uint32_t struct_size;         /**< sizeof(ssc_fit_frame_report), set by the caller. */
    uint32_t failed;              /**< Non-zero: the frame's fit did not find the person (problem says why). */
    uint32_t left_out;            /**< Non-zero: failed, so kept out of the shared shape (several frames);
                                       its pose is its own best fit, not to be trusted. */
    uint32_t problem;             /**< ssc_fit_problem. */
    int32_t joint;                /**< The joint furthest past its range, or -1 when none is. */
    int32_t region;               /**< ssc_body_region off the scan (LIMB_OFF_SCAN), off its points
                                       (ARM_OFF_POINTS), the arm of a hand off its points (HAND_OFF_POINTS) or through
                                       the body (LIMB_INSIDE), else the part most
                                       outside the scan's extent (a partial scan), or -1. */
    float unexplained_fraction;   /**< As ssc_fit_report's, for this frame. */
    float joint_excess_degrees;   /**< How far that joint lies past its range. */
    const char* problem_text;     /**< One line: what is wrong, where, how much; "" when nothing. */
    const char* unscanned;        /**< One line on parts the scan does not show (a partial scan), or "". */
} ssc_fit_frame_report;

/** Called when a frame has been fitted (see ssc_fitter_set_frame_callback); non-zero cancels. */
typedef int (*ssc_frame_fn)(void* user, uint32_t frame, const ssc_fit_frame_report* report);

/** The unexplained_fraction above which a fit is reported as not converged: it failed. */
#define SSC_FIT_UNEXPLAINED_LIMIT 0.1f

/**
 * Fits the model to every frame's observations: a rigid start (from landmarks when there are at
 * least 3, else from the clouds' principal axes trying the plausible facing directions), then
 * Levenberg-Marquardt over shape, pose, translation (and scale), coarse to fine.
 * Not converging within max_iterations is reported in report->converged, not as an error.
 * @param progress  NULL or a callback; non-zero from it stops the solve with SSC_ERROR_CANCELLED
 *                  (the results then hold the state reached).
 * @param report    NULL or a report to fill (struct_size set by the caller).
 * @return SSC_ERROR_INVALID_ARGUMENT when a frame has too little data (fewer than 3 landmarks and
 *         16 points) or there are no frames.
 * Threads: the fitter's thread. With clouds, the search over arm and leg poses also runs on the
 * worker threads of the model's context (ssc_context_def.worker_count; 1 = none); the results do
 * not depend on their number.
 */
SSC_EXPERIMENTAL ssc_status ssc_fitter_solve(ssc_fitter* fitter, ssc_progress_fn progress, void* user, ssc_fit_report* report);

/**
 * How one frame's fit was judged, after a solve.
 * @param out  filled up to out->struct_size; its strings are owned by the fitter and valid until its
 *             next solve, clear or destroy.
 * @return SSC_ERROR_INVALID_ARGUMENT before a successful solve or for a frame beyond the last.
 * Ownership: the strings belong to the fitter. Threads: the fitter's thread.
 */
SSC_EXPERIMENTAL ssc_status ssc_fitter_get_frame_report(const ssc_fitter* fitter, uint32_t frame, ssc_fit_frame_report* out);

/**
 * A callback for ssc_fitter_solve's progress frame by frame: with several frames, called after each
 * frame's own fit (in order) and again when a later try from a neighbouring frame fixes a failed
 * one; with one frame, once at the end. NULL removes it. The report's strings live for the call.
 * Ownership: user stays the caller's. Threads: called on the thread that runs ssc_fitter_solve.
 */
SSC_EXPERIMENTAL ssc_status ssc_fitter_set_frame_callback(ssc_fitter* fitter, ssc_frame_fn callback, void* user);

/** The fitted shape (standard deviations); capacity >= ssc_model_shape_count (unused components 0).
 *  @return SSC_ERROR_INVALID_ARGUMENT before a successful solve. Threads: the fitter's thread. */
SSC_EXPERIMENTAL ssc_status ssc_fitter_get_shape(const ssc_fitter* fitter, float* out, uint32_t capacity);

/**
 * One segment's fitted coefficients (its shape_count values, ssc_segment_info; zeros when the fit had
 * no segments: ssc_fitter_def.fit_segments 0 or fewer shape components than the model's). With
 * ssc_fitter_get_shape and ssc_fitter_get_pose, ssc_body_set_segment_shape rebuilds the fitted body.
 * @return SSC_ERROR_INVALID_ARGUMENT before a successful solve, for NULL or a bad segment;
 *         SSC_ERROR_BUFFER_TOO_SMALL for a capacity below its shape_count. Threads: the fitter's thread.
 */
SSC_EXPERIMENTAL ssc_status ssc_fitter_get_segment_shape(const ssc_fitter* fitter, uint32_t segment, float* out, uint32_t capacity);

/**
 * The fitted pose of a frame: joint_capacity >= ssc_model_joint_count quaternions (x y z w, each
 * joint's rest frame, as ssc_body_set_pose takes), translation (3 floats, metres) and scale (1
 * float). Any output may be NULL. The fitted surface is scale * (posed body) + translation.
 * Threads: the fitter's thread.
 */
SSC_EXPERIMENTAL ssc_status ssc_fitter_get_pose(const ssc_fitter* fitter, uint32_t frame, float* rotations, uint32_t joint_capacity,
                                       float* translation, float* scale);

/** The fitted surface of a frame (scale and translation applied): capacity in vertices, stride in
 *  bytes (0 = packed). Threads: the fitter's thread. */
SSC_EXPERIMENTAL ssc_status ssc_fitter_get_vertices(const ssc_fitter* fitter, uint32_t frame, float* out, uint32_t capacity,
                                           size_t stride);

/**
 * Per-point residuals of a frame after a solve, in the order the points were added (all clouds of
 * the frame, one after another): the distance in metres from each point to the fitted surface
 * (along the normal of the nearest fitted vertex). Outliers keep their (large) distances.
 * @param capacity  floats out holds: at least the frame's point count.
 * Threads: the fitter's thread.
 */
SSC_EXPERIMENTAL ssc_status ssc_fitter_get_point_residuals(const ssc_fitter* fitter, uint32_t frame, float* out, uint32_t capacity);

/** Number of points added to a frame (0 for an unknown frame). */
SSC_EXPERIMENTAL uint32_t ssc_fitter_point_count(const ssc_fitter* fitter, uint32_t frame);

/* ---------------------------------------------------------------------------------------------- */
/* Scan registration (SSC_EXPERIMENTAL: may change in a minor version)                             */

/**
 * A registration deforms the model's template mesh onto a raw body scan, vertex for vertex: the
 * result has the model's vertex count and order, so scans registered this way can be compared and
 * learned from. It starts from the model fitted to the scan (or from landmarks), then gives every
 * template vertex its own affine transform, solved for with correspondences to the scan found again
 * each iteration while the stiffness is relaxed round by round (docs/registration.md). Many
 * registrations may share one model.
 */
typedef struct ssc_registration ssc_registration;

/** Where the deformation starts. */
typedef enum ssc_registration_start {
    SSC_REGISTRATION_START_MODEL = 0,  /**< The model fitted to the scan (and landmarks when given). */
    SSC_REGISTRATION_START_RIGID = 1,  /**< The template at rest, aligned (with scale) to 3 or more landmarks. */
    SSC_REGISTRATION_START_RBF = 2,    /**< The template at rest warped through 4 or more landmarks onto the
                                            scan's by radial basis functions (see ssc_rbf_kernel). */
    SSC_REGISTRATION_START_FORCE32 = 0x7FFFFFFF
} ssc_registration_start;

/** How the stiffness changes over the rounds. */
typedef enum ssc_registration_schedule {
    SSC_REGISTRATION_RELAXED = 0,   /**< Stiffness and landmark weight fall by 4 each round until the
                                         stiffness has fallen by 1000 (6 rounds). */
    SSC_REGISTRATION_CONSTANT = 1,  /**< The same rounds at the final weights throughout. */
    SSC_REGISTRATION_SCHEDULE_FORCE32 = 0x7FFFFFFF
} ssc_registration_schedule;

/** Kernels of the SSC_REGISTRATION_START_RBF warp, r the distance to a landmark, s the def's rbf_scale. */
typedef enum ssc_rbf_kernel {
    SSC_RBF_THIN_PLATE = 0,    /**< r^2 log r */
    SSC_RBF_MULTIQUADRIC = 1,  /**< sqrt(r^2 + s^2) */
    SSC_RBF_GAUSSIAN = 2,      /**< exp(-r^2 / s^2) */
    SSC_RBF_KERNEL_FORCE32 = 0x7FFFFFFF
} ssc_rbf_kernel;

/** Options of ssc_registration_create. Fill with ssc_registration_def_init; append-only. */
typedef struct ssc_registration_def {
    uint32_t struct_size;                /**< sizeof(ssc_registration_def), set by ssc_registration_def_init. */
    ssc_registration_start start;        /**< Default SSC_REGISTRATION_START_MODEL. */
    ssc_registration_schedule schedule;  /**< Default SSC_REGISTRATION_RELAXED. */
    float stiffness;                     /**< First round's smoothness weight, (0, 1e6]. Default 0.03. */
    float landmark_weight;               /**< First round's landmark weight, [0, 1e6]. Default 10. */
    float gamma;                         /**< Weight of the transforms' translation in the smoothness, (0, 1e3]. Default 1. */
    uint32_t max_iterations;             /**< Solves per round at most, 1..100. Default 4. */
    ssc_rbf_kernel rbf_kernel;           /**< Kernel of the rbf start. Default SSC_RBF_THIN_PLATE. */
    float rbf_scale;                     /**< Metres, (0, 10]: s of the multiquadric and Gaussian kernels. Default 0.1. */
    uint32_t fit_segments;               /**< Non-zero: the model's segment shape spaces (but the head's), when it
                                              has them, join the model fit's whole-body components, for bodies
                                              whose proportions the whole body's cannot hold (real people's).
                                              Default 1; 0: whole body only, a little better on bodies the
                                              model holds (docs/registration.md). */
} ssc_registration_def;

/** Fills def with defaults; size = sizeof(*def). Threads: any. */
SSC_EXPERIMENTAL void ssc_registration_def_init(ssc_registration_def* def, size_t size);

/**
 * Creates a registration with no scan.
 * @param model  the model; the registration takes a reference to it.
 * @param def    options; NULL = defaults.
 * @param out    receives the registration; set only on success.
 * @return SSC_ERROR_INVALID_ARGUMENT for NULL or options out of range.
 * Ownership: the caller owns *out, ended by ssc_registration_destroy. Threads: any; the
 * registration itself is used from one thread at a time.
 */
SSC_EXPERIMENTAL ssc_status ssc_registration_create(ssc_model* model, const ssc_registration_def* def, ssc_registration** out);

/** Destroys a registration and drops its model reference. NULL is ignored. Threads: its thread. */
SSC_EXPERIMENTAL void ssc_registration_destroy(ssc_registration* registration);

/**
 * Sets the scan (replacing one set before; forgets the result).
 * @param points          count points, 3 floats each at stride bytes (0 = packed), metres.
 * @param normals         NULL, or count outward normals at the same stride: unit, or (0, 0, 0) where
 *                        unknown (estimated from the neighbouring points).
 * @param count           at least 100 points.
 * @param triangles       NULL for a point cloud, or 3 * triangle_count point indices of the scan's mesh
 *                        (its hole rims are then its border edges).
 * @return SSC_ERROR_INVALID_ARGUMENT for NULL, a bad stride, too few points, non-finite values or
 *         coordinates beyond 1e6 in magnitude, normals neither unit nor zero, triangle indices out of
 *         range; nothing is changed then.
 * Ownership: the arrays are copied. Threads: the registration's thread.
 */
SSC_EXPERIMENTAL ssc_status ssc_registration_set_scan(ssc_registration* registration, const float* points, const float* normals,
                                                      uint32_t count, size_t stride, const uint32_t* triangles,
                                                      uint32_t triangle_count);

/**
 * Sets landmarks on the scan by name (the model's landmark names, e.g. "Sellion"), replacing those
 * set before; count 0 removes them.
 * @param positions  3 * count floats, metres, in the scan's frame.
 * @return SSC_ERROR_NOT_FOUND (nothing set) for a name that is not one of the model's;
 *         SSC_ERROR_INVALID_ARGUMENT for NULL or positions that are no measurement.
 * Ownership: copied. Threads: the registration's thread.
 */
SSC_EXPERIMENTAL ssc_status ssc_registration_set_landmarks_by_name(ssc_registration* registration, const char* const* names,
                                                                   const float* positions, uint32_t count);

/** Called as a long operation goes: its stage ("fit", "deform"), work done and total (0 when unknown); return non-zero to cancel. */
typedef int (*ssc_stage_progress_fn)(void* user, const char* stage, uint32_t done, uint32_t total);

/** How well a registration (or one body region of it) covers its scan. */
typedef struct ssc_registration_quality {
    float scan_mean, scan_median, scan_p95;  /**< Each scan point's distance to the registered surface, metres. */
    float within[4];                         /**< Shares of template vertices within 2, 5, 10 and 20 mm of a
                                                  compatible scan point (normals less than 60 degrees apart; for
                                                  a point cloud, the distance to the nearest point's tangent plane). */
} ssc_registration_quality;

/** What a run did. Fill struct_size (sizeof) before the call; fields beyond it are not written. */
typedef struct ssc_registration_report {
    uint32_t struct_size;              /**< sizeof(ssc_registration_report), set by the caller. */
    uint32_t rounds;                   /**< Stiffness rounds run. */
    uint32_t solves;                   /**< Linear solves. */
    uint32_t valid_vertices;           /**< Template vertices that ended on a compatible scan point. */
    float seconds;                     /**< Wall time, the model fit included. */
    float fit_seconds;                 /**< The model fit's share (SSC_REGISTRATION_START_MODEL). */
    ssc_registration_quality quality;  /**< Over the whole body. */
    uint32_t scan_points;              /**< Points of the scan registered to. */
    uint32_t landmarks;                /**< Landmarks on the scan that were used (0 when a file job was reused). */
} ssc_registration_report;

/**
 * Registers the scan.
 * @param progress  NULL or a callback; non-zero from it stops the run with SSC_ERROR_CANCELLED (no
 *                  result then).
 * @param report    NULL or a report to fill (struct_size set by the caller).
 * @return SSC_ERROR_INVALID_ARGUMENT without a scan, for SSC_REGISTRATION_START_RIGID with fewer than
 *         3 landmarks, for SSC_REGISTRATION_START_RBF with fewer than 4 (or all in one plane), or
 *         when the model cannot be fitted to the scan.
 * Threads: the registration's thread; the model fit and the correspondence searches also use the
 * worker threads of the model's context.
 */
SSC_EXPERIMENTAL ssc_status ssc_registration_run(ssc_registration* registration, ssc_stage_progress_fn progress, void* user,
                                                 ssc_registration_report* report);

/** The registered mesh after a run: capacity in vertices (>= ssc_model_vertex_count), stride in
 *  bytes (0 = packed); the model's triangles. Threads: the registration's thread. */
SSC_EXPERIMENTAL ssc_status ssc_registration_get_vertices(const ssc_registration* registration, float* out, uint32_t capacity,
                                                          size_t stride);

/** Per vertex after a run: 1 where it ended on a compatible scan point, 0 where it was filled in by
 *  its neighbours (holes, parts the scan does not show). Threads: the registration's thread. */
SSC_EXPERIMENTAL ssc_status ssc_registration_get_valid(const ssc_registration* registration, uint8_t* out, uint32_t capacity);

/** Per vertex after a run: its distance to the scan in metres (to the nearest compatible scan point,
 *  along that point's normal where it has one), or -1 where no compatible point lies within 5 cm.
 *  Threads: the registration's thread. */
SSC_EXPERIMENTAL ssc_status ssc_registration_get_vertex_distances(const ssc_registration* registration, float* out, uint32_t capacity);

/**
 * The model fit that started the run (SSC_REGISTRATION_START_MODEL only, else
 * SSC_ERROR_INVALID_ARGUMENT): shape (shape_capacity >= ssc_model_shape_count), pose (joint_capacity
 * >= ssc_model_joint_count quaternions x y z w), translation (3 floats) and scale; any output may be
 * NULL. Threads: the registration's thread.
 */
SSC_EXPERIMENTAL ssc_status ssc_registration_get_fit(const ssc_registration* registration, float* shape, uint32_t shape_capacity,
                                                     float* rotations, uint32_t joint_capacity, float* translation, float* scale);

/**
 * One segment's coefficients in that model fit (its shape_count values, ssc_segment_info; zeros when
 * the fit had no segments: ssc_registration_def.fit_segments 0, or the head's). With ssc_registration_get_fit's
 * shape and pose, ssc_body_set_segment_shape rebuilds the fitted body. SSC_ERROR_INVALID_ARGUMENT
 * as ssc_registration_get_fit, or for a bad segment or a capacity below its shape_count.
 * Threads: the registration's thread.
 */
SSC_EXPERIMENTAL ssc_status ssc_registration_get_fit_segment_shape(const ssc_registration* registration, uint32_t segment, float* out,
                                                                   uint32_t capacity);

/** Body regions of the quality report (the model's vertex sets: head, torso, arms, ...), after a run. */
SSC_EXPERIMENTAL uint32_t ssc_registration_region_count(const ssc_registration* registration);

/**
 * One region's quality after a run.
 * @param name  receives the region's name, owned by the registration (valid until its next run or
 *              destruction); may be NULL.
 * Threads: the registration's thread.
 */
SSC_EXPERIMENTAL ssc_status ssc_registration_get_region(const ssc_registration* registration, uint32_t index, const char** name,
                                                        ssc_registration_quality* quality);

#ifdef __cplusplus
}
#endif

#endif /* SSCAPE_SSCAPE_H */
